// What the viewer's panels, keys, script and frame renderer share: the subjects (the original and
// the packages with their renderers), the camera, the light, the layout and the last frame's
// statistics. Only the viewer includes this.
#pragma once

#include <standin/camera.h>
#include <standin/mesh.h>
#include <standin/package.h>
#include <standin/render.h>
#include <standin/status.h>

#include <glm/glm.hpp>

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace standin::viewer {

// The original mesh or one package, with its renderer built from its run-time options.
struct Subject {
    std::string path;
    std::string label;                // "original: bunny.ply", "package 1: bunny.standin"
    std::string contents;             // "69451 triangles", or the package summary's headline
    std::optional<Mesh> mesh;         // the original only
    std::unique_ptr<Package> package; // packages only
    RenderOptions options;            // packages only (the mesh renderer has none): the run-time
                                      // options its representation declares, and its debug view
    std::unique_ptr<Renderer> renderer;

    bool is_original() const { return mesh.has_value(); }
    std::string representation() const { return package ? package->representation() : "original mesh"; }
};

enum class Layout { single, split, side_by_side };

// Measurements of one subject in the last frame.
struct SubjectStats {
    int subject = -1;
    double gpu_ms = 0.0;  // GL_TIME_ELAPSED around draw()
    double wall_ms = 0.0; // CPU time from submission to glFinish (what counts on llvmpipe)
    DrawStats draw;
    std::size_t covered_pixels = 0;  // alpha > 0 in the render target
    double fetches_per_pixel = -1.0; // -1 when not counted
};

struct FrameStats {
    glm::ivec2 render_size{0};
    std::vector<SubjectStats> subjects; // one per subject drawn this frame
    std::size_t hole_pixels = 0, excess_pixels = 0; // debug view "holes" only
};


struct ViewerState {
    std::vector<Subject> subjects; // the original first, when there is one
    int original = -1;             // index of the original, -1 without one
    int shown = 0;                 // the subject shown in the single layout
    int stand_in = -1;             // the package compared with the original (split, side by side, holes)
    Layout layout = Layout::single;
    float split_position = 0.5f;   // of the width
    std::string debug_view;        // "" (off), a shared debug view's name, or "holes" (the viewer's own)

    // camera and light
    BoundingSphere sphere;         // the model's (packages store their source's bounds)
    OrbitView home;                // where reset returns to
    OrbitView orbit;
    glm::vec2 pan{0.0f};           // orbit centre offset along the camera's right and up, in radii
    bool light_follows_camera = true;
    bool shadows = false;          // shadows of the light (render.h ShadowMap), fitted to `sphere`
    float light_azimuth = 0.0f, light_elevation = 45.0f;
    bool home_light_follows = true;
    float home_light_azimuth = 0.0f, home_light_elevation = 45.0f;

    // resolution
    bool render_follows_window = true;
    glm::ivec2 render_size{800, 600};

    bool show_panels = true, show_overlay = true, count_fetches = false;
    FrameStats stats;
    std::string message; // the last thing worth telling the user, shown in the panel

    // requests carried out by the main loop
    std::string screenshot_path; // the script's next screenshot, empty: none
    bool want_screenshot = false; // a screenshot under the next free standin-view-NNN.png
    bool want_reload = false, want_quit = false;
    glm::ivec2 window_request{0};
};

// loading (subjects.cpp)
// Every package gets the options its representation declares; an option that no package declares
// is refused.
Status load_subjects(const std::vector<std::string>& inputs, const OptionValues& options, ViewerState& state);
// Builds (or rebuilds) a subject's renderer from its options in the current context; on failure
// the previous renderer stays and the status says why.
Status build_renderer(Subject& subject);
// Sets the debug view of every package that draws it ("holes" and "" of all) and rebuilds their
// renderers; refused when no package draws it.
Status set_debug_view(ViewerState& state, const std::string& name);
// The debug views some package shown draws, then "holes" when there is a model and a package.
std::vector<std::string> available_debug_views(const ViewerState& state);
// Sets one run-time option of a package (as its representation declares it) and rebuilds its
// renderer; on failure the previous options stay.
Status set_package_option(Subject& subject, const std::string& name, const std::string& value);
// Rebuilds every renderer, shaders read from `shader_directory` (src/ of a source tree).
Status reload_shaders(ViewerState& state, const std::string& shader_directory);
int package_count(const ViewerState& state);
int package_subject(const ViewerState& state, int n); // subject index of package n (1-based), -1 if none

// camera and light (subjects.cpp)
Camera current_camera(const ViewerState& state, float aspect);
Light current_light(const ViewerState& state, const Camera& camera);
void reset_view(ViewerState& state);
// Shows subject `index` alone, or as the stand-in of the split layouts when it is a package.
void show_subject(ViewerState& state, int index);

// panels (ui_<panel>.cpp), each one collapsing section of the side window
void ui_view_panel(ViewerState& state);
void ui_subjects_panel(ViewerState& state);
void ui_debug_panel(ViewerState& state);
// the overlay (frame time, primitives, pixels covered) is in frame_renderer.h: ui_overlay

// mouse and keyboard (input.cpp); does nothing while ImGui wants the input
void handle_input(ViewerState& state);
extern const char* const k_key_help;

} // namespace standin::viewer
