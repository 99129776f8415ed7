// A pool of helper threads, made once, that share a loop's chunks with the thread that runs it.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <thread>
#include <type_traits>
#include <vector>

namespace hapticut {

/// Runs `task(chunk)` for every chunk of a loop on the calling thread and the pool's helpers together.
///
/// Made once: a loop takes no lock, allocates nothing and starts no thread. Chunks are claimed one at a
/// time from a shared counter, so a helper that the scheduler has not run yet (a machine with fewer
/// cores than threads) delays nothing: the calling thread claims the chunks it leaves and only ever
/// waits for a chunk a helper has begun. What a chunk computes must not depend on which thread runs it;
/// callers keep one partial result per chunk and combine them in chunk order, so that a result is the
/// same, to the bit, with any number of threads.
///
/// Helpers spin for a while after a loop, where the next one usually follows within microseconds (the
/// passes of a conjugate-gradient solve), and then sleep on a futex until the next. They run at a lower
/// priority (nice +10), so that where cores are short they give way to the haptic thread: with two solve
/// threads on a 2-core machine, a real-time run missed 293 haptic periods in 7.5 s instead of 710 (one
/// solve thread: 2-10). One thread calls forEach at a time.
class WorkerPool {
public:
    /// `threads` counts the calling thread: 1 makes no helper, and every loop runs on the caller.
    explicit WorkerPool(unsigned threads);
    ~WorkerPool();
    WorkerPool(const WorkerPool&) = delete;
    WorkerPool& operator=(const WorkerPool&) = delete;

    /// The calling thread and the helpers.
    unsigned threads() const { return static_cast<unsigned>(helpers_.size()) + 1; }

    /// Calls task(chunk) for chunk = 0 .. chunks - 1, each once, and returns when all have returned. A task
    /// that takes (chunk, worker) is also told which thread runs it, 0 .. threads() - 1 (0: the caller),
    /// for scratch space of its own.
    template <class Task>
    void forEach(std::size_t chunks, Task&& task) {
        using Callable = std::remove_reference_t<Task>;
        if (chunks == 0) return;
        if (chunks == 1 || helpers_.empty()) {
            for (std::size_t chunk = 0; chunk < chunks; ++chunk) invoke(task, chunk, 0);
            return;
        }
        run(
            chunks,
            [](void* context, std::size_t chunk, unsigned worker) {
                invoke(*static_cast<Callable*>(context), chunk, worker);
            },
            const_cast<void*>(static_cast<const void*>(&task)));
    }

    /// The machine's cores (hardware threads), at least 1.
    static unsigned hardwareThreads();

    /// Calls task(chunk, worker), or task(chunk) when it takes no worker.
    template <class Task>
    static void invoke(Task& task, std::size_t chunk, unsigned worker) {
        if constexpr (std::is_invocable_v<Task&, std::size_t, unsigned>)
            task(chunk, worker);
        else
            task(chunk);
    }

private:
    using Call = void (*)(void*, std::size_t, unsigned);
    void run(std::size_t chunks, Call call, void* context);
    void helperLoop(unsigned worker);
    /// Claims and runs chunks of the loop numbered `loop` on thread `worker` until none is left or that
    /// loop is over.
    void work(std::uint32_t loop, unsigned worker);

    std::vector<std::thread> helpers_;
    std::uint32_t lastLoop_ = 0;  // the calling thread's count of loops
    // The loop's number (high 32 bits) and how many of its chunks are still unclaimed (low 32 bits), in
    // one word: a helper late for a loop can never claim a chunk of the next one.
    alignas(64) std::atomic<std::uint64_t> claim_{0};
    alignas(64) std::atomic<std::uint32_t> loop_{0};  // the latest loop's number, what sleeping helpers wait on
    std::atomic<std::uint32_t> sleepers_{0};
    std::atomic<bool> stop_{false};
    alignas(64) std::atomic<std::size_t> done_{0};  // chunks of the current loop finished
    // The current loop, written before its number is published and read only by a thread holding one
    // of its chunks (so never while the next loop writes them).
    Call call_ = nullptr;
    void* context_ = nullptr;
    std::size_t chunks_ = 0;
};

/// A pool owned by a copyable object: a copy makes a pool of its own with as many threads (threads are
/// not shared between copies, which may step on different threads).
class OwnedWorkerPool {
public:
    OwnedWorkerPool() = default;
    OwnedWorkerPool(const OwnedWorkerPool& other) { *this = other; }
    OwnedWorkerPool& operator=(const OwnedWorkerPool& other) {
        if (this != &other) resize(other.threads());
        return *this;
    }
    OwnedWorkerPool(OwnedWorkerPool&&) noexcept = default;
    OwnedWorkerPool& operator=(OwnedWorkerPool&&) noexcept = default;

    unsigned threads() const { return pool_ ? pool_->threads() : 1; }
    /// Makes the pool again with `threads` threads (1: none) unless it has that many already.
    void resize(unsigned threads) {
        if (threads != this->threads()) pool_ = threads > 1 ? std::make_unique<WorkerPool>(threads) : nullptr;
    }
    /// As WorkerPool::forEach; every chunk on the calling thread when there is no pool.
    template <class Task>
    void forEach(std::size_t chunks, Task&& task) {
        if (pool_)
            pool_->forEach(chunks, task);
        else
            for (std::size_t chunk = 0; chunk < chunks; ++chunk) WorkerPool::invoke(task, chunk, 0);
    }

private:
    std::unique_ptr<WorkerPool> pool_;
};

}  // namespace hapticut
