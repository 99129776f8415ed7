// --units and --scale.
#include "unit_options.h"

#include <iostream>

#include "hapticut/scene/model_size.h"
#include "hapticut/scene/scene_file.h"

namespace hapticut::app {

std::optional<double> UnitOptions::factor() const {
    if (units.empty() && !scaleGiven) return std::nullopt;
    return scene::unitScale(units.empty() ? "m" : units).value_or(1.0) * scale;
}

void UnitOptions::applyTo(scene::SceneOverrides& overrides) const {
    overrides.scale = factor();
    if (center) overrides.center = true;
    if (fitSize_m) overrides.fitSize_m = fitSize_m;
    if (!parts.empty()) overrides.parts = parts;
}

void addUnitOptions(CLI::App* cmd, UnitOptions& o) {
    cmd->add_option("--units", o.units,
                    "The unit the model file's coordinates are in: mm (most segmentation tools), cm or m "
                    "(the default); overrides a scene's [model] scale")
        ->check(CLI::IsMember({"mm", "cm", "m"}));
    cmd->add_option_function<double>(
           "--scale", [&o](double s) { o.scale = s, o.scaleGiven = true; },
           "Multiply the model's coordinates by this (after --units)")
        ->check(CLI::Range(1e-9, 1e9));
    cmd->add_flag("--center", o.center,
                  "Move the model's bounding-box centre to the origin, where tools and trajectories expect it "
                  "(a segmentation in body coordinates sits far from it)");
    cmd->add_option("--fit-size", o.fitSize_m,
                    "Scale the model about its centre so that its largest extent is this many metres (after "
                    "--units and --scale)")
        ->check(CLI::Range(1e-4, 100.0));
    cmd->add_option("--part", o.parts,
                    "Only this named part of the model file (an OBJ group, a glTF or FBX mesh; `hapticut info` "
                    "lists them); repeat it for several")
        ->allow_extra_args(false);  // one name each: `--part valve out.obj` must leave out.obj alone
}

void applyUnits(const UnitOptions& o, std::span<Vec3> positions, const std::string& name) {
    if (const auto f = o.factor())
        for (Vec3& p : positions) p *= *f;
    scene::centerAndFit(positions, o.center, o.fitSize_m);
    if (const auto unusual = scene::sizeWarning(positions, name))
        std::cerr << "warning: " << unusual->toString() << "\n";
    if (const auto away = scene::offCentreWarning(positions, name))
        std::cerr << "warning: " << away->toString() << "\n";
}

}  // namespace hapticut::app
