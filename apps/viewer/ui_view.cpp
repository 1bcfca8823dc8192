// The "View" panel: camera, light, render resolution and window size.
#include "viewer_state.h"

#include <imgui.h>

#include <cstdio>

namespace standin::viewer {

static void camera_section(ViewerState& state)
{
    OrbitView& orbit = state.orbit;
    ImGui::SliderFloat("azimuth", &orbit.azimuth_degrees, -180.0f, 180.0f, "%.1f deg");
    ImGui::SliderFloat("elevation", &orbit.elevation_degrees, -90.0f, 90.0f, "%.1f deg");
    ImGui::SliderFloat("distance", &orbit.distance_rel, 0.05f, 20.0f, "%.2f", ImGuiSliderFlags_Logarithmic);
    ImGui::Checkbox("orthographic", &orbit.orthographic);
    if (!orbit.orthographic) ImGui::SliderFloat("fov", &orbit.fov_y_degrees, 5.0f, 120.0f, "%.0f deg");
    ImGui::Text("pan %.2f, %.2f radii", state.pan.x, state.pan.y);
    ImGui::SameLine();
    if (ImGui::Button("reset (R)")) reset_view(state);
}

static void light_section(ViewerState& state)
{
    ImGui::Checkbox("shadows (H)", &state.shadows);
    ImGui::Checkbox("light follows the camera", &state.light_follows_camera);
    if (state.light_follows_camera) return;
    ImGui::SliderFloat("light azimuth", &state.light_azimuth, -180.0f, 180.0f, "%.1f deg");
    ImGui::SliderFloat("light elevation", &state.light_elevation, -90.0f, 90.0f, "%.1f deg");
    ImGui::TextDisabled("Ctrl + drag moves the light");
}

static void resolution_section(ViewerState& state)
{
    ImGui::Checkbox("render at window size", &state.render_follows_window);
    // the seed's presets (000 §4.1)
    const glm::ivec2 presets[] = {{800, 600}, {400, 300}, {200, 150}};
    for (glm::ivec2 preset : presets) {
        char label[32];
        std::snprintf(label, sizeof label, "%dx%d", preset.x, preset.y);
        if (ImGui::Button(label)) {
            state.render_size = preset;
            state.render_follows_window = false;
        }
        ImGui::SameLine();
    }
    ImGui::NewLine();
    int size[2] = {state.render_size.x, state.render_size.y};
    if (ImGui::InputInt2("render size", size, ImGuiInputTextFlags_EnterReturnsTrue)) {
        state.render_size = glm::clamp(glm::ivec2(size[0], size[1]), glm::ivec2(1), glm::ivec2(8192));
        state.render_follows_window = false;
    }
    ImGui::Text("window:");
    for (glm::ivec2 preset : presets) {
        ImGui::SameLine();
        char label[40];
        std::snprintf(label, sizeof label, "%dx%d##window", preset.x, preset.y);
        if (ImGui::Button(label)) state.window_request = preset;
    }
}

void ui_view_panel(ViewerState& state)
{
    if (!ImGui::CollapsingHeader("View", ImGuiTreeNodeFlags_DefaultOpen)) return;
    camera_section(state);
    ImGui::Separator();
    light_section(state);
    ImGui::Separator();
    resolution_section(state);
    if (ImGui::TreeNode("Keys")) {
        ImGui::TextUnformatted(k_key_help);
        ImGui::TreePop();
    }
}

} // namespace standin::viewer
