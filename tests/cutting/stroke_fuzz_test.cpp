// The cutting fuzz: 10,000 random scalpel strokes on the heart in four seeded parts (so ctest can run
// them side by side), every invariant checked after every operation that changed the mesh, the heart
// closed throughout. Under a sanitizer, which makes every check ten times slower, a tenth of each
// part, and scripts/test-sanitizers runs the first part only (the long runs under AddressSanitizer are
// by hand: docs/testing.md).
#include <gtest/gtest.h>

#include <cstdio>

#include "hapticut/common/assert.h"
#include "hapticut/cutting/stroke_fuzzer.h"
#include "hapticut/mesh/procedural/heart.h"

namespace hapticut::cutting {
namespace {

class StrokeFuzz : public ::testing::TestWithParam<std::uint64_t> {};

#ifdef HAPTICUT_SANITIZED
constexpr long kStrokes = 250;
#else
constexpr long kStrokes = 2500;
#endif

TEST_P(StrokeFuzz, TwoAndAHalfThousandRandomStrokesKeepEveryInvariant) {
    StrokeFuzzConfig config;
    config.seed = GetParam();
    config.strokes = kStrokes;
    const StrokeFuzzResult r = fuzzStrokes(mesh::procedural::makeHeart({}), config);
    ASSERT_TRUE(r.ok()) << r.problems.front();
    EXPECT_EQ(r.strokes, kStrokes);
    EXPECT_EQ(r.organs, (kStrokes + 199) / 200);  // 200 strokes an organ
    // The strokes did cut, a lot: cut points, openings and fresh faces on every organ.
    EXPECT_GT(r.cutPoints, 5 * r.strokes / 2);
    EXPECT_GT(r.meshChanges, r.strokes);
    EXPECT_GT(r.invariantChecks, r.strokes * 2);
    EXPECT_TRUE(r.opened);
    // Every opening was closed with walls, and the closed heart stayed closed through every check;
    // a stroke that runs into an earlier wound cuts through its walls and goes on beyond it.
    EXPECT_TRUE(r.closedOrgan);
    EXPECT_GT(r.wallsClosed, r.cutPoints / 3);
    EXPECT_GT(r.woundsCrossed, kStrokes / 50);
    EXPECT_EQ(r.joins, 0);
    std::printf("%ld strokes: %ld earlier wounds crossed, %ld joins\n", r.strokes, r.woundsCrossed, r.joins);
    EXPECT_GT(r.largestFaces, 2000);
}

INSTANTIATE_TEST_SUITE_P(Seeds, StrokeFuzz, ::testing::Values(1u, 2u, 3u, 4u));

TEST(StrokeFuzzer, NamesTheSeedOrganAndStrokeOfAFailureAndStopsThere) {
    // A broken organ: the fuzzer's first check must catch it and say where.
    mesh::SurfaceMesh heart = mesh::procedural::makeHeart({});
    std::swap(heart.faces[0][1], heart.faces[0][2]);  // one face turned inside out
    StrokeFuzzConfig config;
    config.seed = 42;
    config.strokes = 50;
    // Where asserts are compiled in (Debug, sanitizer builds) the cutter's own check would stop the
    // process at the broken face first; let it go on, so the fuzzer's check is the one tested.
    const AssertHandler previous = setAssertHandler([](const char*, int, const char*) {});
    const StrokeFuzzResult r = fuzzStrokes(heart, config);
    setAssertHandler(previous);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.problems.front().find("seed 42, organ 0, stroke 0"), std::string::npos) << r.problems.front();
    EXPECT_NE(r.problems.front().find("orientation"), std::string::npos) << r.problems.front();
    EXPECT_EQ(r.strokes, 0);
}

}  // namespace
}  // namespace hapticut::cutting
