// Simulation: a scene brought to life. It owns the organ being cut, the hands with their devices
// (a virtual device each, moved by a program or the viewer's mouse; a replayed path; a hardware
// device) and the haptic loop stepping on the wall clock; the user's changes rebuild what they must.
#pragma once

#include <array>
#include <atomic>
#include <memory>
#include <optional>
#include <string>

#include "hapticut/common/error.h"
#include "hapticut/cutting/cut_model.h"
#include "hapticut/haptics/loop_scheduler.h"
#include "hapticut/haptics/replay_device.h"
#include "hapticut/haptics/step_log.h"
#include "hapticut/haptics/virtual_device.h"
#include "hapticut/scene/scene.h"

namespace hapticut::scene {

enum class MaterialKnob { Mass, StructuralStiffness, StructuralDamping, PositioningStiffness, PositioningDamping };
inline constexpr int kMaterialKnobs = 5;

class Simulation {
public:
    explicit Simulation(Scene scene);
    ~Simulation();
    Simulation(const Simulation&) = delete;
    Simulation& operator=(const Simulation&) = delete;

    /// Starts the loop on a fresh copy of the scene's organ.
    void resetModel();
    /// Restarts the loop with `config()` on the same organ (integrator or rate changed).
    void restartLoop();

    /// One hand or two on the organ (the loop restarts on the same organ). A second hand starts with
    /// the next tool, beside the first; the mouse drives the active hand, the other holds still.
    void setHandCount(int hands);
    int handCount() const { return handCount_; }
    void setActiveHand(int hand);
    int activeHand() const { return activeHand_; }

    /// The tool in the active hand.
    void setTool(std::size_t index);
    std::size_t tool(int hand) const { return tool_[static_cast<std::size_t>(hand)]; }
    std::size_t tool() const { return tool(activeHand_); }
    std::array<int, haptics::kMaxHands> toolsInHands() const;
    /// The active hand's cut threshold: its tool's until the user changes it.
    double cutThreshold() const { return threshold_[static_cast<std::size_t>(activeHand_)]; }
    void setCutThreshold(double threshold_N);
    /// The radius hand `hand`'s tool spreads its load over: its tool's (haptics::Hand::tipRadius_m).
    double tipRadius(int hand) const;

    /// Drives a hand with a hardware device instead of the mouse (a servo device steps the loop).
    void useDevice(std::unique_ptr<haptics::Device> device, int hand = 0);
    /// A hand's own limits and coupling, from the scene's [[devices]] entry for it; applied when the
    /// loop next starts (useDevice, a reset).
    void setHandSettings(int hand, const SceneDevice& settings);
    bool hardware() const { return hardwareDevice() != nullptr; }
    /// The active hand's hardware device, if it has one.
    const haptics::Device* hardwareDevice() const;
    /// Replays a trajectory file in the first hand instead of its virtual device.
    Status replay(const std::string& file);
    void useMouse();
    /// Whether the mouse drives the active hand (no replay, no hardware there).
    bool mouseDrives() const;
    /// How the haptic loop's thread is scheduled (RealTimeScheduler::scheduling), while it runs.
    std::string hapticScheduling() const;

    /// Loads another model into the same scene.
    Status loadModel(const std::string& model);
    /// Adds a tool from a tool file (thesis format: its mesh and cut threshold), named after the file,
    /// and takes it in hand.
    Status loadTool(const std::string& file);
    /// Sets a material knob to `scale` times the scene's value, live through the loop's queue.
    void setMaterialScale(MaterialKnob knob, double scale);
    /// Writes the organ as the snapshot shows it (deformed, with every cut).
    WriteStatus exportMesh(const std::string& file, const haptics::Snapshot& snapshot) const;

    /// Records the active hand's device path at the loop's rate: every step, handed off the loop's
    /// thread through a lock-free ring (haptics::StepLogWriter), as `t,x,y,z,button,qw,qx,qy,qz,tool,
    /// fx,fy,fz` with times from 0, the stylus's orientation (0,0,0,0 until the device reports one), the
    /// tool in hand and the force the hand was sent: a session, which replays as a trajectory and which
    /// `hapticut assess` scores. It goes on through loop
    /// restarts, its times continuing. An error when the file cannot be written.
    Status startRecording(const std::string& file);
    /// Ends the recording and completes its file (until then it is a temporary file beside it); the
    /// errors of writing it, if any.
    std::vector<Error> stopRecording();
    bool recording() const { return recorder_ != nullptr; }
    const std::string& recordingFile() const { return recordingFile_; }
    /// Rows written so far, and steps the ring had no room for.
    long recordedSteps() const { return recorder_ ? recorder_->rowsWritten() : 0; }
    long droppedRecordingSteps() const { return recorder_ ? recorder_->droppedSteps() : 0; }

    haptics::HapticLoop& loop() { return *loop_; }
    haptics::LoopConfig& config() { return config_; }
    /// The active hand's mouse device.
    haptics::VirtualDevice& mouseDevice() { return *mice_[static_cast<std::size_t>(activeHand_)]; }
    bool replaying() const { return replay_ != nullptr; }
    const std::string& replayFile() const { return replayFile_; }
    const Scene& scene() const { return scene_; }
    double materialScale(MaterialKnob knob) const { return materialScale_[static_cast<int>(knob)]; }
    long resets() const { return resets_; }
    /// Why the loop could not start (a device's servo refused), or empty.
    const std::string& loopError() const { return loopError_; }

private:
    void startLoop();
    /// Stops the loop's clock, then the loop, before what they step goes away.
    void stopLoop();
    haptics::Device& deviceOf(int hand);
    /// Sees every step, on the loop's thread: hands it to the recording, if one is on.
    void observeStep(const haptics::StepOutput& step) noexcept;

    Scene scene_;
    haptics::LoopConfig config_;
    std::array<std::unique_ptr<haptics::VirtualDevice>, haptics::kMaxHands> mice_;
    std::unique_ptr<haptics::ReplayDevice> replay_;  // in the first hand
    std::array<std::unique_ptr<haptics::Device>, haptics::kMaxHands> hardware_;
    std::string replayFile_;
    std::unique_ptr<cutting::CutModel> organ_;
    std::unique_ptr<haptics::HapticLoop> loop_;
    std::unique_ptr<haptics::RealTimeScheduler> clock_;  // steps loop_; stopped before it goes (stopLoop)
    std::string loopError_;
    int handCount_ = 1, activeHand_ = 0;
    std::array<std::size_t, haptics::kMaxHands> tool_{0, 0};
    std::array<double, haptics::kMaxHands> threshold_{1e9, 1e9};
    std::array<std::optional<SceneDevice>, haptics::kMaxHands> handSettings_{};
    std::array<double, kMaterialKnobs> materialScale_{1, 1, 1, 1, 1};
    long resets_ = 0;
    // The recording: the writer is the UI thread's; the loop's thread sees it through recording_.
    std::unique_ptr<haptics::StepLogWriter> recorder_;
    std::string recordingFile_;
    std::atomic<haptics::StepLogWriter*> recording_{nullptr};
    std::atomic<int> recordingHand_{0};
    std::atomic<int> recordedTool_{0};    // the recorded hand's tool: a session's tool column
    std::atomic<int> recordingClock_{0};  // what the next observed step sets the clock by (observeStep)
    std::atomic<long> observedSteps_{0};
    double recordingOffset_s_ = 0, lastRecorded_s_ = 0;  // the loop's thread's
};

}  // namespace hapticut::scene
