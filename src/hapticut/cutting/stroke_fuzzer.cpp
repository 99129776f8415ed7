// The stroke fuzzer: random strokes, invariants after every operation, a simulation at the end.
#include "hapticut/cutting/stroke_fuzzer.h"

#include <chrono>
#include <random>

#include "hapticut/cutting/invariants.h"
#include "hapticut/cutting/progressive_cutter.h"
#include "hapticut/geometry/aabb.h"
#include "hapticut/geometry/random_vec.h"
#include "hapticut/geometry/triangle_queries.h"
#include "hapticut/physics/integrators.h"
#include "hapticut/physics/material.h"

namespace hapticut::cutting {

RestTouch touchRestSurface(const CutModel& cut, const Vec3& p) {
    const mesh::SurfaceMesh& m = cut.mesh();
    RestTouch best;
    double bestD = 1e300;
    for (std::uint32_t f = 0; f < m.faces.size(); ++f) {
        const Vec3 &a = m.positions[m.faces[f][0]], &b = m.positions[m.faces[f][1]], &c = m.positions[m.faces[f][2]];
        // The distance to the face's box bounds the distance to the face from below: a face whose box is
        // no nearer than the best so far cannot win, and skipping it keeps the answer exactly the same.
        const Vec3 below = a.cwiseMin(b).cwiseMin(c) - p, above = p - a.cwiseMax(b).cwiseMax(c);
        if (below.cwiseMax(above).cwiseMax(0.0).squaredNorm() >= bestD) continue;
        const auto hit = geometry::closestPointOnTriangle(p, a, b, c);
        const double d = (hit.point - p).squaredNorm();
        if (d < bestD) bestD = d, best = {f, hit.bary, hit.point};
    }
    return best;
}

StrokeFuzzResult fuzzStrokes(const mesh::SurfaceMesh& organ, const StrokeFuzzConfig& config,
                             const std::function<void(long, long)>& progress) {
    const auto start = std::chrono::steady_clock::now();
    StrokeFuzzResult r;
    LatencyHistogram cutAt_us(0.1, 100'000);
    std::mt19937_64 rng(config.seed);
    std::uniform_real_distribution<double> unit(-1, 1), length(0.005, 0.04);
    const geometry::Aabb box = geometry::boundsOf(organ.positions);
    const double reach = box.extent().norm();

    for (long organIndex = 0; r.strokes < config.strokes && !r.stoppedEarly; ++organIndex) {
        CutModel cut(organ, physics::buildModel(organ, physics::Material{}));
        const double mass = physics::totalMass(cut.model());
        ProgressiveCutter cutter(cut);
        // The haptic loop's stepper follows the edits (Stepper::topologyChanged); this one does too.
        physics::Stepper live(physics::Scheme::RungeKutta4);
        live.setAutoSubstep(false);
        live.setActiveRegion(true);
        live.prepare(cut.model());
        std::vector<std::uint32_t> woken;  // every node the edits touched, which `live` woke
        ++r.organs;
        const auto fail = [&](long stroke, long operation, const std::string& what) {
            r.problems.push_back("seed " + std::to_string(config.seed) + ", organ " + std::to_string(organIndex) +
                                 ", stroke " + std::to_string(stroke) +
                                 (operation >= 0 ? ", operation " + std::to_string(operation) : std::string()) + ": " +
                                 what);
        };
        for (long s = 0; s < config.strokesPerOrgan && r.strokes < config.strokes; ++s, ++r.strokes) {
            if (config.stopRequested && config.stopRequested()) {
                r.stoppedEarly = true;
                break;
            }
            const Vec3 from = touchRestSurface(cut, box.center() + randomVec3(unit, rng).normalized() * reach).point;
            const Vec3 direction =
                randomVec3(unit, rng).normalized();  // before the length: the order the seeds were made in
            const Vec3 to = touchRestSurface(cut, from + length(rng) * direction).point;
            const int samples = 1 + static_cast<int>(rng() % 40);
            for (int i = 0; i <= samples; ++i) {
                const RestTouch t = touchRestSurface(cut, from + (to - from) * (static_cast<double>(i) / samples));
                const auto before = std::chrono::steady_clock::now();
                const bool changed = cutter.cutAt(t.face, t.bary);
                if (changed)
                    cutAt_us.record(
                        std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - before).count());
                live.topologyChanged(cut.model(), cut.changes().nodes, cut.changes().springs);
                // The log lists every changed spring's ends among its nodes, so these are all `live` woke.
                woken.insert(woken.end(), cut.changes().nodes.begin(), cut.changes().nodes.end());
                cut.clearChanges();
                r.meshChanges += changed;
                ++r.operations;
                if ((config.checkEveryOperation && changed) || i == samples) {
                    ++r.invariantChecks;
                    const InvariantReport report = checkInvariants(cut, mass, cut.closedBeforeCuts());
                    if (!report.ok()) {
                        fail(s, i, report.problems.front());
                        r.wallTime_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
                        return r;
                    }
                }
            }
            cutter.endCut();
            if (progress) progress(r.strokes + 1, config.strokes);
        }
        const CutStats& st = cutter.stats();
        r.cutPoints += st.cutPoints;
        r.verticesAdded += st.verticesAdded;
        r.facesAdded += st.facesAdded;
        r.joins += st.joins;
        r.wallsClosed += st.wallsClosed;
        r.woundsCrossed += st.woundsCrossed;
        r.closedOrgan = cut.closedBeforeCuts();
        r.opened |= st.opened;
        r.largestFaces = std::max(r.largestFaces, static_cast<long>(cut.mesh().faces.size()));
        // The cut organ must still simulate: no NaN, at the stable step the cuts left it, the same with
        // the stepper that followed the edits as with a fresh one.
        physics::Stepper fresh(physics::Scheme::RungeKutta4);
        fresh.setAutoSubstep(false);
        fresh.setActiveRegion(true);
        fresh.prepare(cut.model());
        for (std::uint32_t n : woken) fresh.wake(n);  // the same region awake in both
        if (live.stableStep_s() > fresh.stableStep_s() * (1 + 1e-12))
            fail(config.strokesPerOrgan, -1,
                 "the stable step kept through the edits (" + std::to_string(live.stableStep_s()) +
                     " s) exceeds the model's (" + std::to_string(fresh.stableStep_s()) + " s)");
        physics::MassSpringModel copy = cut.model();
        const double dt = live.stableStep_s();
        for (int i = 0; i < config.simulateSteps && r.problems.empty(); ++i) {
            if (!live.step(cut.model(), dt).finite || !fresh.step(copy, dt).finite)
                fail(config.strokesPerOrgan, -1, "the cut organ's simulation produced a non-finite value");
            double apart = 0;
            for (std::size_t n = 0; n < copy.nodes.size(); ++n)
                apart = std::max(apart, (copy.nodes.position[n] - cut.model().nodes.position[n]).norm());
            if (apart > 1e-9)
                fail(config.strokesPerOrgan, -1,
                     "after " + std::to_string(i + 1) + " steps the incrementally updated stepper is " +
                         std::to_string(apart * 1e9) + " nm from a fresh one");
        }
        if (!r.problems.empty()) break;
    }
    r.wallTime_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    r.cutAt_us = cutAt_us.summary();
    return r;
}

}  // namespace hapticut::cutting
