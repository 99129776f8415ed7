// The loop's flat hash map, spread either way: the same answers as std::unordered_map through random
// inserts, updates and erases (keys crowded into few slots, so probe runs wrap and deletions shift them),
// no allocation while it stays within the room reserved, and a cut's edges on a few pages.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <unordered_map>

#include "hapticut/common/flat_key_map.h"
#include "hapticut/common/reserve.h"
#include "hapticut/mesh/surface_mesh.h"

namespace hapticut {
namespace {

class FlatKeyMapSpread : public testing::TestWithParam<FlatKeyMap::Spread> {};

TEST_P(FlatKeyMapSpread, AnswersAsAStandardMapThroughRandomInsertsUpdatesAndErases) {
    std::mt19937_64 rng(7);
    // Few keys: long runs; many: growth. Spread by high halves, the keys are a band's edges, each vertex
    // joined to the next 24 (more than a run holds, so runs spill into their neighbours'), and the
    // vertices outnumber the table's runs at first, so homes wrap round onto each other.
    const bool band = GetParam() == FlatKeyMap::Spread::ByHighHalf;
    for (const std::uint32_t vertices : {8u, 60u, 2000u}) {
        FlatKeyMap map(GetParam());
        std::unordered_map<std::uint64_t, std::uint32_t> expected;
        std::uniform_int_distribution<std::uint32_t> vertex(0, vertices - 1), step(1, 24);
        auto randomEdge = [&] {
            const std::uint32_t a = vertex(rng);
            return mesh::edgeKey(a, band ? a + step(rng) : vertex(rng));
        };
        for (int op = 0; op < 200'000; ++op) {
            const std::uint64_t key = randomEdge();
            const auto value = static_cast<std::uint32_t>(rng());
            if (rng() % 3 == 0) {
                ASSERT_EQ(map.erase(key), expected.erase(key) == 1) << "op " << op;
            } else {
                map.set(key, value);
                expected[key] = value;
            }
            ASSERT_EQ(map.size(), expected.size());
            const std::uint64_t probe = randomEdge();
            const auto it = expected.find(probe);
            ASSERT_EQ(map.find(probe), it == expected.end() ? std::nullopt : std::optional(it->second)) << "op " << op;
        }
        for (const auto& [key, value] : expected) ASSERT_EQ(map.find(key), value);
    }
}

TEST_P(FlatKeyMapSpread, NeverGrowsWithinTheRoomReservedHoweverManyErasesAndInsertsPassThrough) {
    FlatKeyMap map(GetParam());
    map.reserve(1000);
    const std::size_t room = map.room();
    ASSERT_GE(room, 1000u);
    std::mt19937_64 rng(3);
    std::vector<std::uint64_t> keys;
    for (std::uint32_t i = 0; i < 1000; ++i) keys.push_back(mesh::edgeKey(i, i + 1)), map.set(keys.back(), i);
    // A cut moves springs: one edge key out, another in, again and again. Tombstones would fill the
    // table; shifted deletions leave it as if the erased keys had never been there.
    for (int op = 0; op < 100'000; ++op) {
        const std::size_t i = rng() % keys.size();
        ASSERT_TRUE(map.erase(keys[i]));
        keys[i] = mesh::edgeKey(static_cast<std::uint32_t>(rng() % 100'000), 100'000 + static_cast<std::uint32_t>(i));
        map.set(keys[i], static_cast<std::uint32_t>(i));
    }
    EXPECT_EQ(map.room(), room);
    EXPECT_EQ(map.size(), keys.size());
    for (std::size_t i = 0; i < keys.size(); ++i) EXPECT_EQ(map.find(keys[i]), static_cast<std::uint32_t>(i));
    EXPECT_FALSE(map.contains(mesh::edgeKey(5, 7)));
    EXPECT_FALSE(map.erase(mesh::edgeKey(5, 7)));
}

INSTANTIATE_TEST_SUITE_P(BothSpreads, FlatKeyMapSpread,
                         testing::Values(FlatKeyMap::Spread::Hashed, FlatKeyMap::Spread::ByHighHalf),
                         [](const testing::TestParamInfo<FlatKeyMap::Spread>& spread) {
                             return spread.param == FlatKeyMap::Spread::Hashed ? "Hashed" : "ByHighHalf";
                         });

// The edges round a patch of a mesh numbered for locality (the rows of a grid's vertices, each joined to
// its right and upper neighbours and across a diagonal) lie on a few pages when spread by their lower
// vertex, and all over the table when hashed: what a cut's lookups touch.
TEST(FlatKeyMap, TheEdgesOfNeighbouringVerticesShareAFewPagesWhenSpreadByTheirLowerVertex) {
    constexpr std::uint32_t kSide = 700;  // 490,000 vertices, 1.47 million edges: the 1,000,000 heart's size
    auto pagesTouched = [&](FlatKeyMap::Spread spread) {
        FlatKeyMap map(spread);
        map.reserve(3 * kSide * kSide, kSide * kSide);
        auto edgesOf = [&](std::uint32_t v, auto&& visit) {
            const std::uint32_t row = v / kSide, column = v % kSide;
            if (column + 1 < kSide) visit(mesh::edgeKey(v, v + 1));
            if (row + 1 < kSide) visit(mesh::edgeKey(v, v + kSide));
            if (column + 1 < kSide && row + 1 < kSide) visit(mesh::edgeKey(v, v + kSide + 1));
        };
        std::uint32_t value = 0;
        for (std::uint32_t v = 0; v < kSide * kSide; ++v) edgesOf(v, [&](std::uint64_t key) { map.set(key, value++); });
        // A 5 × 5 patch in the middle: every edge of its 25 vertices.
        std::vector<std::size_t> pages;
        for (std::uint32_t row = kSide / 2; row < kSide / 2 + 5; ++row)
            for (std::uint32_t v = row * kSide + kSide / 2; v < row * kSide + kSide / 2 + 5; ++v)
                edgesOf(v, [&](std::uint64_t key) {
                    const std::optional<std::size_t> slot = map.slotOf(key);
                    ASSERT_TRUE(slot.has_value());
                    pages.push_back(*slot * 16 / 4096);  // a slot is 16 bytes
                });
        std::sort(pages.begin(), pages.end());
        return static_cast<std::size_t>(std::unique(pages.begin(), pages.end()) - pages.begin());
    };
    EXPECT_LE(pagesTouched(FlatKeyMap::Spread::ByHighHalf), 10u);  // each row's five vertices on a page or two
    EXPECT_GE(pagesTouched(FlatKeyMap::Spread::Hashed), 60u);      // of 75 edges
}

// Reserved as the cut model reserves its edges (room to grow by half, for vertices too), a mesh's edges
// leave every vertex's run of slots room to spare, so a lookup reads a slot or two, and one of an edge
// that is not there (a cut asks whether two vertices are joined) stops as soon. With four slots a run,
// which this grid's size rounded to, each vertex's three edges filled its run three quarters, the runs'
// probes joined into clusters, and a miss read 5-8 slots on the hearts of that size.
TEST(FlatKeyMap, AnEdgeLookupReadsASlotOrTwoWhetherTheEdgeIsThereOrNot) {
    constexpr std::uint32_t kSide = 150, kVertices = kSide * kSide;
    std::vector<std::uint64_t> edges;
    for (std::uint32_t v = 0; v < kVertices; ++v) {
        const std::uint32_t row = v / kSide, column = v % kSide;
        if (column + 1 < kSide) edges.push_back(mesh::edgeKey(v, v + 1));
        if (row + 1 < kSide) edges.push_back(mesh::edgeKey(v, v + kSide));
        if (column + 1 < kSide && row + 1 < kSide) edges.push_back(mesh::edgeKey(v, v + kSide + 1));
    }
    FlatKeyMap map(FlatKeyMap::Spread::ByHighHalf);
    map.reserve(roomToGrow(edges.size()), roomToGrow(kVertices));
    for (std::uint32_t k = 0; k < edges.size(); ++k) map.set(edges[k], k);
    double found = 0, missed = 0;
    for (std::uint64_t key : edges) found += static_cast<double>(map.probes(key));
    for (std::uint32_t v = 0; v + 2 < kVertices; ++v)
        missed += static_cast<double>(map.probes(mesh::edgeKey(v, v + 2)));
    EXPECT_LT(found / static_cast<double>(edges.size()), 1.3);
    EXPECT_LT(missed / (kVertices - 2), 1.5);
}

}  // namespace
}  // namespace hapticut
