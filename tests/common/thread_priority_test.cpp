// Other threads yield to the haptic loop; the loop's thread asks for real-time scheduling.
#include <gtest/gtest.h>

#include <pthread.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <thread>

#include "hapticut/common/thread_priority.h"

namespace hapticut {
namespace {

TEST(ThreadPriority, OtherThreadsYieldAndTheCallerKeepsItsPriority) {
    std::atomic<long> workerTid{0};
    std::atomic<bool> done{false};
    std::thread worker([&] {
        pthread_setname_np(pthread_self(), "renderer-like");
        workerTid = syscall(SYS_gettid);
        while (!done) std::this_thread::yield();
    });
    while (workerTid == 0) std::this_thread::yield();
    const long self = syscall(SYS_gettid);
    const int before = threadNiceness(self);

    const std::vector<std::string> names = deprioritiseOtherThreads(before + 7);
    EXPECT_NE(std::find(names.begin(), names.end(), "renderer-like"), names.end());
    EXPECT_EQ(threadNiceness(workerTid), before + 7);
    EXPECT_EQ(threadNiceness(self), before) << "the calling thread (the one that starts the loop) is left alone";
    EXPECT_TRUE(deprioritiseOtherThreads(before + 7).empty()) << "a thread already that nice is not touched again";
    done = true;
    worker.join();
}

}  // namespace
}  // namespace hapticut
