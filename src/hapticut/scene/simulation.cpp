// A live simulation: organ, hands and loop, and the user's changes to them.
#include "hapticut/scene/simulation.h"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <span>
#include <thread>

#include "hapticut/common/assert.h"
#include "hapticut/geometry/aabb.h"
#include "hapticut/mesh/io/mesh_file.h"
#include "hapticut/mesh/io/thesis_format.h"
#include "hapticut/mesh/procedural/tools.h"
#include "hapticut/physics/material.h"
#include "hapticut/scene/open_device.h"

namespace hapticut::scene {

namespace {

// What the next observed step sets a recording's clock by: nothing, a fresh start at 0, or going on
// from the last row after the loop restarted.
constexpr int kKeepClock = 0, kStartClock = 1, kContinueClock = 2;

haptics::LoopCommand::Kind commandFor(MaterialKnob knob) {
    using K = haptics::LoopCommand::Kind;
    switch (knob) {
        case MaterialKnob::Mass: return K::ScaleMass;
        case MaterialKnob::StructuralStiffness: return K::ScaleStructuralStiffness;
        case MaterialKnob::StructuralDamping: return K::ScaleStructuralDamping;
        case MaterialKnob::PositioningStiffness: return K::ScalePositioningStiffness;
        case MaterialKnob::PositioningDamping: return K::ScalePositioningDamping;
    }
    return K::ScaleMass;
}

}  // namespace

Simulation::Simulation(Scene scene) : scene_(std::move(scene)) {
    for (auto& mouse : mice_) {
        mouse = std::make_unique<haptics::VirtualDevice>(scene_.settings.maxForce_N);
        mouse->setFollowTime(0.015);  // about a frame: the cursor's jumps reach the hand as motion
    }
    config_ = scene_.loopConfig();
    // Each hand's threshold is its tool's: the loop gets them per hand, not from config_.
    threshold_.fill(scene_.tools.empty() ? config_.cutThreshold_N : scene_.tools[0].threshold_N);
    resetModel();
}

Simulation::~Simulation() {
    stopLoop();
    if (recorder_) recorder_->finish();  // a recording the window closed on keeps what it has
}

void Simulation::stopLoop() {
    clock_.reset();
    loop_.reset();
}

haptics::Device& Simulation::deviceOf(int hand) {
    const auto h = static_cast<std::size_t>(hand);
    if (hardware_[h]) return *hardware_[h];
    if (hand == 0 && replay_) return *replay_;
    return *mice_[h];
}

void Simulation::startLoop() {
    std::array<haptics::Hand, haptics::kMaxHands> hands{};
    for (int h = 0; h < handCount_; ++h) {
        haptics::Hand& hand = hands[static_cast<std::size_t>(h)];
        hand.device = &deviceOf(h);
        hand.cutThreshold_N = threshold_[static_cast<std::size_t>(h)];
        hand.tipRadius_m = tipRadius(h);
        // A mouse touches only while its button is held: hovering, a view change or a switch of hands
        // moves it anywhere without pressing or cutting.
        hand.touchesOnlyWhileButtonHeld = hand.device == mice_[static_cast<std::size_t>(h)].get();
        if (const auto& s = handSettings_[static_cast<std::size_t>(h)]) applyHandSettings(*s, hand);
    }
    // One or two hands, each with a device, on an organ with faces at a scene's checked rate: the loop
    // can only fail to build if memory runs out, and then nothing here could go on.
    auto created = haptics::HapticLoop::create(
        *organ_, std::span<const haptics::Hand>(hands.data(), static_cast<std::size_t>(handCount_)), config_);
    HAPTICUT_ASSERT(created.has_value());
    loop_ = std::move(created.value());
    loopError_.clear();
    clock_ = std::make_unique<haptics::RealTimeScheduler>(*loop_);
    // A recording goes on through the restart: the new loop's time starts at 0 again. One that has no
    // row yet still starts at 0.
    int recorded = kKeepClock;
    if (recorder_) recordingClock_.compare_exchange_strong(recorded, kContinueClock, std::memory_order_acq_rel);
    if (const auto error = clock_->start(-1, [this](const haptics::StepOutput& s) { observeStep(s); }))
        loopError_ = error->message;
}

std::string Simulation::hapticScheduling() const { return clock_ ? clock_->scheduling() : "not running"; }

void Simulation::observeStep(const haptics::StepOutput& step) noexcept {
    if (haptics::StepLogWriter* recorder = recording_.load(std::memory_order_acquire)) {
        const int clock = recordingClock_.exchange(kKeepClock, std::memory_order_acq_rel);
        if (clock == kStartClock) recordingOffset_s_ = -step.t_s;
        if (clock == kContinueClock) recordingOffset_s_ = lastRecorded_s_ + 1 / loop_->rate_hz() - step.t_s;
        haptics::StepOutput row = step;  // on the stack: nothing allocates here
        row.hands[0] = step.hands[static_cast<std::size_t>(
            std::min(recordingHand_.load(std::memory_order_relaxed), step.handCount - 1))];
        row.hands[0].tool = recordedTool_.load(std::memory_order_relaxed);
        row.handCount = 1;
        row.t_s = step.t_s + recordingOffset_s_;
        lastRecorded_s_ = row.t_s;
        recorder->push(row);
    }
    // Counted after the push: once the count has moved on, no step still holds a recorder it loaded.
    observedSteps_.fetch_add(1, std::memory_order_release);
}

Status Simulation::startRecording(const std::string& file) {
    if (recorder_) stopRecording();
    auto recorder = haptics::StepLogWriter::open({{file, haptics::StepLogColumns::Session}},
                                                 haptics::StepLogWriter::WhenFull::Drop);
    if (!recorder) return recorder.error();
    recorder_ = std::move(*recorder);
    recordingFile_ = file;
    recordingHand_.store(activeHand_, std::memory_order_relaxed);
    recordedTool_.store(static_cast<int>(tool_[static_cast<std::size_t>(activeHand_)]), std::memory_order_relaxed);
    recordingClock_.store(kStartClock, std::memory_order_release);
    recording_.store(recorder_.get(), std::memory_order_release);
    return std::nullopt;
}

std::vector<Error> Simulation::stopRecording() {
    if (!recorder_) return {};
    recording_.store(nullptr, std::memory_order_release);
    // Wait until the loop's thread has finished a step begun before: it no longer holds the recorder.
    if (clock_) {
        const long seen = observedSteps_.load(std::memory_order_acquire);
        const auto giveUp = std::chrono::steady_clock::now() + std::chrono::milliseconds(200);
        while (observedSteps_.load(std::memory_order_acquire) < seen + 2 && std::chrono::steady_clock::now() < giveUp)
            std::this_thread::sleep_for(std::chrono::microseconds(200));
        if (observedSteps_.load(std::memory_order_acquire) < seen + 2) stopLoop(), startLoop();  // a stuck loop
    }
    std::vector<Error> errors = recorder_->finish();
    recorder_.reset();
    return errors;
}

void Simulation::setHandCount(int hands) {
    hands = std::clamp(hands, 1, haptics::kMaxHands);
    if (hands == handCount_) return;
    stopLoop();
    if (hands == 2 && !scene_.tools.empty()) {
        // The second hand takes the next tool, and rests beside the first, in front of the organ
        // (+z, towards the default camera) rather than in it.
        tool_[1] = (tool_[0] + 1) % scene_.tools.size();
        threshold_[1] = scene_.tools[tool_[1]].threshold_N;
        Vec3 rest = mice_[0]->read(0).position_m + Vec3(-0.02, 0, 0);  // the loop is stopped: no other reader
        rest.z() = std::max(rest.z(), geometry::boundsOf(scene_.source.mesh.positions).max.z() + 0.01);
        mice_[1]->setPosition(rest);
    }
    handCount_ = hands;
    activeHand_ = std::min(activeHand_, handCount_ - 1);
    startLoop();
}

void Simulation::setActiveHand(int hand) { activeHand_ = std::clamp(hand, 0, handCount_ - 1); }

std::array<int, haptics::kMaxHands> Simulation::toolsInHands() const {
    std::array<int, haptics::kMaxHands> tools{};
    for (std::size_t h = 0; h < tools.size(); ++h) tools[h] = static_cast<int>(tool_[h]);
    return tools;
}

const haptics::Device* Simulation::hardwareDevice() const {
    return hardware_[static_cast<std::size_t>(activeHand_)].get();
}

bool Simulation::mouseDrives() const {
    return !hardware_[static_cast<std::size_t>(activeHand_)] && !(activeHand_ == 0 && replay_);
}

void Simulation::setHandSettings(int hand, const SceneDevice& settings) {
    handSettings_[static_cast<std::size_t>(std::clamp(hand, 0, haptics::kMaxHands - 1))] = settings;
}

void Simulation::useDevice(std::unique_ptr<haptics::Device> device, int hand) {
    hand = std::clamp(hand, 0, haptics::kMaxHands - 1);
    stopLoop();
    if (hand == 0) replay_.reset();
    hardware_[static_cast<std::size_t>(hand)] = std::move(device);
    handCount_ = std::max(handCount_, hand + 1);
    startLoop();
}

void Simulation::resetModel() {
    stopLoop();  // before the organ it steps goes away
    organ_ = std::make_unique<cutting::CutModel>(scene_.source.mesh, scene_.buildModel());
    startLoop();
    // The user's material settings outlive a reset: apply them to the fresh model.
    for (int k = 0; k < kMaterialKnobs; ++k)
        if (materialScale_[k] != 1)
            loop_->commands().push({commandFor(static_cast<MaterialKnob>(k)), materialScale_[k]});
    ++resets_;
}

void Simulation::restartLoop() {
    stopLoop();
    startLoop();
}

void Simulation::setTool(std::size_t index) {
    if (index >= scene_.tools.size()) return;
    tool_[static_cast<std::size_t>(activeHand_)] = index;
    if (recorder_ && activeHand_ == recordingHand_.load(std::memory_order_relaxed))
        recordedTool_.store(static_cast<int>(index), std::memory_order_relaxed);
    setCutThreshold(scene_.tools[index].threshold_N);
    loop_->commands().push({haptics::LoopCommand::Kind::SetTipRadius, scene_.tools[index].tipRadius_m, activeHand_});
}

double Simulation::tipRadius(int hand) const {
    const std::size_t tool = tool_[static_cast<std::size_t>(hand)];
    return tool < scene_.tools.size() ? scene_.tools[tool].tipRadius_m : config_.tipRadius_m;
}

void Simulation::setCutThreshold(double threshold_N) {
    threshold_[static_cast<std::size_t>(activeHand_)] = threshold_N;
    loop_->commands().push({haptics::LoopCommand::Kind::SetCutThreshold, threshold_N, activeHand_});
}

Status Simulation::replay(const std::string& file) {
    auto trajectory = haptics::readTrajectory(file);
    if (!trajectory) return trajectory.error();
    stopLoop();
    replay_ = std::make_unique<haptics::ReplayDevice>(std::move(*trajectory), scene_.settings.maxForce_N);
    hardware_[0].reset();
    replayFile_ = file;
    startLoop();
    return std::nullopt;
}

void Simulation::useMouse() {
    const auto h = static_cast<std::size_t>(activeHand_);
    if (!(activeHand_ == 0 && replay_) && !hardware_[h]) return;
    stopLoop();
    if (activeHand_ == 0) {
        replay_.reset();
        replayFile_.clear();
    }
    hardware_[h].reset();
    startLoop();
}

Status Simulation::loadModel(const std::string& model) {
    SceneRequest request;
    request.overrides.model = model;
    auto loaded = loadScene(request);
    if (!loaded) return loaded.error();
    scene_.source = std::move(loaded->source);
    resetModel();
    return std::nullopt;
}

Status Simulation::loadTool(const std::string& file) {
    auto tool = mesh::io::readToolFile(file);
    if (!tool) return tool.error();
    scene_.tools.push_back({std::filesystem::path(file).stem().string(), std::move(tool->mesh), tool->threshold_N,
                            mesh::procedural::tipRadiusForThreshold_m(tool->threshold_N)});
    setTool(scene_.tools.size() - 1);
    return std::nullopt;
}

void Simulation::setMaterialScale(MaterialKnob knob, double scale) {
    double& current = materialScale_[static_cast<int>(knob)];
    if (!(scale > 0) || scale == current) return;
    loop_->commands().push({commandFor(knob), scale / current});
    current = scale;
}

WriteStatus Simulation::exportMesh(const std::string& file, const haptics::Snapshot& snapshot) const {
    mesh::SurfaceMesh m;
    m.positions = snapshot.positions;
    m.faces = snapshot.faces;
    m.uvs = snapshot.uvs;
    m.uvs.resize(m.faces.size());
    m.edges = mesh::edgesOfFaces(m.faces);
    mesh::computeFaceNormals(m);
    return mesh::io::saveMesh(file, m, scene_.source.physics);
}

}  // namespace hapticut::scene
