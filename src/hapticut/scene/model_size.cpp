// Whether a model has the size of an organ.
#include "hapticut/scene/model_size.h"

#include <cmath>
#include <cstdio>
#include <limits>

#include "hapticut/geometry/aabb.h"

namespace hapticut::scene {

namespace {
std::string lengthText(double metres) {
    char out[48];
    if (metres >= 1)
        std::snprintf(out, sizeof out, "%.3g m", metres);
    else if (metres >= 0.01)
        std::snprintf(out, sizeof out, "%.3g cm", metres * 100);
    else
        std::snprintf(out, sizeof out, "%.3g mm", metres * 1000);
    return out;
}
}  // namespace

std::optional<double> unitScale(std::string_view unit) {
    if (unit == "mm") return 0.001;
    if (unit == "cm") return 0.01;
    if (unit == "m") return 1.0;
    return std::nullopt;
}

std::optional<Warning> sizeWarning(std::span<const Vec3> positions, const std::string& name) {
    if (positions.empty()) return std::nullopt;
    const geometry::Aabb box = geometry::boundsOf(positions);
    const double extent_m = (box.max - box.min).maxCoeff();
    if (!std::isfinite(extent_m) || extent_m <= 0 || (extent_m >= kSmallestOrgan_m && extent_m <= kLargestOrgan_m))
        return std::nullopt;
    // The file's unit, if the model is in metres now: the one whose factor brings it nearest to 10 cm.
    const char* best = nullptr;
    double bestScale = 1, bestMiss = std::abs(std::log(extent_m / 0.1));
    for (const char* unit : {"mm", "cm"}) {  // metres are what it is read as already
        const double scale = *unitScale(unit), miss = std::abs(std::log(extent_m * scale / 0.1));
        if (miss < bestMiss) best = unit, bestScale = scale, bestMiss = miss;
    }
    std::string message = "the model is " + lengthText(extent_m) + " across, and organs are " +
                          lengthText(kSmallestOrgan_m) + " to " + lengthText(kLargestOrgan_m) +
                          " (coordinates are read as metres)";
    if (best)
        message += "; if the file is in " + std::string(best) + ", give --units " + best + " (it is then " +
                   lengthText(extent_m * bestScale) +
                   " across), or [model] scale = " + (bestScale < 0.005 ? "0.001" : "0.01") + " in a scene";
    else
        message += "; give --scale to bring it to an organ's size";
    return Warning{name, 0, message};
}

std::optional<Warning> offCentreWarning(std::span<const Vec3> positions, const std::string& name) {
    if (positions.empty()) return std::nullopt;
    const geometry::Aabb box = geometry::boundsOf(positions);
    const double away_m = box.center().norm(), extent_m = (box.max - box.min).maxCoeff();
    if (!std::isfinite(away_m) || away_m <= std::max(0.05, extent_m)) return std::nullopt;
    return Warning{name, 0,
                   "the model's centre is " + lengthText(away_m) +
                       " from the origin, where tools, the mouse and trajectories begin; --center (or [model] "
                       "center = true in a scene) moves it there"};
}

std::optional<Warning> farFromModelWarning(std::span<const Vec3> model, std::span<const Vec3> points,
                                           const std::string& what, const std::string& file) {
    if (model.empty() || points.empty()) return std::nullopt;
    const geometry::Aabb box = geometry::boundsOf(model);
    const double extent_m = (box.max - box.min).maxCoeff();
    const double reach_m = std::max(0.02, extent_m / 4);
    double nearest_m = std::numeric_limits<double>::infinity();
    for (const Vec3& p : points) {
        const Vec3 outside = (box.min - p).cwiseMax(p - box.max).cwiseMax(0.0);
        nearest_m = std::min(nearest_m, outside.norm());
    }
    if (!(nearest_m > reach_m)) return std::nullopt;
    return Warning{file, 0,
                   what + " never comes near the model: at its nearest it is " + lengthText(nearest_m) +
                       " from the model's bounding box, and the model is " + lengthText(extent_m) +
                       " across (both are read as metres; give the model --units, or the points in metres)"};
}

}  // namespace hapticut::scene
