// The loop's flat hash map: the same answers as std::unordered_map through random inserts, updates and
// erases (keys crowded into few slots, so probe runs wrap and deletions shift them), and no allocation
// while it stays within the room reserved.
#include <gtest/gtest.h>

#include <random>
#include <unordered_map>

#include "hapticut/common/flat_key_map.h"
#include "hapticut/mesh/surface_mesh.h"

namespace hapticut {
namespace {

TEST(FlatKeyMap, AnswersAsAStandardMapThroughRandomInsertsUpdatesAndErases) {
    std::mt19937_64 rng(7);
    for (const std::uint32_t vertices : {8u, 60u, 2000u}) {  // few keys: long runs; many: growth
        FlatKeyMap map;
        std::unordered_map<std::uint64_t, std::uint32_t> expected;
        std::uniform_int_distribution<std::uint32_t> vertex(0, vertices - 1);
        for (int op = 0; op < 200'000; ++op) {
            const std::uint64_t key = mesh::edgeKey(vertex(rng), vertex(rng));
            const auto value = static_cast<std::uint32_t>(rng());
            if (rng() % 3 == 0) {
                ASSERT_EQ(map.erase(key), expected.erase(key) == 1) << "op " << op;
            } else {
                map.set(key, value);
                expected[key] = value;
            }
            ASSERT_EQ(map.size(), expected.size());
            const std::uint64_t probe = mesh::edgeKey(vertex(rng), vertex(rng));
            const auto it = expected.find(probe);
            ASSERT_EQ(map.find(probe), it == expected.end() ? std::nullopt : std::optional(it->second)) << "op " << op;
        }
        for (const auto& [key, value] : expected) ASSERT_EQ(map.find(key), value);
    }
}

TEST(FlatKeyMap, NeverGrowsWithinTheRoomReservedHoweverManyErasesAndInsertsPassThrough) {
    FlatKeyMap map;
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

}  // namespace
}  // namespace hapticut
