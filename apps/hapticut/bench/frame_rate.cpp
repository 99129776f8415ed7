// The frame-rate benchmark: a pressed heart, its loop at 1 kHz, frames drawn as fast as they go.
#include "bench/frame_rate.h"

#include <epoxy/gl.h>
#include <array>

#include <chrono>
#include <cmath>
#include <map>
#include <memory>

#include "hapticut/cutting/cut_model.h"
#include "hapticut/haptics/loop_scheduler.h"
#include "hapticut/haptics/virtual_device.h"
#include "hapticut/mesh/procedural/tools.h"
#include "hapticut/scene/bench_scenes.h"
#include "render/gl_context.h"
#include "render/offscreen.h"
#include "render/renderer.h"
#include "render/snapshot_frame.h"

namespace hapticut::bench {

namespace {

using Clock = std::chrono::steady_clock;

/// A heart with a probe pressed 3 mm into its front, the loop stepping in its own thread.
struct PressedHeart {
    std::unique_ptr<cutting::CutModel> organ;
    haptics::VirtualDevice device;
    std::unique_ptr<haptics::HapticLoop> loop;
    std::unique_ptr<haptics::RealTimeScheduler> clock;  // declared after the loop: stops before it goes

    explicit PressedHeart(int triangles) {
        const scene::Scene heart = scene::benchHeart(triangles);
        organ = std::make_unique<cutting::CutModel>(heart.source.mesh, heart.buildModel());
        device.setPosition(scene::frontVertex_m(heart.source.mesh, 0, -0.01) - Vec3(0, 0, 0.003), 1);
        loop = std::make_unique<haptics::HapticLoop>(*organ, device);
        clock = std::make_unique<haptics::RealTimeScheduler>(*loop);
        (void)clock->start();  // a virtual device has no servo to fail
    }
};

}  // namespace

bool measureFrameRates(const std::vector<FrameRateCase>& cases, double seconds, std::vector<FrameRateResult>& results,
                       std::string& renderer, std::string& error,
                       const std::function<void(const FrameRateResult&)>& onResult) {
    render::WindowOptions windowOptions;
    windowOptions.width = 64;
    windowOptions.height = 64;
    windowOptions.visible = false;
    auto window = render::GlWindow::open(windowOptions, error);
    if (!window) return false;
    renderer = window->rendererDescription();
    const std::vector<mesh::SurfaceMesh> tools = {mesh::procedural::makeProbe()};
    auto draw = render::Renderer::create(tools, error);
    if (!draw) return false;

    std::map<int, std::unique_ptr<PressedHeart>> hearts;
    for (const FrameRateCase& c : cases) {
        if (!hearts.count(c.triangles)) {
            hearts.clear();  // one loop at a time: the benchmark measures the renderer beside one loop
            hearts[c.triangles] = std::make_unique<PressedHeart>(c.triangles);
        }
        const auto& heart = hearts[c.triangles];
        auto target = render::OffscreenTarget::create(c.width, c.height, 4, error);
        if (!target) return false;
        render::ViewSettings view;
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
            draw->draw(render::frameOf(s, std::array{0}, heart->device.maxForce_N()), view, c.width, c.height);
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

}  // namespace hapticut::bench
