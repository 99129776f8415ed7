// A training exercise scored (a scene's [exercise]): a recorded session replayed headless through the
// haptic loop, in simulated time and so the same on every run, and measured against the exercise's
// target: an incision's line along the surface, a palpation's hidden lumps.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "hapticut/common/error.h"
#include "hapticut/common/result.h"
#include "hapticut/haptics/trajectory.h"
#include "hapticut/scene/haptic_run.h"
#include "hapticut/scene/scene.h"

namespace hapticut::scene {

/// One part of a score: a metric, the threshold from the exercise it is judged against, and the points
/// it gave out of its weight, so that a trainee sees why.
struct ScorePart {
    std::string metric;  // the report's name for it, e.g. "deviation_rms_mm"
    double value = 0;
    double threshold = 0;  // the exercise's figure it is judged against, in the metric's unit
    std::string rule;      // how value and threshold give points, in words
    double weight = 0, points = 0;
};

struct Assessment {
    SceneExercise exercise;
    double session_s = 0;           // the part of the session replayed: all of it, or up to the time limit
    bool timeLimitReached = false;  // the session went on past the exercise's limit, which was not scored
    double duration_s = 0;          // from the first touch of the organ to the last cut or mark
    double maxForce_N = 0;          // the largest force the hand felt
    double meanForce_N = 0;         // over the steps in contact
    // An incision. The cut is where the blade's edge was, on the rest surface, in each step in which it
    // cut; the target is the line through the exercise's points, along the rest surface.
    double deviationRms_mm = 0, deviationMax_mm = 0;  // of the cut from the target
    double coverage_pct = 0;                          // of the target's length within the corridor of a cut
    double outsideCorridor_mm = 0;                    // length of cut farther from the target than the corridor
    double cutLength_mm = 0, targetLength_mm = 0;
    double depthMean_mm = 0, depthMax_mm = 0;  // of the blade under the rest surface while it cut
    long strokes = 0;                          // separate cuts: the blade lifted or stopped cutting between them
    std::vector<Vec3> target_m;                // the target line, sampled every half millimetre
    std::vector<std::vector<Vec3>> cuts_m;     // each stroke's cut
    // A palpation. A mark is a press of the device's second button (the viewer's key m); where the tool
    // touched then, mapped onto the rest surface, is compared with the surface point above each lump.
    struct Mark {
        double t_s = 0;
        Vec3 at_m = Vec3::Zero();
        int lump = -1;  // the lump it found (within the radius), or -1
    };
    struct Lump {
        Vec3 center_m = Vec3::Zero();
        Vec3 surface_m = Vec3::Zero();  // the point of the rest surface nearest its centre: where to mark it
        bool found = false;
        std::optional<double> error_mm;  // from the nearest mark; none without marks
    };
    std::vector<Mark> marks;
    std::vector<Lump> lumps;
    long found = 0;
    std::optional<double> localisationError_mm;  // the mean over the lumps of error_mm; none without marks
    // Both
    double score = 0;  // 0-100: the parts' points
    std::vector<ScorePart> parts;
    std::vector<float> forceTime_s, force_N;  // |F| in every step
    HapticRunResult run;
};

/// The tool an exercise is done with: its own, else the scalpel for an incision and the probe for a palpation.
std::string exerciseTool(const SceneExercise& exercise);

/// An incision's target line, sampled every half millimetre along the rest surface, with the surface's
/// outward normal at each sample (what the viewer draws it by); empty without an incision.
struct TargetLine {
    std::vector<Vec3> points, normals;
};
TargetLine targetLine(const Scene& scene);

/// An incision's cut against its target, both lines on the rest surface.
struct IncisionMeasures {
    double deviationRms_m = 0, deviationMax_m = 0;  // over the cut, every half millimetre, from the target
    double coverage_pct = 0;                        // of the target's length within corridor_m of a cut
    double outsideCorridor_m = 0;                   // of the cut's length farther than corridor_m from the target
    double cutLength_m = 0;
};
IncisionMeasures measureIncision(const std::vector<Vec3>& target, const std::vector<std::vector<Vec3>>& cuts,
                                 double corridor_m);

/// Replays `session` (a recording of the viewer, or any trajectory; its tool column switches tools) on
/// the scene's organ and scores it against the scene's exercise. An error when the scene has none, when
/// a tool index is not one of the scene's, or when the run cannot start.
Result<Assessment, Error> assess(const Scene& scene, const haptics::Trajectory& session,
                                 const std::filesystem::path& sessionFile);

/// How far an exercise's point may be from the organ's surface: it is moved onto it.
inline constexpr double kExercisePointTolerance_m = 0.005;

/// An error naming the scene's file and line for the first of the exercise's points that is farther
/// than `tolerance_m` from the organ's rest surface (given in the wrong unit, or for another organ).
Status checkExercisePlacement(const Scene& scene, double tolerance_m);

}  // namespace hapticut::scene
