// `hapticut convert IN OUT`: import any supported mesh, clean or repair it, and write the thesis
// format, OBJ or PLY.
#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <optional>

#include "commands.h"
#include "hapticut/common/line_reader.h"
#include "hapticut/common/output_path.h"
#include "hapticut/mesh/io/mesh_file.h"
#include "hapticut/mesh/io/thesis_format.h"
#include "hapticut/mesh/mesh_report.h"
#include "hapticut/mesh/remesh.h"
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
    std::optional<double> mass, ks, kd, kp, kdp, weld, targetEdge;
    double featureAngle_deg = 0;
    std::optional<long> remeshTriangles;
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
    auto source = loadModelSource(o.in, o.triangles, o.units.parts);
    if (!source) return 1;
    mesh::SurfaceMesh& m = source->mesh;
    applyUnits(o.units, m.positions, source->name);
    for (const Warning& w : scene::describeInMetres(*source)) std::cerr << "warning: " << w.toString() << "\n";
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
    if (o.remeshTriangles || o.targetEdge) {
        const mesh::MeshReport before = mesh::validateMesh(m);
        mesh::RemeshOptions options;
        options.featureAngle_deg = o.featureAngle_deg;
        options.targetEdge_m = o.targetEdge
                                   ? *o.targetEdge
                                   : mesh::targetEdgeForTriangles(m, static_cast<std::size_t>(*o.remeshTriangles));
        if (o.remeshTriangles) options.targetTriangles = static_cast<std::size_t>(*o.remeshTriangles);
        auto remeshed = mesh::remeshIsotropic(m, options);
        if (!remeshed) {
            std::cerr << "hapticut convert: " << o.in << ": cannot remesh: " << remeshed.error() << "; " << o.out
                      << " was not written\n";
            return 1;
        }
        const mesh::MeshReport after = mesh::validateMesh(remeshed->mesh);
        const auto mm = [](double metres) { return threeDigits(metres * 1e3) + " mm"; };
        std::cout << "  remeshed to " << mm(remeshed->targetEdge_m) << " edges: " << before.faces << " -> "
                  << after.faces << " faces; smallest angle " << threeDigits(before.minAngleDeg) << " -> "
                  << threeDigits(after.minAngleDeg) << " deg; shortest edge " << mm(before.shortestEdge_m) << " -> "
                  << mm(after.shortestEdge_m) << "; " << remeshed->featureEdges << " sharp or boundary edges kept; "
                  << remeshed->sliversMended << " edits mended thin or folded triangles; distance to the input "
                  << mm(remeshed->distanceMean_m) << " mean, " << mm(remeshed->distanceMax_m) << " max\n";
        if (remeshed->smoothedFirst)
            std::cout << "  the input is rough (" << std::lround(100 * remeshed->foldedInputShare)
                      << "% of its edges fold its faces against each other): smoothed before remeshing, then "
                         "projected back onto it\n";
        m = std::move(remeshed->mesh);
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
    auto* remesh = cmd->add_option("--remesh", o->remeshTriangles,
                                   "Remesh isotropically to about this many triangles (after --repair): even edges, "
                                   "no slivers, sharp edges and boundaries kept")
                       ->check(CLI::Range(4L, 20'000'000L));
    cmd->add_option("--target-edge", o->targetEdge, "Remesh isotropically to this edge length, m (after --units)")
        ->check(CLI::PositiveNumber)
        ->excludes(remesh);
    cmd->add_option("--feature-angle", o->featureAngle_deg,
                    "With --remesh: keep edges where faces meet at more than this many degrees (a tool or a "
                    "machined part; organs have none, and noise would count)")
        ->check(CLI::Range(0.0, 180.0));
    return [o] { return convert(*o); };
}

}  // namespace hapticut::app
