// libFuzzer target: the thesis model and tool parsers and the OBJ and PLY readers must return a
// value or an Error for any bytes, never crash, hang or exhaust memory.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "hapticut/mesh/io/obj_format.h"
#include "hapticut/mesh/io/ply_format.h"
#include "hapticut/mesh/io/thesis_format.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    auto model = hapticut::mesh::io::parseModel(text, "fuzz.txt");
    if (model) (void)hapticut::mesh::io::formatModel(model->mesh, model->physics);
    (void)hapticut::mesh::io::parseTool(text, "fuzz.txt");
    (void)hapticut::mesh::io::parseObj(text, "fuzz.obj");
    (void)hapticut::mesh::io::parsePly(text, "fuzz.ply");
    return 0;
}
