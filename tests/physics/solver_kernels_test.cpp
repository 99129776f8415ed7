// The implicit solve's matrix against the forces' Jacobian by finite differences, and the SIMD kernels
// giving the same answers under every instruction set this machine runs.
#include <gtest/gtest.h>

#include <array>
#include <numeric>

#include "hapticut/mesh/procedural/heart.h"
#include "hapticut/physics/backward_euler_system.h"
#include "hapticut/physics/material.h"
#include "hapticut/physics/solver_kernels.h"
#include "hapticut/physics/spring_forces.h"
#include "test_support.h"

namespace hapticut::physics {
namespace {

/// The 1,619 heart blown up by 1% about its centre, so that every spring is stretched (a compressed
/// spring's transverse stiffness is dropped on purpose), at rest, with the whole model as the region.
struct StretchedHeart {
    MassSpringModel model;
    std::vector<std::uint32_t> nodes, springs;
    BackwardEulerSystem system;
    static constexpr double kStep_s = 1e-3;

    StretchedHeart() : model(buildModel(mesh::procedural::makeHeart({}), Material{})) {
        for (Vec3& x : model.nodes.position) x *= 1.01;
        nodes.resize(model.nodes.size());
        springs.resize(model.springs.size());
        std::iota(nodes.begin(), nodes.end(), 0u);
        std::iota(springs.begin(), springs.end(), 0u);
        system.reserve(nodes.size(), springs.size());
        system.resize(nodes.size());
        system.assemble(model, kStep_s, {nodes, nodes, springs});
    }
    kernels::Field field(double size) const {
        kernels::Field f;
        f.resize(system.rows());
        for (std::size_t k = 0; k < nodes.size(); ++k) {
            const Vec3 w = test::wobble(k, size);
            f.x[k] = w.x(), f.y[k] = w.y(), f.z[k] = w.z();
        }
        return f;
    }
};

Vec3 at(const kernels::Field& f, std::size_t k) { return {f.x[k], f.y[k], f.z[k]}; }

// A = M - h ∂f/∂v - h² ∂f/∂x, with both derivatives taken by central differences of the forces.
TEST(BackwardEulerSystem, IsTheForcesJacobianByFiniteDifferences) {
    StretchedHeart h;
    const kernels::Field y = h.field(1.0);
    kernels::Field product;
    product.resize(h.system.rows());
    (void)kernels::multiply(h.system.matrix(), y, product);

    const std::size_t n = h.nodes.size();
    auto forces = [&](const std::vector<Vec3>& x, const std::vector<Vec3>& v) {
        std::vector<Vec3> a(n);
        computeAccelerations(h.model, x, v, a);
        for (std::size_t i = 0; i < n; ++i) a[i] *= h.model.nodes.mass[i];
        return a;
    };
    const double e = 1e-7;
    std::vector<Vec3> xPlus = h.model.nodes.position, xMinus = xPlus, vPlus(n, Vec3::Zero()), vMinus = vPlus;
    for (std::size_t i = 0; i < n; ++i) {
        xPlus[i] += e * at(y, i), xMinus[i] -= e * at(y, i);
        vPlus[i] += e * at(y, i), vMinus[i] -= e * at(y, i);
    }
    const std::vector<Vec3> zero(n, Vec3::Zero());
    const auto fxPlus = forces(xPlus, zero), fxMinus = forces(xMinus, zero);
    const auto fvPlus = forces(h.model.nodes.position, vPlus), fvMinus = forces(h.model.nodes.position, vMinus);
    const double dt = StretchedHeart::kStep_s;
    double worst = 0, scale = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3 kY = (fxPlus[i] - fxMinus[i]) / (2 * e), dY = (fvPlus[i] - fvMinus[i]) / (2 * e);
        const Vec3 expected = h.model.nodes.mass[i] * at(y, i) - dt * dY - dt * dt * kY;
        worst = std::max(worst, (at(product, i) - expected).norm());
        scale = std::max(scale, expected.norm());
    }
    // The matrix is kept in single precision.
    EXPECT_LT(worst, 1e-5 * scale) << "worst difference " << worst << " in products up to " << scale;
}

/// Every number of two assembled systems' rows is the same: right-hand side, products and preconditioner;
/// the `pinned` rows are zero in both.
void expectSameSystem(const BackwardEulerSystem& kept, const BackwardEulerSystem& fresh, const kernels::Field& y,
                      std::span<const std::uint32_t> pinned, const char* when) {
    ASSERT_EQ(kept.rows(), fresh.rows()) << when;
    kernels::Field keptProduct, freshProduct;
    keptProduct.resize(kept.rows()), freshProduct.resize(fresh.rows());
    EXPECT_EQ(kernels::multiply(kept.matrix(), y, keptProduct), kernels::multiply(fresh.matrix(), y, freshProduct))
        << when;
    const kernels::SymmetricBlocks &a = kept.inverseBlocks(), &b = fresh.inverseBlocks();
    for (std::size_t k = 0; k < kept.rows(); ++k) {
        ASSERT_EQ(at(kept.rhs(), k), at(fresh.rhs(), k)) << when << ", row " << k;
        ASSERT_EQ(at(keptProduct, k), at(freshProduct, k)) << when << ", row " << k;
        ASSERT_TRUE(a.xx[k] == b.xx[k] && a.xy[k] == b.xy[k] && a.xz[k] == b.xz[k] && a.yy[k] == b.yy[k] &&
                    a.yz[k] == b.yz[k] && a.zz[k] == b.zz[k])
            << when << ", row " << k;
    }
    for (std::uint32_t k : pinned) {
        EXPECT_EQ(at(keptProduct, k), Vec3::Zero()) << when << ", pinned row " << k;
        EXPECT_EQ(at(kept.rhs(), k), Vec3::Zero()) << when << ", pinned row " << k;
    }
}

// A step over the layout of the last one writes the springs' terms where they were laid out; the system
// must be the one laid out afresh, as the organ moves and as nodes are pinned and freed, over the whole
// organ and over a region with resting neighbours.
TEST(BackwardEulerSystem, AStepOverTheLastLayoutAssemblesWhatAFreshLayoutWould) {
    StretchedHeart h;
    MassSpringModel& m = h.model;
    // A region: the nodes within 3 cm of one, its springs and their resting ends.
    std::vector<std::uint32_t> near, touched, springs;
    std::vector<std::uint8_t> in(m.nodes.size(), 0), seen(m.nodes.size(), 0);
    for (std::uint32_t i = 0; i < m.nodes.size(); ++i)
        if ((m.nodes.position[i] - m.nodes.position[0]).norm() < 0.03) near.push_back(i), in[i] = seen[i] = 1;
    touched = near;
    for (std::uint32_t e = 0; e < m.springs.size(); ++e) {
        const std::uint32_t a = m.springs.a[e], b = m.springs.b[e];
        if (!in[a] && !in[b]) continue;
        springs.push_back(e);
        for (std::uint32_t j : {a, b})
            if (!seen[j]) seen[j] = 1, touched.push_back(j);
    }
    ASSERT_GT(near.size(), 20u);
    ASSERT_LT(near.size(), h.nodes.size() / 2);
    const SolveRegion whole{h.nodes, h.nodes, h.springs, 7}, part{near, touched, springs, 8};
    BackwardEulerSystem kept, fresh;
    for (BackwardEulerSystem* s : {&kept, &fresh})
        s->reserve(h.nodes.size(), h.springs.size()), s->resize(h.nodes.size());
    for (const SolveRegion& region : {whole, part}) {
        SolveRegion afresh = region;
        afresh.layout = 0;
        for (int round = 0; round < 4; ++round) {
            const std::string when =
                std::string(region.layout == 7 ? "whole organ" : "region") + ", round " + std::to_string(round);
            // The organ moves; in round 1 two nodes are pinned, in round 2 freed, in round 3 a spring's
            // ends meet.
            for (std::size_t i = 0; i < m.nodes.size(); ++i)
                m.nodes.position[i] += test::wobble(i + 31 * round, 1e-4), m.nodes.velocity[i] = test::wobble(i, 1e-2);
            for (std::uint32_t i : {near[3], near[11]}) m.nodes.inverseMass[i] = round == 1 ? 0 : 1 / m.nodes.mass[i];
            if (round == 3) m.nodes.position[m.springs.b[springs[5]]] = m.nodes.position[m.springs.a[springs[5]]];
            kept.assemble(m, StretchedHeart::kStep_s, region);
            fresh.assemble(m, StretchedHeart::kStep_s, afresh);
            kernels::Field y;
            y.resize(kept.rows());
            for (std::size_t k = 0; k < region.nodes.size(); ++k) {
                const Vec3 w = test::wobble(k + 5, 1.0);
                y.x[k] = w.x(), y.y[k] = w.y(), y.z[k] = w.z();
            }
            // The pinned nodes' unknowns: their places in the region's list.
            std::vector<std::uint32_t> pinned;
            for (std::uint32_t k = 0; k < region.nodes.size(); ++k)
                if (m.nodes.inverseMass[region.nodes[k]] == 0) pinned.push_back(k);
            EXPECT_EQ(pinned.size(), round == 1 ? 2u : 0u);
            expectSameSystem(kept, fresh, y, pinned, when.c_str());
            // The whole organ has no resting neighbours, and its product leaves their zero blocks unread.
            EXPECT_EQ(kept.matrix().anyResting, region.layout != 7) << when;
            kernels::SystemRows reading = kept.matrix();
            reading.anyResting = true;
            kernels::Field read, skipped;
            read.resize(kept.rows()), skipped.resize(kept.rows());
            EXPECT_EQ(kernels::multiply(reading, y, read), kernels::multiply(kept.matrix(), y, skipped)) << when;
            for (std::size_t k = 0; k < kept.rows(); ++k)
                ASSERT_EQ(at(read, k), at(skipped, k)) << when << ", row " << k;
        }
    }
}

TEST(SolverKernels, EveryInstructionSetComputesTheSameProductAndPasses) {
    StretchedHeart h;
    const kernels::Field y = h.field(1.0), other = h.field(0.3);
    const std::vector<const char*> targets = kernels::supportedTargets();
    ASSERT_FALSE(targets.empty());
    kernels::Field reference;
    double referenceYAy = 0;
    for (const char* target : targets) {
        ASSERT_TRUE(kernels::forceTarget(target)) << target;
        kernels::Field product, r, z, p, x = other;
        for (auto* f : {&product, &r, &z, &p}) f->resize(h.system.rows());
        const double yAy = kernels::multiply(h.system.matrix(), y, product);
        const kernels::Sums start =
            kernels::startPass({0, h.system.rows()}, h.system.rhs(), product, h.system.inverseBlocks(), r, z, p);
        const kernels::Sums update =
            kernels::updatePass({0, h.system.rows()}, 0.5, y, product, h.system.inverseBlocks(), x, r, z);
        kernels::directionPass({0, h.system.rows()}, 0.25, z, p);
        EXPECT_GT(start.r2, 0);
        EXPECT_GT(update.r2, 0);
        // The largest row residual, which the solve's force tolerance reads, is r's own on every target.
        double largest2 = 0;
        for (std::size_t k = 0; k < h.system.rows(); ++k) largest2 = std::max(largest2, at(r, k).squaredNorm());
        EXPECT_NEAR(update.rowMax2, largest2, 1e-12 * largest2) << target;
        EXPECT_LT(update.rowMax2, update.r2) << target;
        // Each row sums in the same order on every target; only fused multiply-adds round differently.
        if (reference.x.empty()) {
            reference = product;
            referenceYAy = yAy;
            continue;
        }
        EXPECT_NEAR(yAy, referenceYAy, 1e-12 * std::abs(referenceYAy)) << target;
        double worst = 0, scale = 0;
        for (std::size_t k = 0; k < h.nodes.size(); ++k) {
            worst = std::max(worst, (at(product, k) - at(reference, k)).norm());
            scale = std::max(scale, at(reference, k).norm());
        }
        EXPECT_LT(worst, 1e-12 * scale) << target;
    }
    EXPECT_TRUE(kernels::forceTarget(nullptr));
    EXPECT_STREQ(kernels::targetName(), targets.front());
    EXPECT_FALSE(kernels::forceTarget("no such instruction set"));
}

// A coarse level's product, rows of several widths in two slices and a padded tail, against the same
// sums taken entry by entry from a list of (row, column, block), on every instruction set.
TEST(SolverKernels, TheBlockProductIsTheMatrixTimesTheVectorOnEveryInstructionSet) {
    constexpr std::size_t kRows = 21, kPadded = 32;  // two slices, the second with 11 padding rows
    using Block = std::array<float, 6>;
    auto blockOf = [](std::size_t a, std::size_t b) {
        const auto s = static_cast<float>(a * 31 + b * 7 % 13);
        return Block{1 + s / 50, 0.1f * (s - 3), -0.2f, 2 - s / 90, 0.05f * s, 1.5f};
    };
    kernels::SymmetricBlocks diagonal;
    diagonal.resize(kPadded);
    kernels::SlicedBlocks couplings;
    std::vector<std::array<std::size_t, 2>> entries;  // (row, column), in each row's slot order
    for (std::size_t row = 0; row < kRows; ++row)
        for (std::size_t j = 0; j < row % 5; ++j) entries.push_back({row, (row + 3 * j + 1) % kRows});
    for (std::size_t slice = 0; slice * kernels::kSliceRows < kPadded; ++slice) {
        std::size_t width = 0;
        for (std::size_t row = slice * kernels::kSliceRows; row < (slice + 1) * kernels::kSliceRows; ++row)
            width = std::max(width, row < kRows ? row % 5 : 0);
        couplings.sliceBegin.push_back(static_cast<std::uint32_t>(couplings.other.size()));
        const std::size_t begin = couplings.other.size();
        couplings.other.resize(begin + width * kernels::kSliceRows);
        couplings.blocks.resize(couplings.other.size());
        for (std::size_t row = slice * kernels::kSliceRows; row < (slice + 1) * kernels::kSliceRows; ++row)
            for (std::size_t j = 0; j < width; ++j) {
                const std::size_t slot = begin + j * kernels::kSliceRows + row % kernels::kSliceRows;
                const bool real = row < kRows && j < row % 5;
                const std::size_t column = real ? (row + 3 * j + 1) % kRows : row;
                const Block b = real ? blockOf(row, column) : Block{};
                couplings.other[slot] = static_cast<std::int32_t>(column);
                couplings.blocks.xx[slot] = b[0], couplings.blocks.xy[slot] = b[1], couplings.blocks.xz[slot] = b[2];
                couplings.blocks.yy[slot] = b[3], couplings.blocks.yz[slot] = b[4], couplings.blocks.zz[slot] = b[5];
            }
    }
    couplings.sliceBegin.push_back(static_cast<std::uint32_t>(couplings.other.size()));
    for (std::size_t row = 0; row < kRows; ++row) {
        const Block b = blockOf(row, row);
        diagonal.xx[row] = b[0], diagonal.xy[row] = b[1], diagonal.xz[row] = b[2];
        diagonal.yy[row] = b[3], diagonal.yz[row] = b[4], diagonal.zz[row] = b[5];
    }
    kernels::Field y, b;
    y.resize(kPadded), b.resize(kPadded);
    for (std::size_t k = 0; k < kRows; ++k) {
        const Vec3 w = test::wobble(k, 1.0), c = test::wobble(k + 100, 2.0);
        y.x[k] = w.x(), y.y[k] = w.y(), y.z[k] = w.z();
        b.x[k] = c.x(), b.y[k] = c.y(), b.z[k] = c.z();
    }
    auto times = [](const Block& m, const Vec3& v) {
        const auto e = [&](int i) { return static_cast<double>(m[static_cast<std::size_t>(i)]); };
        return Vec3(e(0) * v.x() + e(1) * v.y() + e(2) * v.z(), e(1) * v.x() + e(3) * v.y() + e(4) * v.z(),
                    e(2) * v.x() + e(4) * v.y() + e(5) * v.z());
    };
    std::vector<Vec3> expected(kRows);
    for (std::size_t row = 0; row < kRows; ++row) expected[row] = times(blockOf(row, row), at(y, row));
    for (const auto& [row, column] : entries) expected[row] += times(blockOf(row, column), at(y, column));

    const kernels::BlockRows a{kPadded, &diagonal, &couplings};
    for (const char* target : kernels::supportedTargets()) {
        ASSERT_TRUE(kernels::forceTarget(target)) << target;
        kernels::Field product, residual;
        product.resize(kPadded), residual.resize(kPadded);
        kernels::blockProduct(a, y, nullptr, product, {0, kPadded});
        kernels::blockProduct(a, y, &b, residual, {0, kPadded});
        for (std::size_t row = 0; row < kPadded; ++row) {
            const Vec3 want = row < kRows ? expected[row] : Vec3::Zero();
            EXPECT_LT((at(product, row) - want).norm(), 1e-12 * (1 + want.norm())) << target << " row " << row;
            EXPECT_LT((at(residual, row) - (at(b, row) - want)).norm(), 1e-12 * (1 + want.norm()))
                << target << " row " << row;
        }
    }
    EXPECT_TRUE(kernels::forceTarget(nullptr));
}

}  // namespace
}  // namespace hapticut::physics
