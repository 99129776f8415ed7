// prefaultThreadHeap: the small allocations a thread makes afterwards, as a cut's lists of faces and
// springs are, fault no page in until they outgrow the memory made ready.
#include <gtest/gtest.h>
#include <sys/resource.h>

#include <cstdint>
#include <thread>
#include <vector>

#include "hapticut/common/reserve.h"
#include "hapticut/common/thread_heap.h"

namespace hapticut {
namespace {

long threadPageFaults() {
    rusage usage{};
    getrusage(RUSAGE_THREAD, &usage);
    return usage.ru_minflt + usage.ru_majflt;
}

TEST(ThreadHeap, SmallAllocationsFaultNoPageInUntilTheyOutgrowThePrefaultedHeap) {
#ifdef HAPTICUT_SANITIZED
    GTEST_SKIP() << "a sanitizer's allocator is not glibc's";
#endif
    long within = -1, beyond = -1;
    std::thread thread([&] {  // a thread of its own, whose arena has not grown yet
        constexpr std::size_t kWithin = 60'000, kBeyond = 200'000;
        std::vector<std::vector<std::uint32_t>> lists;
        reserveTouched(lists, kWithin + kBeyond);
        prefaultThreadHeap(8u << 20);
        // Lists grown one value at a time to eight, as a new vertex's faces are: 48 bytes each in the end.
        auto grow = [&](std::size_t count) {
            for (std::size_t i = 0; i < count; ++i) {
                lists.emplace_back();
                for (std::uint32_t k = 0; k < 8; ++k) lists.back().push_back(k);
            }
        };
        const long before = threadPageFaults();
        grow(kWithin);  // about 3 MB
        within = threadPageFaults() - before;
        grow(kBeyond);  // about 10 MB more
        beyond = threadPageFaults() - before - within;
    });
    thread.join();
    EXPECT_LE(within, 2) << "pages faulted in by 60,000 small lists within the prefaulted 8 MB";
    EXPECT_GT(beyond, 100) << "the arena grew past it a page at a time: the count sees faults";
}

}  // namespace
}  // namespace hapticut
