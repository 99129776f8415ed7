// Whether a model has the size of an organ, and if not, which unit its file was most likely written in:
// segmentation tools write millimetres, so a 15 cm organ read as metres is 150 m across.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "hapticut/common/error.h"
#include "hapticut/geometry/vec.h"

namespace hapticut::scene {

/// The sizes organs have, as the largest extent of their bounding box, m.
inline constexpr double kSmallestOrgan_m = 0.01, kLargestOrgan_m = 0.5;

/// The scale a unit name gives coordinates read as metres: mm 0.001, cm 0.01, m 1; nothing for others.
std::optional<double> unitScale(std::string_view unit);

/// A warning naming `name` when the model's largest extent is outside kSmallestOrgan_m to
/// kLargestOrgan_m, with the unit (mm, cm or m) that would bring it nearest to 10 cm; nothing for a
/// model of an organ's size, or an empty one.
std::optional<Warning> sizeWarning(std::span<const Vec3> positions, const std::string& name);

/// A warning naming `name` when the model's centre is farther from the origin than its own size and
/// 5 cm: tools, the mouse and the shipped trajectories start at the origin, and a segmentation in
/// body (scanner) coordinates sits half a metre away. It names --center.
std::optional<Warning> offCentreWarning(std::span<const Vec3> positions, const std::string& name);

/// A warning naming `file` when none of `points` comes near the model: within a quarter of its
/// largest extent (at least 2 cm) of its bounding box. `what` says what the points are ("the device's
/// path"). A millimetre trajectory on a metre model presses nothing, and nothing else would say so.
std::optional<Warning> farFromModelWarning(std::span<const Vec3> model, std::span<const Vec3> points,
                                           const std::string& what, const std::string& file = {});

}  // namespace hapticut::scene
