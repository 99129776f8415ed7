// Every BVH query against brute force, on random meshes and random queries, after refits and added faces.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "hapticut/collision/bvh.h"
#include "hapticut/geometry/random_vec.h"
#include "hapticut/geometry/triangle_queries.h"
#include "hapticut/mesh/procedural/heart.h"

namespace hapticut::collision {
namespace {

struct Soup {
    std::vector<Vec3> positions;
    std::vector<mesh::Face> faces;
    SurfaceView view() const { return {positions, faces}; }
};

/// Random small triangles in a 0.1 m cube, plus a few large ones that span many boxes.
Soup randomSoup(std::mt19937& rng, int count) {
    std::uniform_real_distribution<double> u(-0.05, 0.05), small(-0.01, 0.01);
    Soup s;
    for (int i = 0; i < count; ++i) {
        const Vec3 c = randomVec3(u, rng);
        const double scale = i % 50 == 0 ? 5.0 : 1.0;
        for (int k = 0; k < 3; ++k) s.positions.push_back(c + scale * randomVec3(small, rng));
        const auto v = static_cast<std::uint32_t>(3 * i);
        s.faces.push_back({v, v + 1, v + 2});
    }
    return s;
}

Soup heartSoup(int triangles) {
    mesh::procedural::HeartOptions options;
    options.triangles = triangles;
    const mesh::SurfaceMesh m = mesh::procedural::makeHeart(options);
    return {m.positions, m.faces};
}

double bruteClosest(const Soup& s, const Vec3& p) {
    double best = 1e300;
    for (const mesh::Face& f : s.faces)
        best = std::min(
            best,
            (geometry::closestPointOnTriangle(p, s.positions[f[0]], s.positions[f[1]], s.positions[f[2]]).point - p)
                .norm());
    return best;
}

std::optional<double> bruteFirstHit(const Soup& s, const Vec3& a, const Vec3& b, int* crossings = nullptr) {
    std::optional<double> best;
    if (crossings) *crossings = 0;
    for (const mesh::Face& f : s.faces)
        if (const auto hit =
                geometry::intersectSegmentTriangle(a, b, s.positions[f[0]], s.positions[f[1]], s.positions[f[2]])) {
            if (crossings) ++*crossings;
            if (!best || hit->t < *best) best = hit->t;
        }
    return best;
}

void expectMatchesBruteForce(const Bvh& bvh, const Soup& s, std::mt19937& rng, int queries) {
    std::uniform_real_distribution<double> u(-0.09, 0.09);
    std::vector<std::uint32_t> found;
    for (int q = 0; q < queries; ++q) {
        const Vec3 p = randomVec3(u, rng), r = randomVec3(u, rng);
        const auto closest = bvh.closestPoint(s.view(), p);
        ASSERT_TRUE(closest.has_value());
        EXPECT_NEAR(closest->distance, bruteClosest(s, p), 1e-15);
        const mesh::Face& f = s.faces[closest->face];
        const Vec3 rebuilt = closest->bary.x() * s.positions[f[0]] + closest->bary.y() * s.positions[f[1]] +
                             closest->bary.z() * s.positions[f[2]];
        EXPECT_LT((rebuilt - closest->point).norm(), 1e-12);

        int crossings = 0;
        const auto brute = bruteFirstHit(s, p, r, &crossings);
        const auto hit = bvh.firstHit(s.view(), p, r);
        ASSERT_EQ(hit.has_value(), brute.has_value());
        if (hit) {
            EXPECT_DOUBLE_EQ(hit->t, *brute);
        }
        EXPECT_EQ(bvh.countCrossings(s.view(), p, r), crossings);

        const double radius = 0.01;
        bvh.facesWithinRadius(s.view(), p, radius, found);
        std::vector<std::uint32_t> expected;
        for (std::uint32_t i = 0; i < s.faces.size(); ++i) {
            const mesh::Face& g = s.faces[i];
            if ((geometry::closestPointOnTriangle(p, s.positions[g[0]], s.positions[g[1]], s.positions[g[2]]).point - p)
                    .norm() <= radius)
                expected.push_back(i);
        }
        std::sort(found.begin(), found.end());
        EXPECT_EQ(found, expected);
    }
}

TEST(Bvh, QueriesMatchBruteForceOnRandomTriangles) {
    std::mt19937 rng(1);
    const Soup s = randomSoup(rng, 3000);
    Bvh bvh;
    bvh.build(s.view());
    expectMatchesBruteForce(bvh, s, rng, 300);
}

// Segments along an axis through a vertex lie in the planes of the boxes round it: the slab test must
// neither lose those boxes nor let the run along their faces decide (a zero direction component).
TEST(Bvh, SegmentsAlongTheAxesInTheBoxesFacePlanesMatchBruteForce) {
    const Soup s = heartSoup(1619);
    Bvh bvh;
    bvh.build(s.view());
    for (std::size_t v = 0; v < s.positions.size(); v += 7)
        for (int axis = 0; axis < 3; ++axis) {
            const Vec3& through = s.positions[v];
            Vec3 a = through, b = through;
            a[axis] -= 0.2;
            b[axis] += 0.2;
            int crossings = 0;
            const auto brute = bruteFirstHit(s, a, b, &crossings);
            const auto hit = bvh.firstHit(s.view(), a, b);
            ASSERT_EQ(hit.has_value(), brute.has_value()) << "vertex " << v << ", axis " << axis;
            if (hit) {
                EXPECT_DOUBLE_EQ(hit->t, *brute);
            }
            EXPECT_EQ(bvh.countCrossings(s.view(), a, b), crossings);
        }
}

TEST(Bvh, QueriesMatchBruteForceOnTheHeartAfterDeformingAndRefitting) {
    std::mt19937 rng(2);
    Soup s = heartSoup(9714);
    Bvh bvh;
    bvh.build(s.view());
    expectMatchesBruteForce(bvh, s, rng, 200);
    std::normal_distribution<double> n(0, 0.004);
    for (Vec3& p : s.positions) p += randomVec3(n, rng);
    bvh.refit(s.view());
    expectMatchesBruteForce(bvh, s, rng, 200);
}

// Boxes grown by a margin, computed from where the vertices were: every query is exact on the surface
// as it is now while each vertex stays within the margin of where the boxes saw it, with no refit.
TEST(Bvh, BoxesGrownByAMarginHoldASurfaceThatMovedLessThanIt) {
    std::mt19937 rng(11);
    for (Soup reference : {randomSoup(rng, 2000), heartSoup(9714)}) {
        constexpr double margin_m = 0.002;
        Bvh bvh;
        bvh.setMargin(margin_m);
        bvh.build(reference.view());
        Soup now = reference;
        std::normal_distribution<double> n(0, 1);
        std::uniform_real_distribution<double> share(0.5, 0.999);
        for (Vec3& p : now.positions) {
            const Vec3 direction = randomVec3(n, rng).normalized();  // before the share, as the seed's were
            p += margin_m * share(rng) * direction;
        }
        expectMatchesBruteForce(bvh, now, rng, 300);
        // Refitted from the reference positions, as the haptic loop refits nodes that stayed put.
        bvh.refit(reference.view());
        expectMatchesBruteForce(bvh, now, rng, 300);
    }
}

// A dent in one region of the heart, refitted through the faces round the moved vertices only: the
// queries everywhere still match brute force, and a second dent elsewhere after the first too. Large
// dents and small ones: a large one marks enough of the tree to be swept in node order, a small one is
// ordered by depth.
TEST(Bvh, RefittingOnlyTheFacesRoundMovedVerticesKeepsEveryQueryExact) {
    std::mt19937 rng(7);
    Soup s = heartSoup(9714);
    Bvh bvh;
    bvh.build(s.view());
    std::normal_distribution<double> n(0, 0.004);
    const Vec3 onSurface = s.positions[s.positions.size() / 3], elsewhere = s.positions[2 * s.positions.size() / 3];
    for (const auto& [centre, radius] : {std::pair{Vec3(0, 0, 0.05), 0.025}, std::pair{Vec3(0, -0.04, -0.03), 0.025},
                                         std::pair{onSurface, 0.008}, std::pair{elsewhere, 0.008}}) {
        std::vector<std::uint32_t> faces;
        std::vector<char> moved(s.positions.size(), 0);
        for (std::size_t v = 0; v < s.positions.size(); ++v)
            if ((s.positions[v] - centre).norm() < radius) {
                s.positions[v] += randomVec3(n, rng);
                moved[v] = 1;
            }
        for (std::uint32_t f = 0; f < s.faces.size(); ++f)
            for (std::uint32_t v : s.faces[f])
                if (moved[v]) faces.push_back(f);  // once per moved corner: repeats are allowed
        ASSERT_GT(faces.size(), 20u);
        ASSERT_LT(faces.size(), s.faces.size());
        bvh.refitFaces(s.view(), faces);
        expectMatchesBruteForce(bvh, s, rng, 200);
    }
}

TEST(Bvh, AddedFacesAreFoundBeforeAndAfterTheRebuild) {
    std::mt19937 rng(3);
    Soup s = randomSoup(rng, 1000);
    Bvh bvh;
    bvh.build(s.view());
    // Faces anywhere in the cube, not only inside old ones: the boxes on their way must grow.
    const Soup extra = randomSoup(rng, 1200);
    std::size_t mostAdded = 0;
    for (int batch = 0; batch < 60; ++batch) {
        for (int i = 0; i < 20; ++i) {
            const auto base = static_cast<std::uint32_t>(s.positions.size());
            for (int k = 0; k < 3; ++k)
                s.positions.push_back(extra.positions[static_cast<std::size_t>(3 * (20 * batch + i) + k)]);
            s.faces.push_back({base, base + 1, base + 2});
        }
        bvh.facesChanged(s.view());
        mostAdded = std::max(mostAdded, bvh.addedFaces());
        expectMatchesBruteForce(bvh, s, rng, 30);
    }
    EXPECT_GE(mostAdded, 400u) << "faces must be added to the tree, not rebuilt every time";
    EXPECT_LT(bvh.addedFaces(), 1200u) << "a rebuild must have absorbed the added faces once they were half the tree";
    EXPECT_LE(2 * bvh.addedFaces(), s.faces.size() - bvh.addedFaces());
}

TEST(Bvh, FacesWhoseCornersChangedAreFoundWithoutARefit) {
    std::mt19937 rng(4);
    Soup s = heartSoup(1619);
    Bvh bvh;
    bvh.build(s.view());
    // Re-point some faces at a far corner and add faces there, as a cut's wall pushed inward might.
    std::uniform_int_distribution<std::uint32_t> pick(0, static_cast<std::uint32_t>(s.faces.size() - 1));
    std::vector<std::uint32_t> changed;
    for (int i = 0; i < 40; ++i) {
        const std::uint32_t f = pick(rng);
        s.positions.push_back(s.positions[s.faces[f][0]] + Vec3(0.02, -0.03, 0.01) * (i % 3 - 1));
        s.faces[f][0] = static_cast<std::uint32_t>(s.positions.size() - 1);
        changed.push_back(f);
        if (i % 4 == 0) s.faces.push_back({s.faces[f][0], s.faces[f][2], s.faces[f][1]});
    }
    bvh.facesChanged(s.view(), changed);
    expectMatchesBruteForce(bvh, s, rng, 300);
    bvh.refit(s.view());
    expectMatchesBruteForce(bvh, s, rng, 100);
}

// The queries walk boxes stored in single precision: widened by the rounding's bound, they must stay
// exact for an organ of any size and anywhere, and for queries from far away. The heart (about 0.1 m)
// shrunk to a tenth of a millimetre, grown to 3.6 m, moved 48 m from the origin, and shrunk to 1 mm 3.7 m
// from it; segments lying in the boxes' face planes, and segments from a kilometre off that end on a vertex.
TEST(Bvh, QueriesStayExactForOrgansOfAnySizeFarFromTheOriginAndFromFarAway) {
    std::mt19937 rng(12);
    const Soup heart = heartSoup(1619);
    for (const auto& [scale, offset] : {std::pair{1e-3, Vec3(0, 0, 0)}, std::pair{30.0, Vec3(0, 0, 0)},
                                        std::pair{1.0, Vec3(25, -40, 7)}, std::pair{1e-2, Vec3(-3, 2, 1)}}) {
        Soup s = heart;
        for (Vec3& p : s.positions) p = offset + scale * p;
        Bvh bvh;
        bvh.build(s.view());
        std::uniform_real_distribution<double> u(-0.09, 0.09);
        std::uniform_int_distribution<std::size_t> vertex(0, s.positions.size() - 1);
        std::normal_distribution<double> n(0, 1);
        std::vector<std::pair<Vec3, Vec3>> segments;
        for (int q = 0; q < 150; ++q) {
            const Vec3 target = s.positions[vertex(rng)];
            const int axis = q % 3;
            Vec3 a = target, b = target;
            a[axis] -= 0.2 * scale;
            b[axis] += 0.2 * scale;
            segments.emplace_back(a, b);                                                // in face planes
            segments.emplace_back(target + 1000 * scale * randomVec3(n, rng), target);  // from afar
            const Vec3 end = offset + scale * randomVec3(u, rng);  // the end first, as the seed's were
            segments.emplace_back(offset + scale * randomVec3(u, rng), end);
        }
        for (const auto& [a, b] : segments) {
            int crossings = 0;
            const auto brute = bruteFirstHit(s, a, b, &crossings);
            const auto hit = bvh.firstHit(s.view(), a, b);
            ASSERT_EQ(hit.has_value(), brute.has_value()) << "scale " << scale;
            if (hit) {
                EXPECT_DOUBLE_EQ(hit->t, *brute);
            }
            EXPECT_EQ(bvh.countCrossings(s.view(), a, b), crossings) << "scale " << scale;
            for (const Vec3& p : {a, b}) {
                const auto closest = bvh.closestPoint(s.view(), p);
                ASSERT_TRUE(closest.has_value());
                EXPECT_NEAR(closest->distance, bruteClosest(s, p), 1e-14 * (scale + closest->distance))
                    << "scale " << scale;
            }
        }
    }
}

TEST(Bvh, SegmentThroughASharedEdgeOrVertexHitsTheSurface) {
    // A flat square of two triangles; segments through the diagonal and the corner must hit.
    Soup s;
    s.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
    s.faces = {{0, 1, 2}, {0, 2, 3}};
    Bvh bvh;
    bvh.build(s.view());
    EXPECT_TRUE(bvh.firstHit(s.view(), Vec3(0.5, 0.5, 1), Vec3(0.5, 0.5, -1)).has_value());
    EXPECT_TRUE(bvh.firstHit(s.view(), Vec3(0, 0, 1), Vec3(0, 0, -1)).has_value());
    EXPECT_TRUE(bvh.firstHit(s.view(), Vec3(0.3, 0.7, -1), Vec3(0.3, 0.7, 1)).has_value())
        << "back faces collide too (R10)";
    EXPECT_FALSE(bvh.firstHit(s.view(), Vec3(1.5, 0.5, 1), Vec3(1.5, 0.5, -1)).has_value());
}

}  // namespace
}  // namespace hapticut::collision
