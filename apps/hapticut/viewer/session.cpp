// The viewer's simulation: organ, device and loop, and the user's changes to them.
#include "viewer/session.h"

#include <algorithm>
#include <filesystem>

#include "hapticut/mesh/io/mesh_file.h"
#include "hapticut/mesh/io/thesis_format.h"
#include "hapticut/physics/material.h"

namespace hapticut::viewer {

namespace {

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

Session::Session(app::LoadedScene scene) : scene_(std::move(scene)), mouse_(scene_.settings.maxForce_N) {
    mouse_.setFollowTime(0.015);  // about a frame: the cursor's jumps reach the hand as motion
    config_.scheme = scene_.settings.scheme;
    config_.rate_hz = scene_.settings.rate_hz;
    config_.couplingStiffness_N_per_m = scene_.settings.couplingStiffness_N_per_m;
    config_.couplingDamping_Ns_per_m = scene_.settings.couplingDamping_Ns_per_m;
    config_.activeRegion = scene_.settings.activeRegion;
    config_.proxy.staticFriction = scene_.settings.staticFriction;
    config_.proxy.dynamicFriction = scene_.settings.dynamicFriction;
    if (!scene_.tools.empty()) config_.cutThreshold_N = scene_.tools[0].threshold_N;
    resetModel();
}

Session::~Session() { loop_.reset(); }

void Session::startLoop() {
    haptics::Device& device = hardware_ ? *hardware_ : replay_ ? static_cast<haptics::Device&>(*replay_) : mouse_;
    loop_ = std::make_unique<haptics::HapticLoop>(*organ_, device, config_);
    loopError_.clear();
    loop_->start(-1, {}, loopError_);
}

void Session::useDevice(std::unique_ptr<haptics::Device> device) {
    loop_.reset();
    replay_.reset();
    hardware_ = std::move(device);
    startLoop();
}

void Session::resetModel() {
    loop_.reset();  // stops the thread before the organ it steps goes away
    organ_ = std::make_unique<cutting::CutModel>(scene_.source.mesh, scene_.buildModel());
    startLoop();
    // The user's material settings outlive a reset: apply them to the fresh model.
    for (int k = 0; k < kMaterialKnobs; ++k)
        if (materialScale_[k] != 1) loop_->commands().push({commandFor(static_cast<MaterialKnob>(k)), materialScale_[k]});
    ++resets_;
}

void Session::restartLoop() {
    loop_.reset();
    startLoop();
}

void Session::setTool(std::size_t index) {
    if (index >= scene_.tools.size()) return;
    tool_ = index;
    config_.cutThreshold_N = scene_.tools[index].threshold_N;
    loop_->commands().push({haptics::LoopCommand::Kind::SetCutThreshold, config_.cutThreshold_N});
}

bool Session::replay(const std::string& file, std::string& error) {
    auto trajectory = haptics::readTrajectory(file);
    if (!trajectory) {
        error = trajectory.error().toString();
        return false;
    }
    loop_.reset();
    replay_ = std::make_unique<haptics::ReplayDevice>(std::move(*trajectory), scene_.settings.maxForce_N);
    replayFile_ = file;
    startLoop();
    return true;
}

void Session::useMouse() {
    if (!replay_ && !hardware_) return;
    loop_.reset();
    replay_.reset();
    hardware_.reset();
    replayFile_.clear();
    startLoop();
}

bool Session::loadModel(const std::string& model, std::string& error) {
    app::SceneChoice choice;
    choice.model = model;
    auto loaded = app::loadScene(choice);
    if (!loaded) {
        error = "could not load " + model + " (the terminal says why)";
        return false;
    }
    scene_.source = std::move(loaded->source);
    resetModel();
    return true;
}

bool Session::loadTool(const std::string& file, std::string& error) {
    auto tool = mesh::io::readToolFile(file);
    if (!tool) {
        error = tool.error().toString();
        return false;
    }
    scene_.tools.push_back({std::filesystem::path(file).stem().string(), std::move(tool->mesh), tool->threshold_N});
    setTool(scene_.tools.size() - 1);
    return true;
}

void Session::setMaterialScale(MaterialKnob knob, double scale) {
    double& current = materialScale_[static_cast<int>(knob)];
    if (!(scale > 0) || scale == current) return;
    loop_->commands().push({commandFor(knob), scale / current});
    current = scale;
}

std::optional<std::string> Session::exportMesh(const std::string& file, const haptics::Snapshot& snapshot) const {
    mesh::SurfaceMesh m;
    m.positions = snapshot.positions;
    m.faces = snapshot.faces;
    m.uvs = snapshot.uvs;
    m.uvs.resize(m.faces.size());
    m.edges = mesh::edgesOfFaces(m.faces);
    mesh::computeFaceNormals(m);
    if (const auto error = mesh::io::saveMesh(file, m, scene_.source.physics)) return error->toString();
    return std::nullopt;
}

}  // namespace hapticut::viewer
