// The frame: organ, tool, markers and force arrow, once per eye.
#include "render/renderer.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <vector>

#include "hapticut/geometry/aabb.h"
#include "hapticut/mesh/procedural/primitives.h"
#include "render/gpu_mesh.h"
#include "render/organ_surface.h"
#include "render/shader.h"
#include "render/shaders.h"
#include "render/textures.h"

namespace hapticut::render {

namespace {

Eigen::Matrix4f toFloat(const Eigen::Matrix4d& m) { return m.cast<float>(); }
Eigen::Vector3f toFloat(const Vec3& v) { return v.cast<float>(); }

GLuint uploadTexture2D(const Image& image) {
    GLuint id = 0;
    glGenTextures(1, &id);
    glBindTexture(GL_TEXTURE_2D, id);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, image.width, image.height, 0, GL_RGBA, GL_UNSIGNED_BYTE,
                 image.rgba.data());
    glGenerateMipmap(GL_TEXTURE_2D);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
    return id;
}

GLuint uploadCubeMap(const std::array<Image, 6>& faces) {
    GLuint id = 0;
    glGenTextures(1, &id);
    glBindTexture(GL_TEXTURE_CUBE_MAP, id);
    for (int f = 0; f < 6; ++f)
        glTexImage2D(static_cast<GLenum>(GL_TEXTURE_CUBE_MAP_POSITIVE_X + f), 0, GL_RGBA8, faces[f].width,
                     faces[f].height, 0, GL_RGBA, GL_UNSIGNED_BYTE, faces[f].rgba.data());
    glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    for (GLenum wrap : {GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T, GL_TEXTURE_WRAP_R})
        glTexParameteri(GL_TEXTURE_CUBE_MAP, wrap, GL_CLAMP_TO_EDGE);
    return id;
}

/// A closed cone, base at z = 0 with radius 1, apex at z = 1.
mesh::SurfaceMesh makeCone(int segments) {
    mesh::SurfaceMesh m;
    m.positions.push_back(Vec3(0, 0, 1));
    m.positions.push_back(Vec3(0, 0, 0));
    for (int i = 0; i < segments; ++i) {
        const double a = 2 * M_PI * i / segments;
        m.positions.push_back(Vec3(std::cos(a), std::sin(a), 0));
    }
    for (std::uint32_t i = 0; i < static_cast<std::uint32_t>(segments); ++i) {
        const std::uint32_t a = 2 + i, b = 2 + (i + 1) % static_cast<std::uint32_t>(segments);
        m.faces.push_back({a, b, 0});
        m.faces.push_back({b, a, 1});
    }
    return m;
}

std::unique_ptr<GpuMesh> uploadStatic(const mesh::SurfaceMesh& m, double creaseAngle_rad) {
    std::vector<float> vertices;
    std::vector<std::uint32_t> indices;
    flattenWithCreases(m, creaseAngle_rad, vertices, indices);
    auto gpu = std::make_unique<GpuMesh>();
    gpu->upload(vertices, indices);
    return gpu;
}

Eigen::Matrix4d placement(const Vec3& at, const Eigen::Quaterniond& rotation, const Vec3& scale) {
    Eigen::Affine3d t = Eigen::Translation3d(at) * rotation * Eigen::Scaling(scale);
    return t.matrix();
}

}  // namespace

struct Renderer::Impl {
    ShaderProgram organ, metal, flat;
    GLuint diffuse = 0, detail = 0, environment = 0;
    OrganSurface surface;
    bool wallsShown = true;
    GpuMesh organMesh;
    long topologyVersion = LONG_MIN;
    std::vector<std::unique_ptr<GpuMesh>> tools;
    std::unique_ptr<GpuMesh> sphere, shaft, head;

    Impl(ShaderProgram o, ShaderProgram m, ShaderProgram f)
        : organ(std::move(o)), metal(std::move(m)), flat(std::move(f)) {}

