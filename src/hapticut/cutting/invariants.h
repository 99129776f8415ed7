// The guarantees cutting keeps (DESIGN "Cutting"), checked in one place by tests and debug builds.
#pragma once

#include <string>
#include <vector>

#include "hapticut/cutting/cut_model.h"

namespace hapticut::cutting {

struct InvariantReport {
    std::vector<std::string> problems;  // empty when every invariant holds
    bool ok() const { return problems.empty(); }
};

/// Edge- and vertex-manifold (no two fans of faces pinched at a vertex); consistently oriented; no degenerate rest
/// triangle; every face edge has exactly one structural spring and every spring is a face edge; springs, edges and
/// lookups agree; total mass equals `expected_mass_kg` (to 1e-12 relative); every position, velocity and UV finite.
/// `closed`: the organ was closed before it was cut, so it must still be (no boundary edge: walls close every wound).
InvariantReport checkInvariants(const CutModel& model, double expected_mass_kg, bool closed = false);

}  // namespace hapticut::cutting
