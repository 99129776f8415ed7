// Procedural tool meshes: the scalpel and the probe (forceps), tip at the origin, handle along +z.
#pragma once

#include "hapticut/mesh/surface_mesh.h"

namespace hapticut::mesh::procedural {

/// Default cut threshold of the scalpel, N: a firm press, below the default device's 3.3 N maximum.
inline constexpr double kScalpelThreshold_N = 2.0;
/// The probe never cuts: its threshold is far above any force a haptic device can exert.
inline constexpr double kProbeThreshold_N = 1e9;
/// The radius over which a tool's tip spreads its load on the surface (haptics/contact_footprint.h),
/// m: the tissue a tip presses down with it, wider than the tip (anchors alone, a Winkler foundation,
/// have no shear to spread a load). The probe's 2.5 mm ball pressed a few millimetres in, and the
/// scalpel's point with the first centimetre of its edge, press down the tissue within about 7 mm.
/// With it the same 6 mm press gives the same force within 4% on the 1,619 to 100,000 hearts.
inline constexpr double kProbeTipRadius_m = 0.007;
inline constexpr double kScalpelTipRadius_m = 0.007;
/// A tool's tip when only its threshold is known (a thesis tool file): a blade's if it can cut.
inline double tipRadiusForThreshold_m(double threshold_N) {
    return threshold_N < 1e6 ? kScalpelTipRadius_m : kProbeTipRadius_m;
}

/// A scalpel: a flat blade whose point is the tool's interaction point, on a round handle.
SurfaceMesh makeScalpel();

/// A blunt probe: a ball tip on a thin shaft.
SurfaceMesh makeProbe();

}  // namespace hapticut::mesh::procedural
