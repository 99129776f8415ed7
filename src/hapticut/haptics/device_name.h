// Which device drives a hand: `virtual`, `replay:FILE`, `openhaptics[:NAME]` or `sdl[:INDEX]`, as the
// command line's --device and a scene's [[devices]] name them.
#pragma once

#include <string>
#include <string_view>

#include "hapticut/common/error.h"
#include "hapticut/common/result.h"

namespace hapticut::haptics {

enum class DeviceKind { Virtual, Replay, OpenHaptics, Sdl };

struct DeviceName {
    DeviceKind kind = DeviceKind::Virtual;
    std::string argument;  // replay: the trajectory file; openhaptics: the device's name; sdl: the joystick index

    /// Back to the text it was parsed from.
    std::string toString() const;
};

std::string_view deviceKindName(DeviceKind kind);

/// Parses a device name; the error says what was found and what is accepted.
Result<DeviceName, Error> parseDeviceName(std::string_view text);

}  // namespace hapticut::haptics
