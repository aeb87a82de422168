#include "BackgroundSampler.h"

#include <exception>
#include <new>

#include "RayEnds.h"

namespace sightline::ui {

BackgroundSampler::BackgroundSampler(Deliver deliver) : deliver_(std::move(deliver)), thread_([this] { run(); }) {}

BackgroundSampler::~BackgroundSampler()
{
    {
        std::lock_guard lock(mutex_);
        stop_ = true;
        next_.reset();
    }
    wake_.notify_one();
    thread_.join();
}

void BackgroundSampler::request(Request request)
{
    {
        std::lock_guard lock(mutex_);
        next_ = std::move(request);
    }
    wake_.notify_one();
}

void BackgroundSampler::run()
{
    LiveVisibility sampler;   // no GL: the CPU bitmask sampler, the same code as the GUI thread's
    const Scene* sceneOf = nullptr;
    std::shared_ptr<const Scene> scene;            // held so sceneOf stays meaningful
    std::shared_ptr<const ReceiverHeights> heights;
    std::unique_ptr<pvs::FirstHitCaster> hits;   // built for a scene the first time ray ends are asked
    const Scene* hitsOf = nullptr;
    for (;;) {
        Request request;
        {
            std::unique_lock lock(mutex_);
            wake_.wait(lock, [this] { return stop_ || next_; });
            if (stop_)
                return;
            request = std::move(*next_);
            next_.reset();
        }
        VisibilityResult result;
        try {
            if (request.scene && request.scene.get() != sceneOf) {
                sampler.setScene(*request.scene);
                scene = request.scene;
                sceneOf = scene.get();
            }
            if (request.heights != heights) {
                heights = request.heights;
                sampler.setReceiverHeights(heights ? *heights : ReceiverHeights{});
            }
            sampler.setReceiverHeightsError(request.heightsError);
            result = sampler.sample(request.source, request.receiver);
            if (result.valid && request.rayEndsCap > 0 && scene) {
                if (!hits || hitsOf != scene.get()) {
                    hits = std::make_unique<pvs::FirstHitCaster>(*scene);
                    hitsOf = scene.get();
                }
                const RaySubset subset = raySubset(result.map.sourceCount(), result.map.receiverCount(), request.rayEndsCap);
                result.rayEnds = drawnRayEnds(*hits, result.map, request.source, request.receiver, subset);
                result.rayEndsCap = request.rayEndsCap;
            }
        } catch (const std::bad_alloc&) {
            result = {};
            result.error = "out of memory while sampling the patches";
        } catch (const std::exception& e) {
            result = {};
            result.error = e.what();
        }
        result.source = request.source;
        result.receiver = request.receiver;
        deliver_(request.generation, std::move(result));
    }
}

} // namespace sightline::ui
