// `hapticut info`: the validation report of a model or tool file, or of the procedural heart.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <iostream>

#include "commands.h"
#include "hapticut/mesh/mesh_report.h"
#include "hapticut/mesh/parts.h"
#include "hapticut/scene/model_info.h"
#include "terminal.h"
#include "unit_options.h"

namespace hapticut::app {

namespace {

struct InfoOptions {
    std::string model;
    int triangles = 1619;
    bool json = false;
    UnitOptions units;
};

int info(const InfoOptions& o) {
    auto source = loadModelSource(o.model, o.triangles, o.units.parts);
    if (!source) return 1;
    applyUnits(o.units, source->mesh.positions, source->name);
    for (const Warning& w : scene::describeInMetres(*source)) std::cerr << "warning: " << w.toString() << "\n";
    const mesh::MeshReport r = mesh::validateMesh(source->mesh);
    if (o.json) {
        std::cout << scene::modelInfo(*source).dump(2) << "\n";
        return 0;
    }
    auto yes = [](bool b) { return b ? "yes" : "no"; };
    std::printf("%s\n", source->name.c_str());
    std::printf("  vertices %zu, faces %zu, edges %zu (springs %zu)\n", r.vertices, r.faces, r.edges, r.springs);
    std::printf("  boundary edges %zu, non-manifold edges %zu\n", r.boundaryEdges, r.nonManifoldEdges);
    std::printf("  closed %s, manifold %s, oriented %s, components %zu, Euler characteristic %ld\n", yes(r.closed),
                yes(r.manifold), yes(r.oriented), r.components, r.eulerCharacteristic);
    std::printf(
        "  degenerate faces %zu, unused vertices %zu, springs off the faces %zu, face edges without a spring %zu\n",
        r.degenerateFaces, r.unusedVertices, r.springsNotOnFaces, r.faceEdgesWithoutSpring);
    std::printf("  bounding box (%.4g, %.4g, %.4g) to (%.4g, %.4g, %.4g) m\n", r.bboxMin.x(), r.bboxMin.y(),
                r.bboxMin.z(), r.bboxMax.x(), r.bboxMax.y(), r.bboxMax.z());
    std::printf("  min angle %.2f deg, mean edge %.4g m, shortest edge %.4g m, area %.4g m^2\n", r.minAngleDeg,
                r.meanEdgeLength_m, r.shortestEdge_m, r.area_m2);
    const mesh::VertexOrderResult& order = source->vertexOrder;
    if (order.renumbered)
        std::printf("  vertex order: renumbered for locality (reverse Cuthill-McKee), mean edge span %.0f -> %.0f\n",
                    order.spanBefore, order.spanAfter);
    else
        std::printf("  vertex order: kept, mean edge span %.0f\n", order.spanBefore);
    for (const mesh::PartSummary& p : mesh::summariseParts(source->mesh))
        std::printf("  part '%s': %zu faces, %zu vertices, %s\n", p.name.c_str(), p.faces, p.vertices,
                    p.closed() ? "closed" : (std::to_string(p.boundaryEdges) + " boundary edges").c_str());
    if (source->toolThreshold_N)
        std::printf("  tool cut threshold %g N\n", *source->toolThreshold_N);
    else
        std::printf("  physics: mass %g, ks %g, kd %g, kp %g, kdp %g\n", source->physics.mass,
                    source->physics.structuralStiffness, source->physics.structuralDamping,
                    source->physics.positioningStiffness, source->physics.positioningDamping);
    return 0;
}

}  // namespace

Command addInfoCommand(CLI::App& app) {
    auto o = std::make_shared<InfoOptions>();
    CLI::App* cmd = app.add_subcommand("info", "Validate a mesh: counts, boundary, manifoldness, orientation, quality");
    cmd->add_option("model", o->model, "'heart' or a model/tool file (.txt, .obj, .ply)")->required();
    addUnitOptions(cmd, o->units);
    cmd->add_option("--triangles", o->triangles, "Triangle count of the procedural heart")
        ->capture_default_str()
        ->check(CLI::Range(12, 20'000'000));
    cmd->add_flag("--json", o->json, "Print the report as JSON");
    return [o] { return info(*o); };
}

}  // namespace hapticut::app
