// A mesh on the GPU: positions, normals, colours and UVs at the ATTRIB_* locations of
// shaders/common/bindings.h, and an index buffer, in one vertex array. The ground truth, the view
// atlas' normal capture and the enhanced billboards' coarse mesh each draw one.
#pragma once

#include "gpu/gl.h"

#include <standin/mesh.h>

#include <cstdint>
#include <span>

namespace standin::gpu {

class MeshBuffers {
public:
    // Uploads `mesh`. `indices` replaces mesh.indices when given (a reordering, e.g. by material);
    // colours missing from the mesh are a mid grey, UVs missing are zero. Needs a current context.
    static MeshBuffers upload(const Mesh& mesh, std::span<const std::uint32_t> indices = {});
    // Binds the vertex array (draw with glDrawElements*, GL_UNSIGNED_INT).
    void bind() const { glBindVertexArray(vertex_array_.get()); }
    GLsizei index_count() const { return index_count_; }
    explicit operator bool() const { return bool(vertex_array_); }

private:
    Buffer positions_, normals_, colors_, uvs_, indices_;
    VertexArray vertex_array_;
    GLsizei index_count_ = 0;
};

} // namespace standin::gpu
