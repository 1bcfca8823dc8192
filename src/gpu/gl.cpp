// GL object helpers and program building from the embedded shader sources (see
// cmake/embed_shaders.cmake): #include lines are expanded here at run time, so the viewer can
// reload the same files from disk.
#include "gpu/gl.h"

#include "gpu/embedded_shaders.h"

#include <standin/files.h>

#include <filesystem>
#include <mutex>
#include <regex>
#include <sstream>
#include <string_view>
#include <vector>

// the shaders of this layer (gpu/shaders/common), registered at static initialisation
#include "embedded_shaders.inc"

namespace standin::gpu {

namespace {

struct ShaderTable {
    std::mutex mutex;
    std::vector<EmbeddedShader> shaders;
};

ShaderTable& shader_table()
{
    static ShaderTable table; // constructed on first use: registrations run at static initialisation
    return table;
}

std::string_view find_embedded_shader_locked(const ShaderTable& table, std::string_view name)
{
    for (const EmbeddedShader& shader : table.shaders)
        if (shader.name == name) return shader.source;
    return {};
}

} // namespace

std::string gl_error_text(GLenum error)
{
    std::string text = "OpenGL error " + std::to_string(error);
    if (error == GL_OUT_OF_MEMORY)
        text += " (out of GPU memory: what this draws does not fit on this device; a package baked with a smaller "
                "--resolution or --page-size, or a smaller image, needs less)";
    return text;
}

bool software_rasteriser()
{
    const char* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    if (!renderer) return false;
    const std::string_view name(renderer);
    return name.find("llvmpipe") != std::string_view::npos || name.find("softpipe") != std::string_view::npos;
}

std::string_view find_embedded_shader(std::string_view name)
{
    ShaderTable& table = shader_table();
    std::lock_guard lock(table.mutex);
    return find_embedded_shader_locked(table, name);
}

bool register_embedded_shaders(const EmbeddedShader* shaders, int count)
{
    ShaderTable& table = shader_table();
    std::lock_guard lock(table.mutex);
    for (int i = 0; i < count; ++i)
        if (find_embedded_shader_locked(table, shaders[i].name).empty()) table.shaders.push_back(shaders[i]);
    return true;
}

static std::mutex g_source_mutex;
static std::string g_source_directory;

Buffer make_buffer(const void* data, std::size_t bytes, GLbitfield flags)
{
    GLuint name = 0;
    glCreateBuffers(1, &name);
    glNamedBufferStorage(name, GLsizeiptr(std::max<std::size_t>(bytes, 4)), bytes ? data : nullptr, flags);
    return Buffer(name);
}

Texture make_texture_2d(GLenum internal_format, int width, int height, int levels)
{
    GLuint name = 0;
    glCreateTextures(GL_TEXTURE_2D, 1, &name);
    glTextureStorage2D(name, levels, internal_format, width, height);
    return Texture(name);
}

Framebuffer make_framebuffer()
{
    GLuint name = 0;
    glCreateFramebuffers(1, &name);
    return Framebuffer(name);
}

VertexArray make_vertex_array()
{
    GLuint name = 0;
    glCreateVertexArrays(1, &name);
    return VertexArray(name);
}

Query make_query(GLenum target)
{
    GLuint name = 0;
    glCreateQueries(target, 1, &name);
    return Query(name);
}

void set_shader_source_directory(const std::string& src_root)
{
    std::lock_guard lock(g_source_mutex);
    g_source_directory = src_root;
}

static Result<std::string> raw_shader_source(const std::string& name)
{
    {
        std::lock_guard lock(g_source_mutex);
        if (!g_source_directory.empty()) {
            std::string path = g_source_directory + "/" + name;
            if (std::filesystem::exists(path)) return read_file(path);
        }
    }
    std::string_view embedded = find_embedded_shader(name);
    if (!embedded.empty()) return std::string(embedded);
    return error(StatusCode::not_found, "shader " + name + ": not embedded in this build");
}

static Result<std::string> expand_includes(const std::string& name, int depth)
{
    if (depth > 16) return error(StatusCode::bad_data, "shader " + name + ": #include nesting too deep");
    Result<std::string> source = raw_shader_source(name);
    if (!source) return source;
    static const std::regex include_line(R"re(^\s*#include\s+"([^"]+)"\s*$)re");
    std::istringstream lines(*source);
    std::string line, out;
    int line_number = 0;
    while (std::getline(lines, line)) {
        ++line_number;
        std::smatch match;
        if (std::regex_match(line, match, include_line)) {
            Result<std::string> included = expand_includes(match[1].str(), depth + 1);
            if (!included) return included;
            out += *included;
            out += "\n";
        } else {
            out += line;
            out += "\n";
        }
    }
    return out;
}

Result<std::string> load_shader_source(const std::string& name) { return expand_includes(name, 0); }

static GLenum stage_of(const std::string& name)
{
    auto ends_with = [&](std::string_view ext) { return name.size() >= ext.size() && name.compare(name.size() - ext.size(), ext.size(), ext) == 0; };
    if (ends_with(".vert")) return GL_VERTEX_SHADER;
    if (ends_with(".frag")) return GL_FRAGMENT_SHADER;
    if (ends_with(".comp")) return GL_COMPUTE_SHADER;
    if (ends_with(".geom")) return GL_GEOMETRY_SHADER;
    if (ends_with(".tesc")) return GL_TESS_CONTROL_SHADER;
    if (ends_with(".tese")) return GL_TESS_EVALUATION_SHADER;
    return 0;
}

static std::string insert_defines(const std::string& source,
                                  const std::vector<std::pair<std::string, std::string>>& defines)
{
    if (defines.empty()) return source;
    std::size_t version_end = source.find('\n', source.find("#version"));
    std::string text;
    for (const auto& [key, value] : defines) text += "#define " + key + " " + value + "\n";
    return source.substr(0, version_end + 1) + text + source.substr(version_end + 1);
}

Result<Program> Program::create(const std::vector<std::string>& stage_sources,
                                const std::vector<std::pair<std::string, std::string>>& defines)
{
    ProgramHandle program(glCreateProgram());
    std::vector<GLuint> shaders;
    auto cleanup = [&] {
        for (GLuint s : shaders) glDeleteShader(s);
    };
    for (const std::string& name : stage_sources) {
        GLenum stage = stage_of(name);
        if (!stage) {
            cleanup();
            return error(StatusCode::invalid_argument, "shader " + name + ": unknown stage extension");
        }
        Result<std::string> source = load_shader_source(name);
        if (!source) {
            cleanup();
            return source.status();
        }
        std::string text = insert_defines(*source, defines);
        GLuint shader = glCreateShader(stage);
        const char* ptr = text.c_str();
        glShaderSource(shader, 1, &ptr, nullptr);
        glCompileShader(shader);
        shaders.push_back(shader);
        GLint ok = 0;
        glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
        if (!ok) {
            char log[4096] = {};
            glGetShaderInfoLog(shader, sizeof log, nullptr, log);
            cleanup();
            std::string first_line(log);
            return error(StatusCode::gpu_error, "shader " + name + " does not compile: " + first_line);
        }
        glAttachShader(program.get(), shader);
    }
    glLinkProgram(program.get());
    cleanup();
    GLint linked = 0;
    glGetProgramiv(program.get(), GL_LINK_STATUS, &linked);
    if (!linked) {
        char log[4096] = {};
        glGetProgramInfoLog(program.get(), sizeof log, nullptr, log);
        return error(StatusCode::gpu_error, "program " + stage_sources.front() + " does not link: " + log);
    }
    Program result;
    result.handle_ = std::move(program);
    return result;
}

} // namespace standin::gpu
