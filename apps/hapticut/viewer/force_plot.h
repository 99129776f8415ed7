// The live force-vs-time plot: a fixed ring of samples drawn with Dear ImGui.
#pragma once

#include <array>
#include <cstddef>

#include "hapticut/geometry/vec.h"

namespace hapticut::viewer {

class ForcePlot {
public:
    static constexpr std::size_t kSamples = 1200;  // twenty seconds at 60 frames per second
    static constexpr double kWindow_s = 10;        // the plot shows the last ten seconds

    void add(double t_s, const Vec3& force_N);
    void clear() { count_ = 0; }
    /// Draws |F| (white) and its x, y, z (red, green, blue) over the last kWindow_s seconds, against time
    /// with a tick each second, scaled to `maxForce_N`.
    void draw(double maxForce_N, float width, float height) const;

private:
    struct Sample {
        double t_s;
        Vec3 force_N;
    };
    std::array<Sample, kSamples> samples_{};
    std::size_t next_ = 0, count_ = 0;
};

}  // namespace hapticut::viewer
