// The viewer's script parser (script.h): lines to commands, every argument checked here so that a
// script fails before the window opens rather than half-way through.
#include "script.h"

#include <standin/debug_view.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace standin::viewer {

namespace {

std::vector<std::string> split_words(std::string_view line)
{
    std::vector<std::string> words;
    std::istringstream stream{std::string(line)};
    for (std::string word; stream >> word;) words.push_back(word);
    return words;
}

bool parse_float(const std::string& text, float& value)
{
    const char* end = text.data() + text.size();
    auto [ptr, ec] = std::from_chars(text.data(), end, value);
    return ec == std::errc() && ptr == end && std::isfinite(value);
}

bool parse_int(const std::string& text, int& value)
{
    const char* end = text.data() + text.size();
    auto [ptr, ec] = std::from_chars(text.data(), end, value);
    return ec == std::errc() && ptr == end;
}

// what one line's words mean; returns an empty string or the problem
std::string parse_words(const std::vector<std::string>& w, ScriptCommand& c, std::span<const OptionSpec> options)
{
    const std::string& verb = w[0];
    const std::size_t args = w.size() - 1;
    auto want = [&](std::size_t n, const char* usage) -> std::string {
        return args == n ? std::string() : std::string("expected '") + usage + "'";
    };
    auto one_of = [&](const std::string& word, std::initializer_list<const char*> choices,
                      const char* usage) -> std::string {
        for (const char* choice : choices)
            if (word == choice) return {};
        return std::string("expected '") + usage + "', got '" + word + "'";
    };
    auto numbers = [&](std::size_t n, const char* usage) -> std::string {
        if (std::string e = want(n, usage); !e.empty()) return e;
        for (std::size_t i = 0; i < n; ++i)
            if (!parse_float(w[i + 1], c.numbers[i])) return "'" + w[i + 1] + "' is not a finite number";
        return {};
    };

    if (verb == "camera") {
        c.op = ScriptOp::camera;
        if (std::string e = numbers(3, "camera AZIMUTH ELEVATION DISTANCE"); !e.empty()) return e;
        if (!(std::abs(c.numbers[1]) <= 90.0f)) return "elevation must be within -90..90 degrees";
        if (!(c.numbers[2] > 0.0f && c.numbers[2] <= 1e4f)) return "distance must be within (0, 10000]";
        return {};
    }
    if (verb == "pan") {
        c.op = ScriptOp::pan;
        return numbers(2, "pan X Y");
    }
    if (verb == "projection") {
        c.op = ScriptOp::projection;
        if (std::string e = want(1, "projection perspective|orthographic"); !e.empty()) return e;
        c.word = w[1];
        return one_of(c.word, {"perspective", "orthographic"}, "projection perspective|orthographic");
    }
    if (verb == "reset" || verb == "reload" || verb == "quit") {
        c.op = verb == "reset" ? ScriptOp::reset : verb == "reload" ? ScriptOp::reload : ScriptOp::quit;
        return want(0, verb.c_str());
    }
    if (verb == "light") {
        c.op = ScriptOp::light;
        if (args == 1 && w[1] == "camera") {
            c.word = "camera";
            return {};
        }
        if (std::string e = numbers(2, "light AZIMUTH ELEVATION"); !e.empty()) return e;
        if (!(std::abs(c.numbers[1]) <= 90.0f)) return "elevation must be within -90..90 degrees";
        return {};
    }
    if (verb == "show") {
        c.op = ScriptOp::show;
        if (args == 1 && w[1] == "original") {
            c.word = "original";
            return {};
        }
        if (args != 2 || w[1] != "package") return "expected 'show original' or 'show package N'";
        c.word = "package";
        if (!parse_int(w[2], c.count) || c.count < 1) return "package number must be 1 or more, got '" + w[2] + "'";
        return {};
    }
    if (verb == "split") {
        c.op = ScriptOp::split;
        if (std::string e = want(1, "split on|off|side"); !e.empty()) return e;
        c.word = w[1];
        return one_of(c.word, {"on", "off", "side"}, "split on|off|side");
    }
    if (verb == "split-position") {
        c.op = ScriptOp::split_position;
        if (std::string e = numbers(1, "split-position FRACTION"); !e.empty()) return e;
        return c.numbers[0] >= 0.0f && c.numbers[0] <= 1.0f ? "" : "split position must be within 0..1";
    }
    if (verb == "debug") {
        c.op = ScriptOp::debug;
        if (std::string e = want(1, "debug NAME|off"); !e.empty()) return e;
        c.word = w[1] == "off" ? "" : w[1];
        std::vector<std::string> names = script_debug_views();
        std::string usage;
        for (const std::string& n : names) usage += (usage.empty() ? "debug " : "|") + n;
        if (std::find(names.begin(), names.end(), w[1]) == names.end())
            return "expected '" + usage + "', got '" + w[1] + "'";
        return {};
    }
    if (verb == "set") {
        c.op = ScriptOp::set;
        if (std::string e = want(2, "set KNOB VALUE"); !e.empty()) return e;
        c.word = w[1];
        c.value = w[2];
        std::string problem, known;
        for (const OptionSpec& spec : options) {
            if (known.find(" " + spec.name + ",") == std::string::npos) known += " " + spec.name + ",";
            if (spec.name != c.word) continue;
            Result<Options::Value> value = parse_option_value(spec, c.value);
            if (value) return {};
            problem = value.status().message();
        }
        if (!problem.empty()) return problem;
        if (!known.empty()) known.pop_back();
        return "unknown option '" + c.word + "' (the packages' run-time options:" + known + ")";
    }
    if (verb == "resolution" || verb == "window") {
        c.op = verb == "resolution" ? ScriptOp::resolution : ScriptOp::window;
        if (std::string e = want(1, (verb + " WxH").c_str()); !e.empty()) return e;
        if (c.op == ScriptOp::resolution && w[1] == "window") {
            c.word = "window";
            return {};
        }
        if (!parse_size(w[1], c.size[0], c.size[1])) return "expected a size WxH within 1x1..16384x16384, got '" + w[1] + "'";
        return {};
    }
    if (verb == "shadows") {
        c.op = ScriptOp::shadows;
        if (std::string e = want(1, "shadows on|off"); !e.empty()) return e;
        c.word = w[1];
        return one_of(c.word, {"on", "off"}, "shadows on|off");
    }
    if (verb == "panels" || verb == "overlay") {
        c.op = verb == "panels" ? ScriptOp::panels : ScriptOp::overlay;
        if (std::string e = want(1, (verb + " on|off").c_str()); !e.empty()) return e;
        c.word = w[1];
        return one_of(c.word, {"on", "off"}, (verb + " on|off").c_str());
    }
    if (verb == "screenshot") {
        c.op = ScriptOp::screenshot;
        if (std::string e = want(1, "screenshot FILE.png"); !e.empty()) return e;
        c.word = w[1];
        if (c.word.size() < 5 || c.word.substr(c.word.size() - 4) != ".png") return "screenshot must be a .png file";
        return {};
    }
    if (verb == "wait") {
        c.op = ScriptOp::wait;
        if (std::string e = want(1, "wait FRAMES"); !e.empty()) return e;
        if (!parse_int(w[1], c.count) || c.count < 0 || c.count > 100000) return "frames must be within 0..100000";
        return {};
    }
    return "unknown command '" + verb + "'";
}

} // namespace

