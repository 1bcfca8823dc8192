// A thin RAII layer over OpenGL 4.5 objects (direct state access throughout), plus programs built
// from the embedded GLSL sources. Only this layer and the renderers include GL headers.
#pragma once

#include <standin/status.h>

#include <epoxy/gl.h>
#include <glm/glm.hpp>

#include <string>
#include <utility>
#include <vector>

namespace standin::gpu {

// "OpenGL error N" for a status message; GL_OUT_OF_MEMORY also says what to do about it (a
// package's maps or pages, or an image, larger than the device, or llvmpipe, will hold).
std::string gl_error_text(GLenum error);

// Owns one GL name; Deleter is a function deleting one name.
template <void (*Delete)(GLuint)>
class GlHandle {
public:
    GlHandle() = default;
    explicit GlHandle(GLuint name) : name_(name) {}
    GlHandle(GlHandle&& other) noexcept : name_(std::exchange(other.name_, 0)) {}
    GlHandle& operator=(GlHandle&& other) noexcept
    {
        if (this != &other) {
            reset();
            name_ = std::exchange(other.name_, 0);
        }
        return *this;
    }
    GlHandle(const GlHandle&) = delete;
    GlHandle& operator=(const GlHandle&) = delete;
    ~GlHandle() { reset(); }
    void reset()
    {
        if (name_) Delete(name_);
        name_ = 0;
    }
    GLuint get() const { return name_; }
    explicit operator bool() const { return name_ != 0; }

private:
    GLuint name_ = 0;
};

inline void delete_buffer(GLuint n) { glDeleteBuffers(1, &n); }
inline void delete_texture(GLuint n) { glDeleteTextures(1, &n); }
inline void delete_framebuffer(GLuint n) { glDeleteFramebuffers(1, &n); }
inline void delete_vertex_array(GLuint n) { glDeleteVertexArrays(1, &n); }
inline void delete_program(GLuint n) { glDeleteProgram(n); }
inline void delete_query(GLuint n) { glDeleteQueries(1, &n); }
inline void delete_sampler(GLuint n) { glDeleteSamplers(1, &n); }

using Buffer = GlHandle<delete_buffer>;
using Texture = GlHandle<delete_texture>;
using Framebuffer = GlHandle<delete_framebuffer>;
using VertexArray = GlHandle<delete_vertex_array>;
using ProgramHandle = GlHandle<delete_program>;
using Query = GlHandle<delete_query>;
using Sampler = GlHandle<delete_sampler>;

// Immutable buffer storage holding `bytes` (flags as glNamedBufferStorage).
Buffer make_buffer(const void* data, std::size_t bytes, GLbitfield flags = 0);
template <typename T>
Buffer make_buffer(const std::vector<T>& values, GLbitfield flags = 0)
{
    return make_buffer(values.data(), values.size() * sizeof(T), flags);
}
Texture make_texture_2d(GLenum internal_format, int width, int height, int levels = 1);
Framebuffer make_framebuffer();
VertexArray make_vertex_array();
Query make_query(GLenum target);

// A linked program from embedded sources named by their path under src/, e.g.
// {"reference/shaders/mesh.vert", "reference/shaders/mesh.frag"}. #include "path" lines are
// expanded; `defines` are inserted after #version as "#define NAME VALUE" lines.
class Program {
public:
    static Result<Program> create(const std::vector<std::string>& stage_sources,
                                  const std::vector<std::pair<std::string, std::string>>& defines = {});
    GLuint id() const { return handle_.get(); }
    GLint uniform(const char* name) const { return glGetUniformLocation(handle_.get(), name); }
    void use() const { glUseProgram(handle_.get()); }

private:
    ProgramHandle handle_;
};

// The source of an embedded shader file with its includes expanded, or an error naming it.
Result<std::string> load_shader_source(const std::string& name);
// Where the viewer may reload shaders from (empty: embedded only).
void set_shader_source_directory(const std::string& src_root);

bool has_current_context();

// Whether the current context rasterises in software (Mesa's llvmpipe or softpipe): it runs a
// fragment shader that writes gl_FragDepth before its depth test whatever the shader declares
// (no early test under layout(depth_greater)), and shades a pixel's fragments one at a time in
// the order of their primitives. reps/common/depth_batches.h relies on both.
bool software_rasteriser();

} // namespace standin::gpu
