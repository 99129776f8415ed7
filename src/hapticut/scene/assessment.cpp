// Scoring an exercise: the session replayed through the loop, the blade's cut and the marks traced on
// the rest surface, and each metric turned into points against the exercise's thresholds.
#include "hapticut/scene/assessment.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>

#include "hapticut/collision/bvh.h"
#include "hapticut/common/line_reader.h"
#include "hapticut/geometry/triangle_queries.h"
#include "hapticut/haptics/replay_device.h"
#include "hapticut/scene/model_source.h"
#include "hapticut/scene/open_device.h"

namespace hapticut::scene {

namespace {

/// Lines are measured at this spacing: fine beside any corridor a trainee is given.
constexpr double kSample_m = 5e-4;

/// The organ's rest surface, for projecting points onto it.
class RestSurface {
public:
    explicit RestSurface(const mesh::SurfaceMesh& mesh) : mesh_(mesh) { bvh_.build(view()); }
    collision::SurfaceView view() const { return {mesh_.positions, mesh_.faces}; }
    collision::SurfacePoint closest(const Vec3& p) const { return *bvh_.closestPoint(view(), p); }
    const mesh::SurfaceMesh& mesh() const { return mesh_; }

private:
    const mesh::SurfaceMesh& mesh_;
    collision::Bvh bvh_;
};

double distanceToSegment(const Vec3& p, const Vec3& a, const Vec3& b) {
    const Vec3 ab = b - a;
    const double len2 = ab.squaredNorm();
    const double u = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
    return (p - (a + u * ab)).norm();
}

double distanceToLine(const Vec3& p, const std::vector<Vec3>& line) {
    if (line.size() == 1) return (p - line.front()).norm();
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i + 1 < line.size(); ++i) best = std::min(best, distanceToSegment(p, line[i], line[i + 1]));
    return best;
}

double lengthOf(const std::vector<Vec3>& line) {
    double length = 0;
    for (std::size_t i = 0; i + 1 < line.size(); ++i) length += (line[i + 1] - line[i]).norm();
    return length;
}

/// The line through `points` with a point at least every kSample_m.
std::vector<Vec3> densify(const std::vector<Vec3>& points) {
    std::vector<Vec3> out;
    for (std::size_t i = 0; i + 1 < points.size(); ++i) {
        const int n = std::max(1, static_cast<int>(std::ceil((points[i + 1] - points[i]).norm() / kSample_m)));
        for (int k = 0; k < n; ++k)
            out.push_back(points[i] + (points[i + 1] - points[i]) * (static_cast<double>(k) / n));
    }
    if (!points.empty()) out.push_back(points.back());
    return out;
}

std::string millimetres(double m) {
    char text[32];
    std::snprintf(text, sizeof text, "%.1f mm", 1e3 * m);
    return text;
}

std::string secondsText(double s) {
    char text[32];
    std::snprintf(text, sizeof text, "%g s", s);
    return text;
}

/// 1 at or under the threshold, falling to 0 at twice it.
double underThreshold(double value, double threshold) { return std::clamp(2 - value / threshold, 0.0, 1.0); }

/// The centre of a hidden region: a sphere's or box's, or the mean of a mesh region's vertices.
Result<Vec3, Error> centreOf(const SceneRegion& region, const std::filesystem::path& sceneFile) {
    if (region.shape != SceneRegion::Shape::Mesh) return region.center_m;
    auto source = loadModelSource(region.mesh, 0, {});
    if (!source) return unexpected(Error{sceneFile, region.line, "regions: " + source.error().toString()});
    const auto& p = source->mesh.positions;
    const Vec3 sum = std::accumulate(p.begin(), p.end(), Vec3(Vec3::Zero()));
    return Vec3(sum / static_cast<double>(std::max<std::size_t>(1, p.size())));
}

/// A part of the score: `share` (0-1) of its weight.
void addPart(Assessment& a, std::string metric, double value, double threshold, std::string rule, double weight,
             double share) {
    a.parts.push_back({std::move(metric), value, threshold, std::move(rule), weight, weight * share});
}

void scoreIncision(Assessment& a) {
    const SceneExercise& e = a.exercise;
    const double covered = a.coverage_pct / 100;
    const double corridor_mm = 1e3 * e.corridor_m, depth_mm = 1e3 * e.depth_m;
    // The parts after coverage count only for the share of the line that was cut: a session that cuts
    // nothing scores nothing, however gently it did so.
    addPart(a, "coverage_pct", a.coverage_pct, 100,
            "points in proportion to the share of the target cut within the corridor", 40, covered);
    addPart(a, "deviation_rms_mm", a.deviationRms_mm, corridor_mm,
            "all at 0 mm, none at the corridor's half width; times the coverage", 30,
            covered * std::clamp(1 - a.deviationRms_mm / corridor_mm, 0.0, 1.0));
    const double allowedOutside_mm = 0.25 * a.targetLength_mm;
    addPart(a, "outside_corridor_mm", a.outsideCorridor_mm, allowedOutside_mm,
            "all at 0 mm, none at a quarter of the target's length; times the coverage", 10,
            covered * std::clamp(1 - a.outsideCorridor_mm / std::max(allowedOutside_mm, 1e-9), 0.0, 1.0));
    addPart(a, "depth_mean_mm", a.depthMean_mm, depth_mm,
            "all at the exercise's depth, none at 0 or twice it; times the coverage", 10,
            covered * std::clamp(1 - std::abs(a.depthMean_mm - depth_mm) / depth_mm, 0.0, 1.0));
    addPart(a, "max_force_N", a.maxForce_N, e.maxForce_N,
            "all up to the exercise's maximum, none at twice it; times the coverage", 10,
            covered * underThreshold(a.maxForce_N, e.maxForce_N));
}

void scorePalpation(Assessment& a) {
    const SceneExercise& e = a.exercise;
    const double lumps = static_cast<double>(std::max<std::size_t>(1, a.lumps.size()));
    const double foundShare = static_cast<double>(a.found) / lumps;
    const double radius_mm = 1e3 * e.radius_m;
    double closeness = 0;
    for (const Assessment::Lump& l : a.lumps)
        if (l.found) closeness += std::clamp(1 - *l.error_mm / radius_mm, 0.0, 1.0) / lumps;
    const long onLumps =
        std::count_if(a.marks.begin(), a.marks.end(), [](const Assessment::Mark& m) { return m.lump >= 0; });
    const double rightMarks = a.marks.empty() ? 0 : static_cast<double>(onLumps) / static_cast<double>(a.marks.size());
    addPart(a, "found", static_cast<double>(a.found), lumps,
            "points in proportion to the lumps found (a mark within the radius)", 50, foundShare);
    addPart(a, "localisation_error_mm", a.localisationError_mm.value_or(0), radius_mm,
            "for each lump found: all at 0 mm, none at the radius", 30, closeness);
    addPart(a, "marks_on_lumps_pct", 100 * rightMarks, 100,
            "points in proportion to the marks that found a lump; times the share found", 10, foundShare * rightMarks);
    addPart(a, "max_force_N", a.maxForce_N, e.maxForce_N,
            "all up to the exercise's maximum, none at twice it; times the share found", 10,
            foundShare * underThreshold(a.maxForce_N, e.maxForce_N));
}

}  // namespace

