// Declared options, checked once (include/standin/options.h).
#include <standin/options.h>

#include <algorithm>
#include <cassert>
#include <charconv>
#include <cmath>
#include <cstdlib>

namespace standin {

namespace {

std::string format_number(double x)
{
    char text[64];
    auto [end, ec] = std::to_chars(text, text + sizeof text, x);
    return ec == std::errc() ? std::string(text, end) : std::to_string(x);
}

std::string format_float(float x)
{
    char text[64];
    auto [end, ec] = std::to_chars(text, text + sizeof text, x);
    return ec == std::errc() ? std::string(text, end) : std::to_string(x);
}

bool parse_flag(const std::string& text, bool& value)
{
    static const char* const k_on[] = {"on", "true", "yes", "1"};
    static const char* const k_off[] = {"off", "false", "no", "0"};
    for (const char* word : k_on)
        if (text == word) return value = true, true;
    for (const char* word : k_off)
        if (text == word) return value = false, true;
    return false;
}

} // namespace

OptionSpec integer_option(std::string name, int default_value, int min, int max, std::string help)
{
    OptionSpec s;
    s.name = std::move(name);
    s.type = OptionType::integer;
    s.default_value = std::to_string(default_value);
    s.min = min;
    s.max = max;
    s.help = std::move(help);
    return s;
}

OptionSpec number_option(std::string name, std::string default_value, double min, double max, std::string help,
                         bool min_exclusive)
{
    OptionSpec s;
    s.name = std::move(name);
    s.type = OptionType::number;
    s.default_value = std::move(default_value);
    s.min = min;
    s.max = max;
    s.min_exclusive = min_exclusive;
    s.help = std::move(help);
    return s;
}

OptionSpec choice_option(std::string name, std::string default_value, std::vector<std::string> choices, std::string help)
{
    OptionSpec s;
    s.name = std::move(name);
    s.type = OptionType::choice;
    s.default_value = std::move(default_value);
    s.choices = std::move(choices);
    s.help = std::move(help);
    return s;
}

OptionSpec flag_option(std::string name, bool default_value, std::string help)
{
    OptionSpec s;
    s.name = std::move(name);
    s.type = OptionType::flag;
    s.default_value = default_value ? "on" : "off";
    s.help = std::move(help);
    return s;
}

std::string describe_values(const OptionSpec& spec)
{
    switch (spec.type) {
    case OptionType::integer: return "INT in " + std::to_string(std::int64_t(spec.min)) + ".." + std::to_string(std::int64_t(spec.max));
    case OptionType::number:
        return std::string("NUMBER in ") + (spec.min_exclusive ? "(" : "[") + format_number(spec.min) + ", " +
               format_number(spec.max) + "]";
    case OptionType::choice: {
        std::string list;
        for (const std::string& c : spec.choices) list += (list.empty() ? "" : "|") + c;
        return list;
    }
    case OptionType::flag: return "on|off";
    }
    return {};
}

OptionValues OptionValues::only(std::span<const OptionSpec> specs) const
{
    OptionValues out;
    for (const OptionSpec& spec : specs)
        if (auto it = values_.find(spec.name); it != values_.end()) out.set(spec.name, it->second);
    return out;
}

Result<Options::Value> parse_option_value(const OptionSpec& spec, const std::string& text)
{
    const std::string option = "--" + spec.name;
    Options::Value value;
    value.type = spec.type;
    switch (spec.type) {
    case OptionType::integer: {
        std::int64_t x = 0;
        auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), x);
        if (ec != std::errc() || end != text.data() + text.size())
            return error(StatusCode::invalid_argument, option + ": '" + text + "' is not an integer");
        if (double(x) < spec.min || double(x) > spec.max)
            return error(StatusCode::invalid_argument, option + ": " + text + " is out of range " +
                                                           std::to_string(std::int64_t(spec.min)) + ".." +
                                                           std::to_string(std::int64_t(spec.max)));
        value.integer = x;
        return value;
    }
    case OptionType::number: {
        // Parsed as float, as the renderers and bakers hold them, so that a package records
        // exactly the value that was used.
        char* end = nullptr;
        float x = std::strtof(text.c_str(), &end);
        if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(x))
            return error(StatusCode::invalid_argument, option + ": '" + text + "' is not a finite number");
        bool below = spec.min_exclusive ? !(double(x) > spec.min) : double(x) < spec.min;
        if (below || double(x) > spec.max)
            return error(StatusCode::invalid_argument, option + ": " + text + " is out of range " +
                                                           (spec.min_exclusive ? "(" : "[") + format_number(spec.min) +
                                                           ", " + format_number(spec.max) + "]");
        value.number = x;
        return value;
    }
    case OptionType::choice:
        if (std::find(spec.choices.begin(), spec.choices.end(), text) == spec.choices.end())
            return error(StatusCode::invalid_argument,
                         option + ": '" + text + "' is not one of " + describe_values(spec));
        value.choice = text;
        return value;
    case OptionType::flag:
        if (!parse_flag(text, value.flag))
            return error(StatusCode::invalid_argument, option + ": '" + text + "' is not on or off");
        return value;
    }
    return error(StatusCode::invalid_argument, option + ": unknown type");
}

