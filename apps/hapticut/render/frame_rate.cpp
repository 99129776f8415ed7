// The frame-rate benchmark: a pressed heart, its loop at 1 kHz, frames drawn as fast as they go.
#include "render/frame_rate.h"

#include <array>
#include <epoxy/gl.h>

#include <chrono>
#include <cmath>
#include <map>
#include <memory>

#include "hapticut/cutting/cut_model.h"
#include "hapticut/geometry/aabb.h"
#include "hapticut/haptics/loop_scheduler.h"
#include "hapticut/haptics/virtual_device.h"
#include "hapticut/mesh/procedural/heart.h"
#include "hapticut/mesh/procedural/tools.h"
#include "hapticut/physics/material.h"
#include "render/gl_context.h"
#include "render/offscreen.h"
#include "render/renderer.h"
#include "render/snapshot_frame.h"

namespace hapticut::render {

namespace {

using Clock = std::chrono::steady_clock;

/// A heart with a probe pressed 3 mm into its front, the loop stepping in its own thread.
struct PressedHeart {
    std::unique_ptr<cutting::CutModel> organ;
    haptics::VirtualDevice device;
    std::unique_ptr<haptics::HapticLoop> loop;
    std::unique_ptr<haptics::RealTimeScheduler> clock;  // declared after the loop: stops before it goes

    explicit PressedHeart(int triangles) {
        mesh::procedural::HeartOptions options;
        options.triangles = triangles;
        mesh::SurfaceMesh heart = mesh::procedural::makeHeart(options);
        organ = std::make_unique<cutting::CutModel>(heart, physics::buildModel(heart, physics::Material{}));
        // The front: the vertex furthest out along +z near (0, -1 cm).
        Vec3 front = geometry::boundsOf(heart.positions).center();
        for (const Vec3& p : heart.positions)
            if (std::abs(p.x()) < 0.01 && std::abs(p.y() + 0.01) < 0.01 && p.z() > front.z()) front = p;
        device.setPosition(front - Vec3(0, 0, 0.003), 1);
        loop = std::make_unique<haptics::HapticLoop>(*organ, device);
        clock = std::make_unique<haptics::RealTimeScheduler>(*loop);
        (void)clock->start();  // a virtual device has no servo to fail
    }
};

}  // namespace

bool measureFrameRates(const std::vector<FrameRateCase>& cases, double seconds, std::vector<FrameRateResult>& results, std::string& renderer,
                       std::string& error, const std::function<void(const FrameRateResult&)>& onResult) {
    WindowOptions windowOptions;
    windowOptions.width = 64;
    windowOptions.height = 64;
    windowOptions.visible = false;
    auto window = GlWindow::open(windowOptions, error);
    if (!window) return false;
    renderer = window->rendererDescription();
    const std::vector<mesh::SurfaceMesh> tools = {mesh::procedural::makeProbe()};
    auto draw = Renderer::create(tools, error);
    if (!draw) return false;

    std::map<int, std::unique_ptr<PressedHeart>> hearts;
    for (const FrameRateCase& c : cases) {
        if (!hearts.count(c.triangles)) {
            hearts.clear();  // one loop at a time: the benchmark measures the renderer beside one loop
            hearts[c.triangles] = std::make_unique<PressedHeart>(c.triangles);
        }
        const auto& heart = hearts[c.triangles];
        auto target = OffscreenTarget::create(c.width, c.height, 4, error);
        if (!target) return false;
        ViewSettings view;
        view.frameOrgan(heart->organ->mesh().positions);
        view.stereo = c.stereo;
        draw->invalidateOrgan();  // a new heart, or the same one at another size: upload it afresh
        target->bind();
        FrameRateResult r{c};
        const long step0 = heart->loop->snapshots().readLatest().step;
        const auto start = Clock::now();
        auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - start).count(); };
        while (elapsed() < seconds || r.frames < 3) {
            const haptics::Snapshot& s = heart->loop->snapshots().readLatest();
            draw->draw(frameOf(s, std::array{0}, heart->device.maxForce_N()), view, c.width, c.height);
            glFinish();
            ++r.frames;
            r.faces = static_cast<int>(s.faces.size());
        }
        const double wall_s = elapsed();
        r.fps = static_cast<double>(r.frames) / wall_s;
        r.hapticRate_hz = static_cast<double>(heart->loop->snapshots().readLatest().step - step0) / wall_s;
        results.push_back(r);
        if (onResult) onResult(r);
    }
    return true;
}

}  // namespace hapticut::render
