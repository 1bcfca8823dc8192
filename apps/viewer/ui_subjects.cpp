// The "Subjects" panel: which subject is shown, the layout against the original, and each
// package's run-time options, one widget per option its representation declares (the same options
// as `standin render --NAME VALUE`).
#include "viewer_state.h"

#include <imgui.h>

#include <algorithm>
#include <cstdio>

namespace standin::viewer {

// the value an option has in a subject: given, or its declared default
static std::string current_value(const Subject& subject, const OptionSpec& spec)
{
    auto it = subject.options.values.items().find(spec.name);
    return it != subject.options.values.items().end() ? it->second : spec.default_value;
}

static void set(ViewerState& state, Subject& subject, const OptionSpec& spec, const std::string& value)
{
    if (Status s = set_package_option(subject, spec.name, value); !s) state.message = s.message();
}

static void option_widget(ViewerState& state, Subject& subject, const OptionSpec& spec)
{
    std::string value = current_value(subject, spec);
    switch (spec.type) {
    case OptionType::choice: {
        if (ImGui::BeginCombo(spec.name.c_str(), value.c_str())) {
            for (const std::string& choice : spec.choices)
                if (ImGui::Selectable(choice.c_str(), choice == value) && choice != value) set(state, subject, spec, choice);
            ImGui::EndCombo();
        }
        break;
    }
    case OptionType::flag: {
        bool on = value == "on" || value == "true" || value == "yes" || value == "1";
        if (ImGui::Checkbox(spec.name.c_str(), &on)) set(state, subject, spec, on ? "on" : "off");
        break;
    }
    case OptionType::integer: {
        int number = std::atoi(value.c_str());
        ImGui::InputInt(spec.name.c_str(), &number);
        if (ImGui::IsItemDeactivatedAfterEdit()) {
            number = std::clamp(number, int(spec.min), int(spec.max));
            set(state, subject, spec, std::to_string(number));
        }
        break;
    }
    case OptionType::number: {
        float number = std::strtof(value.c_str(), nullptr);
        ImGui::InputFloat(spec.name.c_str(), &number, 0.0f, 0.0f, "%.4g");
        if (ImGui::IsItemDeactivatedAfterEdit()) {
            char text[32];
            std::snprintf(text, sizeof text, "%.6g", std::clamp(double(number), spec.min, spec.max));
            set(state, subject, spec, text);
        }
        break;
    }
    }
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", spec.help.c_str());
}

static void options_panel(ViewerState& state, Subject& subject)
{
    const std::vector<OptionSpec>& specs = representation_of(*subject.package).render_options;
    if (specs.empty()) ImGui::TextDisabled("no run-time options");
    for (const OptionSpec& spec : specs) option_widget(state, subject, spec);
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
            ImGui::TextDisabled("%s", subject.contents.c_str());
            options_panel(state, subject);
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
