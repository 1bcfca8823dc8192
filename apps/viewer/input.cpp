// Mouse and keyboard: orbit (left drag, arrows), pan (right or middle drag, Shift + left drag),
// zoom (wheel, +/-), the light (Ctrl + left drag), and keys for the rest (k_key_help).
#include "viewer_state.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>

#include <algorithm>
#include <cmath>

namespace standin::viewer {

namespace {


bool pressed(int key) { return ImGui::IsKeyPressed(key, false); }
bool pressed_repeat(int key) { return ImGui::IsKeyPressed(key, true); }

float wrap_degrees(float degrees) { return std::remainder(degrees, 360.0f); }

void mouse(ViewerState& state)
{
    static bool dragging[3] = {false, false, false}; // started outside the panels
    ImGuiIO& io = ImGui::GetIO();
    for (int button = 0; button < 3; ++button) {
        if (ImGui::IsMouseClicked(button)) dragging[button] = !io.WantCaptureMouse;
        if (!io.MouseDown[button]) dragging[button] = false;
    }
    const glm::vec2 delta(io.MouseDelta.x, io.MouseDelta.y);
    const float pan_scale = 2.0f * state.orbit.distance_rel / std::max(io.DisplaySize.y, 1.0f);
    if (dragging[0] && io.KeyCtrl) {
        state.light_follows_camera = false;
        state.light_azimuth = wrap_degrees(state.light_azimuth - 0.4f * delta.x);
        state.light_elevation = std::clamp(state.light_elevation + 0.4f * delta.y, -90.0f, 90.0f);
    } else if ((dragging[0] && io.KeyShift) || dragging[1] || dragging[2]) {
        state.pan += glm::vec2(-delta.x, delta.y) * pan_scale;
    } else if (dragging[0]) {
        state.orbit.azimuth_degrees = wrap_degrees(state.orbit.azimuth_degrees - 0.4f * delta.x);
        state.orbit.elevation_degrees = std::clamp(state.orbit.elevation_degrees + 0.4f * delta.y, -89.9f, 89.9f);
    }
    if (!io.WantCaptureMouse && io.MouseWheel != 0.0f)
        state.orbit.distance_rel = std::clamp(state.orbit.distance_rel * std::pow(0.9f, io.MouseWheel), 0.01f, 1e4f);
}

void keyboard(ViewerState& state)
{
    // camera
    if (pressed_repeat(GLFW_KEY_LEFT)) state.orbit.azimuth_degrees = wrap_degrees(state.orbit.azimuth_degrees - 5.0f);
    if (pressed_repeat(GLFW_KEY_RIGHT)) state.orbit.azimuth_degrees = wrap_degrees(state.orbit.azimuth_degrees + 5.0f);
    if (pressed_repeat(GLFW_KEY_UP)) state.orbit.elevation_degrees = std::min(state.orbit.elevation_degrees + 5.0f, 89.9f);
    if (pressed_repeat(GLFW_KEY_DOWN)) state.orbit.elevation_degrees = std::max(state.orbit.elevation_degrees - 5.0f, -89.9f);
    if (pressed_repeat(GLFW_KEY_EQUAL) || pressed_repeat(GLFW_KEY_KP_ADD) || pressed_repeat(GLFW_KEY_PAGE_UP))
        state.orbit.distance_rel *= 0.9f;
    if (pressed_repeat(GLFW_KEY_MINUS) || pressed_repeat(GLFW_KEY_KP_SUBTRACT) || pressed_repeat(GLFW_KEY_PAGE_DOWN))
        state.orbit.distance_rel /= 0.9f;
    if (pressed(GLFW_KEY_R)) reset_view(state);
    if (pressed(GLFW_KEY_O)) state.orbit.orthographic = !state.orbit.orthographic;

    // what is shown: Tab toggles the original and the stand-in at the same camera
    if (pressed(GLFW_KEY_TAB)) {
        bool on_original = state.subjects[state.shown].is_original();
        if (on_original && state.stand_in >= 0) show_subject(state, state.stand_in);
        else if (!on_original && state.original >= 0) show_subject(state, state.original);
        else show_subject(state, (state.shown + 1) % int(state.subjects.size()));
    }
    if (pressed(GLFW_KEY_0) && state.original >= 0) show_subject(state, state.original);
    for (int n = 1; n <= 9; ++n)
        if (pressed(GLFW_KEY_0 + n) && package_subject(state, n) >= 0) show_subject(state, package_subject(state, n));
    if (pressed(GLFW_KEY_S))
        state.layout = state.layout == Layout::single ? Layout::split
                       : state.layout == Layout::split ? Layout::side_by_side : Layout::single;
    if (pressed(GLFW_KEY_D)) {
        // the next debug view some package draws, then off
        std::vector<std::string> views = available_debug_views(state);
        views.insert(views.begin(), "");
        auto at = std::find(views.begin(), views.end(), state.debug_view);
        std::string next = at == views.end() || at + 1 == views.end() ? views.front() : *(at + 1);
        if (Status s = set_debug_view(state, next); !s) state.message = s.message();
    }

    // the application
    if (pressed(GLFW_KEY_H)) state.shadows = !state.shadows;
    if (pressed(GLFW_KEY_F1)) state.show_panels = !state.show_panels;
    if (pressed(GLFW_KEY_F2)) state.show_overlay = !state.show_overlay;
    if (pressed(GLFW_KEY_F5)) state.want_reload = true;
    if (pressed(GLFW_KEY_F12) || pressed(GLFW_KEY_P)) state.want_screenshot = true;
    if (pressed(GLFW_KEY_ESCAPE) || pressed(GLFW_KEY_Q)) state.want_quit = true;
}

} // namespace

const char* const k_key_help =
    "left drag: orbit    right/middle or Shift+left drag: pan\n"
    "wheel, +/-: zoom    arrows: orbit    Ctrl+left drag: light\n"
    "R: reset camera and light    O: orthographic    H: shadows\n"
    "Tab: original <-> stand-in    0: original    1-9: package N\n"
    "S: alone / split / side by side    D: next debug view\n"
    "F1: panels    F2: overlay    F5: reload shaders\n"
    "F12 or P: screenshot    Esc or Q: quit";

void handle_input(ViewerState& state)
{
    mouse(state);
    if (!ImGui::GetIO().WantCaptureKeyboard) keyboard(state);
}

} // namespace standin::viewer
