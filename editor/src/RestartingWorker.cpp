#include "editor/RestartingWorker.h"

namespace sightline::ui {

void RestartingWorker::start(Job job)
{
    cancel();
    Run run;
    run.cancel = std::make_shared<std::atomic<bool>>(false);
    run.done = std::make_shared<std::atomic<bool>>(false);
    // Kept only once its thread runs: a thread that failed to start leaves nothing to join.
    run.thread = std::thread([job = std::move(job), cancel = run.cancel, done = run.done] {
        struct Ended {
            std::atomic<bool>& done;
            ~Ended() { done.store(true); }
        } ended{*done};
        job(cancel);
    });
    current_ = std::move(run);
}

void RestartingWorker::cancel()
{
    if (current_.cancel) {
        {
            // Under the lock the job tests its wake-up under: set between its test and its wait,
            // the flag's notification would be lost and the job (and stop()) never return.
            std::lock_guard lock(mutex_);
            current_.cancel->store(true);
        }
        wake_.notify_all();
        retired_.push_back(std::move(current_));
        current_ = {};
    }
    reap(false);
}

void RestartingWorker::reap(bool wait)
{
    std::erase_if(retired_, [wait](Run& run) {
        if (!wait && !run.done->load())
            return false;
        if (run.thread.joinable())
            run.thread.join();
        return true;
    });
}

void RestartingWorker::stop()
{
    cancel();
    reap(true);
}

} // namespace sightline::ui
