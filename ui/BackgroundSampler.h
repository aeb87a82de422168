#pragma once
// Live sampling off the GUI thread (on it, sampling a 512x512 floor would freeze the window on
// every update). One worker thread owns a CPU bitmask sampler; the viewport posts the pair
// it wants sampled and keeps drawing. The latest request wins: a request that arrives while one
// is being sampled replaces any request still waiting, so a drag never queues stale work, and
// every answer carries the generation it was asked for, so the caller can tell a stale one.
// Plain C++ (no Qt): the caller decides how an answer reaches its own thread.

#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "LiveVisibility.h"

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
    void run();

    Deliver deliver_;
    std::mutex mutex_;
    std::condition_variable wake_;
    std::optional<Request> next_;
    bool stop_ = false;
    std::thread thread_;   // last: starts once everything above exists
};

} // namespace sightline::ui
