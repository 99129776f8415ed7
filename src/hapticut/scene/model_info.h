// A model's validation report as JSON: what `hapticut info --json` prints and hapticut.info() returns.
#pragma once

#include <nlohmann/json.hpp>

#include "hapticut/scene/model_source.h"

namespace hapticut::scene {

/// Counts, boundary, manifoldness, orientation, shape, parts, and the physics constants of a model (or a
/// tool's cut threshold), with the model's coordinates as they are now.
nlohmann::ordered_json modelInfo(const ModelSource& source);

/// Whether the model's vertices were renumbered for locality, and the edges' mean span in index before
/// and after (mesh/vertex_order.h): {renumbered, mean_edge_span_before, mean_edge_span_after}.
nlohmann::ordered_json vertexOrderJson(const ModelSource& source);

}  // namespace hapticut::scene
