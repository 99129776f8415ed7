// libFuzzer target: the real import of a user's mesh file (our OBJ and PLY readers, Assimp for STL and
// the rest), then the repair, must return a mesh or an Error for any bytes, never crash, hang or
// exhaust memory. The first byte picks the extension, so one corpus covers every format.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "hapticut/mesh/io/mesh_file.h"
#include "hapticut/mesh/mesh_report.h"
#include "hapticut/mesh/repair.h"

namespace {

/// The process's own scratch folder, removed when the fuzzer or the corpus replay exits.
struct ScratchFolder {
    std::filesystem::path path =
        std::filesystem::temp_directory_path() / ("hapticut-import-fuzz-" + std::to_string(::getpid()));
    ScratchFolder() { std::filesystem::create_directories(path); }
    ~ScratchFolder() {
        std::error_code ignored;
        std::filesystem::remove_all(path, ignored);
    }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size == 0) return 0;
    static const char* const kExtensions[] = {".obj", ".ply", ".stl", ".txt"};
    static const ScratchFolder folder;
    const std::filesystem::path file = folder.path / (std::string("input") + kExtensions[data[0] % 4]);
    std::ofstream(file, std::ios::binary)
        .write(reinterpret_cast<const char*>(data + 1), static_cast<std::streamsize>(size - 1));
    auto loaded = hapticut::mesh::io::loadMesh(file);
    if (loaded) {
        hapticut::mesh::RepairOptions options;
        options.repair = true;
        (void)hapticut::mesh::cleanMesh(loaded->mesh, options);
        (void)hapticut::mesh::validateMesh(loaded->mesh);
    }
    return 0;
}
