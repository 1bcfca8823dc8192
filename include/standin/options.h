// Options that a representation declares: its bake parameters and its run-time (render) options.
// A representation lists OptionSpecs; the command line, `--help`, the viewer's knobs panel and its
// script are generated from them, and values given by name (OptionValues) are checked against them
// once (Options::parse), the way pbrt-v4 reads a shape's parameters by name and reports unused ones.
#pragma once

#include <standin/status.h>

#include <cstdint>
#include <map>
#include <set>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace standin {

enum class OptionType {
    integer, // a whole number within [min, max]
    number,  // a finite real number within [min, max] (or (min, max] when min_exclusive)
    choice,  // one of `choices`
    flag,    // on or off; given as on/off, true/false, yes/no or 1/0
};

// One declared option. Names are lowercase words joined by '-' ("hit-range"): `--hit-range` on the
// command line, `set hit-range 0.02` in a viewer script, "hit_range" in a package manifest.
struct OptionSpec {
    std::string name;
    OptionType type = OptionType::number;
    // As the user would type it ("exact", "100", "0.01", "on"). Empty: none; the representation
    // derives the value from others (for example a texel size from a resolution).
    std::string default_value;
    double min = 0.0, max = 0.0; // integer, number
    bool min_exclusive = false;  // number: min itself is refused
    std::vector<std::string> choices;
    std::string help; // one line, no trailing period
};

// Declaration helpers, so that a representation's list reads as a table.
OptionSpec integer_option(std::string name, int default_value, int min, int max, std::string help);
OptionSpec number_option(std::string name, std::string default_value, double min, double max, std::string help,
                         bool min_exclusive = false);
OptionSpec choice_option(std::string name, std::string default_value, std::vector<std::string> choices,
                         std::string help);
OptionSpec flag_option(std::string name, bool default_value, std::string help);

// "INT in 16..16384", "NUMBER in (0, 1]", "exact|seed", "on|off": what a value must look like.
std::string describe_values(const OptionSpec& spec);

// Values by name, as text, before they are checked: what a command line, a viewer script or a bench
// `--param NAME=VALUE` gives.
class OptionValues {
public:
    void set(const std::string& name, std::string value) { values_[name] = std::move(value); }
    bool has(const std::string& name) const { return values_.count(name) != 0; }
    const std::map<std::string, std::string>& items() const { return values_; }
    bool empty() const { return values_.empty(); }
    // The values whose names `specs` declares.
    OptionValues only(std::span<const OptionSpec> specs) const;

private:
    std::map<std::string, std::string> values_;
};

// Typed values of every declared option: those given, checked, and the defaults of the rest.
// Reading a name that was not declared with that type is a programmer error (assert).
class Options {
public:
    Options() = default;

    // Every given name must be declared (else "--NAME does not apply to OWNER"), every value must
    // parse as its type and lie within its range or choices ("--NAME: 'x' is not an integer",
    // "--NAME: 20000 is out of range 16..16384"). Errors are invalid_argument, one line.
    static Result<Options> parse(std::span<const OptionSpec> specs, const OptionValues& given, const std::string& owner);

    int integer(std::string_view name) const;
    float number(std::string_view name) const;
    const std::string& choice(std::string_view name) const;
    bool flag(std::string_view name) const;
    // Whether the value was given rather than defaulted (the default of an option without one
    // reads as 0 / "" / off).
    bool given(std::string_view name) const;
    bool declared(std::string_view name) const;

    // Replaces a value with one the representation resolved (a derived texel size, say), so that a
    // package records what was used. The value must already satisfy the declaration.
    void set_integer(std::string_view name, int value);
    void set_number(std::string_view name, float value);
    void set_choice(std::string_view name, std::string value);

    // The value as the user would type it ("0.01", "on").
    std::string text(std::string_view name) const;

    struct Value {
        OptionType type = OptionType::number;
        std::int64_t integer = 0;
        float number = 0.0f;
        std::string choice;
        bool flag = false;
        bool given = false;
        bool requested = false; // given, with another value than the declared default
    };
    // The options given with another value than their default, as text by name: what a user asked
    // for beyond the defaults (a package records it; a batch bake compares it to skip up-to-date
    // packages).
    std::map<std::string, std::string> requested() const;
    // Marks exactly `names` as requested: a package read back keeps the record its manifest holds
    // rather than counting every resolved value (a derived texel size) as asked for.
    void set_requested(const std::set<std::string>& names);
    // In declaration order.
    const std::vector<std::pair<std::string, Value>>& values() const { return values_; }

private:
    const Value& at(std::string_view name, OptionType type) const;
    Value& at(std::string_view name, OptionType type);
    std::vector<std::pair<std::string, Value>> values_;
};

// Parses one value against its declaration; the error names `--NAME`.
Result<Options::Value> parse_option_value(const OptionSpec& spec, const std::string& text);

} // namespace standin
