// Linearised backward Euler (Baraff & Witkin 1998): one Newton step of the implicit update per time
// step (more where the springs turn or stretch too far in it), solved by conjugate gradients with a
// block-Jacobi preconditioner, warm-started from the last step's answer. Unconditionally stable on the springs and the
// tool coupling, so a step is one solve at any mesh resolution, sliver or coupling stiffness, where the explicit
// schemes need substeps.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "hapticut/common/worker_pool.h"

#include "hapticut/physics/backward_euler_system.h"
#include "hapticut/physics/multilevel_preconditioner.h"

namespace hapticut::physics {

/// The most iterations a solve may be allowed (a setting above it is taken as this).
inline constexpr int kMaxSolverIterations = 10'000;
/// The most threads a solve may be given.
inline constexpr unsigned kMaxSolverThreads = 256;
/// The threads a solve takes when asked for 0: every core but two, and at least one. A core is left to
/// the haptic thread and one to the rest (the viewer's drawing, the system): measured on a 2-core machine,
/// a held press on the 1,000,000 heart with two solve threads in real time missed 700 haptic periods in
/// 7.5 s, against 2-10 with one.
unsigned automaticSolverThreads();
/// `threads`, or automaticSolverThreads() for 0, at most kMaxSolverThreads.
unsigned solverThreads(unsigned threads);

/// The conjugate-gradient solve's preconditioner.
enum class Preconditioner {
    Auto,         // block-Jacobi while it does well, multilevel where it needs many iterations (below)
    BlockJacobi,  // each node's 3×3 diagonal block inverted
    Multilevel,   // aggregation multigrid (multilevel_preconditioner.h)
};
/// Auto's rule. An iteration with the multilevel cycle costs about kMultilevelIterationCost of
/// block-Jacobi's (two more products with the matrix, and the coarse levels' work), so it pays only where
/// block-Jacobi needs several times its iterations: on fine meshes at long steps, where the springs
/// outweigh the nodes' mass by most and a region is many rings across, and round a cut's walls. The press
/// on the 1,000,000 heart stopped 46 of 1,450 block-Jacobi solves at the 40-iteration cap, and 1
/// multilevel; the fully awake 100,000 heart took 12 block-Jacobi iterations a step against 4 multilevel
/// ones, and the fully awake 1,000,000 heart at 1 ms steps 83 against 44, and both were faster with
/// block-Jacobi. So auto tries the multilevel cycle once a block-Jacobi solve over a region of at least
/// kMultilevelUnknowns nodes stops at the cap or needs more than kJacobiIterationsForMultilevel
/// iterations. It keeps it while the region stays that large, unless a multilevel solve costs as much as
/// the block-Jacobi one did (iterations times kMultilevelIterationCost); then block-Jacobi again, not
/// tried again for kMultilevelPause steps unless a solve stops at the cap. The threshold on the region is
/// low because size is not what makes a solve hard: under the scalpel on the 100,000 heart, solves over a
/// few thousand nodes stopped at the cap (104 of 1,900 with the threshold at 4,096 nodes, none at 512).
inline constexpr std::size_t kMultilevelUnknowns = 512;
inline constexpr int kJacobiIterationsForMultilevel = 30;
inline constexpr int kMultilevelIterationCost = 3;
inline constexpr int kMultilevelPause = 500;
std::string_view preconditionerName(Preconditioner p);
std::optional<Preconditioner> parsePreconditioner(std::string_view name);

/// When the conjugate-gradient solve stops: at a residual below `tolerance` times the step's right-hand
/// side (both Euclidean norms, in newton-seconds), or after `maxIterations`, whichever comes first. A
/// Newton correction is measured against the step's first right-hand side too, not its own much smaller
/// one: it only has to bring the step as close as the first solve did.
struct SolverSettings {
    double tolerance = 1e-4;
    /// Or once no node's residual force (its residual divided by the step, N) exceeds this: tissue near
    /// rest has a right-hand side so small that `tolerance` of it asks for nanonewtons, which no hand
    /// feels and which took as many iterations as a press. Node by node, because the whole residual's
    /// norm grows with the region: a press held on the 1,000,000 heart, 60,000 nodes awake, took 12
    /// iterations a step to bring that norm under 1 µN, and fell behind real time; 4 with this.
    double forceTolerance_N = 1e-6;
    int maxIterations = 40;
    /// Newton iterations per step, the first included. Another is taken while the last one moved some
    /// spring's ends apart by more than kLinearMotion of its rest length: there the springs turned
    /// or stretched too far within the step for one linearisation to hold.
    int maxNewtonIterations = 4;
    /// The threads that share a solve's passes, the calling one included (a pool made once: see
    /// worker_pool.h); 0: automaticSolverThreads(). Results are the same, to the bit, with any number.
    unsigned threads = 0;
    Preconditioner preconditioner = Preconditioner::Auto;
};

/// A step whose springs' ends move apart by less than this fraction of their rest length is taken to
/// be linear enough for one Newton iteration.
inline constexpr double kLinearMotion = 0.05;

/// How one solve went.
struct SolveReport {
    int iterations = 0;           // conjugate-gradient iterations, over all Newton iterations
    int newtonIterations = 1;     // linearisations solved
    double relativeResidual = 0;  // |b - A Δv| / |b| at the end, against the step's first b; 0 when b is zero
    bool converged = true;        // false: stopped by the iteration cap (or a breakdown) above the tolerance
    bool newtonCutShort = false;  // a further Newton iteration was due, but the wall clock said no (keepPace)
    bool multilevel = false;      // solved with the multilevel preconditioner
};

class BackwardEuler {
public:
    void reserve(std::size_t nodes, std::size_t springs);
    /// Room for a model of this size; new nodes start without a warm start.
    void resize(std::size_t nodes);
    void setSettings(SolverSettings settings);
    const SolverSettings& settings() const { return settings_; }

