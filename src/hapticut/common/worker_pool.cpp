// The worker pool's helpers: claiming chunks, spinning briefly between loops, sleeping on a futex.
#include "hapticut/common/worker_pool.h"

#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>

#include "hapticut/common/thread_priority.h"

namespace hapticut {

namespace {

void relax() {
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#else
    std::this_thread::yield();
#endif
}

// How long a helper spins for the next loop before it sleeps: a solve's passes follow each other within
// microseconds, while the gap between two steps is a millisecond or more.
constexpr auto kSpinBeforeSleep = std::chrono::microseconds(50);

constexpr int kHelperNiceness = 10;  // added to the creating thread's nice value

constexpr std::uint64_t kUnclaimedMask = 0xffff'ffffu;

}  // namespace

WorkerPool::WorkerPool(unsigned threads) {
    helpers_.reserve(threads > 1 ? threads - 1 : 0);
    for (unsigned i = 1; i < threads; ++i) helpers_.emplace_back([this, i] { helperLoop(i); });
}

WorkerPool::~WorkerPool() {
    stop_.store(true);
    loop_.fetch_add(1);
    loop_.notify_all();
    for (std::thread& helper : helpers_) helper.join();
}

unsigned WorkerPool::hardwareThreads() { return std::max(1u, std::thread::hardware_concurrency()); }

void WorkerPool::run(std::size_t chunks, Call call, void* context) {
    call_ = call, context_ = context, chunks_ = chunks;
    done_.store(0, std::memory_order_relaxed);
    const std::uint32_t loop = ++lastLoop_;
    claim_.store(std::uint64_t{loop} << 32 | chunks, std::memory_order_release);
    // Sequentially consistent with the helpers' count of sleepers: either a helper going to sleep sees
    // the new number, or this sees the sleeper and wakes it.
    loop_.store(loop);
    if (sleepers_.load() > 0) loop_.notify_all();
    work(loop, 0);
    // Only chunks a helper has begun are left; wait for them.
    for (unsigned spins = 0; done_.load(std::memory_order_acquire) != chunks; ++spins)  // wraps harmlessly
        if (spins < 4096)
            relax();
        else
            std::this_thread::yield();
}

void WorkerPool::work(std::uint32_t loop, unsigned worker) {
    for (;;) {
        std::uint64_t word = claim_.load(std::memory_order_acquire);
        do {
            if (word >> 32 != loop || (word & kUnclaimedMask) == 0) return;
        } while (!claim_.compare_exchange_weak(word, word - 1, std::memory_order_acq_rel, std::memory_order_acquire));
        // Holding a chunk of this loop: its caller is still waiting, so the loop's fields are its own.
        const std::size_t unclaimed = word & kUnclaimedMask;
        call_(context_, chunks_ - unclaimed, worker);
        done_.fetch_add(1, std::memory_order_release);
    }
}

void WorkerPool::helperLoop(unsigned worker) {
    {
        const long self = syscall(SYS_gettid);
        setpriority(PRIO_PROCESS, static_cast<id_t>(self), threadNiceness(self) + kHelperNiceness);
    }
    std::uint32_t seen = 0;
    for (;;) {
        auto spinUntil = std::chrono::steady_clock::now() + kSpinBeforeSleep;
        std::uint32_t loop = loop_.load(std::memory_order_acquire);
        for (unsigned spins = 0; loop == seen && !stop_.load(std::memory_order_relaxed); ++spins) {
            relax();
            if (spins % 64 == 63 && std::chrono::steady_clock::now() > spinUntil) {
                sleepers_.fetch_add(1);
                if (loop_.load() == seen && !stop_.load()) loop_.wait(seen);
                sleepers_.fetch_sub(1);
                spinUntil = std::chrono::steady_clock::now() + kSpinBeforeSleep;
            }
            loop = loop_.load(std::memory_order_acquire);
        }
        if (stop_.load()) return;
        seen = loop;
        work(loop, worker);
    }
}

}  // namespace hapticut