std::vector<std::string> script_debug_views()
{
    std::vector<std::string> names = {"off"};
    for (int v = 1; v < k_debug_view_count; ++v) names.push_back(debug_view_name(DebugView(v)));
    names.push_back("holes");
    return names;
}

bool parse_size(std::string_view text, int& width, int& height)
{
    char x = 0, rest = 0;
    std::string s(text);
    if (std::sscanf(s.c_str(), "%d%c%d%c", &width, &x, &height, &rest) != 3 || (x != 'x' && x != 'X')) return false;
    return width >= 1 && height >= 1 && width <= 16384 && height <= 16384;
}

Result<std::vector<ScriptCommand>> parse_script(std::string_view text, const std::string& name,
                                                std::span<const OptionSpec> options)
{
    std::vector<ScriptCommand> commands;
    int line_number = 0;
    std::size_t start = 0;
    while (start < text.size()) {
        std::size_t end = text.find('\n', start);
        if (end == std::string_view::npos) end = text.size();
        std::string_view line = text.substr(start, end - start);
        start = end + 1;
        ++line_number;

        // comments and blank lines
        if (std::size_t hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
        std::vector<std::string> words = split_words(line);
        if (words.empty()) continue;

        ScriptCommand command;
        command.line = line_number;
        if (std::string problem = parse_words(words, command, options); !problem.empty())
            return error(StatusCode::invalid_argument, name + " line " + std::to_string(line_number) + ": " + problem);
        commands.push_back(std::move(command));
    }
    return commands;
}

} // namespace standin::viewer
