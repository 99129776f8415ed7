// Vertex array, vertex and index buffers for one mesh.
#include "render/gpu_mesh.h"

#include <epoxy/gl.h>

#include <cmath>

#include "hapticut/mesh/vertex_faces.h"

namespace hapticut::render {

GpuMesh::GpuMesh() {
    glGenVertexArrays(1, &vao_);
    glGenBuffers(1, &vbo_);
    glGenBuffers(1, &ebo_);
    glBindVertexArray(vao_);
    glBindBuffer(GL_ARRAY_BUFFER, vbo_);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, ebo_);
    const GLsizei stride = kFloatsPerVertex * sizeof(float);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<void*>(0));
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<void*>(3 * sizeof(float)));
    glEnableVertexAttribArray(2);
    glVertexAttribPointer(2, 2, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<void*>(6 * sizeof(float)));
    glEnableVertexAttribArray(3);
    glVertexAttribPointer(3, 1, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<void*>(8 * sizeof(float)));
    glBindVertexArray(0);
}

GpuMesh::~GpuMesh() {
    glDeleteBuffers(1, &ebo_);
    glDeleteBuffers(1, &vbo_);
    glDeleteVertexArrays(1, &vao_);
}

void GpuMesh::uploadVertices(std::span<const float> vertices) {
    glBindBuffer(GL_ARRAY_BUFFER, vbo_);
    const std::size_t bytes = vertices.size_bytes();
    if (bytes > vertexCapacity_) {
        // Headroom, so a growing (cut) organ does not reallocate every frame.
        vertexCapacity_ = bytes + bytes / 4;
        glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(vertexCapacity_), nullptr, GL_DYNAMIC_DRAW);
    }
    glBufferSubData(GL_ARRAY_BUFFER, 0, static_cast<GLsizeiptr>(bytes), vertices.data());
}

void GpuMesh::upload(std::span<const float> vertices, std::span<const std::uint32_t> indices) {
    uploadVertices(vertices);
    glBindVertexArray(vao_);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, ebo_);
    const std::size_t bytes = indices.size_bytes();
    if (bytes > indexCapacity_) {
        indexCapacity_ = bytes + bytes / 4;
        glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(indexCapacity_), nullptr, GL_DYNAMIC_DRAW);
    }
    glBufferSubData(GL_ELEMENT_ARRAY_BUFFER, 0, static_cast<GLsizeiptr>(bytes), indices.data());
    glBindVertexArray(0);
    indexCount_ = static_cast<int>(indices.size());
}

void GpuMesh::draw() const {
    glBindVertexArray(vao_);
    glDrawElements(GL_TRIANGLES, indexCount_, GL_UNSIGNED_INT, nullptr);
    glBindVertexArray(0);
}

void flattenWithCreases(const mesh::SurfaceMesh& m, double creaseAngle_rad, std::vector<float>& vertices,
                        std::vector<std::uint32_t>& indices) {
    const mesh::VertexFaces around = mesh::buildVertexFaces(m.faces, m.positions.size());
    std::vector<Vec3> faceNormal(m.faces.size());
    for (std::size_t f = 0; f < m.faces.size(); ++f) {
        const auto& [a, b, c] = m.faces[f];
        faceNormal[f] = (m.positions[b] - m.positions[a]).cross(m.positions[c] - m.positions[a]);
    }
    const double cosCrease = std::cos(creaseAngle_rad);
    vertices.clear();
    indices.clear();
    for (std::size_t f = 0; f < m.faces.size(); ++f) {
        const Vec3 own = faceNormal[f].normalized();
        for (int c = 0; c < 3; ++c) {
            const std::uint32_t v = m.faces[f][c];
            Vec3 n = Vec3::Zero();
            for (const std::uint32_t g : around.around[v])
                if (faceNormal[g].normalized().dot(own) >= cosCrease) n += faceNormal[g];
            n = n.norm() > 0 ? Vec3(n.normalized()) : own;
            const Vec2 uv = f < m.uvs.size() ? m.uvs[f][c] : Vec2::Zero();
            for (int i = 0; i < 3; ++i) vertices.push_back(static_cast<float>(m.positions[v][i]));
            for (int i = 0; i < 3; ++i) vertices.push_back(static_cast<float>(n[i]));
            vertices.push_back(static_cast<float>(uv.x()));
            vertices.push_back(static_cast<float>(uv.y()));
            vertices.push_back(0.0f);
            indices.push_back(static_cast<std::uint32_t>(indices.size()));
        }
    }
}

}  // namespace hapticut::render