    void setLights(ShaderProgram& p) {
        p.set("uLightDirection[0]", Eigen::Vector3f(-0.45f, 0.6f, 0.65f));
        p.set("uLightDirection[1]", Eigen::Vector3f(0.7f, -0.1f, 0.5f));
        p.set("uLightColour[0]", Eigen::Vector3f(0.95f, 0.92f, 0.88f));
        p.set("uLightColour[1]", Eigen::Vector3f(0.28f, 0.28f, 0.33f));
        p.set("uAmbient", Eigen::Vector3f(0.16f, 0.15f, 0.16f));
    }

    void setCamera(ShaderProgram& p, const Eigen::Matrix4d& view, const Eigen::Matrix4d& projection, bool monochrome) {
        p.use();
        p.set("uView", toFloat(view));
        p.set("uProjection", toFloat(projection));
        p.set("uMonochrome", monochrome ? 1 : 0);
    }

    void drawFlat(GpuMesh& m, const Eigen::Matrix4d& model, const Eigen::Vector4f& colour) {
        flat.use();
        flat.set("uModel", toFloat(model));
        flat.set("uColour", colour);
        m.draw();
    }

    void drawEye(const SceneFrame& frame, const ViewSettings& settings, Eye eye, int x, int y, int w, int h,
                 bool monochrome) {
        glViewport(x, y, w, h);
        const OrbitCamera& camera = settings.camera;
        Lens lens;
        lens.fovY_rad = camera.fovY_rad;
        lens.aspect = static_cast<double>(w) / std::max(h, 1);
        lens.near_m = std::max(camera.distance_m * 0.05, 1e-4);
        lens.far_m = camera.distance_m * 20;
        lens.eyeSeparation_m = settings.eyeSeparation_m;
        lens.focalLength_m = settings.focalLength_m;
        lens.centreX_ndc = camera.centreX_ndc;
        const Frustum f = eyeFrustum(lens, eye);
        const Eigen::Matrix4d projection = projectionMatrix(f), view = eyeView(camera.view(), f);
        for (ShaderProgram* p : {&organ, &metal, &flat}) setCamera(*p, view, projection, monochrome);

        // The organ: shaded, or its edges (R18).
        if (settings.wireframe) {
            glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
            drawFlat(organMesh, Eigen::Matrix4d::Identity(), Eigen::Vector4f(1.0f, 0.55f, 0.5f, 1.0f));
            glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
        } else {
            organ.use();
            organ.set("uModel", Eigen::Matrix4f::Identity().eval());
            organ.set("uBumpHeight_m", settings.normalMapping ? 0.0006f : 0.0f);
            glActiveTexture(GL_TEXTURE0);
            glBindTexture(GL_TEXTURE_2D, diffuse);
            glActiveTexture(GL_TEXTURE1);
            glBindTexture(GL_TEXTURE_2D, detail);
            organMesh.draw();
        }
        if (!frame.showDevice) return;

        // Each tool stands on its proxy, turned as its device's stylus is, or else with its handle up and
        // towards the viewer, as a hand would hold it.
        const Eigen::Quaterniond upright =
            Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), toolHandleDirection(camera));
        const double r = std::max(camera.distance_m * 0.004, 2e-4);
        const int handCount = std::clamp(frame.handCount, 0, static_cast<int>(frame.hands.size()));
        for (int i = 0; i < handCount; ++i) {
            const SceneFrame::Hand& hand = frame.hands[static_cast<std::size_t>(i)];
            if (hand.tool >= 0 && hand.tool < static_cast<int>(tools.size())) {
                metal.use();
                metal.set("uModel",
                          toFloat(placement(hand.proxy_m, hand.oriented ? hand.orientation : upright, Vec3::Ones())));
                metal.set("uCameraPosition", toFloat(Vec3(camera.eye())));
                glActiveTexture(GL_TEXTURE2);
                glBindTexture(GL_TEXTURE_CUBE_MAP, environment);
                tools[static_cast<std::size_t>(hand.tool)]->draw();
            }
            drawFlat(*sphere, placement(hand.proxy_m, Eigen::Quaterniond::Identity(), Vec3::Constant(r)),
                     Eigen::Vector4f(1.0f, 0.85f, 0.2f, 1.0f));
            // The force on the hand: an arrow from the proxy, green to red as it nears the device's maximum.
            const double magnitude = hand.force_N.norm();
            if (magnitude > 1e-3) {
                const double length = magnitude * settings.forceArrowLength_m_per_N;
                const Eigen::Quaterniond along =
                    Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), hand.force_N / magnitude);
                const float t = static_cast<float>(std::clamp(magnitude / frame.maxForce_N, 0.0, 1.0));
                const Eigen::Vector4f colour(0.2f + 0.8f * t, 0.9f - 0.7f * t, 0.2f, 1.0f);
                const double headLength = std::min(length * 0.35, r * 4);
                drawFlat(*shaft, placement(hand.proxy_m, along, Vec3(r * 0.45, r * 0.45, length - headLength)), colour);
                drawFlat(*head,
                         placement(hand.proxy_m + hand.force_N / magnitude * (length - headLength), along,
                                   Vec3(r * 1.3, r * 1.3, headLength)),
                         colour);
            }
        }
        // Where the hands really are, seen through the tissue.
        glDisable(GL_DEPTH_TEST);
        glEnable(GL_BLEND);
        glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
        for (int i = 0; i < handCount; ++i) {
            const SceneFrame::Hand& hand = frame.hands[static_cast<std::size_t>(i)];
            const Eigen::Vector4f cyan(0.3f, 0.8f, 1.0f, 0.55f);
            drawFlat(*sphere, placement(hand.device_m, Eigen::Quaterniond::Identity(), Vec3::Constant(r * 0.8)), cyan);
            // The coupling spring the hand feels, from the tool on the surface to the device inside: without
            // it the device's marker reads as a ball come loose from the tool.
            const Vec3 spring = hand.device_m - hand.proxy_m;
            if (spring.norm() > r)
                drawFlat(*shaft,
                         placement(hand.proxy_m, Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), spring),
                                   Vec3(r * 0.2, r * 0.2, spring.norm())),
                         cyan);
        }
        glDisable(GL_BLEND);
        glEnable(GL_DEPTH_TEST);
    }
};

