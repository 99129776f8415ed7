// What produced a report.
#include "provenance.h"

#include <fstream>
#include <string>

#include "hapticut/physics/solver_kernels.h"

#ifndef HAPTICUT_COMMIT
#define HAPTICUT_COMMIT "unknown"
#endif
#ifndef HAPTICUT_VERSION
#define HAPTICUT_VERSION "unknown"
#endif

namespace hapticut::app {

namespace {
std::string& commandLine() {
    static std::string line;
    return line;
}

std::string cpuName() {
    std::ifstream in("/proc/cpuinfo");
    for (std::string line; std::getline(in, line);)
        if (line.rfind("model name", 0) == 0) {
            const std::size_t colon = line.find(':');
            if (colon != std::string::npos) return line.substr(line.find_first_not_of(" \t", colon + 1));
        }
    return "unknown";
}
}  // namespace

void recordCommandLine(int argc, char** argv) {
    std::string& line = commandLine();
    line.clear();
    for (int i = 0; i < argc; ++i) {
        const std::string arg = argv[i];
        // Quoted when a shell would split it, so the line can be run again.
        const bool quote = arg.empty() || arg.find_first_of(" \t'\"$\\\\") != std::string::npos;
        line += (i ? " " : "") + (quote ? "'" + arg + "'" : arg);
    }
}

nlohmann::ordered_json provenance() {
    nlohmann::ordered_json j;
    j["hapticut"] = HAPTICUT_VERSION;
    j["commit"] = HAPTICUT_COMMIT;
    j["command"] = commandLine();
    j["cpu"] = cpuName();
    j["simd_target"] = physics::kernels::targetName();
    return j;
}

}  // namespace hapticut::app
