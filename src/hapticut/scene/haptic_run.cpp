// A haptic run driven by a replayed trajectory.
#include "hapticut/scene/haptic_run.h"

#include <chrono>
#include <cmath>
#include <thread>

#include "hapticut/collision/inside_test.h"
#include "hapticut/cutting/invariants.h"
#include "hapticut/haptics/replay_device.h"
#include "hapticut/mesh/io/line_reader.h"

namespace hapticut::scene {

HapticRunResult runHaptic(cutting::CutModel& organ, const haptics::Trajectory& trajectory, const HapticRunConfig& config) {
    HapticRunResult r;
    const long steps = config.steps >= 0 ? config.steps : std::lround(trajectory.duration_s() * config.loop.rate_hz) + 1;
    const double mass_kg = physics::totalMass(organ.model());
    physics::MassSpringModel& model = organ.model();
    haptics::ReplayDevice device(trajectory);
    haptics::HapticLoop loop(organ, device, config.loop);
    r.log.reserve(static_cast<std::size_t>(steps));
    // The observer runs on the loop's thread in real time: it only appends to reserved memory and
    // runs the inside test, which allocates nothing.
    auto observe = [&](const haptics::StepOutput& s) {
        if (r.log.size() < r.log.capacity()) r.log.push_back(s);
        // The ray-parity test needs a closed surface: an opened cut leaves the proxy free to enter the
        // wound (a scalpel down in its own cut), which is no penetration.
        if (!loop.cutter()->stats().opened)
            r.maxProxyPenetration_m = std::max(r.maxProxyPenetration_m, collision::penetrationDepth(loop.bvh(), loop.surface(), s.hand().proxy_m));
        r.maxDisplacement_m = std::max(r.maxDisplacement_m, physics::maxDisplacement(model));
    };
    if (config.realtime) {
        loop.start(steps, observe);
        while (loop.running()) std::this_thread::sleep_for(std::chrono::milliseconds(2));
        loop.stop();
    } else {
        loop.runSimulated(steps, observe);
    }
    const haptics::LoopStats& st = loop.stats();
    r.steps = st.steps;
    r.simTime_s = static_cast<double>(st.steps) / config.loop.rate_hz;
    r.wallTime_s = st.wallTime_s;
    r.hapticRate_hz = st.wallTime_s > 0 ? static_cast<double>(st.steps) / st.wallTime_s : 0;
    r.stepTime_us = st.stepTime_us.summary();
    r.periodError_us = st.periodError_us.summary();
    r.overruns = st.overruns;
    r.contactSteps = st.contactSteps;
    r.nonFiniteEvents = st.nonFiniteEvents;
    r.watchdogTripped = st.watchdogTripped;
    r.maxForce_N = st.maxForce_N;
    r.finalMaxDisplacement_m = physics::maxDisplacement(model);
    r.cut = loop.cutter()->stats();
    r.cutEvents = st.cutEvents;
    r.cutTime_us = st.cutTime_us.summary();
    r.invariantProblems = cutting::checkInvariants(organ, mass_kg).problems;
    physics::Stepper probe(config.loop.scheme);
    probe.setToolStiffness(config.loop.couplingStiffness_N_per_m);
    probe.prepare(model);
    r.substeps = probe.substepsFor(1 / config.loop.rate_hz);
    return r;
}

std::string formatForceLog(const std::vector<haptics::StepOutput>& log) {
    using mesh::io::formatDouble;
    std::string out = "t,device_x,device_y,device_z,proxy_x,proxy_y,proxy_z,fx,fy,fz,contact,face,cut\n";
    out.reserve(out.size() + log.size() * 160);
    for (const haptics::StepOutput& s : log) {
        out += formatDouble(s.t_s);
        for (const Vec3* v : {&s.hand().device_m, &s.hand().proxy_m, &s.hand().force_N})
            for (int k = 0; k < 3; ++k) out += "," + formatDouble((*v)[k]);
        out += s.hand().contact ? ",1," : ",0,";
        out += std::to_string(s.hand().face) + (s.cut ? ",1\n" : ",0\n");
    }
    return out;
}

}  // namespace hapticut::scene
