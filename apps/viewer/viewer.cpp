// `standin view`: the window, the main loop and the script runner. Everything that can be checked
// without a display is checked first (the script, the inputs); then GLFW opens a window with an
// OpenGL 4.5 core context, the subjects' renderers are built in it, and each frame draws the
// subjects (frame_renderer.cpp) under the ImGui panels (ui_<panel>.cpp).
#include "viewer.h"

#include "frame_renderer.h"
#include "script.h"
#include "viewer_state.h"

#include <standin/files.h>
#include <standin/image.h>
#include <standin/package.h>

// epoxy declares the GL functions; GLFW must not include a GL header of its own
#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#ifndef STANDIN_VIEWER_SHADER_DIR
#define STANDIN_VIEWER_SHADER_DIR ""
#endif

namespace standin::viewer {

namespace {

constexpr std::uint64_t k_max_script_bytes = 16u << 20;

const char* const k_no_display_hint = "; use 'standin render' for offscreen pictures";

// where shader reload reads from: src/ of the source tree this was built from, or $STANDIN_SHADER_DIR
std::string shader_directory()
{
    const char* overridden = std::getenv("STANDIN_SHADER_DIR");
    return overridden && *overridden ? overridden : STANDIN_VIEWER_SHADER_DIR;
}

// ---------------------------------------------------------------------------------------------
// the script, one command at a time between frames

class ScriptRunner {
public:
    ScriptRunner(std::vector<ScriptCommand> commands, std::string name)
        : commands_(std::move(commands)), name_(std::move(name)) {}

    // Runs commands until one needs a frame drawn (wait, screenshot, window); `done` at quit or
    // the end. A command that cannot be carried out stops the script with its line.
    Status step(ViewerState& state, GLFWwindow* window, bool& done);

private:
    Status run(const ScriptCommand& c, ViewerState& state, GLFWwindow* window, bool& yield, bool& done);
    Status fail(const ScriptCommand& c, const std::string& message) const
    {
        return error(StatusCode::invalid_argument, name_ + " line " + std::to_string(c.line) + ": " + message);
    }