void ViewSettings::frameOrgan(std::span<const Vec3> positions, double zoom, double aspect) {
    const geometry::Aabb box = geometry::boundsOf(positions);
    camera.frame(box.center(), 0.5 * box.extent().norm(), aspect);
    camera.distance_m /= zoom;
    focalLength_m = camera.distance_m;
    eyeSeparation_m = camera.distance_m / 30;
}

std::unique_ptr<Renderer> Renderer::create(std::span<const mesh::SurfaceMesh> tools, std::string& error,
                                           int textureSize) {
    const std::string header = std::string("#version 330 core\n") + shaders::kLightingCommon;
    auto organ = ShaderProgram::build("organ", shaders::kVertex, (header + shaders::kOrganFragment).c_str(), error);
    if (!organ) return nullptr;
    auto metal = ShaderProgram::build("tool", shaders::kVertex, (header + shaders::kMetalFragment).c_str(), error);
    if (!metal) return nullptr;
    auto flat = ShaderProgram::build("marker", shaders::kVertex, (header + shaders::kFlatFragment).c_str(), error);
    if (!flat) return nullptr;
    auto impl = std::make_unique<Impl>(std::move(*organ), std::move(*metal), std::move(*flat));

    const OrganTextures textures = makeOrganTextures(textureSize);
    impl->diffuse = uploadTexture2D(textures.diffuse);
    impl->detail = uploadTexture2D(textures.detail);
    impl->environment = uploadCubeMap(makeStudioEnvironment());
    impl->organ.use();
    impl->setLights(impl->organ);
    impl->organ.set("uDiffuse", 0);
    impl->organ.set("uDetail", 1);
    impl->organ.set("uUvScale", 1.0f);
    impl->organ.set("uShininess", 40.0f);
    impl->organ.set("uInsideColour", Eigen::Vector3f(0.55f, 0.08f, 0.10f));
    impl->metal.use();
    impl->setLights(impl->metal);
    impl->metal.set("uEnvironment", 2);
    impl->metal.set("uShininess", 90.0f);
    impl->metal.set("uBaseColour", Eigen::Vector3f(0.78f, 0.80f, 0.84f));
    impl->metal.set("uReflectivity", 0.55f);
    impl->flat.use();
    impl->flat.set("uShininess", 1.0f);

    for (const mesh::SurfaceMesh& tool : tools) impl->tools.push_back(uploadStatic(tool, 0.6));
    impl->sphere = uploadStatic(mesh::procedural::makeSphere(Vec3::Zero(), 1.0, 16, 10), M_PI);
    impl->shaft = uploadStatic(mesh::procedural::makeCylinder(Vec3::Zero(), Vec3::UnitZ(), 1.0, 1.0, 12), 0.6);
    impl->head = uploadStatic(makeCone(16), 0.6);
    if (const GLenum e = glGetError(); e != GL_NO_ERROR) {
        error = "OpenGL error " + std::to_string(e) + " while setting up the renderer";
        return nullptr;
    }
    return std::unique_ptr<Renderer>(new Renderer(std::move(impl)));
}

