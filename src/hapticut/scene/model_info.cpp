// A model's validation report as JSON.
#include "hapticut/scene/model_info.h"

#include "hapticut/mesh/mesh_report.h"
#include "hapticut/mesh/parts.h"

namespace hapticut::scene {

nlohmann::ordered_json vertexOrderJson(const ModelSource& source) {
    const mesh::VertexOrderResult& o = source.vertexOrder;
    return {
        {"renumbered", o.renumbered}, {"mean_edge_span_before", o.spanBefore}, {"mean_edge_span_after", o.spanAfter}};
}

nlohmann::ordered_json modelInfo(const ModelSource& source) {
    const mesh::MeshReport r = mesh::validateMesh(source.mesh);
    nlohmann::ordered_json j;
    j["model"] = source.name;
    j["vertices"] = r.vertices;
    j["vertex_order"] = vertexOrderJson(source);
    j["faces"] = r.faces;
    j["edges"] = r.edges;
    j["boundary_edges"] = r.boundaryEdges;
    j["non_manifold_edges"] = r.nonManifoldEdges;
    j["closed"] = r.closed;
    j["manifold"] = r.manifold;
    j["oriented"] = r.oriented;
    j["components"] = r.components;
    j["euler_characteristic"] = r.eulerCharacteristic;
    j["degenerate_faces"] = r.degenerateFaces;
    j["unused_vertices"] = r.unusedVertices;
    j["springs"] = r.springs;
    j["springs_not_on_faces"] = r.springsNotOnFaces;
    j["face_edges_without_spring"] = r.faceEdgesWithoutSpring;
    j["bbox_min"] = {r.bboxMin.x(), r.bboxMin.y(), r.bboxMin.z()};
    j["bbox_max"] = {r.bboxMax.x(), r.bboxMax.y(), r.bboxMax.z()};
    j["min_angle_deg"] = r.minAngleDeg;
    const auto advice = mesh::shapeAdvice(r);
    j["shape_advice"] = advice ? nlohmann::ordered_json(*advice) : nlohmann::ordered_json(nullptr);
    j["mean_edge_length_m"] = r.meanEdgeLength_m;
    j["shortest_edge_m"] = r.shortestEdge_m;
    j["area_m2"] = r.area_m2;
    j["parts"] = nlohmann::ordered_json::array();
    for (const mesh::PartSummary& p : mesh::summariseParts(source.mesh))
        j["parts"].push_back({{"name", p.name},
                              {"faces", p.faces},
                              {"vertices", p.vertices},
                              {"boundary_edges", p.boundaryEdges},
                              {"closed", p.closed()}});
    if (source.toolThreshold_N)
        j["tool_threshold_N"] = *source.toolThreshold_N;
    else
        j["physics"] = {{"mass", source.physics.mass},
                        {"ks", source.physics.structuralStiffness},
                        {"kd", source.physics.structuralDamping},
                        {"kp", source.physics.positioningStiffness},
                        {"kdp", source.physics.positioningDamping}};
    return j;
}

}  // namespace hapticut::scene
