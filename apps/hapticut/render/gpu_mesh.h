// A triangle mesh on the GPU in the renderer's one vertex layout: position, normal, uv, wound (9 floats).
#pragma once

#include <cstdint>
#include <span>

#include "hapticut/mesh/surface_mesh.h"
#include "render/vertex_layout.h"

namespace hapticut::render {

class GpuMesh {
public:
    GpuMesh();
    ~GpuMesh();
    GpuMesh(const GpuMesh&) = delete;
    GpuMesh& operator=(const GpuMesh&) = delete;

    /// Replaces the vertices (kFloatsPerVertex floats each) and, if given, the triangle indices. Buffers grow as
    /// needed.
    void upload(std::span<const float> vertices, std::span<const std::uint32_t> indices);
    void uploadVertices(std::span<const float> vertices);
    void draw() const;

private:
    unsigned vao_ = 0, vbo_ = 0, ebo_ = 0;
    std::size_t vertexCapacity_ = 0, indexCapacity_ = 0;
    int indexCount_ = 0;
};

/// Flattens a static mesh (a tool, a marker) to the renderer's layout. Corners get the mean normal of
/// the faces round their vertex that bend less than `creaseAngle_rad` from their own face, so round
/// handles look round and the blade's edges stay sharp.
void flattenWithCreases(const mesh::SurfaceMesh& mesh, double creaseAngle_rad, std::vector<float>& vertices,
                        std::vector<std::uint32_t>& indices);

}  // namespace hapticut::render
