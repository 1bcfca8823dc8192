// A mesh on the GPU (mesh_buffers.h).
#include "gpu/mesh_buffers.h"

#include "gpu/shaders/common/bindings.h"

#include <vector>

namespace standin::gpu {

static void attach_attribute(GLuint vao, GLuint attribute, GLuint buffer, int components, std::size_t stride)
{
    glVertexArrayVertexBuffer(vao, attribute, buffer, 0, GLsizei(stride));
    glVertexArrayAttribFormat(vao, attribute, components, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(vao, attribute, attribute);
    glEnableVertexArrayAttrib(vao, attribute);
}

MeshBuffers MeshBuffers::upload(const Mesh& mesh, std::span<const std::uint32_t> indices)
{
    MeshBuffers b;
    const std::size_t vertices = mesh.vertex_count();
    b.positions_ = make_buffer(mesh.positions);
    b.normals_ = make_buffer(mesh.normals);
    std::vector<glm::vec4> colors = mesh.colors;
    if (colors.size() != vertices) colors.assign(vertices, glm::vec4(0.8f, 0.8f, 0.8f, 1.0f));
    b.colors_ = make_buffer(colors);
    std::vector<glm::vec2> uvs = mesh.uvs;
    if (uvs.size() != vertices) uvs.assign(vertices, glm::vec2(0.0f));
    b.uvs_ = make_buffer(uvs);
    std::span<const std::uint32_t> order = indices.empty() ? std::span<const std::uint32_t>(mesh.indices) : indices;
    b.indices_ = make_buffer(order.data(), order.size_bytes());
    b.index_count_ = GLsizei(order.size());
    b.vertex_array_ = make_vertex_array();
    GLuint vao = b.vertex_array_.get();
    attach_attribute(vao, ATTRIB_POSITION, b.positions_.get(), 3, sizeof(glm::vec3));
    attach_attribute(vao, ATTRIB_NORMAL, b.normals_.get(), 3, sizeof(glm::vec3));
    attach_attribute(vao, ATTRIB_COLOR, b.colors_.get(), 4, sizeof(glm::vec4));
    attach_attribute(vao, ATTRIB_UV, b.uvs_.get(), 2, sizeof(glm::vec2));
    glVertexArrayElementBuffer(vao, b.indices_.get());
    return b;
}

} // namespace standin::gpu
