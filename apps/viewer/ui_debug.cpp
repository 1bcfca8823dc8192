// The "Debug" panel: the renderers' debug views, the viewer's holes view, fetch counting, shader
// reload and screenshots.
#include "viewer_state.h"

#include <imgui.h>

namespace standin::viewer {

static const char* describe(const std::string& view)
{
    if (view.empty()) return "off";
    if (view == "billboard") return "billboard (which billboard each pixel came from)";
    if (view == "depth") return "depth";
    if (view == "normal") return "normals";
    if (view == "fetches") return "height-field fetches per pixel (heat map)";
    if (view == "boxes") return "billboard boxes (lines; front planes red)";
    return "holes against the original";
}

void ui_debug_panel(ViewerState& state)
{
    if (!ImGui::CollapsingHeader("Debug", ImGuiTreeNodeFlags_DefaultOpen)) return;
    for (const char* view : k_debug_views) {
        if (ImGui::RadioButton(describe(view), state.debug_view == view) && state.debug_view != view) {
            if (Status s = set_debug_view(state, view); !s) state.message = s.message();
        }
    }
    ImGui::TextDisabled("D cycles; package renderers only, holes needs the model");
    ImGui::Checkbox("count fetches", &state.count_fetches);
    ImGui::Separator();
    if (ImGui::Button("reload shaders (F5)")) state.want_reload = true;
    ImGui::SameLine();
    if (ImGui::Button("screenshot (F12)")) state.want_screenshot = true;
    ImGui::Checkbox("overlay (F2)", &state.show_overlay);
    if (!state.message.empty()) ImGui::TextWrapped("%s", state.message.c_str());
}

} // namespace standin::viewer
