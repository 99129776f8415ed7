// The project's own textures, generated at start-up (SPEC R19): a red muscle with vessels, a wet
// black-and-white specular noise, a height field for normal mapping, and a studio cube map for tools.
#pragma once

#include <array>
#include <cstdint>

#include "render/image.h"

namespace hapticut::render {

struct OrganTextures {
    Image diffuse;  // k_d: red muscle fibres, darker vessels, a little fat along the large vessels
    Image detail;   // R: k_s (the wet noise), G: height (vessels raised, fibres faint), for bump mapping
};

/// Square textures of `size` pixels that tile in both directions (the heart's u wraps round it).
OrganTextures makeOrganTextures(int size = 512, std::uint32_t seed = 7);

/// The six faces of a cube map in OpenGL's order (+x, -x, +y, -y, +z, -z): a soft studio with two
/// light boxes above and a darker floor, which the metal tools reflect.
std::array<Image, 6> makeStudioEnvironment(int size = 128);

/// Value noise in [0, 1] over the unit square that tiles in both directions: the first of `octaves`
/// octaves has cellsU x cellsV cells, each further one twice as many each way.
double tiledNoise(double u, double v, int cellsU, int cellsV, int octaves, std::uint32_t seed);

}  // namespace hapticut::render
