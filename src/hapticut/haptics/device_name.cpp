// Device names.
#include "hapticut/haptics/device_name.h"

#include <charconv>

namespace hapticut::haptics {

std::string_view deviceKindName(DeviceKind kind) {
    switch (kind) {
        case DeviceKind::Virtual: return "virtual";
        case DeviceKind::Replay: return "replay";
        case DeviceKind::OpenHaptics: return "openhaptics";
        case DeviceKind::Sdl: return "sdl";
    }
    return "virtual";
}

std::string DeviceName::toString() const {
    std::string text(deviceKindName(kind));
    if (!argument.empty()) text += ":" + argument;
    return text;
}

Result<DeviceName, Error> parseDeviceName(std::string_view text) {
    const auto colon = text.find(':');
    const std::string_view kind = text.substr(0, colon);
    const std::string_view argument = colon == std::string_view::npos ? std::string_view() : text.substr(colon + 1);
    const bool hasArgument = colon != std::string_view::npos;
    auto fail = [&](const std::string& why) {
        return unexpected(Error{{},
                                0,
                                "device '" + std::string(text) + "': " + why +
                                    "; expected virtual, replay:FILE, openhaptics[:NAME] or sdl[:INDEX] (hapticut "
                                    "devices lists what works here)"});
    };
    DeviceName spec;
    spec.argument = std::string(argument);
    if (kind == "virtual" || kind == "mouse") {
        if (hasArgument) return fail("the virtual device takes no argument");
        spec.kind = DeviceKind::Virtual;
    } else if (kind == "replay") {
        if (argument.empty()) return fail("replay needs a trajectory file, as replay:FILE");
        spec.kind = DeviceKind::Replay;
    } else if (kind == "openhaptics") {
        if (hasArgument && argument.empty()) return fail("the device name after 'openhaptics:' is empty");
        spec.kind = DeviceKind::OpenHaptics;
    } else if (kind == "sdl") {
        if (hasArgument) {
            int index = -1;
            const auto [end, ec] = std::from_chars(argument.data(), argument.data() + argument.size(), index);
            if (ec != std::errc() || end != argument.data() + argument.size() || index < 0)
                return fail("the joystick index after 'sdl:' must be a whole number from 0");
        }
        spec.kind = DeviceKind::Sdl;
    } else {
        return fail("unknown kind '" + std::string(kind) + "'");
    }
    return spec;
}

}  // namespace hapticut::haptics
