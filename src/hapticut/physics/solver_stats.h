// What the implicit scheme's linear solves did over a run: iterations, the cap, residuals. Recording
// never allocates, so the haptic loop keeps it.
#pragma once

#include <algorithm>

#include "hapticut/common/latency_histogram.h"
#include "hapticut/physics/backward_euler.h"

namespace hapticut::physics {

struct SolverStats {
    long solves = 0;
    long unconverged = 0;  // solves stopped by the iteration cap (or a breakdown) above the tolerance
    long corrected = 0;    // steps that needed more than one Newton iteration
    long cutShort = 0;     // steps whose Newton iterations the wall clock cut short (BackwardEuler::keepPace)
    long multilevel = 0;   // solves preconditioned by the multilevel cycle
    int maxNewtonIterations = 0;
    double maxRelativeResidual = 0;  // of the unconverged solves: a converged one may stop at the force floor
    LatencyHistogram iterations{1, kMaxSolverIterations};  // one bin per iteration count

    void record(const SolveReport& report) noexcept {
        ++solves;
        if (!report.converged) {
            ++unconverged;
            maxRelativeResidual = std::max(maxRelativeResidual, report.relativeResidual);
        }
        if (report.newtonIterations > 1) ++corrected;
        if (report.newtonCutShort) ++cutShort;
        if (report.multilevel) ++multilevel;
        maxNewtonIterations = std::max(maxNewtonIterations, report.newtonIterations);
        iterations.record(report.iterations);
    }
};

}  // namespace hapticut::physics
