#pragma once
// One worker thread that answers the latest request: a request that arrives while another is
// being worked on replaces any request still waiting, so a drag never queues stale work, and
// every answer carries the generation it was asked for, so the caller can drop a stale one.
// Plain C++ (no Qt): the caller decides how an answer reaches its own thread.

#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>
#include <thread>
#include <utility>

namespace sightline::ui {

template <typename Request, typename Answer>
class LatestRequestWorker {
public:
    /// Runs on the worker thread; must not throw (an answer can carry an error instead).
    using Work = std::function<Answer(const Request&)>;
    /// Called on the worker thread with the request's generation and its answer.
    using Deliver = std::function<void(std::uint64_t generation, Answer answer)>;

    LatestRequestWorker(Work work, Deliver deliver) : work_(std::move(work)), deliver_(std::move(deliver)) {}
    /// Waits for the request being worked on, drops any waiting one.
    ~LatestRequestWorker()
    {
        {
            const std::lock_guard lock(mutex_);
            stop_ = true;
            next_.reset();
        }
        wake_.notify_all();
        thread_.join();
    }
    LatestRequestWorker(const LatestRequestWorker&) = delete;
    LatestRequestWorker& operator=(const LatestRequestWorker&) = delete;

    /// Queues `request`, replacing a request that has not started yet.
    void request(std::uint64_t generation, Request request)
    {
        {
            const std::lock_guard lock(mutex_);
            next_.emplace(generation, std::move(request));
        }
        wake_.notify_one();
    }

private:
    void run()
    {
        for (;;) {
            std::optional<std::pair<std::uint64_t, Request>> job;
            {
                std::unique_lock lock(mutex_);
                wake_.wait(lock, [this] { return stop_ || next_.has_value(); });
                if (stop_)
                    return;
                job = std::move(next_);
                next_.reset();
            }
            deliver_(job->first, work_(job->second));
        }
    }

    Work work_;
    Deliver deliver_;
    std::mutex mutex_;
    std::condition_variable wake_;
    std::optional<std::pair<std::uint64_t, Request>> next_;
    bool stop_ = false;
    std::thread thread_{[this] { run(); }};   // last: starts once everything above exists
};

} // namespace sightline::ui
