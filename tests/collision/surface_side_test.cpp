// The side of a closed surface from the faces round the nearest point, against ray parity.
#include <gtest/gtest.h>

#include <random>

#include "hapticut/collision/point_inside.h"
#include "hapticut/collision/surface_side.h"
#include "hapticut/geometry/random_vec.h"
#include "hapticut/mesh/procedural/heart.h"
#include "hapticut/mesh/procedural/primitives.h"

namespace hapticut::collision {
namespace {

struct Tally {
    int outside = 0, inside = 0, unsure = 0, wrong = 0;
};

/// Points within 2 mm of the surface (the proxy's reach), round random points of random faces and
/// round exact corners and edge midpoints, in random directions: each answer against ray parity.
Tally compareWithParity(const mesh::SurfaceMesh& m, std::mt19937& rng, int samples) {
    const SurfaceView view{m.positions, m.faces};
    Bvh bvh;
    bvh.build(view);
    const mesh::VertexFaces topology = mesh::buildVertexFaces(m.faces, m.positions.size());
    std::uniform_int_distribution<std::size_t> anyFace(0, m.faces.size() - 1);
    std::uniform_real_distribution<double> unit(0, 1), logDistance(std::log(1e-6), std::log(2e-3));
    std::normal_distribution<double> gauss;
    Tally t;
    for (int i = 0; i < samples; ++i) {
        const mesh::Face& f = m.faces[anyFace(rng)];
        Vec3 bary = randomVec3(unit, rng);
        if (i % 3 == 1) bary = Vec3(1, 0, 0);      // a corner
        if (i % 3 == 2) bary = Vec3(0.5, 0.5, 0);  // an edge's midpoint
        bary /= bary.sum();
        const Vec3 on = bary.x() * m.positions[f[0]] + bary.y() * m.positions[f[1]] + bary.z() * m.positions[f[2]];
        const Vec3 direction = randomVec3(gauss, rng).normalized();  // before the distance, as the seed's were
        const Vec3 p = on + std::exp(logDistance(rng)) * direction;
        const auto near = bvh.closestPoint(view, p, 2e-3);
        if (!near) continue;
        const Side side = sideOfClosedSurface(view, topology, *near, p);
        if (side == Side::Unsure) {
            ++t.unsure;
            continue;
        }
        const bool inside = insideClosedSurface(bvh, view, p);
        (inside ? t.inside : t.outside)++;
        t.wrong += inside != (side == Side::Inside);
    }
    return t;
}

TEST(SurfaceSide, AgreesWithRayParityNearTheHeartAndIsRarelyUnsure) {
    std::mt19937 rng(7);
    for (int triangles : {1619, 9714}) {
        SCOPED_TRACE(triangles);
        mesh::procedural::HeartOptions options;
        options.triangles = triangles;
        const Tally t = compareWithParity(mesh::procedural::makeHeart(options), rng, 6000);
        EXPECT_EQ(t.wrong, 0);
        EXPECT_GT(t.inside, 1000);
        EXPECT_GT(t.outside, 1000);
        EXPECT_LT(t.unsure, 60) << "under 1% left to ray parity";
    }
}

// Jittered by 0.3 mm (an eighth of its 2.4 mm edges), the heart has creases and needles: the faces round
// a feature disagree more often, and the answer is then Unsure, never wrong. (At 0.6 mm the surface
// crosses itself, 260 edges through faces, where neither test has a meaning.)
TEST(SurfaceSide, OnACrumpledHeartItIsNeverWrongAndSaysWhenItCannotTell) {
    std::mt19937 rng(8);
    mesh::procedural::HeartOptions options;
    options.triangles = 9714;
    mesh::SurfaceMesh m = mesh::procedural::makeHeart(options);
    std::normal_distribution<double> jitter(0, 0.3e-3);
    for (Vec3& p : m.positions) p += randomVec3(jitter, rng);
    const Tally t = compareWithParity(m, rng, 6000);
    EXPECT_EQ(t.wrong, 0);
    EXPECT_GT(t.inside + t.outside, 4000);
    EXPECT_GT(t.unsure, 0) << "folds make some features undecidable locally";
}

// A cube's edges and corners are 90° creases: just outside and just inside each, exact answers.
TEST(SurfaceSide, ACubesEdgesAndCornersAreDecidedBothWays) {
    const std::vector<Vec2> square = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    const mesh::SurfaceMesh cube = mesh::procedural::makePrism(square, 0, 1);
    const SurfaceView view{cube.positions, cube.faces};
    Bvh bvh;
    bvh.build(view);
    const mesh::VertexFaces topology = mesh::buildVertexFaces(cube.faces, cube.positions.size());
    struct Case {
        Vec3 p;
        Side expected;
    };
    const std::vector<Case> cases = {
        {{1.01, 1.02, 0.5}, Side::Outside},    // beyond the edge x = y = 1
        {{1.01, 1.02, 1.03}, Side::Outside},   // beyond the corner (1, 1, 1)
        {{-0.01, 0.5, -0.02}, Side::Outside},  // beyond the edge x = z = 0
        {{0.99, 0.98, 0.5}, Side::Inside},     // inside, nearest a face beside the edge
        {{0.5, 0.5, 0.999}, Side::Inside},    {{0.5, 0.5, 1.001}, Side::Outside},
    };
    for (const Case& c : cases) {
        const auto near = bvh.closestPoint(view, c.p);
        ASSERT_TRUE(near);
        EXPECT_EQ(sideOfClosedSurface(view, topology, *near, c.p), c.expected) << c.p.transpose();
    }
}

// A face of zero area beside the nearest point has no normal to agree with: Unsure.
TEST(SurfaceSide, AFaceWithoutAreaLeavesItUnsure) {
    const std::vector<Vec2> square = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    mesh::SurfaceMesh cube = mesh::procedural::makePrism(square, 0, 1);
    const SurfaceView view{cube.positions, cube.faces};
    Bvh bvh;
    bvh.build(view);
    const mesh::VertexFaces topology = mesh::buildVertexFaces(cube.faces, cube.positions.size());
    const Vec3 p(0.5, 0.5, 1.2);
    auto near = bvh.closestPoint(view, p);
    ASSERT_TRUE(near);
    ASSERT_EQ(sideOfClosedSurface(view, topology, *near, p), Side::Outside);
    // Collapse the nearest face's corners onto one line: its normal is gone.
    const mesh::Face& f = cube.faces[near->face];
    cube.positions[f[2]] = 0.5 * (cube.positions[f[0]] + cube.positions[f[1]]);
    const SurfaceView flat{cube.positions, cube.faces};
    near->bary = Vec3(1.0 / 3, 1.0 / 3, 1.0 / 3);
    near->point = (cube.positions[f[0]] + cube.positions[f[1]] + cube.positions[f[2]]) / 3;
    EXPECT_EQ(sideOfClosedSurface(flat, topology, *near, p), Side::Unsure);
}

}  // namespace
}  // namespace hapticut::collision
