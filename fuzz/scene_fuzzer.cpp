// libFuzzer target: the scene parser returns a scene or an Error for any bytes, never crashes.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "hapticut/scene/scene_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    (void)hapticut::scene::parseScene(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.toml", ".");
    return 0;
}