Result<Options> Options::parse(std::span<const OptionSpec> specs, const OptionValues& given, const std::string& owner)
{
    for (const auto& [name, text] : given.items()) {
        bool declared = std::any_of(specs.begin(), specs.end(), [&](const OptionSpec& s) { return s.name == name; });
        if (!declared) return error(StatusCode::invalid_argument, "--" + name + " does not apply to " + owner);
    }
    Options options;
    for (const OptionSpec& spec : specs) {
        assert(std::none_of(options.values_.begin(), options.values_.end(), [&](const auto& v) { return v.first == spec.name; }));
        auto it = given.items().find(spec.name);
        Value value;
        value.type = spec.type;
        if (it != given.items().end()) {
            Result<Value> parsed = parse_option_value(spec, it->second);
            if (!parsed) return parsed.status();
            value = *parsed;
            value.given = true;
            value.requested = spec.default_value.empty() || it->second != spec.default_value;
            if (value.requested && !spec.default_value.empty()) {
                // "0.010" asks for the default 0.01 too: compare the parsed values
                Result<Value> fallback = parse_option_value(spec, spec.default_value);
                value.requested = !fallback || fallback->integer != value.integer || fallback->number != value.number ||
                                  fallback->choice != value.choice || fallback->flag != value.flag;
            }
        } else if (!spec.default_value.empty()) {
            Result<Value> parsed = parse_option_value(spec, spec.default_value);
            assert(parsed.is_ok() && "a declared default must satisfy its own declaration");
            if (parsed) value = *parsed;
        }
        options.values_.push_back({spec.name, value});
    }
    return options;
}

const Options::Value& Options::at(std::string_view name, OptionType type) const
{
    auto it = std::find_if(values_.begin(), values_.end(), [&](const auto& v) { return v.first == name; });
    assert(it != values_.end() && "option not declared");
    assert(it->second.type == type && "option read with another type");
    (void)type;
    return it->second;
}

Options::Value& Options::at(std::string_view name, OptionType type)
{
    return const_cast<Value&>(static_cast<const Options&>(*this).at(name, type));
}

int Options::integer(std::string_view name) const { return int(at(name, OptionType::integer).integer); }
float Options::number(std::string_view name) const { return at(name, OptionType::number).number; }
const std::string& Options::choice(std::string_view name) const { return at(name, OptionType::choice).choice; }
bool Options::flag(std::string_view name) const { return at(name, OptionType::flag).flag; }

bool Options::given(std::string_view name) const
{
    auto it = std::find_if(values_.begin(), values_.end(), [&](const auto& v) { return v.first == name; });
    return it != values_.end() && it->second.given;
}

bool Options::declared(std::string_view name) const
{
    return std::any_of(values_.begin(), values_.end(), [&](const auto& v) { return v.first == name; });
}

void Options::set_integer(std::string_view name, int value) { at(name, OptionType::integer).integer = value; }
void Options::set_number(std::string_view name, float value) { at(name, OptionType::number).number = value; }
void Options::set_choice(std::string_view name, std::string value) { at(name, OptionType::choice).choice = std::move(value); }

std::map<std::string, std::string> Options::requested() const
{
    std::map<std::string, std::string> out;
    for (const auto& [name, value] : values_)
        if (value.requested) out[name] = text(name);
    return out;
}

void Options::set_requested(const std::set<std::string>& names)
{
    for (auto& [name, value] : values_) value.requested = names.count(name) > 0;
}

std::string Options::text(std::string_view name) const
{
    auto it = std::find_if(values_.begin(), values_.end(), [&](const auto& v) { return v.first == name; });
    assert(it != values_.end());
    const Value& v = it->second;
    switch (v.type) {
    case OptionType::integer: return std::to_string(v.integer);
    case OptionType::number: return format_float(v.number);
    case OptionType::choice: return v.choice;
    case OptionType::flag: return v.flag ? "on" : "off";
    }
    return {};
}

} // namespace standin
