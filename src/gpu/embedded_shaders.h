// GLSL sources embedded at build time (cmake/shaders.cmake): every target with shaders registers
// its own at static initialisation, and Program::create finds them by their path under src/.
#pragma once

#include <string_view>

namespace standin::gpu {

struct EmbeddedShader {
    std::string_view name;   // path under src/, e.g. "gpu/shaders/common/frame.glsl"
    std::string_view source; // the file verbatim (includes unexpanded)
};

// Adds `count` sources; a name registered twice keeps its first source. Returns true (so that a
// namespace-scope constant can run it at static initialisation).
bool register_embedded_shaders(const EmbeddedShader* shaders, int count);

// The registered source of `name`, or empty when none is.
std::string_view find_embedded_shader(std::string_view name);

} // namespace standin::gpu
