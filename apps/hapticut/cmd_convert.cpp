// `hapticut convert IN OUT`: import any supported mesh, clean or repair it, and write the thesis
// format, OBJ or PLY.
#include <CLI/CLI.hpp>

#include <iostream>
#include <optional>

#include "commands.h"
#include "hapticut/common/line_reader.h"
#include "hapticut/common/output_path.h"
#include "hapticut/mesh/io/mesh_file.h"
#include "hapticut/mesh/io/thesis_format.h"
#include "hapticut/mesh/mesh_report.h"
#include "hapticut/mesh/repair.h"
#include "hapticut/physics/material.h"
#include "terminal.h"
#include "unit_options.h"

namespace hapticut::app {

namespace {

struct ConvertOptions {
    std::string in, out;
    int triangles = 1619;
    UnitOptions units;
    std::optional<double> mass, ks, kd, kp, kdp, weld;
    bool fitUnitBox = false, repair = false;
};

int convert(const ConvertOptions& o) {
    if (!mesh::io::formatFromExtension(o.out)) {
        std::cerr << "hapticut convert: cannot write '" << o.out << "': expected .txt (thesis format), .obj or .ply\n";
        return 2;
    }
    if (const Status unwritable = checkOutputPath(o.out)) {
        std::cerr << "hapticut convert: " << unwritable->toString() << "\n";
        return 2;
    }
    auto source = loadModelSource(o.in, o.triangles);
    if (!source) return 1;
    mesh::SurfaceMesh& m = source->mesh;
    applyUnits(o.units, m.positions, source->name);
    if (o.weld || o.repair) {
        mesh::RepairOptions options;
        options.weldEpsilon_m = o.weld.value_or(-1);
        options.repair = o.repair;
        const mesh::RepairReport r = mesh::cleanMesh(m, options);
        for (const std::string& note : r.notes) std::cout << "  " << note << "\n";
        if (r.notes.empty()) std::cout << "  nothing to clean or repair\n";
        if (m.faces.empty()) {
            std::cerr << "hapticut convert: nothing left to write: "
                      << (o.weld ? "a weld of " + formatDouble(*o.weld) +
                                       " m joined the model's vertices until no face was left"
                                 : std::string("cleaning removed every face"))
                      << "; " << o.out << " was not written\n";
            return 1;
        }
        if (!source->fromThesisFile) source->physics = physics::thesisPhysicsFor(m, physics::Material{});
    }
    if (o.fitUnitBox) {
        mesh::fitUnitBox(m);
        mesh::computeFaceNormals(m);
        std::cout << "  fitted into the unit box centred at the origin (1 m across: the thesis's convention, not "
                     "an organ's size)\n";
        if (!source->fromThesisFile) source->physics = physics::thesisPhysicsFor(m, physics::Material{});
    }
    if (o.mass) source->physics.mass = *o.mass;
    if (o.ks) source->physics.structuralStiffness = *o.ks;
    if (o.kd) source->physics.structuralDamping = *o.kd;
    if (o.kp) source->physics.positioningStiffness = *o.kp;
    if (o.kdp) source->physics.positioningDamping = *o.kdp;

    const mesh::MeshReport report = mesh::validateMesh(m);
    std::cout << "  " << report.vertices << " vertices, " << report.faces << " faces, " << report.edges << " edges; "
              << (report.closed ? "closed"
                                : std::to_string(report.boundaryEdges) + " boundary edges (holes or open ends)")
              << "; "
              << (report.manifold ? "manifold" : std::to_string(report.nonManifoldEdges) + " non-manifold edges")
              << "; " << (report.oriented ? "consistently oriented" : "inconsistently oriented") << "; "
              << report.components << " component(s)\n";

    const bool toThesis = mesh::io::formatFromExtension(o.out) == mesh::io::MeshFormat::Thesis;
    const auto error = toThesis && source->toolThreshold_N ? mesh::io::writeToolFile(o.out, m, *source->toolThreshold_N)
                                                           : mesh::io::saveMesh(o.out, m, source->physics);
    if (error) {
        std::cerr << error->toString() << "\n";
        return 1;
    }
    std::cout << "wrote " << o.out << ": " << m.positions.size() << " vertices, " << m.faces.size() << " faces, "
              << m.edges.size() << " edges\n";
    return 0;
}

}  // namespace

Command addConvertCommand(CLI::App& app) {
    auto o = std::make_shared<ConvertOptions>();
    CLI::App* cmd = app.add_subcommand(
        "convert",
        "Import a mesh (thesis .txt, OBJ, PLY, STL, glTF, 3DS, FBX, Collada, ...), clean it, write .txt/.obj/.ply");
    cmd->add_option("in", o->in, "Input file, or 'heart' for the procedural heart")->required();
    cmd->add_option("out", o->out, "Output file (.txt, .obj or .ply)")->required();
    addUnitOptions(cmd, o->units);
    cmd->add_option("--triangles", o->triangles, "Triangle count when the input is 'heart'")
        ->capture_default_str()
        ->check(CLI::Range(12, 20'000'000));
    cmd->add_option("--mass", o->mass, "Total mass written to the physics line, kg")->check(CLI::PositiveNumber);
    cmd->add_option("--ks", o->ks, "Structural spring stiffness per edge, N/m")->check(CLI::NonNegativeNumber);
    cmd->add_option("--kd", o->kd, "Structural spring damping per edge, N·s/m")->check(CLI::NonNegativeNumber);
    cmd->add_option("--kp", o->kp, "Positioning spring stiffness per node, N/m")->check(CLI::NonNegativeNumber);
    cmd->add_option("--kdp", o->kdp, "Positioning spring damping per node, N·s/m")->check(CLI::NonNegativeNumber);
    cmd->add_flag("--fit-unit-box", o->fitUnitBox, "Scale and centre into the unit box, as the thesis's models were");
    cmd->add_option("--weld", o->weld,
                    "Join vertices closer than this, m (imports other than OBJ/PLY weld exact duplicates anyway)")
        ->check(CLI::NonNegativeNumber);
    cmd->add_flag("--repair", o->repair,
                  "Orient faces consistently and outward, split non-manifold edges, remove small fragments");
    return [o] { return convert(*o); };
}

}  // namespace hapticut::app
