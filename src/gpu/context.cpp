// Headless OpenGL 4.5 core contexts through EGL: the surfaceless platform (Mesa: llvmpipe or a GPU
// driver), then the device platform (NVIDIA's headless path), then the default display.
// Nothing here needs a window system.
#include "gpu/gl.h"

#include <standin/log.h>
#include <standin/render.h>

#include <epoxy/egl.h>

#include <cstring>
#include <string>
#include <vector>

namespace standin {

namespace {

#ifndef NDEBUG
void GLAPIENTRY forward_gl_debug_message(GLenum, GLenum type, GLuint, GLenum severity, GLsizei, const GLchar* message,
                                         const void*)
{
    if (severity == GL_DEBUG_SEVERITY_NOTIFICATION) return;
    log_message(type == GL_DEBUG_TYPE_ERROR ? LogLevel::error : LogLevel::debug, std::string("GL: ") + message);
}
#endif

class EglContext final : public GpuContext {
public:
    EglContext(EGLDisplay display, EGLContext context) : display_(display), context_(context) {}
    ~EglContext() override
    {
        eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        eglDestroyContext(display_, context_);
        eglTerminate(display_);
    }
    std::string device_name() const override { return reinterpret_cast<const char*>(glGetString(GL_RENDERER)); }
    std::string version() const override { return reinterpret_cast<const char*>(glGetString(GL_VERSION)); }

private:
    EGLDisplay display_;
    EGLContext context_;
};

bool has_extension(const char* list, const char* name)
{
    if (!list) return false;
    std::size_t n = std::strlen(name);
    for (const char* p = list; (p = std::strstr(p, name)); p += n)
        if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
    return false;
}

std::vector<EGLDisplay> candidate_displays()
{
    std::vector<EGLDisplay> displays;
    const char* client_extensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (has_extension(client_extensions, "EGL_MESA_platform_surfaceless")) {
        EGLDisplay d = eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
        if (d != EGL_NO_DISPLAY) displays.push_back(d);
    }
    if (has_extension(client_extensions, "EGL_EXT_platform_device") &&
        has_extension(client_extensions, "EGL_EXT_device_enumeration")) {
        EGLDeviceEXT devices[16];
        EGLint count = 0;
        if (eglQueryDevicesEXT(16, devices, &count))
            for (EGLint i = 0; i < count; ++i) {
                EGLDisplay d = eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr);
                if (d != EGL_NO_DISPLAY) displays.push_back(d);
            }
    }
    EGLDisplay d = eglGetDisplay(EGL_DEFAULT_DISPLAY);
    if (d != EGL_NO_DISPLAY) displays.push_back(d);
    return displays;
}

EGLContext create_core_context(EGLDisplay display)
{
    EGLint major = 0, minor = 0;
    if (!eglInitialize(display, &major, &minor)) return EGL_NO_CONTEXT;
    if (!eglBindAPI(EGL_OPENGL_API)) return EGL_NO_CONTEXT;
    const EGLint config_attributes[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
    EGLConfig config = nullptr;
    EGLint config_count = 0;
    bool no_config = has_extension(eglQueryString(display, EGL_EXTENSIONS), "EGL_KHR_no_config_context");
    if (!eglChooseConfig(display, config_attributes, &config, 1, &config_count) || config_count == 0) {
        if (!no_config) return EGL_NO_CONTEXT;
        config = EGL_NO_CONFIG_KHR;
    }
    const EGLint context_attributes[] = {
        EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5,
        EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
#ifndef NDEBUG
        EGL_CONTEXT_OPENGL_DEBUG, EGL_TRUE,
#endif
        EGL_NONE};
    EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, context_attributes);
    if (context == EGL_NO_CONTEXT) return EGL_NO_CONTEXT;
    if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
        eglDestroyContext(display, context);
        return EGL_NO_CONTEXT;
    }
    return context;
}

} // namespace

Result<std::unique_ptr<GpuContext>> create_headless_context()
{
    for (EGLDisplay display : candidate_displays()) {
        EGLContext context = create_core_context(display);
        if (context == EGL_NO_CONTEXT) {
            eglTerminate(display);
            continue;
        }
        if (epoxy_gl_version() < 45) {
            eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
            eglDestroyContext(display, context);
            eglTerminate(display);
            continue;
        }
#ifndef NDEBUG
        glEnable(GL_DEBUG_OUTPUT);
        glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
        glDebugMessageCallback(forward_gl_debug_message, nullptr);
#endif
        std::unique_ptr<GpuContext> result = std::make_unique<EglContext>(display, context);
        log_message(LogLevel::info, "OpenGL " + result->version() + " on " + result->device_name());
        return result;
    }
    return error(StatusCode::gpu_error,
                 "no OpenGL 4.5 core context could be created through EGL (surfaceless or device platform); "
                 "install Mesa (libegl-mesa0, libgl1-mesa-dri) or a GPU driver");
}

namespace gpu {
bool has_current_context() { return eglGetCurrentContext() != EGL_NO_CONTEXT; }
} // namespace gpu

} // namespace standin
