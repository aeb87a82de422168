#include "editor/BackgroundSampler.h"

#include <exception>
#include <new>

#include "editor/RayEnds.h"

namespace sightline::ui {

class BackgroundSampler::Samples {
public:
    VisibilityResult sample(const Request& request)
    {
        VisibilityResult result;
        try {
            if (request.scene && request.scene.get() != sceneOf_) {
                sampler_.setScene(*request.scene);
                scene_ = request.scene;
                sceneOf_ = scene_.get();
            }
            if (request.heights != heights_) {
                heights_ = request.heights;
                sampler_.setReceiverHeights(heights_ ? *heights_ : ReceiverHeights{});
            }
            sampler_.setReceiverHeightsError(request.heightsError);
            result = sampler_.sample(request.source, request.receiver);
            if (result.valid && request.rayEndsCap > 0 && scene_) {
                if (!hits_ || hitsOf_ != scene_.get()) {
                    hits_ = std::make_unique<pvs::FirstHitCaster>(*scene_);
                    hitsOf_ = scene_.get();
                }
                const RaySubset subset = raySubset(result.map.sourceCount(), result.map.receiverCount(), request.rayEndsCap);
                result.rayEnds = drawnRayEnds(*hits_, result.map, request.source, request.receiver, subset);
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
        return result;
    }

private:
    LiveVisibility sampler_;   // no GL: the CPU bitmask sampler, the same code as the GUI thread's
    const Scene* sceneOf_ = nullptr;
    std::shared_ptr<const Scene> scene_;   // held so sceneOf_ stays meaningful
    std::shared_ptr<const ReceiverHeights> heights_;
    std::unique_ptr<pvs::FirstHitCaster> hits_;   // built for a scene the first time ray ends are asked
    const Scene* hitsOf_ = nullptr;
};

BackgroundSampler::BackgroundSampler(Deliver deliver)
    : samples_(std::make_shared<Samples>()),
      worker_([samples = samples_](const Request& request) { return samples->sample(request); }, std::move(deliver))
{
}

BackgroundSampler::~BackgroundSampler() = default;

void BackgroundSampler::request(Request request)
{
    const std::uint64_t generation = request.generation;
    worker_.request(generation, std::move(request));
}

} // namespace sightline::ui
