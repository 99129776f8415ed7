// Random scalpel strokes on an organ, with every cutting invariant checked after every operation:
// the fuzz the test suite runs (seeded, 10,000 strokes) and `hapticut soak` runs for as long as asked.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "hapticut/common/latency_histogram.h"
#include "hapticut/mesh/surface_mesh.h"

namespace hapticut::cutting {

class CutModel;

/// A point of the organ's rest surface: its face, barycentric coordinates and position.
struct RestTouch {
    std::uint32_t face = 0;
    Vec3 bary = Vec3::Zero();
    Vec3 point = Vec3::Zero();
};

/// Where a scalpel at `p` touches the rest surface: the closest point over every face (brute force, so
/// a check of the cutter does not lean on the collision tree).
RestTouch touchRestSurface(const CutModel& cut, const Vec3& p);

struct StrokeFuzzConfig {
    std::uint64_t seed = 1;
    long strokes = 1000;
    /// A fresh organ after this many strokes: a real organ is not cut ten thousand times, and the checks
    /// cost grows with the mesh.
    long strokesPerOrgan = 200;
    /// Check the invariants after every cutAt that changed the mesh (one that changed nothing cannot
    /// break anything), and at the end of every stroke; else at the end of every stroke only.
    bool checkEveryOperation = true;
    /// Simulate the cut organ (RK4 at its stable step) for this many steps after each organ's strokes,
    /// twice: with a stepper that followed every edit incrementally, as the haptic loop's does, and
    /// with a freshly prepared one. They must agree, and the incremental stable step must not exceed
    /// the fresh one.
    int simulateSteps = 20;
    /// Asked before every stroke; true ends the fuzz early (Ctrl-C), with the current organ checked.
    std::function<bool()> stopRequested;
};

struct StrokeFuzzResult {
    long strokes = 0, operations = 0, meshChanges = 0, organs = 0, invariantChecks = 0;
    bool stoppedEarly = false;  // StrokeFuzzConfig::stopRequested ended it before config.strokes
    long cutPoints = 0, verticesAdded = 0, facesAdded = 0;
    long joins = 0;            // cuts that ran into an open edge (or an earlier wound left open) and joined it
    long wallsClosed = 0;      // openings closed with walls
    long woundsCrossed = 0;    // earlier wounds a stroke cut through (their walls down to the floor)
    bool closedOrgan = false;  // the organ was closed, and every check also found it closed
    long largestFaces = 0;     // the largest a cut organ grew
    bool opened = false;       // some cut opened
    /// Empty when everything held. Otherwise the first failure: which organ, stroke and operation, and
    /// the seed that replays it.
    std::vector<std::string> problems;
    double wallTime_s = 0;
    /// How long each cutAt that changed the mesh took, walls included (the haptic loop's cut event adds
    /// the tree, stepper and snapshot updates).
    Summary cutAt_us;
    bool ok() const { return problems.empty(); }
};

/// Strokes start at random points of the rest surface, run in random tangent-ish directions for 0.5 to
/// 4 cm, sampled 1 to 40 times (so some are fast strokes crossing many faces in one call), and cross
/// earlier cuts as they come. `progress(done, total)` is called after every stroke.
StrokeFuzzResult fuzzStrokes(const mesh::SurfaceMesh& organ, const StrokeFuzzConfig& config,
                             const std::function<void(long, long)>& progress = {});

}  // namespace hapticut::cutting
