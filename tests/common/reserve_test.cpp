// Room reserved for growth is already in memory: the pages behind the size were written, so the haptic
// loop growing into them takes no page fault. Checked with mincore, for plain and Eigen elements.
#include <gtest/gtest.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cstdint>
#include <vector>

#include "hapticut/common/reserve.h"
#include "hapticut/geometry/vec.h"

namespace hapticut {
namespace {

// How many of the pages under [begin, end) are not resident.
template <class T>
long pagesNotResident(const T* begin, const T* end) {
    const auto page = static_cast<std::uintptr_t>(sysconf(_SC_PAGESIZE));
    const std::uintptr_t from = reinterpret_cast<std::uintptr_t>(begin) / page * page;
    const std::uintptr_t to = reinterpret_cast<std::uintptr_t>(end);
    std::vector<unsigned char> resident((to - from + page - 1) / page);
    if (mincore(reinterpret_cast<void*>(from), to - from, resident.data()) != 0) return -1;
    long missing = 0;
    for (unsigned char r : resident) missing += (r & 1) == 0;
    return missing;
}

template <class T>
void expectTouched(const T& first) {
    // Big enough for its own mapping, which starts out with no page in memory.
    std::vector<T> v{first};
    reserveTouched(v, 1 << 20);
    ASSERT_EQ(v.size(), 1u);
    ASSERT_GE(v.capacity(), 1u << 20);
    EXPECT_EQ(v[0], first);
    EXPECT_EQ(pagesNotResident(v.data(), v.data() + v.capacity()), 0);
}

TEST(ReserveTouched, TheRoomBehindTheSizeIsInMemoryForPlainElements) { expectTouched(3.5); }

TEST(ReserveTouched, TheRoomBehindTheSizeIsInMemoryForEigenVectorsWhoseDefaultLeavesThemUnwritten) {
    expectTouched(Vec3(1, 2, 3));
}

TEST(ReserveTouched, NeverShrinksOrLosesElements) {
    std::vector<int> v{1, 2, 3};
    reserveTouched(v, 2);
    EXPECT_EQ(v, (std::vector<int>{1, 2, 3}));
    reserveTouched(v, 100);
    EXPECT_EQ(v, (std::vector<int>{1, 2, 3}));
    EXPECT_GE(v.capacity(), 100u);
}

}  // namespace
}  // namespace hapticut
