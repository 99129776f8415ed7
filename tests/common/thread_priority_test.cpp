// Other threads yield to the haptic loop; the loop's thread asks for real-time scheduling.
#include <gtest/gtest.h>

#include <pthread.h>
#include <sched.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
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

// Granted, the thread runs under SCHED_FIFO at the priority asked for; refused, it keeps the normal
// scheduler and says why. scheduleNormally takes it back.
TEST(ThreadPriority, RealtimeSchedulingIsGrantedOrRefusedWithAReason) {
    std::thread([] {
        const RealtimeScheduling got = scheduleRealtime(40);
        sched_param param{};
        int policy = -1;
        pthread_getschedparam(pthread_self(), &policy, &param);
        if (got.granted) {
            EXPECT_EQ(policy, SCHED_FIFO);
            EXPECT_EQ(param.sched_priority, 40);
            EXPECT_EQ(got.error, 0);
        } else {
            EXPECT_EQ(policy, SCHED_OTHER);
            EXPECT_EQ(got.error, EPERM) << "only a missing privilege refuses a valid priority";
        }
        scheduleNormally();
        pthread_getschedparam(pthread_self(), &policy, &param);
        EXPECT_EQ(policy, SCHED_OTHER);
    }).join();
}

TEST(ThreadPriority, APriorityOutsideSchedFifosRangeIsRefused) {
    std::thread([] {
        const RealtimeScheduling got = scheduleRealtime(1000);
        EXPECT_FALSE(got.granted);
        EXPECT_EQ(got.error, EINVAL);
        EXPECT_EQ(sched_getscheduler(0), SCHED_OTHER);
    }).join();
}

}  // namespace
}  // namespace hapticut
