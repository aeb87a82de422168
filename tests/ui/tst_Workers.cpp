// The editor's two worker patterns, tested once for every user: LatestRequestWorker (short jobs;
// the latest waiting request wins) and RestartingWorker (long jobs; a new one cancels the running
// one without waiting).

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <future>
#include <mutex>
#include <vector>

#include <gtest/gtest.h>

#include "editor/LatestRequestWorker.h"
#include "editor/RestartingWorker.h"

namespace {

using namespace sightline::ui;
using namespace std::chrono_literals;

/// A gate a job waits at until the test opens it.
struct Gate {
    std::mutex mutex;
    std::condition_variable changed;
    bool open = false;
    int waiting = 0;

    void pass()
    {
        std::unique_lock lock(mutex);
        ++waiting;
        changed.notify_all();
        changed.wait(lock, [&] { return open; });
    }
    void waitForOne()
    {
        std::unique_lock lock(mutex);
        ASSERT_TRUE(changed.wait_for(lock, 10s, [&] { return waiting > 0; }));
    }
    void openUp()
    {
        {
            std::lock_guard lock(mutex);
            open = true;
        }
        changed.notify_all();
    }
};

TEST(LatestRequestWorker, ARequestArrivingWhileOneRunsReplacesTheWaitingOneAndAnswersCarryTheirGeneration)
{
    Gate gate;
    std::mutex mutex;
    std::condition_variable answered;
    std::vector<std::pair<std::uint64_t, int>> answers;
    {
        LatestRequestWorker<int, int> worker(
            [&](const int& request) {
                if (request == 1)
                    gate.pass();   // the first job holds the worker while more requests arrive
                return request * 10;
            },
            [&](std::uint64_t generation, int answer) {
                std::lock_guard lock(mutex);
                answers.emplace_back(generation, answer);
                answered.notify_all();
            });
        worker.request(1, 1);
        gate.waitForOne();
        worker.request(2, 2);   // waits; replaced by the next two in turn
        worker.request(3, 3);
        worker.request(4, 4);
        gate.openUp();
        std::unique_lock lock(mutex);
        ASSERT_TRUE(answered.wait_for(lock, 10s, [&] { return answers.size() >= 2; }));
    }
    // The worker is gone: nothing more can arrive.
    ASSERT_EQ(answers.size(), 2u);
    EXPECT_EQ(answers[0], (std::pair<std::uint64_t, int>{1, 10}));
    EXPECT_EQ(answers[1], (std::pair<std::uint64_t, int>{4, 40}));
}

TEST(LatestRequestWorker, DestroyingItWaitsForTheRunningJobAndDropsTheWaitingOne)
{
    Gate gate;
    std::atomic<int> started{0}, delivered{0};
    auto worker = std::make_unique<LatestRequestWorker<int, int>>(
        [&](const int&) {
            ++started;
            gate.pass();
            return 0;
        },
        [&](std::uint64_t, int) { ++delivered; });
    worker->request(1, 1);
    gate.waitForOne();
    worker->request(2, 2);
    auto destroyed = std::async(std::launch::async, [&] { worker.reset(); });
    EXPECT_EQ(destroyed.wait_for(50ms), std::future_status::timeout);   // the running job holds it
    gate.openUp();
    ASSERT_EQ(destroyed.wait_for(10s), std::future_status::ready);
    EXPECT_EQ(started.load(), 1);
    EXPECT_EQ(delivered.load(), 1);
}

TEST(RestartingWorker, StartingAJobCancelsTheRunningOneWithoutWaitingForIt)
{
    std::mutex mutex;
    std::condition_variable wake;
    std::atomic<int> cancelledSeen{0}, finished{0};
    Gate inside;
    std::promise<void> release;
    std::shared_future<void> released = release.get_future().share();
    RestartingWorker worker(mutex, wake);
    // The first job ignores its flag until released: starting the second must not wait for it.
    worker.start([&](std::shared_ptr<const std::atomic<bool>> cancel) {
        inside.pass();
        released.wait();
        if (cancel->load())
            ++cancelledSeen;
    });
    inside.waitForOne();
    inside.openUp();
    const auto begun = std::chrono::steady_clock::now();
    std::promise<void> secondDone;
    worker.start([&](std::shared_ptr<const std::atomic<bool>> cancel) {
        if (!cancel->load())
            ++finished;
        secondDone.set_value();
    });
    EXPECT_LT(std::chrono::steady_clock::now() - begun, 5s);
    ASSERT_EQ(secondDone.get_future().wait_for(10s), std::future_status::ready);   // ran while the first still blocks
    EXPECT_EQ(worker.threads(), 2u);   // the first still ends on its own
    release.set_value();
    worker.stop();
    EXPECT_EQ(cancelledSeen.load(), 1);
    EXPECT_EQ(finished.load(), 1);
    EXPECT_EQ(worker.threads(), 0u);
}

TEST(RestartingWorker, AJobWaitingUnderTheOwnersLockWakesOnCancellation)
{
    std::mutex mutex;
    std::condition_variable wake;
    std::atomic<bool> ended{false};
    Gate inside;
    RestartingWorker worker(mutex, wake);
    // Waits for a change that never comes: only the cancellation can end it.
    worker.start([&](std::shared_ptr<const std::atomic<bool>> cancel) {
        inside.openUp();
        inside.pass();
        std::unique_lock lock(mutex);
        wake.wait(lock, [&] { return cancel->load(); });
        ended = true;
    });
    inside.waitForOne();
    auto stopped = std::async(std::launch::async, [&] { worker.stop(); });
    ASSERT_EQ(stopped.wait_for(10s), std::future_status::ready);
    EXPECT_TRUE(ended.load());
}

} // namespace
