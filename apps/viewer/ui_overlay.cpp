// The overlay: frame time (GPU timer query and CPU wall time to glFinish), primitives drawn and
// pixels covered per subject, and the labels of the images in the window.
#include "frame_renderer.h"

#include <imgui.h>

namespace standin::viewer {

static void label(float x, float y, const std::string& s)
{
    ImDrawList* draw = ImGui::GetBackgroundDrawList();
    draw->AddText(ImVec2(x + 1, y + 1), IM_COL32(0, 0, 0, 200), s.c_str());
    draw->AddText(ImVec2(x, y), IM_COL32(255, 255, 255, 230), s.c_str());
}

// the divider of the split view always; the names of the images with the overlay
static void labels(const ViewerState& state, const FrameLayout& layout)
{
    if (layout.split_x >= 0.0f)
        ImGui::GetBackgroundDrawList()->AddLine(ImVec2(layout.split_x, layout.left.y),
                                                ImVec2(layout.split_x, layout.left.w), IM_COL32(255, 255, 255, 200));
    if (!state.show_overlay) return;
    const float line = ImGui::GetTextLineHeight();
    label(layout.left.x + 4, layout.left.w - line - 4, layout.left_label);
    if (layout.split_x >= 0.0f) {
        float width = ImGui::CalcTextSize(layout.right_label.c_str()).x;
        label(layout.left.z - width - 4, layout.left.w - 2 * line - 4, layout.right_label);
    } else if (layout.right.z > layout.right.x) {
        label(layout.right.x + 4, layout.right.w - line - 4, layout.right_label);
    }
}

void ui_overlay(const ViewerState& state, const FrameLayout& layout)
{
    labels(state, layout);
    if (!state.show_overlay) return;
    ImGui::SetNextWindowPos(ImVec2(6, 6));
    ImGui::SetNextWindowBgAlpha(0.6f);
    const ImGuiWindowFlags flags = ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize |
                                   ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoFocusOnAppearing |
                                   ImGuiWindowFlags_NoNav | ImGuiWindowFlags_NoInputs;
    if (!ImGui::Begin("overlay", nullptr, flags)) return ImGui::End();
    ImGui::Text("render %dx%d", state.stats.render_size.x, state.stats.render_size.y);
    const double total = double(state.stats.render_size.x) * double(state.stats.render_size.y);
    for (const SubjectStats& s : state.stats.subjects) {
        const Subject& subject = state.subjects[s.subject];
        ImGui::TextUnformatted(subject.label.c_str());
        ImGui::Text("  frame %.2f ms GPU, %.2f ms CPU", s.gpu_ms, s.wall_ms);
        if (!subject.is_original()) ImGui::Text("  %s", subject.contents.c_str());
        ImGui::Text("  %llu %s in %llu draw%s", (unsigned long long)s.draw.primitives,
                    subject.is_original() ? "triangles" : "primitives", (unsigned long long)s.draw.draw_calls,
                    s.draw.draw_calls == 1 ? "" : "s");
        const double percent = total > 0 ? 100.0 * double(s.covered_pixels) / total : 0.0;
        if (s.fetches_per_pixel >= 0.0)
            ImGui::Text("  %zu px covered (%.1f%%), %.1f fetches/px", s.covered_pixels, percent, s.fetches_per_pixel);
        else
            ImGui::Text("  %zu px covered (%.1f%%)", s.covered_pixels, percent);
    }
    if (state.debug_view == "holes")
        ImGui::Text("holes %zu px (red), excess %zu px (blue)", state.stats.hole_pixels, state.stats.excess_pixels);
    ImGui::End();
}

} // namespace standin::viewer
