// The springs' SIMD kernels against the spring formula and its Jacobian written out here, under every
// instruction set this machine runs: the same forces to the bit on every target, whole vectors and the
// springs left over, a listed subset in its own order, and coincident ends that give no force.
#include <gtest/gtest.h>

#include <algorithm>
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

std::vector<Vec3> vectorsOf(const std::vector<ForceRow>& rows) {
    std::vector<Vec3> v;
    for (const ForceRow& r : rows) v.emplace_back(r.x, r.y, r.z);
    return v;
}

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
    // A listed subset in no particular order, of such a length too, led by a spring at the last node,
    // whose coordinates end the arrays (a load past them is what AddressSanitizer's runs would catch).
    const auto lastNode = static_cast<std::uint32_t>(m.nodes.size() - 1);
    std::vector<std::uint32_t> listed;
    for (std::uint32_t k = 0; k < m.springs.size() && listed.empty(); ++k)
        if (m.springs.a[k] == lastNode || m.springs.b[k] == lastNode) listed.push_back(k);
    ASSERT_EQ(listed.size(), 1u);
    listed.push_back(h.collapsed);
    for (std::uint32_t k = static_cast<std::uint32_t>(m.springs.size()); k-- > 0;)
        if (k % 3 != 1) listed.push_back(k);
    while (listed.size() % 16 != 13) listed.pop_back();

    const std::vector<Vec3> expectedAll = formulaForces(m, all), expectedListed = formulaForces(m, listed);
    std::vector<Vec3> firstAll, firstListed;
    const std::vector<const char*> targets = kernels::supportedTargets();
    ASSERT_FALSE(targets.empty());
    for (const char* target : targets) {
        ASSERT_TRUE(kernels::forceTarget(target)) << target;
        std::vector<ForceRow> fRows(m.nodes.size()), gRows(m.nodes.size());
        const kernels::SpringArrays arrays{m.springs.a.data(), m.springs.b.data(), m.springs.restLength.data(),
                                           m.springs.stiffness.data(), m.springs.damping.data()};
        kernels::addSpringForces(arrays, all.size(), m.nodes.position.data()->data(), m.nodes.velocity.data()->data(),
                                 fRows.data());
        kernels::addListedSpringForces(arrays, listed.data(), listed.size(), m.nodes.position.data()->data(),
                                       m.nodes.velocity.data()->data(), gRows.data());
        const std::vector<Vec3> f = vectorsOf(fRows), g = vectorsOf(gRows);
        for (std::size_t i = 0; i < fRows.size(); ++i)
            ASSERT_TRUE(fRows[i].unused == 0 && gRows[i].unused == 0) << target << ": a row's fourth double changed";
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

/// The implicit step's terms of spring k as Baraff & Witkin write them: K = k_s [α I + (1 - α) n nᵀ]
/// (α = max(0, 1 - r/|l|), a compressed spring's negative transverse part dropped), D = k_d n nᵀ, the
/// block h² K + h D, and the right-hand side on end a, h f_a + h² K (v_b - v_a) on a first linearisation.
struct ImplicitTerms {
    Mat3 block;
    Vec3 rhs;
};
ImplicitTerms formulaTerms(const MassSpringModel& m, std::uint32_t k, double h, bool first) {
    const Springs& s = m.springs;
    const Vec3 l = m.nodes.position[s.b[k]] - m.nodes.position[s.a[k]];
    const Vec3 rate = m.nodes.velocity[s.b[k]] - m.nodes.velocity[s.a[k]];
    const Vec3 n = l.normalized();
    const double alpha = std::max(0.0, 1 - s.restLength[k] / l.norm());
    const Mat3 stiffness = s.stiffness[k] * (alpha * Mat3::Identity() + (1 - alpha) * n * n.transpose());
    const Mat3 damping = s.damping[k] * n * n.transpose();
    const Vec3 fa = (s.stiffness[k] * (l.norm() - s.restLength[k]) + s.damping[k] * rate.dot(n)) * n;
    return {h * h * stiffness + h * damping, h * fa + (first ? Vec3(h * h * stiffness * rate) : Vec3::Zero())};
}

TEST(SpringKernels, EveryInstructionSetGivesTheImplicitTermsOfTheJacobian) {
    MovingHeart h;
    const MassSpringModel& m = h.model;
    // A chunk in no particular order, with runs of consecutive springs, a vector's worth that only looks
    // like one, the collapsed spring, one at the last node (whose coordinates end the arrays) and 13
    // left over after whole vectors of 16.
    std::vector<std::uint32_t> list{h.collapsed};
    const auto lastNode = static_cast<std::uint32_t>(m.nodes.size() - 1);
    for (std::uint32_t k = 0; k < m.springs.size(); ++k)
        if (m.springs.a[k] == lastNode || m.springs.b[k] == lastNode) {
            list.push_back(k);
            break;
        }
    for (std::uint32_t k = 100; k < 102; ++k) list.push_back(k);
    for (std::uint32_t k : {300, 310, 290, 303}) list.push_back(k);  // first and last three apart, not a run
    for (std::uint32_t k = 102; k < 140; ++k) list.push_back(k);
    for (std::uint32_t k = static_cast<std::uint32_t>(m.springs.size()); list.size() < 253; k -= 7)
        list.push_back(k - 1);
    ASSERT_EQ(list.size(), 253u);
    ASSERT_LE(list.size(), kernels::SpringJacobians::kSprings);
    const double step = 2e-3;
    const kernels::SpringArrays arrays{m.springs.a.data(), m.springs.b.data(), m.springs.restLength.data(),
                                       m.springs.stiffness.data(), m.springs.damping.data()};
    for (const char* target : kernels::supportedTargets()) {
        ASSERT_TRUE(kernels::forceTarget(target)) << target;
        for (bool first : {true, false}) {
            kernels::SpringJacobians out;
            kernels::springJacobians(arrays, list.data(), list.size(), m.nodes.position.data()->data(),
                                     m.nodes.velocity.data()->data(), step, first, out);
            int compared = 0;
            for (std::size_t i = 0; i < list.size(); ++i) {
                if (list[i] == h.collapsed) {
                    EXPECT_FALSE(out.apart[i]) << target;
                    continue;
                }
                ASSERT_TRUE(out.apart[i]) << target << " spring " << list[i];
                const ImplicitTerms expected = formulaTerms(m, list[i], step, first);
                const Vec3 u(out.ux[i], out.uy[i], out.uz[i]);
                const Mat3 block = out.c0[i] * Mat3::Identity() + u * u.transpose();
                EXPECT_LT((block - expected.block).norm(), 1e-12 * expected.block.norm()) << target << " " << list[i];
                EXPECT_LT((Vec3(out.bx[i], out.by[i], out.bz[i]) - expected.rhs).norm(), 1e-12 * expected.rhs.norm())
                    << target << " spring " << list[i] << (first ? " first" : " correction");
                ++compared;
            }
            EXPECT_EQ(compared,
                      std::count_if(list.begin(), list.end(), [&](std::uint32_t k) { return k != h.collapsed; }))
                << target;
        }
    }
    EXPECT_TRUE(kernels::forceTarget(nullptr));
}

// The preconditioner's blocks: every row's diagonal term, its block to resting neighbours and its
// couplings' c0 I + u uᵀ, inverted. Two slices of rows of different lengths (the padding slots coupled to
// their own row at zero), some with resting neighbours, and a padding row, whose block is zero.
TEST(SpringKernels, EveryInstructionSetInvertsEachRowsBlockToTheScalarLoopsBits) {
    constexpr std::size_t kSlice = kernels::kSliceRows;
    const std::size_t rows = 2 * kSlice, realRows = rows - 1;
    std::vector<std::size_t> length(rows);
    kernels::SlicedCouplings c;
    c.sliceBegin = {0};
    std::vector<double> diagonal(rows, 0.0);
    for (std::size_t slice = 0; slice < 2; ++slice) {
        std::size_t width = 0;
        for (std::size_t lane = 0; lane < kSlice; ++lane) {
            const std::size_t k = slice * kSlice + lane;
            length[k] = k < realRows ? (3 * k + 1) % 9 : 0;  // 0 to 8 couplings
            width = std::max(width, length[k]);
            if (k < realRows) diagonal[k] = 1e-3 * (1 + 0.1 * std::sin(static_cast<double>(k)));
        }
        const std::size_t begin = c.sliceBegin.back();
        c.sliceBegin.push_back(static_cast<std::uint32_t>(begin + width * kSlice));
        for (auto* a : {&c.c0, &c.ux, &c.uy, &c.uz}) a->resize(c.sliceBegin.back(), 0.0f);
        c.other.resize(c.sliceBegin.back());
        for (std::size_t j = 0; j < width; ++j)
            for (std::size_t lane = 0; lane < kSlice; ++lane) {
                const std::size_t k = slice * kSlice + lane, slot = begin + j * kSlice + lane;
                c.other[slot] = static_cast<std::int32_t>(k);
                if (j >= length[k]) continue;
                const Vec3 u = test::wobble(7 * slot + j, 0.03);
                const Eigen::Vector3f uf = u.cast<float>();
                c.c0[slot] = static_cast<float>(2e-5 * (1 + std::cos(static_cast<double>(slot))));
                c.ux[slot] = uf.x(), c.uy[slot] = uf.y(), c.uz[slot] = uf.z();
            }
    }
    kernels::SymmetricBlocks resting;  // every third row has springs to resting neighbours
    resting.resize(rows);
    for (std::size_t k = 0; k < realRows; k += 3) {
        const Vec3 u = test::wobble(5 * k + 2, 0.02);
        resting.xx[k] = static_cast<float>(u.x() * u.x() + 1e-5), resting.xy[k] = static_cast<float>(u.x() * u.y());
        resting.xz[k] = static_cast<float>(u.x() * u.z()), resting.yy[k] = static_cast<float>(u.y() * u.y() + 1e-5);
        resting.yz[k] = static_cast<float>(u.y() * u.z()), resting.zz[k] = static_cast<float>(u.z() * u.z() + 1e-5);
    }
    // The loop the kernel replaces, one row at a time in the couplings' order.
    kernels::SymmetricBlocks expected;
    expected.resize(rows);
    for (std::size_t k = 0; k < realRows; ++k) {
        double xx = diagonal[k] + resting.xx[k], xy = resting.xy[k], xz = resting.xz[k];
        double yy = diagonal[k] + resting.yy[k], yz = resting.yz[k], zz = diagonal[k] + resting.zz[k];
        const std::size_t slice = k / kSlice, lane = k % kSlice;
        for (std::size_t j = 0; j < length[k]; ++j) {
            const std::size_t slot = c.sliceBegin[slice] + j * kSlice + lane;
            const double ux = c.ux[slot], uy = c.uy[slot], uz = c.uz[slot];
            xx += c.c0[slot] + ux * ux, xy += ux * uy, xz += ux * uz;
            yy += c.c0[slot] + uy * uy, yz += uy * uz, zz += c.c0[slot] + uz * uz;
        }
        const double cxx = yy * zz - yz * yz, cxy = xz * yz - xy * zz, cxz = xy * yz - xz * yy;
        const double inverseDet = 1 / (xx * cxx + xy * cxy + xz * cxz);
        const auto f = [&](double value) { return static_cast<float>(value * inverseDet); };
        expected.xx[k] = f(cxx), expected.xy[k] = f(cxy), expected.xz[k] = f(cxz);
        expected.yy[k] = f(xx * zz - xz * xz), expected.yz[k] = f(xy * xz - xx * yz),
        expected.zz[k] = f(xx * yy - xy * xy);
        // And it is the block's inverse.
        Mat3 block;
        block << xx, xy, xz, xy, yy, yz, xz, yz, zz;
        Mat3 inverse;
        inverse << expected.xx[k], expected.xy[k], expected.xz[k], expected.xy[k], expected.yy[k], expected.yz[k],
            expected.xz[k], expected.yz[k], expected.zz[k];
        ASSERT_LT((block * inverse - Mat3::Identity()).norm(), 1e-5) << "row " << k;
    }
    for (const char* target : kernels::supportedTargets()) {
        ASSERT_TRUE(kernels::forceTarget(target)) << target;
        kernels::SymmetricBlocks inverse;
        inverse.resize(rows);
        kernels::invertRowBlocks({rows, diagonal.data(), &resting, &c}, inverse);
        for (std::size_t k = 0; k < realRows; ++k)
            for (auto member :
                 {&kernels::SymmetricBlocks::xx, &kernels::SymmetricBlocks::xy, &kernels::SymmetricBlocks::xz,
                  &kernels::SymmetricBlocks::yy, &kernels::SymmetricBlocks::yz, &kernels::SymmetricBlocks::zz})
                ASSERT_EQ(std::memcmp(&(inverse.*member)[k], &(expected.*member)[k], sizeof(float)), 0)
                    << target << " row " << k << ": " << (inverse.*member)[k] << " against " << (expected.*member)[k];
        EXPECT_EQ(inverse.xx[realRows], 0.0f) << target << ": a padding row is left out";
        EXPECT_EQ(inverse.yz[realRows], 0.0f) << target;
        EXPECT_EQ(inverse.zz[realRows], 0.0f) << target;
    }
    EXPECT_TRUE(kernels::forceTarget(nullptr));
}

}  // namespace
}  // namespace hapticut::physics
