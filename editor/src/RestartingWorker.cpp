#include "editor/RestartingWorker.h"

namespace sightline::ui {

void RestartingWorker::start(Job job)
{
    cancel();
    current_.cancel = std::make_shared<std::atomic<bool>>(false);
    current_.done = std::make_shared<std::atomic<bool>>(false);
    current_.thread = std::thread([job = std::move(job), cancel = current_.cancel, done = current_.done] {
        struct Ended {
            std::atomic<bool>& done;
            ~Ended() { done.store(true); }
        } ended{*done};
        job(cancel);
    });
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
