// `hapticut convert IN OUT`: between the thesis format, OBJ and PLY.
#include <CLI/CLI.hpp>

#include <iostream>

#include "commands.h"
#include "hapticut/mesh/io/mesh_file.h"
#include "hapticut/mesh/io/thesis_format.h"
#include "model_source.h"

namespace hapticut::app {

namespace {

struct ConvertOptions {
    std::string in, out;
    int triangles = 1619;
};

int convert(const ConvertOptions& o) {
    if (!mesh::io::formatFromExtension(o.out)) {
        std::cerr << "hapticut convert: cannot write '" << o.out << "': expected .txt (thesis format), .obj or .ply\n";
        return 2;
    }
    const auto source = loadModelSource(o.in, o.triangles);
    if (!source) return 1;
    const bool toThesis = mesh::io::formatFromExtension(o.out) == mesh::io::MeshFormat::Thesis;
    const auto error = toThesis && source->toolThreshold_N ? mesh::io::writeToolFile(o.out, source->mesh, *source->toolThreshold_N)
                                                           : mesh::io::saveMesh(o.out, source->mesh, source->physics);
    if (error) {
        std::cerr << error->toString() << "\n";
        return 1;
    }
    std::cout << "wrote " << o.out << ": " << source->mesh.positions.size() << " vertices, " << source->mesh.faces.size() << " faces, "
              << source->mesh.edges.size() << " edges\n";
    return 0;
}

}  // namespace

Command addConvertCommand(CLI::App& app) {
    auto o = std::make_shared<ConvertOptions>();
    CLI::App* cmd = app.add_subcommand("convert", "Convert a mesh between the thesis format (.txt), OBJ and PLY");
    cmd->add_option("in", o->in, "Input file, or 'heart' for the procedural heart")->required();
    cmd->add_option("out", o->out, "Output file (.txt, .obj or .ply)")->required();
    cmd->add_option("--triangles", o->triangles, "Triangle count when the input is 'heart'")->capture_default_str()->check(CLI::Range(12, 20'000'000));
    return [o] { return convert(*o); };
}

}  // namespace hapticut::app
