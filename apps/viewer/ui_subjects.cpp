// The "Subjects" panel: which subject is shown, the layout against the original, and each
// package's run-time knobs (the same RenderOptions as `standin render --march ...`).
#include "viewer_state.h"

#include <imgui.h>

namespace standin::viewer {

// rebuilds the renderer after a knob changed; the old options come back when that fails
static void apply(ViewerState& state, Subject& subject, const RenderOptions& previous)
{
    if (Status s = build_renderer(subject); !s) {
        subject.options = previous;
        state.message = s.message();
    }
}

static void enhanced_billboard_knobs(ViewerState& state, Subject& subject)
{
    RenderOptions previous = subject.options;
    RenderOptions& o = subject.options;
    bool seed = o.march == "seed";
    if (ImGui::RadioButton("exact march", !seed)) o.march = "exact";
    ImGui::SameLine();
    if (ImGui::RadioButton("seed march", seed)) o.march = "seed";
    if (o.march != previous.march) return apply(state, subject, previous);
    if (seed) {
        ImGui::SliderInt("steps", &o.steps, 1, 400);
        if (ImGui::IsItemDeactivatedAfterEdit()) return apply(state, subject, previous);
        ImGui::SliderFloat("hit range", &o.hit_range, 0.001f, 0.1f, "%.3f", ImGuiSliderFlags_Logarithmic);
        if (ImGui::IsItemDeactivatedAfterEdit()) return apply(state, subject, previous);
    }
    if (ImGui::Checkbox("coarse mesh fills holes", &o.coarse_mesh)) return apply(state, subject, previous);
}

static void view_atlas_knobs(ViewerState& state, Subject& subject)
{
    RenderOptions previous = subject.options;
    for (const char* style : {"seed", "octahedral-baseline", "corrected"}) {
        if (ImGui::RadioButton(style, subject.options.style == style)) {
            subject.options.style = style;
            return apply(state, subject, previous);
        }
    }
}

static void knobs(ViewerState& state, Subject& subject)
{
    std::string representation = subject.representation();
    if (representation == "enhanced-billboards") return enhanced_billboard_knobs(state, subject);
    if (representation == "view-atlas") return view_atlas_knobs(state, subject);
    ImGui::TextDisabled("no run-time knobs");
}

void ui_subjects_panel(ViewerState& state)
{
    if (!ImGui::CollapsingHeader("Subjects", ImGuiTreeNodeFlags_DefaultOpen)) return;
    for (int i = 0; i < int(state.subjects.size()); ++i) {
        Subject& subject = state.subjects[i];
        ImGui::PushID(i);
        if (ImGui::RadioButton(subject.label.c_str(), state.shown == i)) show_subject(state, i);
        if (!subject.is_original()) {
            ImGui::Indent();
            knobs(state, subject);
            ImGui::Unindent();
        }
        ImGui::PopID();
    }
    ImGui::TextDisabled("Tab toggles original / stand-in, 0-9 pick");

    ImGui::Separator();
    if (state.original < 0 || state.stand_in < 0) {
        ImGui::TextDisabled("split views need the model and a package");
        return;
    }
    int layout = int(state.layout);
    ImGui::RadioButton("alone", &layout, int(Layout::single));
    ImGui::SameLine();
    ImGui::RadioButton("split", &layout, int(Layout::split));
    ImGui::SameLine();
    ImGui::RadioButton("side by side", &layout, int(Layout::side_by_side));
    state.layout = Layout(layout);
    if (state.layout == Layout::split) ImGui::SliderFloat("split at", &state.split_position, 0.0f, 1.0f, "%.2f");
}

} // namespace standin::viewer
