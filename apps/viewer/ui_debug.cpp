// The "Debug" panel: the renderers' debug views, the viewer's holes view, fetch counting, shader
// reload and screenshots.
#include "viewer_state.h"

#include <imgui.h>

namespace standin::viewer {

static std::string describe(const std::string& view)
{
    if (view.empty()) return "off";
    if (view == "holes") return "holes against the original";
    Result<DebugView> parsed = parse_debug_view(view);
    return parsed ? view + ": " + debug_view_description(*parsed) : view;
}

void ui_debug_panel(ViewerState& state)
{
    if (!ImGui::CollapsingHeader("Debug", ImGuiTreeNodeFlags_DefaultOpen)) return;
    std::vector<std::string> views = available_debug_views(state);
    views.insert(views.begin(), "");
    for (const std::string& view : views) {
        if (ImGui::RadioButton(describe(view).c_str(), state.debug_view == view) && state.debug_view != view) {
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
