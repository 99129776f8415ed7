// The thesis's text formats for models and tools (SPEC R21): read with file:line errors, write losslessly.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "hapticut/common/result.h"
#include "hapticut/common/text_file.h"
#include "hapticut/mesh/surface_mesh.h"

namespace hapticut::mesh::io {

/// The `physics` line: per-spring constants exactly as the thesis stored them (heart: 200 20 2 5 1).
struct ThesisPhysics {
    double mass = 0;                  // total mass of the model, kg in Hapticut's files
    double structuralStiffness = 0;   // k_s per edge spring, N/m
    double structuralDamping = 0;     // k_d per edge spring, N·s/m
    double positioningStiffness = 0;  // per node, N/m
    double positioningDamping = 0;    // per node, N·s/m
};

struct ModelFile {
    SurfaceMesh mesh;
    ThesisPhysics physics;
    std::vector<Warning> warnings;
};

struct ToolFile {
    SurfaceMesh mesh;
    double threshold_N = 0;  // how hard the tool must press before it cuts
    std::vector<Warning> warnings;
};

Result<ModelFile, Error> parseModel(std::string_view text, const std::filesystem::path& file_for_errors);
Result<ToolFile, Error> parseTool(std::string_view text, const std::filesystem::path& file_for_errors);
Result<ModelFile, Error> readModelFile(const std::filesystem::path& file);
Result<ToolFile, Error> readToolFile(const std::filesystem::path& file);

/// Every double is written in its shortest exact form, so read(format(m)) == m bit for bit.
std::string formatModel(const SurfaceMesh& mesh, const ThesisPhysics& physics);
std::string formatTool(const SurfaceMesh& mesh, double threshold_N);
[[nodiscard]] WriteStatus writeModelFile(const std::filesystem::path& file, const SurfaceMesh& mesh,
                                         const ThesisPhysics& physics);
[[nodiscard]] WriteStatus writeToolFile(const std::filesystem::path& file, const SurfaceMesh& mesh, double threshold_N);

}  // namespace hapticut::mesh::io
