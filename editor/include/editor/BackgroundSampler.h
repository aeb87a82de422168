#pragma once
// Live sampling off the GUI thread (on it, sampling a 512x512 floor would freeze the window on
// every update). One worker thread (LatestRequestWorker.h: the latest request wins, every answer
// carries its generation) owns a CPU bitmask sampler; the viewport posts the pair it wants
// sampled and keeps drawing. Plain C++ (no Qt): the caller decides how an answer reaches its own
// thread.

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "editor/LatestRequestWorker.h"
#include "editor/LiveVisibility.h"

namespace sightline::ui {

class BackgroundSampler {
public:
    struct Request {
        std::uint64_t generation = 0;
        /// The triangles; the worker copies them into its sampler only when the pointer changes,
        /// so a drag of a patch shares one scene between requests.
        std::shared_ptr<const Scene> scene;
        Patch source, receiver;
        /// The receiver's bumps (§8) for its grid, or null for a flat receiver; same sharing rule.
        std::shared_ptr<const ReceiverHeights> heights;
        /// The project's heights could not be read: the answer is invalid with this message.
        std::string heightsError;
        /// Above 0: also find where the blocked ones of this many drawn rays are first stopped
        /// (VisibilityResult::rayEnds), for drawing them up to there.
        int rayEndsCap = 0;
    };
    /// Called on the worker thread with the request's generation and its answer (never throws
    /// out of the worker: a failure is an invalid result whose error says why).
    using Deliver = std::function<void(std::uint64_t generation, VisibilityResult result)>;

    explicit BackgroundSampler(Deliver deliver);
    /// Waits for the request being sampled, drops any waiting one.
    ~BackgroundSampler();
    BackgroundSampler(const BackgroundSampler&) = delete;
    BackgroundSampler& operator=(const BackgroundSampler&) = delete;

    /// Queues `request`, replacing a request that has not started yet.
    void request(Request request);

private:
    /// What the worker keeps between requests: the sampler with the last scene and heights, and
    /// the first-hit caster for ray ends. Touched on the worker thread only.
    class Samples;
    std::shared_ptr<Samples> samples_;
    LatestRequestWorker<Request, VisibilityResult> worker_;   // last: its thread uses samples_
};

} // namespace sightline::ui
