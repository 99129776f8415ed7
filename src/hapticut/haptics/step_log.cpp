// Step logs as CSV.
#include "hapticut/haptics/step_log.h"

#include "hapticut/common/line_reader.h"

namespace hapticut::haptics {

std::string formatStepLog(std::span<const StepOutput> log, StepLogColumns columns) {
    const bool recording = columns == StepLogColumns::Recording;
    const bool two = !recording && !log.empty() && log.front().handCount > 1;
    std::string out = recording ? "t,x,y,z,button,fx,fy,fz\n"
                                : "t,device_x,device_y,device_z,proxy_x,proxy_y,proxy_z,fx,fy,fz,contact,face,cut";
    if (!recording)
        out += two ? ",device_x2,device_y2,device_z2,proxy_x2,proxy_y2,proxy_z2,fx2,fy2,fz2,contact2,face2\n" : "\n";
    out.reserve(out.size() + log.size() * (two ? 300 : 160));
    auto vec = [&](const Vec3& v) {
        for (int k = 0; k < 3; ++k) out += "," + formatDouble(v[k]);
    };
    auto hand = [&](const HandStep& h) {
        vec(h.device_m), vec(h.proxy_m), vec(h.force_N);
        out += h.contact ? ",1," : ",0,";
        out += std::to_string(h.face);
    };
    for (const StepOutput& s : log) {
        out += formatDouble(s.t_s);
        if (recording) {
            vec(s.hand().device_m);
            out += "," + std::to_string(s.hand().buttons & 1u);
            vec(s.hand().force_N);
        } else {
            hand(s.hands[0]);
            out += s.cut ? ",1" : ",0";
            if (two) hand(s.hands[1]);
        }
        out += "\n";
    }
    return out;
}

}  // namespace hapticut::haptics
