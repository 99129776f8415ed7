// The worker pool: every chunk once, on the thread it says, with results independent of the thread count.
#include "hapticut/common/worker_pool.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <numeric>
#include <thread>
#include <vector>

namespace hapticut {
namespace {

TEST(WorkerPool, RunsEveryChunkOnceInEveryLoop) {
    for (unsigned threads : {1u, 2u, 3u, 8u}) {
        WorkerPool pool(threads);
        EXPECT_EQ(pool.threads(), threads);
        std::vector<std::atomic<int>> runs(257);
        // Loops of every size, back to back and with pauses, so that helpers are caught spinning, asleep
        // and waking.
        for (int loop = 0; loop < 3000; ++loop) {
            const std::size_t chunks = static_cast<std::size_t>(loop % 257);
            pool.forEach(chunks, [&](std::size_t chunk) { runs[chunk].fetch_add(1, std::memory_order_relaxed); });
            for (std::size_t c = 0; c < runs.size(); ++c) {
                ASSERT_EQ(runs[c].load(), c < chunks ? 1 : 0)
                    << threads << " threads, loop " << loop << ", chunk " << c;
                runs[c].store(0);
            }
            if (loop % 500 == 499) std::this_thread::sleep_for(std::chrono::microseconds(200));
        }
    }
}

TEST(WorkerPool, TellsEachChunkWhichThreadRunsIt) {
    WorkerPool pool(3);
    std::vector<unsigned> workerOf(1000, 99);
    pool.forEach(workerOf.size(), [&](std::size_t chunk, unsigned worker) { workerOf[chunk] = worker; });
    for (unsigned worker : workerOf) EXPECT_LT(worker, 3u);
}

TEST(WorkerPool, PartialSumsCombinedInChunkOrderGiveTheSameBitsWithAnyNumberOfThreads) {
    std::vector<double> values(100'000);
    for (std::size_t i = 0; i < values.size(); ++i) values[i] = 1.0 / static_cast<double>(i + 1) * (i % 3 ? 1 : -1e3);
    auto sum = [&](unsigned threads) {
        WorkerPool pool(threads);
        constexpr std::size_t kChunk = 1000;
        std::vector<double> partial(values.size() / kChunk);
        pool.forEach(partial.size(), [&](std::size_t chunk) {
            partial[chunk] =
                std::accumulate(values.begin() + chunk * kChunk, values.begin() + (chunk + 1) * kChunk, 0.0);
        });
        return std::accumulate(partial.begin(), partial.end(), 0.0);
    };
    const double one = sum(1);
    for (unsigned threads : {2u, 4u, 7u}) EXPECT_EQ(sum(threads), one) << threads << " threads";
}

TEST(OwnedWorkerPool, ACopyHasThreadsOfItsOwn) {
    OwnedWorkerPool a;
    EXPECT_EQ(a.threads(), 1u);
    a.resize(3);
    OwnedWorkerPool b = a;
    EXPECT_EQ(b.threads(), 3u);
    std::atomic<int> runs{0};
    b.forEach(100, [&](std::size_t) { ++runs; });
    a.forEach(100, [&](std::size_t) { ++runs; });
    EXPECT_EQ(runs.load(), 200);
    b.resize(1);
    EXPECT_EQ(b.threads(), 1u);
}

}  // namespace
}  // namespace hapticut
