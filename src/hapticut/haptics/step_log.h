// The one writer of what the loop did, step by step, as CSV: the force log and the replayable recording.
#pragma once

#include <span>
#include <string>

#include "hapticut/haptics/haptic_loop.h"

namespace hapticut::haptics {

enum class StepLogColumns {
    /// t,device_x,device_y,device_z,proxy_x,proxy_y,proxy_z,fx,fy,fz,contact,face,cut (cut: 1 when the
    /// scalpel changed the mesh in that step); with two hands the second hand's columns follow, suffixed 2.
    ForceLog,
    /// t,x,y,z,button,fx,fy,fz: the first hand's device path, readable as a trajectory, with the forces it felt.
    Recording,
};

/// Every step of `log` as CSV with those columns; numbers round-trip exactly.
std::string formatStepLog(std::span<const StepOutput> log, StepLogColumns columns);

}  // namespace hapticut::haptics