    /// Advances the region's nodes by h seconds: v += Δv, x += h v. The resting neighbours stay put.
    SolveReport step(MassSpringModel& model, double h, SolveRegion region);
    /// On the wall clock: a step takes a further Newton iteration only while the ones it took, and one
    /// more like them, fit in `share` of the time it simulates (0: off, every iteration the settings
    /// allow). The multi-rate physics keeps pace with the hand this way: on the 1,000,000 heart a scalpel
    /// path's 20 ms steps took four Newton iterations of 40 CG iterations, 40-65 ms, and the tissue fell
    /// to 0.77 of real time while the tool dragged on into it.
    void keepPace(double share) { paceShare_ = share; }
    /// Drops node i's warm start: it was put to rest, so its last change of velocity is no guess.
    void forget(std::uint32_t i) { deltaV_[i].setZero(); }

private:
    /// Solves the assembled system from the warm start in solution_, to `tolerance` of the step's
    /// right-hand side: `stepNorm2`, its squared norm, when positive; else this one's, kept there.
    SolveReport solve(double& stepNorm2);
    /// Builds the system for the step's state, and the multilevel preconditioner's levels when it is used.
    void assemble(MassSpringModel& model, double h, SolveRegion region, std::span<const Vec3> startVelocity);
    /// Calls task(first, end) for the chunks of kernels::kChunkRows rows (or unknowns) that make up
    /// 0 .. size - 1, on the pool's threads when there is one.
    template <class Task>
    void forEachChunk(std::size_t size, Task&& task);
    /// out = A y over every chunk; returns yᵀ A y, summed chunk by chunk in order.
    double multiply(const kernels::Field& y, kernels::Field& out);

    SolverSettings settings_;
    double h_ = 0;          // the step being solved (s)
    double paceShare_ = 0;  // keepPace's
    BackwardEulerSystem system_;
    std::vector<Vec3> deltaV_;  // by node: the last step's change of velocity, the next warm start
    // By unknown (the region's nodes in order): the velocities the step started from, the motion of the
    // last Newton iteration, and the conjugate-gradient vectors (padded rows, for the kernels).
    std::vector<Vec3> startVelocity_, motion_;
    kernels::Field solution_, residual_, preconditioned_, direction_, product_;
    MultilevelPreconditioner multilevel_;
    bool useMultilevel_ = false;          // for the step being solved
    bool autoMultilevel_ = false;         // auto's choice for the next steps
    int jacobiIterations_ = 0;            // the block-Jacobi solve that made auto switch; 0: it stopped at the cap
    int multilevelPause_ = 0;             // steps before auto may try the multilevel cycle again
    std::uint64_t multilevelLayout_ = 0;  // the system's layoutsMade() the levels were laid out for
    OwnedWorkerPool pool_;                // shares the passes out; none when the solve runs on one thread
    std::vector<kernels::Sums> partial_;  // by chunk: its part of a pass's sums
};

}  // namespace hapticut::physics