    std::vector<ScriptCommand> commands_;
    std::string name_;
    std::size_t next_ = 0;
    int frames_to_wait_ = 0;
    glm::ivec2 window_wanted_{0};
    int window_frames_ = 0;
    std::string pending_screenshot_;
};

Status ScriptRunner::step(ViewerState& state, GLFWwindow* window, bool& done)
{
    done = false;
    if (frames_to_wait_ > 0) {
        --frames_to_wait_;
        return Status::ok();
    }
    if (window_wanted_ != glm::ivec2(0)) {
        // the window manager (if any) resizes asynchronously
        glm::ivec2 size;
        glfwGetFramebufferSize(window, &size.x, &size.y);
        if (size != window_wanted_ && ++window_frames_ < 120) return Status::ok();
        if (size != window_wanted_)
            std::fprintf(stderr, "standin: warning: window is %dx%d, not the %dx%d asked for\n", size.x, size.y,
                         window_wanted_.x, window_wanted_.y);
        window_wanted_ = glm::ivec2(0);
    }
    if (!pending_screenshot_.empty()) {
        // taken at the end of the second frame after the changes: ImGui sizes its windows a frame late
        state.screenshot_path = std::move(pending_screenshot_);
        pending_screenshot_.clear();
        return Status::ok();
    }
    while (next_ < commands_.size()) {
        bool yield = false;
        STANDIN_RETURN_IF_ERROR(run(commands_[next_++], state, window, yield, done));
        if (yield || done) return Status::ok();
    }
    done = true;
    return Status::ok();
}

Status ScriptRunner::run(const ScriptCommand& c, ViewerState& state, GLFWwindow* window, bool& yield, bool& done)
{
    const bool can_compare = state.original >= 0 && state.stand_in >= 0;
    switch (c.op) {
    case ScriptOp::camera:
        state.orbit.azimuth_degrees = c.numbers[0];
        state.orbit.elevation_degrees = c.numbers[1];
        state.orbit.distance_rel = c.numbers[2];
        break;
    case ScriptOp::pan: state.pan = {c.numbers[0], c.numbers[1]}; break;
    case ScriptOp::projection: state.orbit.orthographic = c.word == "orthographic"; break;
    case ScriptOp::reset: reset_view(state); break;
    case ScriptOp::light:
        state.light_follows_camera = c.word == "camera";
        if (!state.light_follows_camera) {
            state.light_azimuth = c.numbers[0];
            state.light_elevation = c.numbers[1];
        }
        break;
    case ScriptOp::show:
        if (c.word == "original") {
            if (state.original < 0) return fail(c, "show original: no model was given, only packages");
            show_subject(state, state.original);
        } else {
            int index = package_subject(state, c.count);
            if (index < 0)
                return fail(c, "show package " + std::to_string(c.count) + ": " +
                                   std::to_string(package_count(state)) + " package(s) given");
            show_subject(state, index);
        }
        break;
    case ScriptOp::split:
        if (c.word != "off" && !can_compare) return fail(c, "split " + c.word + ": needs the model and a package");
        state.layout = c.word == "on" ? Layout::split : c.word == "side" ? Layout::side_by_side : Layout::single;
        break;
    case ScriptOp::split_position: state.split_position = c.numbers[0]; break;
    case ScriptOp::debug:
        if (c.word == "holes" && !can_compare) return fail(c, "debug holes: needs the model and a package");
        if (Status s = set_debug_view(state, c.word); !s) return fail(c, s.message());
        break;
    case ScriptOp::set: {
        // the knob of the package shown (or compared)
        int index = state.subjects[state.shown].is_original() ? state.stand_in : state.shown;
        if (index < 0) return fail(c, "set: no package to set it on");
        if (Status s = set_package_option(state.subjects[index], c.word, c.value); !s) return fail(c, s.message());
        break;
    }
    case ScriptOp::resolution:
        state.render_follows_window = c.word == "window";
        if (!state.render_follows_window) state.render_size = {c.size[0], c.size[1]};
        break;
    case ScriptOp::window:
        window_wanted_ = {c.size[0], c.size[1]};
        window_frames_ = 0;
        glfwSetWindowSize(window, c.size[0], c.size[1]);
        yield = true;
        break;
    case ScriptOp::panels: state.show_panels = c.word == "on"; break;
    case ScriptOp::shadows: state.shadows = c.word == "on"; break;
    case ScriptOp::overlay: state.show_overlay = c.word == "on"; break;
    case ScriptOp::reload:
        if (Status s = reload_shaders(state, shader_directory()); !s) return fail(c, s.message());
        break;
    case ScriptOp::screenshot:
        pending_screenshot_ = c.word;
        yield = true;
        break;
    case ScriptOp::wait:
        frames_to_wait_ = c.count > 0 ? c.count - 1 : 0;
        yield = c.count > 0;
        break;
    case ScriptOp::quit: done = true; break;
    }
    return Status::ok();
}

// ---------------------------------------------------------------------------------------------
// the window

std::string g_glfw_error;
void on_glfw_error(int, const char* description) { g_glfw_error = description ? description : "unknown error"; }

// GLFW and ImGui, torn down in reverse order whatever happens
struct WindowSession {
    GLFWwindow* window = nullptr;
    bool imgui = false;
    ~WindowSession()
    {
        if (imgui) {
            ImGui_ImplOpenGL3_Shutdown();
            ImGui_ImplGlfw_Shutdown();
            ImGui::DestroyContext();
        }
        if (window) glfwDestroyWindow(window);
        glfwTerminate();
    }
};

Status open_window(WindowSession& session, const ViewerArgs& args)
{
    const char* display = std::getenv("DISPLAY");
    if (!display || !*display)
        return error(StatusCode::unsupported, std::string("no display for the viewer (DISPLAY is not set)") + k_no_display_hint);
    glfwSetErrorCallback(on_glfw_error);
    if (!glfwInit())
        return error(StatusCode::unsupported, "no display for the viewer (cannot open display '" + std::string(display) +
                                                  "': " + g_glfw_error + ")" + k_no_display_hint);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    session.window = glfwCreateWindow(args.window_width, args.window_height, "standin view", nullptr, nullptr);
    if (!session.window)
        return error(StatusCode::gpu_error, "view: cannot open a window with an OpenGL 4.5 core context (" + g_glfw_error +
                                                ")" + k_no_display_hint);
    glfwMakeContextCurrent(session.window);
    glfwSwapInterval(args.script_path.empty() ? 1 : 0);

    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr; // no imgui.ini left in the working directory
    ImGui::StyleColorsDark();
    ImGui_ImplGlfw_InitForOpenGL(session.window, true);
    ImGui_ImplOpenGL3_Init("#version 410 core");
    session.imgui = true;
    return Status::ok();
}

// the next free standin-view-NNN.png in the working directory
std::string next_screenshot_name()
{
    for (int i = 1;; ++i) {
        char name[32];
        std::snprintf(name, sizeof name, "standin-view-%03d.png", i);
        if (!std::filesystem::exists(name)) return name;
    }
}

Status take_screenshot(ViewerState& state, glm::ivec2 framebuffer_size)
{
    std::string path = state.screenshot_path.empty() ? next_screenshot_name() : state.screenshot_path;
    state.screenshot_path.clear();
    state.want_screenshot = false;
    STANDIN_RETURN_IF_ERROR(write_png(read_window(framebuffer_size), path));
    // one line with the frame's statistics, so that unattended runs can be checked from the log
    std::string line = "wrote " + path + " (" + std::to_string(framebuffer_size.x) + "x" +
                       std::to_string(framebuffer_size.y) + ", render " + std::to_string(state.stats.render_size.x) +
                       "x" + std::to_string(state.stats.render_size.y);
    for (const SubjectStats& s : state.stats.subjects) {
        char text[256];
        std::snprintf(text, sizeof text, "; %s: frame %.2f ms GPU, %.2f ms CPU, %llu primitives, %zu pixels covered",
                      state.subjects[s.subject].label.c_str(), s.gpu_ms, s.wall_ms,
                      (unsigned long long)s.draw.primitives, s.covered_pixels);
        line += text;
    }
    if (!state.debug_view.empty()) line += "; debug view " + state.debug_view;
    line += ")";
    std::fprintf(stderr, "standin: %s\n", line.c_str());
    state.message = "wrote " + path;
    return Status::ok();
}

void panels(ViewerState& state)
{
    if (!state.show_panels) return;
    const ImGuiIO& io = ImGui::GetIO();
    const float width = std::min(320.0f, io.DisplaySize.x * 0.5f);
    ImGui::SetNextWindowPos(ImVec2(io.DisplaySize.x - width, 0.0f), ImGuiCond_Always);
    ImGui::SetNextWindowSize(ImVec2(width, io.DisplaySize.y), ImGuiCond_Always);
    ImGui::SetNextWindowBgAlpha(0.85f);
    // small windows start with the panels folded, so that the model stays visible
    ImGui::SetNextWindowCollapsed(io.DisplaySize.x < 640.0f, ImGuiCond_Once);
    if (ImGui::Begin("standin view (F1 hides)", nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize)) {
        ui_view_panel(state);
        ui_subjects_panel(state);
        ui_debug_panel(state);
    }
    ImGui::End();
}

// the main loop; GL objects made here are gone before the window is
Status run_window(ViewerState& state, GLFWwindow* window, ScriptRunner* script)
{
    for (Subject& subject : state.subjects) STANDIN_RETURN_IF_ERROR(build_renderer(subject));
    FrameRenderer frame;
    Status result;
    for (int frame_index = 0; !glfwWindowShouldClose(window); ++frame_index) {
        glfwPollEvents();
        ImGui_ImplOpenGL3_NewFrame();
        ImGui_ImplGlfw_NewFrame();
        ImGui::NewFrame();

        // the script (after two frames, so that the panels have their sizes) or the user
        if (script) {
            bool done = false;
            if (frame_index >= 2) result = script->step(state, window, done);
            if (!result || done) {
                ImGui::EndFrame();
                break;
            }
        } else {
            handle_input(state);
        }
        if (state.window_request != glm::ivec2(0)) {
            glfwSetWindowSize(window, state.window_request.x, state.window_request.y);
            state.window_request = glm::ivec2(0);
        }
        if (state.want_reload) {
            state.want_reload = false;
            Status s = reload_shaders(state, shader_directory());
            state.message = s ? "reloaded shaders from " + shader_directory() : s.message();
        }
        panels(state);

        glm::ivec2 framebuffer_size;
        glfwGetFramebufferSize(window, &framebuffer_size.x, &framebuffer_size.y);
        FrameLayout layout = frame.draw(state, framebuffer_size);
        ui_overlay(state, layout);
        ImGui::Render();
        ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
        if (!state.screenshot_path.empty() || state.want_screenshot) {
            Status s = take_screenshot(state, framebuffer_size);
            if (!s && script) {
                result = s;
                break;
            }
            if (!s) state.message = s.message();
        }
        glfwSwapBuffers(window);
        if (state.want_quit) break;
    }
    for (Subject& subject : state.subjects) subject.renderer.reset();
    return result;
}

Result<std::unique_ptr<ScriptRunner>> load_script(const std::string& path)
{
    Result<std::string> text = read_file(path, k_max_script_bytes); // a regular file of sane size
    if (!text) return text.status();
    // `set` may name any representation's run-time option
    std::vector<OptionSpec> options;
    for (const Representation& r : representations())
        options.insert(options.end(), r.render_options.begin(), r.render_options.end());
    Result<std::vector<ScriptCommand>> commands = parse_script(*text, path, options);
    if (!commands) return commands.status();
    return std::make_unique<ScriptRunner>(std::move(*commands), path);
}

} // namespace

Status run_viewer(const ViewerArgs& args)
{
    // everything that needs no window first: the script, then the inputs
    std::unique_ptr<ScriptRunner> script;
    if (!args.script_path.empty()) {
        Result<std::unique_ptr<ScriptRunner>> loaded = load_script(args.script_path);
        if (!loaded) return loaded.status();
        script = std::move(*loaded);
    }
    // the window outlives the subjects: renderers are destroyed while their context exists, also
    // when a return below leaves early
    WindowSession session;
    ViewerState state;
    STANDIN_RETURN_IF_ERROR(load_subjects(args.inputs, args.options, state));
    state.home = state.orbit = args.view;
    state.home_light_follows = std::isnan(args.light_azimuth);
    if (!state.home_light_follows) {
        state.home_light_azimuth = args.light_azimuth;
        state.home_light_elevation = args.light_elevation;
    }
    reset_view(state);
    state.render_follows_window = args.render_width <= 0;
    if (!state.render_follows_window) state.render_size = {args.render_width, args.render_height};

    STANDIN_RETURN_IF_ERROR(open_window(session, args));
    // the renderers are built in run_window, with the debug view recorded here
    if (!args.debug_view.empty()) STANDIN_RETURN_IF_ERROR(set_debug_view(state, args.debug_view));
    return run_window(state, session.window, script.get());
}

} // namespace standin::viewer
