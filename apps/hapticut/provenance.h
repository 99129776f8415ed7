// What produced a report, so that a figure can be traced to the build, the command and the machine.
#pragma once

#include <nlohmann/json.hpp>

namespace hapticut::app {

/// Keeps the command line for provenance(); main calls it first.
void recordCommandLine(int argc, char** argv);

/// {"hapticut": version, "commit": the git commit the build was configured at ("unknown" outside a
/// checkout), "command": the command line, "cpu": the processor's name, "simd_target": the instruction
/// set the SIMD kernels chose on this machine}.
nlohmann::ordered_json provenance();

}  // namespace hapticut::app
