// The springs' SIMD kernel against the spring formula written out here, under every instruction set this
// machine runs: the same forces to the bit on every target, whole vectors and the springs left over, a
// listed subset in its own order, and coincident ends that give no force.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <numeric>

#include "hapticut/mesh/procedural/heart.h"
#include "hapticut/physics/material.h"
#include "hapticut/physics/solver_kernels.h"
#include "hapticut/physics/spring_kernels.h"
#include "test_support.h"

namespace hapticut::physics {
namespace {

/// R3 as the thesis writes it: f_a = [k_s(|l| - r) + k_d (l'·l)/|l|] l/|l|, f_b = -f_a, l = x_b - x_a.
std::vector<Vec3> formulaForces(const MassSpringModel& m, std::span<const std::uint32_t> springs) {
    const Springs& s = m.springs;
    std::vector<Vec3> f(m.nodes.size(), Vec3::Zero());
    for (std::uint32_t k : springs) {
        const Vec3 l = m.nodes.position[s.b[k]] - m.nodes.position[s.a[k]];
        if (l.norm() < 1e-12) continue;
        const Vec3 rate = m.nodes.velocity[s.b[k]] - m.nodes.velocity[s.a[k]];
        const Vec3 fa =
            (s.stiffness[k] * (l.norm() - s.restLength[k]) + s.damping[k] * rate.dot(l) / l.norm()) * l.normalized();
        f[s.a[k]] += fa;
        f[s.b[k]] -= fa;
    }
    return f;
}

/// The 1,619 heart moved and moving a little everywhere, with one spring's ends put on one point.
struct MovingHeart {
    MassSpringModel model = buildModel(mesh::procedural::makeHeart({}), Material{});
    std::uint32_t collapsed = 0;
    MovingHeart() {
        for (std::size_t i = 0; i < model.nodes.size(); ++i) {
            model.nodes.position[i] += test::wobble(i, 5e-4);
            model.nodes.velocity[i] = test::wobble(3 * i + 1, 0.05);
        }
        collapsed = static_cast<std::uint32_t>(model.springs.size() / 2);
        const Springs& s = model.springs;
        model.nodes.position[s.b[collapsed]] = model.nodes.position[s.a[collapsed]];
    }
};

double largestDifference(const std::vector<Vec3>& a, const std::vector<Vec3>& b, double& scale) {
    double worst = 0;
    scale = 0;
    for (std::size_t i = 0; i < a.size(); ++i)
        worst = std::max(worst, (a[i] - b[i]).norm()), scale = std::max(scale, b[i].norm());
    return worst;
}

TEST(SpringKernels, EveryInstructionSetGivesTheFormulasForcesAndTheSameBits) {
    MovingHeart h;
    const MassSpringModel& m = h.model;
    // The first springs, as many as leave 13 over after whole vectors of any width up to 16 lanes.
    std::vector<std::uint32_t> all(m.springs.size() - (m.springs.size() + 3) % 16);
    std::iota(all.begin(), all.end(), 0u);
    ASSERT_EQ(all.size() % 16, 13u);
    ASSERT_GT(all.size(), h.collapsed);
    // A listed subset in no particular order, of such a length too.
    std::vector<std::uint32_t> listed{h.collapsed};
    for (std::uint32_t k = static_cast<std::uint32_t>(m.springs.size()); k-- > 0;)
        if (k % 3 != 1) listed.push_back(k);
    while (listed.size() % 16 != 13) listed.pop_back();

    const std::vector<Vec3> expectedAll = formulaForces(m, all), expectedListed = formulaForces(m, listed);
    std::vector<Vec3> firstAll, firstListed;
    const std::vector<const char*> targets = kernels::supportedTargets();
    ASSERT_FALSE(targets.empty());
    for (const char* target : targets) {
        ASSERT_TRUE(kernels::forceTarget(target)) << target;
        std::vector<Vec3> f(m.nodes.size(), Vec3::Zero()), g(m.nodes.size(), Vec3::Zero());
        const kernels::SpringArrays arrays{m.springs.a.data(), m.springs.b.data(), m.springs.restLength.data(),
                                           m.springs.stiffness.data(), m.springs.damping.data()};
        kernels::addSpringForces(arrays, all.size(), m.nodes.size(), m.nodes.position.data()->data(),
                                 m.nodes.velocity.data()->data(), f.data()->data());
        kernels::addListedSpringForces(arrays, listed.data(), listed.size(), m.nodes.size(),
                                       m.nodes.position.data()->data(), m.nodes.velocity.data()->data(),
                                       g.data()->data());
        double scale = 0;
        const double worstAll = largestDifference(f, expectedAll, scale);
        EXPECT_LT(worstAll, 1e-12 * scale) << target;
        EXPECT_GT(scale, 1e-3) << "the moved heart's springs should pull";
        const double worstListed = largestDifference(g, expectedListed, scale);
        EXPECT_LT(worstListed, 1e-12 * scale) << target;
        for (const Vec3& fi : f) ASSERT_TRUE(fi.allFinite()) << target << ": the collapsed spring gave a force";
        if (firstAll.empty()) {
            firstAll = f, firstListed = g;
            continue;
        }
        // Golden force traces must not depend on the machine: the same bits as the first target.
        EXPECT_EQ(std::memcmp(f.data(), firstAll.data(), f.size() * sizeof(Vec3)), 0) << target;
        EXPECT_EQ(std::memcmp(g.data(), firstListed.data(), g.size() * sizeof(Vec3)), 0) << target;
    }
    EXPECT_TRUE(kernels::forceTarget(nullptr));
}

}  // namespace
}  // namespace hapticut::physics
