// Draws one frame: the shaded organ, the tool at the proxy, the device and proxy markers, the force
// arrow, in mono or stereo, into whatever framebuffer is bound.
#pragma once

#include <array>

#include <memory>
#include <optional>
#include <span>
#include <string>

#include <Eigen/Geometry>

#include "hapticut/mesh/surface_mesh.h"
#include "render/camera.h"
#include "render/stereo.h"

namespace hapticut::render {

/// What is in the scene this frame, independent of where it comes from (the loop's snapshot, a
/// headless run). Spans must stay valid for the draw call only.
struct SceneFrame {
    std::span<const Vec3> organPositions;  // deformed, one per vertex
    std::span<const mesh::Face> faces;     // read when topologyVersion differs from the last frame's
    std::span<const mesh::FaceUvs> uvs;
    std::span<const std::uint8_t> wallFaces;  // per face: 1 for a wound's wall
    long topologyVersion = 0;
    /// Each hand's tool: drawn at its proxy, with the device's marker and the force arrow.
    struct Hand {
        int tool = 0;  // index into the tools given to the renderer; -1: none
        Vec3 proxy_m = Vec3::Zero(), device_m = Vec3::Zero(), force_N = Vec3::Zero();
        bool contact = false;
        /// The device's stylus, when it reports one (DeviceSample::oriented): the tool is drawn turned
        /// so, its blade facing the way it cuts; otherwise its handle points up toward the viewer.
        Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
        bool oriented = false;
    };
    std::array<Hand, 2> hands{};
    int handCount = 1;
    bool showDevice = true;   // the tools, markers and force arrows
    double maxForce_N = 3.3;  // the arrow turns red at this force
};

struct ViewSettings {
    OrbitCamera camera;
    StereoMode stereo = StereoMode::Off;
    double eyeSeparation_m = 0.012, focalLength_m = 0.35;
    bool wireframe = false;
    bool normalMapping = true;
    bool woundWalls = true;            // draw the walls of wounds (CutModel::wallFaces)
    bool quadBufferAvailable = false;  // the bound framebuffer has left and right back buffers
    double forceArrowLength_m_per_N = 0.01;

    /// Looks at the whole organ from the current direction (`zoom` times closer), with the stereo focal
    /// plane at the organ's centre; `aspect` is that of the part of the image it is framed in.
    void frameOrgan(std::span<const Vec3> positions, double zoom = 1, double aspect = 1);
};

class Renderer {
public:
    /// Compiles the shaders and uploads the generated textures; nothing (with `error`) when the GL
    /// context lacks what is needed. `tools` are drawn with their tip at the proxy.
    static std::unique_ptr<Renderer> create(std::span<const mesh::SurfaceMesh> tools, std::string& error,
                                            int textureSize = 512);
    ~Renderer();

    /// Draws into the bound framebuffer's (0, 0, width, height).
    void draw(const SceneFrame& frame, const ViewSettings& view, int width, int height);
    /// Forget the organ's topology, e.g. after the model was reset to a different mesh.
    void invalidateOrgan();
    /// The organ's faces before any cut: boundary edges among them are its own open rims, not the lips
    /// of a wound, and hang no walls. Without this every boundary edge counts as a lip.
    void setOrganRims(std::span<const mesh::Face> uncutFaces);
    /// Adds a tool (tip at the origin, handle along +z); SceneFrame::tool indexes the tools in order.
    void addTool(const mesh::SurfaceMesh& tool);
    std::size_t toolCount() const;

private:
    struct Impl;
    explicit Renderer(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

}  // namespace hapticut::render
