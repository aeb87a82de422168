#pragma once
// One long job at a time on a thread of its own, restarted without waiting: starting a job cancels
// the running one and returns at once; the cancelled job ends on its own when it next looks at its
// flag, and its thread is joined once it has (or by stop()). So the caller's thread (the GUI's,
// during a drag) never blocks on a job in its set-up, and an answer the old job may still deliver
// is the caller's to drop by its generation.
//
// The owner's mutex and condition variable are the ones its jobs wait under: the flag is set under
// that mutex and the variable notified, so a job that tests its wake-up condition (which includes
// the flag) and then waits never misses its cancellation. (LatestRequestWorker.h is the other
// pattern: short jobs, each finished before the latest waiting request starts.)

#include <atomic>
#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

namespace sightline::ui {

class RestartingWorker {
public:
    /// The job; returns when done or when it sees `cancel` set. Must not throw.
    using Job = std::function<void(std::shared_ptr<const std::atomic<bool>> cancel)>;

    RestartingWorker(std::mutex& mutex, std::condition_variable& wake) : mutex_(mutex), wake_(wake) {}
    /// Cancels and waits for every job.
    ~RestartingWorker() { stop(); }
    RestartingWorker(const RestartingWorker&) = delete;
    RestartingWorker& operator=(const RestartingWorker&) = delete;

    /// Cancels the running job (without waiting) and starts `job` on a new thread.
    void start(Job job);
    /// Cancels the running job without waiting; joins the cancelled jobs that have ended.
    void cancel();
    /// Cancels and waits for every job.
    void stop();
    /// Threads not yet joined (the running job and the cancelled ones still ending).
    std::size_t threads() const { return retired_.size() + (current_.thread.joinable() ? 1 : 0); }

private:
    struct Run {
        std::thread thread;
        std::shared_ptr<std::atomic<bool>> cancel, done;
    };
    void reap(bool wait);

    std::mutex& mutex_;
    std::condition_variable& wake_;
    Run current_;
    std::vector<Run> retired_;
};

} // namespace sightline::ui
