// A batch experiment's spec (`hapticut batch SPEC.toml`): the run every combination starts from, what
// it replays, and the sweep. Read and checked here so that every mistake names the spec's file and
// line before any run starts; the runs themselves are fanned out from Python (hapticut.batch).
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "hapticut/common/error.h"
#include "hapticut/common/result.h"

namespace hapticut::scene {

/// One swept scene key and the values it takes, each as TOML text ("4400000.0", "'rk4'", "[ 0.5, 0.25 ]").
struct SweepAxis {
    std::string key;  // as a scene file spells it: "material.positioning_stiffness_N_per_m3"
    int line = 0;     // in the spec
    std::vector<std::string> values;
};

struct BatchSpec {
    std::filesystem::path file;
    std::filesystem::path scene;  // empty: the built-in heart with the probe and the scalpel
    std::optional<std::string> model, tool, integrator;
    int toolLine = 0;  // where the spec names the tool, for its error
    std::optional<int> triangles;
    std::optional<long> steps;
    std::optional<double> rate_hz;
    /// What the first hand replays in each run: one trajectory, or each recorded session of a folder in
    /// turn (every .csv in it, by name). Empty: the scene's own replays.
    std::vector<std::filesystem::path> sessions;
    bool sessionsFromFolder = false;
    std::vector<SweepAxis> sweep;  // in the spec's order; every combination is one run
};

/// Reads and checks a spec. Paths in it are relative to its folder. Each swept value is laid over the
/// base scene and checked as a scene file's would be, so an unknown key or a value out of range is an
/// error at the spec's line, not a failed run.
Result<BatchSpec, Error> readBatchSpec(const std::filesystem::path& file);

}  // namespace hapticut::scene
