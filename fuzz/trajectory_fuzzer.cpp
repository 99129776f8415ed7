// libFuzzer target: the trajectory reader returns a trajectory or an Error for any bytes; one it
// accepts formats and reads back to the same points, and replays at any time without a non-finite sample.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "hapticut/haptics/replay_device.h"
#include "hapticut/haptics/trajectory.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace hapticut::haptics;
    const auto parsed = parseTrajectory(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.csv");
    if (!parsed) return 0;
    const auto again = parseTrajectory(formatTrajectory(*parsed), "again.csv");
    if (!again || again->points.size() != parsed->points.size()) std::abort();
    for (std::size_t i = 0; i < parsed->points.size(); ++i)
        if (again->points[i].t_s != parsed->points[i].t_s ||
            again->points[i].sample.position_m != parsed->points[i].sample.position_m)
            std::abort();
    ReplayDevice device(*parsed);
    for (const double t : {-1.0, 0.0, 0.5 * parsed->duration_s(), parsed->duration_s(), 1e9})
        if (!device.read(t).position_m.allFinite()) std::abort();
    return 0;
}
