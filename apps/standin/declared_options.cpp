// Declared options on the command line (declared_options.h).
#include "declared_options.h"

#include <algorithm>
#include <cctype>
#include <map>

namespace standin::cli {

namespace {

std::string type_name(const OptionSpec& spec)
{
    switch (spec.type) {
    case OptionType::integer: return "INT";
    case OptionType::number: return "FLOAT";
    case OptionType::choice: return describe_values(spec);
    case OptionType::flag: return "";
    }
    return "";
}

std::string range_note(const OptionSpec& spec)
{
    if (spec.type == OptionType::integer || spec.type == OptionType::number) return " (" + describe_values(spec) + ")";
    return "";
}

} // namespace

void DeclaredOptions::add_to(CLI::App& command, OptionKind kind)
{
    // name -> every representation's declaration of it, in registry order
    std::vector<std::string> order;
    std::map<std::string, std::vector<std::pair<const Representation*, const OptionSpec*>>> declared;
    for (const Representation& r : representations()) {
        const std::vector<OptionSpec>& specs =
            kind == OptionKind::bake ? r.bake_options : kind == OptionKind::render ? r.render_options : r.export_options;
        for (const OptionSpec& spec : specs) {
            if (!declared.count(spec.name)) order.push_back(spec.name);
            declared[spec.name].push_back({&r, &spec});
        }
    }
    for (const std::string& name : order) {
        const auto& owners = declared[name];
        const Representation& first = *owners.front().first;
        const OptionSpec& spec = *owners.front().second;
        std::string group = first.title + (kind == OptionKind::bake ? " (-r " + first.name + ")" : " packages");
        auto entry = std::make_unique<Entry>();
        entry->name = name;
        std::string help;
        if (owners.size() == 1) {
            help = spec.help + range_note(spec);
        } else {
            for (const auto& [r, s] : owners)
                help += (help.empty() ? "" : "; ") + r->name + ": " + s->help + range_note(*s) +
                        (s->default_value.empty() ? "" : " [" + s->default_value + "]");
        }
        bool all_flags = std::all_of(owners.begin(), owners.end(), [](const auto& o) { return o.second->type == OptionType::flag; });
        if (all_flags) {
            // a flag is given to change its default: --no-NAME when it is on, --NAME when off
            bool on = spec.default_value == "on";
            entry->flag = true;
            entry->flag_value = on ? "off" : "on";
            // "Fill holes ..." becomes "Do not fill holes ..."
            std::string flag_help = help;
            if (on && !flag_help.empty()) flag_help = "Do not " + std::string(1, char(std::tolower(flag_help[0]))) + flag_help.substr(1);
            entry->option = command.add_flag(on ? "--no-" + name : "--" + name)->description(flag_help);
        } else {
            entry->option = command.add_option("--" + name, entry->value, help);
            entry->option->type_name(owners.size() == 1 ? type_name(spec) : spec.type == OptionType::number ? "FLOAT" : "VALUE");
            if (owners.size() == 1 && !spec.default_value.empty()) entry->option->default_str(spec.default_value);
        }
        entry->option->group(group);
        entries_.push_back(std::move(entry));
    }
}

OptionValues DeclaredOptions::given() const
{
    OptionValues values;
    for (const auto& entry : entries_)
        if (entry->option->count() > 0) values.set(entry->name, entry->flag ? entry->flag_value : entry->value);
    return values;
}

std::string DeclaredOptions::command_line() const
{
    std::string line;
    for (const auto& entry : entries_) {
        if (entry->option->count() == 0) continue;
        line += " " + entry->option->get_name();
        if (!entry->flag) line += " " + entry->value;
    }
    return line;
}

Status check_render_options_apply(const RenderOptions& options, std::span<const Representation* const> at_hand)
{
    auto declares = [](const Representation& r, const std::string& name) {
        return std::any_of(r.render_options.begin(), r.render_options.end(), [&](const OptionSpec& s) { return s.name == name; });
    };
    std::string what;
    for (const Representation* r : at_hand) what += (what.empty() ? "" : " or ") + r->name;
    what = what.empty() ? "a model (the ground-truth renderer has no options)" : what + " packages";
    for (const auto& [name, value] : options.values.items()) {
        if (std::any_of(at_hand.begin(), at_hand.end(), [&](const Representation* r) { return declares(*r, name); })) continue;
        std::string owners;
        for (const Representation& r : representations())
            if (declares(r, name)) owners += (owners.empty() ? "" : ", ") + r.name;
        return error(StatusCode::invalid_argument, "--" + name + " does not apply to " + what +
                                                       (owners.empty() ? "" : " (an option of " + owners + ")"));
    }
    if (options.debug_view == DebugView::none) return Status::ok();
    if (at_hand.empty())
        return error(StatusCode::invalid_argument, std::string("--debug-view ") + debug_view_name(options.debug_view) +
                                                       ": the ground-truth renderer of a model has no debug views");
    for (const Representation* r : at_hand)
        if (std::find(r->debug_views.begin(), r->debug_views.end(), options.debug_view) != r->debug_views.end())
            return Status::ok();
    return error(StatusCode::invalid_argument,
                 std::string("--debug-view ") + debug_view_name(options.debug_view) + " is not drawn for " + what);
}

void add_debug_view_option(CLI::App& command, std::string& name, bool with_holes)
{
    std::vector<std::string> names;
    std::string help = "A debug view instead of the shaded picture (package renderers): ";
    for (int v = 1; v < k_debug_view_count; ++v) {
        names.push_back(debug_view_name(DebugView(v)));
        help += std::string(v > 1 ? "; " : "") + names.back() + " = " + debug_view_description(DebugView(v));
    }
    if (with_holes) {
        names.push_back("holes");
        help += "; holes = pixels the stand-in misses or adds against the model";
    }
    names.push_back("off");
    command.add_option("--debug-view", name, help)->check(CLI::IsMember(names));
}

} // namespace standin::cli
