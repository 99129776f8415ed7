// What the viewer simulates: the scene, the organ being cut, the device (the mouse or a replayed
// path) and the haptic loop running in its own thread; rebuilt when the user resets or reloads.
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <string>

#include "hapticut/cutting/cut_model.h"
#include "hapticut/haptics/haptic_loop.h"
#include "hapticut/haptics/replay_device.h"
#include "hapticut/haptics/virtual_device.h"
#include "scene_setup.h"

namespace hapticut::viewer {

enum class MaterialKnob { Mass, StructuralStiffness, StructuralDamping, PositioningStiffness, PositioningDamping };
inline constexpr int kMaterialKnobs = 5;

class Session {
public:
    explicit Session(app::LoadedScene scene);
    ~Session();

    /// Starts the loop on a fresh copy of the scene's organ.
    void resetModel();
    /// Restarts the loop with `config()` on the same organ (integrator or rate changed).
    void restartLoop();
    void setTool(std::size_t index);
    /// Drives the loop with a hardware device instead of the mouse (its servo loop steps the loop).
    void useDevice(std::unique_ptr<haptics::Device> device);
    bool hardware() const { return hardware_ != nullptr; }
    const haptics::Device* hardwareDevice() const { return hardware_.get(); }
    /// Replays a trajectory file instead of the mouse; false with `error` when it does not load.
    bool replay(const std::string& file, std::string& error);
    void useMouse();
    /// Loads another model into the same scene; false (message printed) when it does not load.
    bool loadModel(const std::string& model, std::string& error);
    /// Adds a tool from a tool file (thesis format: its mesh and cut threshold), named after the file,
    /// and takes it in hand; false with `error` when it does not load.
    bool loadTool(const std::string& file, std::string& error);
    /// Sets a material knob to `scale` times the scene's value, live through the loop's queue.
    void setMaterialScale(MaterialKnob knob, double scale);
    /// Writes the organ as the snapshot shows it (deformed, with every cut).
    std::optional<std::string> exportMesh(const std::string& file, const haptics::Snapshot& snapshot) const;

    haptics::HapticLoop& loop() { return *loop_; }
    haptics::LoopConfig& config() { return config_; }
    haptics::VirtualDevice& mouseDevice() { return mouse_; }
    bool replaying() const { return replay_ != nullptr; }
    const std::string& replayFile() const { return replayFile_; }
    const app::LoadedScene& scene() const { return scene_; }
    std::size_t tool() const { return tool_; }
    double materialScale(MaterialKnob knob) const { return materialScale_[static_cast<int>(knob)]; }
    long resets() const { return resets_; }

private:
    void startLoop();
    std::string loopError_;
public:
    /// Why the loop could not start (a device's servo refused), or empty.
    const std::string& loopError() const { return loopError_; }

    app::LoadedScene scene_;
    haptics::LoopConfig config_;
    haptics::VirtualDevice mouse_;
    std::unique_ptr<haptics::ReplayDevice> replay_;
    std::unique_ptr<haptics::Device> hardware_;
    std::string replayFile_;
    std::unique_ptr<cutting::CutModel> organ_;
    std::unique_ptr<haptics::HapticLoop> loop_;
    std::size_t tool_ = 0;
    std::array<double, kMaterialKnobs> materialScale_{1, 1, 1, 1, 1};
    long resets_ = 0;
};

}  // namespace hapticut::viewer
