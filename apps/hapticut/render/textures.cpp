// Procedural textures: tileable value noise shaped into muscle, vessels and a wet sheen.
#include "render/textures.h"

#include <algorithm>
#include <cmath>

#include "hapticut/geometry/vec.h"

namespace hapticut::render {

namespace {

double lattice(int x, int y, int periodX, int periodY, std::uint32_t seed) {
    x = ((x % periodX) + periodX) % periodX;
    y = ((y % periodY) + periodY) % periodY;
    std::uint32_t h =
        static_cast<std::uint32_t>(x) * 374761393u + static_cast<std::uint32_t>(y) * 668265263u + seed * 2246822519u;
    h = (h ^ (h >> 13)) * 1274126177u;
    h ^= h >> 16;
    return (h & 0xffffff) / double(0xffffff);
}

double smooth(double t) { return t * t * (3 - 2 * t); }

double valueNoise(double x, double y, int periodX, int periodY, std::uint32_t seed) {
    const double fx = std::floor(x), fy = std::floor(y);
    const int ix = static_cast<int>(fx), iy = static_cast<int>(fy);
    const double tx = smooth(x - fx), ty = smooth(y - fy);
    const double a = lattice(ix, iy, periodX, periodY, seed), b = lattice(ix + 1, iy, periodX, periodY, seed);
    const double c = lattice(ix, iy + 1, periodX, periodY, seed), d = lattice(ix + 1, iy + 1, periodX, periodY, seed);
    return (a + (b - a) * tx) * (1 - ty) + (c + (d - c) * tx) * ty;
}

double smoothstep(double e0, double e1, double x) { return smooth(std::clamp((x - e0) / (e1 - e0), 0.0, 1.0)); }

/// 1 on the noise's mid-level line, falling off to either side: thin branching lines, like vessels.
double ridge(double n, double width) { return smoothstep(1 - width, 1.0, 1 - std::abs(2 * n - 1)); }

std::uint8_t byte(double v) { return static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0, 1.0) * 255)); }

void put(Image& image, int x, int y, const Vec3& rgb, double alpha = 1) {
    std::uint8_t* p = image.at(x, y);
    p[0] = byte(rgb.x());
    p[1] = byte(rgb.y());
    p[2] = byte(rgb.z());
    p[3] = byte(alpha);
}

}  // namespace

double tiledNoise(double u, double v, int cellsU, int cellsV, int octaves, std::uint32_t seed) {
    double sum = 0, amplitude = 1, total = 0;
    double x = u * cellsU, y = v * cellsV;
    for (int o = 0; o < octaves; ++o) {
        sum += amplitude * valueNoise(x, y, cellsU, cellsV, seed + static_cast<std::uint32_t>(o) * 101u);
        total += amplitude;
        x *= 2;
        y *= 2;
        cellsU *= 2;
        cellsV *= 2;
        amplitude *= 0.5;
    }
    return sum / total;
}

OrganTextures makeOrganTextures(int size, std::uint32_t seed) {
    OrganTextures t{Image(size, size), Image(size, size)};
    const Vec3 muscleDark(0.42, 0.04, 0.05), muscleLight(0.78, 0.13, 0.12), vein(0.30, 0.04, 0.16),
        fat(0.86, 0.70, 0.42);
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const double u = (x + 0.5) / size, v = (y + 0.5) / size;
            // Fibres: noise stretched across v, slanted so the streaks wind round the heart.
            const double fibre = tiledNoise(u + v * 0.25, v, 96, 4, 3, seed);
            const double blotch = tiledNoise(u, v, 12, 4, 4, seed + 11);
            // Two vessel networks: large coronary-like vessels and fine branches.
            const double trunk = tiledNoise(u, v, 6, 2, 5, seed + 23);
            const double large = ridge(trunk, 0.06);
            const double fine = ridge(tiledNoise(u, v, 18, 6, 4, seed + 37), 0.05);
            const double vessel = std::max(large, 0.7 * fine);
            const double fatAmount = 0.3 * smoothstep(0.75, 0.95, 1 - std::abs(2 * trunk - 1)) * (1 - large);
            Vec3 colour = muscleDark + (muscleLight - muscleDark) * (0.55 * fibre + 0.45 * blotch);
            colour = colour + (fat - colour) * fatAmount * smoothstep(0.45, 0.6, blotch);
            colour = colour + (vein - colour) * vessel;
            put(t.diffuse, x, y, colour);

            // The thesis's wet look: black-and-white noise for k_s, a little shinier on the vessels.
            const double sheen = smoothstep(0.45, 0.6, tiledNoise(u, v, 192, 64, 2, seed + 51));
            const double specular = std::clamp(0.15 + 0.75 * sheen + 0.2 * vessel, 0.0, 1.0);
            const double height = 0.6 * large + 0.3 * fine + 0.1 * fibre;
            put(t.detail, x, y, Vec3(specular, height, 0));
        }
    return t;
}

std::array<Image, 6> makeStudioEnvironment(int size) {
    std::array<Image, 6> faces;
    // Direction of pixel (s, t) in [-1, 1] on each face, as OpenGL's cube map lays them out.
    const auto direction = [](int face, double s, double t) -> Vec3 {
        switch (face) {
            case 0: return {1, -t, -s};
            case 1: return {-1, -t, s};
            case 2: return {s, 1, t};
            case 3: return {s, -1, -t};
            case 4: return {s, -t, 1};
            default: return {-s, -t, -1};
        }
    };
    const Vec3 floor(0.10, 0.10, 0.12), horizon(0.55, 0.57, 0.62), sky(0.30, 0.34, 0.42);
    const Vec3 box1 = Vec3(0.4, 0.8, 0.45).normalized(), box2 = Vec3(-0.6, 0.7, -0.4).normalized();
    for (int f = 0; f < 6; ++f) {
        faces[f] = Image(size, size);
        for (int y = 0; y < size; ++y)
            for (int x = 0; x < size; ++x) {
                const Vec3 d = direction(f, 2 * (x + 0.5) / size - 1, 2 * (y + 0.5) / size - 1).normalized();
                Vec3 c = d.y() < 0 ? horizon + (floor - horizon) * smoothstep(0.0, 0.3, -d.y())
                                   : horizon + (sky - horizon) * smoothstep(0.0, 0.6, d.y());
                // Two soft light boxes: the bright streaks that make metal read as metal.
                c += Vec3(1.6, 1.6, 1.5) * smoothstep(0.93, 0.97, d.dot(box1)) +
                     Vec3(0.9, 0.95, 1.1) * smoothstep(0.95, 0.985, d.dot(box2));
                put(faces[f], x, y, c);
            }
    }
    return faces;
}

}  // namespace hapticut::render
