// Procedural tool meshes: the scalpel and the probe (forceps), tip at the origin, handle along +z.
#pragma once

#include "hapticut/mesh/surface_mesh.h"

namespace hapticut::mesh::procedural {

/// Default cut threshold of the scalpel, N: a firm press, below the default device's 3.3 N maximum.
inline constexpr double kScalpelThreshold_N = 2.0;
/// The probe never cuts: its threshold is far above any force a haptic device can exert.
inline constexpr double kProbeThreshold_N = 1e9;

/// A scalpel: a flat blade whose point is the tool's interaction point, on a round handle.
SurfaceMesh makeScalpel();

/// A blunt probe: a ball tip on a thin shaft.
SurfaceMesh makeProbe();

}  // namespace hapticut::mesh::procedural