std::string exerciseTool(const SceneExercise& exercise) {
    if (!exercise.tool.empty()) return exercise.tool;
    return exercise.kind == SceneExercise::Kind::Incision ? "scalpel" : "probe";
}

TargetLine targetLine(const Scene& scene) {
    TargetLine line;
    const auto& e = scene.settings.exercise;
    if (!e || e->kind != SceneExercise::Kind::Incision) return line;
    const RestSurface rest(scene.source.mesh);
    for (const Vec3& p : densify(e->path_m)) {
        const collision::SurfacePoint at = rest.closest(p);
        const mesh::Face& f = rest.mesh().faces[at.face];
        const auto& x = rest.mesh().positions;
        line.points.push_back(at.point);
        line.normals.push_back((x[f[1]] - x[f[0]]).cross(x[f[2]] - x[f[0]]).normalized());
    }
    return line;
}

IncisionMeasures measureIncision(const std::vector<Vec3>& target, const std::vector<std::vector<Vec3>>& cuts,
                                 double corridor_m) {
    IncisionMeasures m;
    std::vector<std::vector<Vec3>> lines;
    double squares = 0, samples = 0;
    for (const std::vector<Vec3>& stroke : cuts) {
        lines.push_back(densify(stroke));
        const std::vector<Vec3>& line = lines.back();
        m.cutLength_m += lengthOf(line);
        for (const Vec3& p : line) {
            const double d = distanceToLine(p, target);
            squares += d * d, samples += 1;
            m.deviationMax_m = std::max(m.deviationMax_m, d);
        }
        for (std::size_t i = 0; i + 1 < line.size(); ++i)
            if (distanceToLine(0.5 * (line[i] + line[i + 1]), target) > corridor_m)
                m.outsideCorridor_m += (line[i + 1] - line[i]).norm();
    }
    m.deviationRms_m = samples > 0 ? std::sqrt(squares / samples) : 0;
    // Coverage: the pieces of the target whose middle has a cut within the corridor.
    const std::vector<Vec3> along = densify(target);
    double covered = 0;
    for (std::size_t i = 0; i + 1 < along.size(); ++i) {
        const Vec3 middle = 0.5 * (along[i] + along[i + 1]);
        if (std::any_of(lines.begin(), lines.end(),
                        [&](const std::vector<Vec3>& c) { return distanceToLine(middle, c) <= corridor_m; }))
            covered += (along[i + 1] - along[i]).norm();
    }
    const double length = lengthOf(along);
    m.coverage_pct = length > 0 ? 100 * covered / length : 0;
    return m;
}