Renderer::Renderer(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

Renderer::~Renderer() {
    const GLuint textures[] = {impl_->diffuse, impl_->detail, impl_->environment};
    glDeleteTextures(3, textures);
}

void Renderer::invalidateOrgan() { impl_->topologyVersion = LONG_MIN; }

void Renderer::setOrganRims(std::span<const mesh::Face> uncutFaces) {
    impl_->surface.setRims(uncutFaces);
    invalidateOrgan();
}

void Renderer::addTool(const mesh::SurfaceMesh& tool) { impl_->tools.push_back(uploadStatic(tool, 0.6)); }

std::size_t Renderer::toolCount() const { return impl_->tools.size(); }

void Renderer::draw(const SceneFrame& frame, const ViewSettings& view, int width, int height) {
    Impl& m = *impl_;
    if (frame.topologyVersion != m.topologyVersion || view.woundWalls != m.wallsShown) {
        m.surface.setWallsShown(view.woundWalls);
        m.wallsShown = view.woundWalls;
        m.surface.setTopology(frame.faces, frame.uvs, frame.wallFaces, frame.organPositions.size());
        m.topologyVersion = frame.topologyVersion;
        m.surface.update(frame.organPositions);
        m.organMesh.upload(m.surface.vertices(), m.surface.indices());
    } else {
        m.surface.update(frame.organPositions);
        m.organMesh.uploadVertices(m.surface.vertices());
    }

    glEnable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);  // the inside of a wound must show
    glEnable(GL_MULTISAMPLE);
    const bool anaglyph =
        view.stereo == StereoMode::Anaglyph || (view.stereo == StereoMode::QuadBuffer && !view.quadBufferAvailable);
    if (anaglyph)
        glClearColor(0.02f, 0.02f, 0.02f, 1.0f);
    else
        glClearColor(0.10f, 0.11f, 0.14f, 1.0f);
    glViewport(0, 0, width, height);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);

    if (view.stereo == StereoMode::Off) {
        m.drawEye(frame, view, Eye::Centre, 0, 0, width, height, false);
    } else if (view.stereo == StereoMode::SideBySide) {
        const int half = width / 2;
        m.drawEye(frame, view, Eye::Left, 0, 0, half, height, false);
        m.drawEye(frame, view, Eye::Right, half, 0, width - half, height, false);
    } else if (anaglyph) {
        // Red filter over the left eye, cyan over the right.
        glColorMask(GL_TRUE, GL_FALSE, GL_FALSE, GL_TRUE);
        m.drawEye(frame, view, Eye::Left, 0, 0, width, height, true);
        glClear(GL_DEPTH_BUFFER_BIT);
        glColorMask(GL_FALSE, GL_TRUE, GL_TRUE, GL_TRUE);
        m.drawEye(frame, view, Eye::Right, 0, 0, width, height, true);
        glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    } else {
        glDrawBuffer(GL_BACK_LEFT);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        m.drawEye(frame, view, Eye::Left, 0, 0, width, height, false);
        glDrawBuffer(GL_BACK_RIGHT);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        m.drawEye(frame, view, Eye::Right, 0, 0, width, height, false);
        glDrawBuffer(GL_BACK);
    }
    glViewport(0, 0, width, height);
}

}  // namespace hapticut::render
