// Small models and meshes shared by the tests.
#include "test_support.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <random>
#include <sstream>

#include "hapticut/geometry/random_vec.h"

namespace hapticut::test {

std::string slurp(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
}

ScratchDir::ScratchDir() {
    const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
    const std::string name = test ? std::string(test->test_suite_name()) + "-" + test->name() : std::string("no-test");
    path_ = std::filesystem::temp_directory_path() / ("hapticut-" + name + "-" + std::to_string(::getpid()));
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
}

ScratchDir::~ScratchDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
}

physics::MassSpringModel oscillator(double m, double k, double c, double x0) {
    physics::MassSpringModel model;
    physics::Nodes& n = model.nodes;
    n.position = {Vec3(x0, 0, 0)};
    n.velocity = {Vec3::Zero()};
    n.restPosition = {Vec3::Zero()};
    n.externalForce = {Vec3::Zero()};
    n.mass = {m};
    n.inverseMass = {1 / m};
    n.anchorStiffness = {k};
    n.anchorDamping = {c};
    model.snapDistance_m = 0;
    model.snapSpeed_m_per_s = 0;
    return model;
}

void pressFrontWithTool(physics::MassSpringModel& model, const mesh::SurfaceMesh& mesh, int step) {
    std::uint32_t front = 0;
    for (std::uint32_t f = 0; f < mesh.faces.size(); ++f)
        if (mesh.normals[f].z() > mesh.normals[front].z()) front = f;
    physics::PointSpring& tool = model.tools[0];
    tool.active = step < 300;
    tool.touchTriangle(mesh.faces[front], Vec3(0.5, 0.3, 0.2));
    const Vec3 surface = tool.heldPoint(mesh.positions);
    tool.anchor_m = surface - 0.003 * std::min(1.0, step / 50.0) * mesh.normals[front];
    tool.stiffness_N_per_m = 400;
    tool.maxForce_N = 3.3;
    tool.normal = mesh.normals[front];
}

mesh::SurfaceMesh tetrahedron() {
    mesh::SurfaceMesh m;
    m.positions = {Vec3(1, 1, 1), Vec3(1, -1, -1), Vec3(-1, 1, -1), Vec3(-1, -1, 1)};
    m.faces = {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}};
    mesh::completeMesh(m);
    return m;
}

double meanEdgeOf(const mesh::SurfaceMesh& m) {
    double edges = 0;
    for (const mesh::Face& f : m.faces)
        for (int k = 0; k < 3; ++k) edges += (m.positions[f[(k + 1) % 3]] - m.positions[f[k]]).norm();
    return edges / (3.0 * static_cast<double>(m.faces.size()));
}

mesh::SurfaceMesh jitteredBy(const mesh::SurfaceMesh& smooth, double amount, unsigned seed) {
    mesh::SurfaceMesh jittered = smooth;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> unit(-1, 1);
    for (Vec3& x : jittered.positions) x += amount * randomVec3(unit, rng);
    return jittered;
}

Vec3 wobble(std::size_t i, double size) {
    const auto x = static_cast<double>(i);
    return size * Vec3(std::sin(1.7 * x + 0.3), std::cos(0.37 * x), std::sin(0.113 * x + 1.1));
}

double signedVolume(const mesh::SurfaceMesh& mesh) {
    double v = 0;
    for (const mesh::Face& f : mesh.faces)
        v += mesh.positions[f[0]].dot(mesh.positions[f[1]].cross(mesh.positions[f[2]])) / 6;
    return v;
}

}  // namespace hapticut::test
