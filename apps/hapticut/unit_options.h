// --units, --scale, --center and --fit-size: the unit a model file's coordinates are in and where the
// model goes, for every command that loads one.
#pragma once

#include <CLI/CLI.hpp>

#include <optional>
#include <span>
#include <string>
#include <vector>

#include "hapticut/geometry/vec.h"
#include "hapticut/scene/scene.h"

namespace hapticut::app {

struct UnitOptions {
    std::string units;  // mm, cm or m; empty: not given
    double scale = 1;
    bool scaleGiven = false;
    bool center = false;
    std::optional<double> fitSize_m;
    std::vector<std::string> parts;  // --part, repeatable

    /// What the model's coordinates are multiplied by: the unit's scale times --scale; nothing when
    /// neither was given (a scene's own [model] scale then holds).
    std::optional<double> factor() const;
    /// The same as a scene's overrides (what was not given is left to the scene).
    void applyTo(scene::SceneOverrides& overrides) const;
};

void addUnitOptions(CLI::App* cmd, UnitOptions& options);

/// Scales `positions` by the options' factor, if any, centres and fits them as asked, and prints a warning naming
/// `name` when the result does not have the size of an organ (scene::sizeWarning).
void applyUnits(const UnitOptions& options, std::span<Vec3> positions, const std::string& name);

}  // namespace hapticut::app