Status checkExercisePlacement(const Scene& scene, double tolerance_m) {
    if (!scene.settings.exercise) return std::nullopt;
    const SceneExercise& e = *scene.settings.exercise;
    if (e.path_m.empty()) return std::nullopt;
    const RestSurface surface(scene.source.mesh);
    for (std::size_t i = 0; i < e.path_m.size(); ++i) {
        const double d = surface.closest(e.path_m[i]).distance;
        if (d > tolerance_m)
            return Error{scene.file, e.pathLines[i],
                         "exercise.path_m[" + std::to_string(i) + "]: " + millimetres(d) +
                             " from the organ's surface; the target's points must lie on it (within " +
                             millimetres(tolerance_m) + ")"};
    }
    return std::nullopt;
}

Result<Assessment, Error> assess(const Scene& scene, const haptics::Trajectory& session,
                                 const std::filesystem::path& sessionFile) {
    if (!scene.settings.exercise)
        return unexpected(Error{scene.file, 0, "the scene has no [exercise] to assess a session against"});
    Assessment a;
    a.exercise = *scene.settings.exercise;
    const SceneExercise& e = a.exercise;
    const bool incision = e.kind == SceneExercise::Kind::Incision;
    for (const haptics::TrajectoryPoint& p : session.points)
        if (p.tool >= static_cast<int>(scene.tools.size()))
            return unexpected(Error{sessionFile, 0,
                                    "tool " + std::to_string(p.tool) + " at " + secondsText(p.t_s) +
                                        ": the scene has " + std::to_string(scene.tools.size()) + " tools"});
    // The tool: the session's, else the exercise's.
    std::size_t tool = scene.toolIndex(exerciseTool(e)).value_or(0);
    if (!session.points.empty() && session.points.front().tool >= 0)
        tool = static_cast<std::size_t>(session.points.front().tool);
    if (tool >= scene.tools.size())
        return unexpected(Error{scene.file, e.line, "exercise: the scene has no tools to do it with"});

    const RestSurface rest(scene.source.mesh);
    if (incision) {
        a.target_m = targetLine(scene).points;
        a.targetLength_mm = 1e3 * lengthOf(a.target_m);
    } else {
        for (const SceneRegion& region : scene.settings.regions) {
            if (!region.hidden) continue;
            auto centre = centreOf(region, scene.file);
            if (!centre) return unexpected(centre.error());
            a.lumps.push_back({*centre, rest.closest(*centre).point, false, std::nullopt});
        }
    }

    cutting::CutModel organ = scene.makeOrgan();
    haptics::ReplayDevice device(session);
    const ToolTip tip{scene.tools[tool].threshold_N, scene.tools[tool].tipRadius_m};
    const haptics::Hand hand = makeHand(scene, device, tip, nullptr);
    HapticRunConfig config;
    config.loop = loopConfigFor(scene, tip);
    config.loop.physicsRate = haptics::LoopConfig::PhysicsRate::Single;  // the same steps on every machine
    const double rate_hz = config.loop.rate_hz;
    a.session_s = session.duration_s();
    if (e.timeLimit_s > 0 && a.session_s > e.timeLimit_s) a.session_s = e.timeLimit_s, a.timeLimitReached = true;
    config.steps = std::lround(a.session_s * rate_hz) + 1;
    config.tool = scene.tools[tool].name;

    const auto steps = static_cast<std::size_t>(config.steps);
    a.forceTime_s.reserve(steps), a.force_N.reserve(steps);
    std::vector<double> depths_m;
    std::size_t cursor = 0;  // the session's point at the step's time, for its tool
    std::uint32_t buttonsBefore = 0;
    bool inStroke = false;
    std::size_t pointsSeen = 0;  // of the cutter's current cut
    long woundsCrossedSeen = 0;
    double firstTouch_s = -1, lastEvent_s = -1, contactForce_N = 0;
    long contactSteps = 0;
    config.afterStep = [&](const haptics::StepOutput& s, haptics::HapticLoop& loop) {
        const haptics::HandStep& h = s.hand();
        const double f = h.force_N.norm();
        a.forceTime_s.push_back(static_cast<float>(s.t_s)), a.force_N.push_back(static_cast<float>(f));
        a.maxForce_N = std::max(a.maxForce_N, f);
        if (h.contact) {
            if (firstTouch_s < 0) firstTouch_s = s.t_s;
            contactForce_N += f, ++contactSteps;
        }
        // The cut: the cutter's points where the mesh was cut, on the rest shape, as they are made (before
        // the lips gape); a cut that ends and starts again is another stroke, one that went on through an
        // earlier wound (from its floor, which is not on the surface) is the same.
        const std::vector<std::uint32_t>& points = loop.cutter().points();
        const long crossed = loop.cutter().stats().woundsCrossed;
        if (points.size() < pointsSeen) pointsSeen = 0, inStroke = inStroke && crossed > woundsCrossedSeen;
        woundsCrossedSeen = crossed;
        if (incision && points.size() > pointsSeen) {
            if (!inStroke) a.cuts_m.emplace_back(), ++a.strokes, inStroke = true;
            for (std::size_t i = pointsSeen; i < points.size(); ++i)
                if (!organ.isFloor(points[i])) a.cuts_m.back().push_back(organ.mesh().positions[points[i]]);
            depths_m.push_back(rest.closest(h.device_m).distance);
            lastEvent_s = s.t_s;
        }
        pointsSeen = points.size();
        if (!loop.cutter().cutting()) inStroke = false, pointsSeen = 0;
        if ((h.buttons & 2u) && !(buttonsBefore & 2u) && !incision) {
            // Where the tool touched, carried from the deformed face to the same place on the rest shape;
            // off the organ, the rest surface's point nearest it.
            Vec3 at = rest.closest(h.proxy_m).point;
            if (h.contact && loop.cutter().stats().cutPoints == 0 && h.face < rest.mesh().faces.size()) {
                const mesh::Face& face = rest.mesh().faces[h.face];
                const collision::SurfaceView now = loop.surface();
                const Vec3 bary = geometry::closestPointOnTriangle(h.proxy_m, now.positions[face[0]],
                                                                   now.positions[face[1]], now.positions[face[2]])
                                      .bary;
                at = bary.x() * rest.mesh().positions[face[0]] + bary.y() * rest.mesh().positions[face[1]] +
                     bary.z() * rest.mesh().positions[face[2]];
            }
            a.marks.push_back({s.t_s, at, -1});
            lastEvent_s = s.t_s;
        }
        buttonsBefore = h.buttons;
        // The tool in hand for the next step, from the session's tool column.
        const double next_s = session.points.front().t_s + s.t_s + 1 / rate_hz;
        while (cursor + 1 < session.points.size() && session.points[cursor + 1].t_s <= next_s) ++cursor;
        const int wanted = session.points[cursor].tool;
        if (wanted >= 0 && static_cast<std::size_t>(wanted) != tool) {
            tool = static_cast<std::size_t>(wanted);
            loop.commands().push({haptics::LoopCommand::Kind::SetCutThreshold, scene.tools[tool].threshold_N, 0});
            loop.commands().push({haptics::LoopCommand::Kind::SetTipRadius, scene.tools[tool].tipRadius_m, 0});
        }
    };
    auto run = runHaptic(organ, std::span<const haptics::Hand>(&hand, 1), config);
    if (!run) return unexpected(run.error());
    a.run = std::move(*run);
    a.meanForce_N = contactSteps > 0 ? contactForce_N / static_cast<double>(contactSteps) : 0;
    a.duration_s = firstTouch_s >= 0 && lastEvent_s >= firstTouch_s ? lastEvent_s - firstTouch_s : 0;

    if (incision) {
        const IncisionMeasures m = measureIncision(a.target_m, a.cuts_m, e.corridor_m);
        a.deviationRms_mm = 1e3 * m.deviationRms_m, a.deviationMax_mm = 1e3 * m.deviationMax_m;
        a.coverage_pct = m.coverage_pct, a.outsideCorridor_mm = 1e3 * m.outsideCorridor_m;
        a.cutLength_mm = 1e3 * m.cutLength_m;
        if (!depths_m.empty()) {
            a.depthMean_mm =
                1e3 * std::accumulate(depths_m.begin(), depths_m.end(), 0.0) / static_cast<double>(depths_m.size());
            a.depthMax_mm = 1e3 * *std::max_element(depths_m.begin(), depths_m.end());
        }
        scoreIncision(a);
    } else {
        double errors = 0;
        for (std::size_t l = 0; l < a.lumps.size(); ++l) {
            Assessment::Lump& lump = a.lumps[l];
            for (Assessment::Mark& m : a.marks) {
                const double d_mm = 1e3 * (m.at_m - lump.surface_m).norm();
                if (!lump.error_mm || d_mm < *lump.error_mm) lump.error_mm = d_mm;
                if (d_mm <= 1e3 * e.radius_m && m.lump < 0) m.lump = static_cast<int>(l);
            }
            lump.found = lump.error_mm && *lump.error_mm <= 1e3 * e.radius_m;
            a.found += lump.found;
            errors += lump.error_mm.value_or(0);
        }
        if (!a.marks.empty() && !a.lumps.empty()) a.localisationError_mm = errors / static_cast<double>(a.lumps.size());
        scorePalpation(a);
    }
    a.score = 0;
    for (const ScorePart& p : a.parts) a.score += p.points;
    return a;
}

}  // namespace hapticut::scene
