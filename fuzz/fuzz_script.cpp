// libFuzzer harness: the viewer's script parser (apps/viewer/script.cpp), pure: text in, commands or
// one Status out. A parsed command must hold arguments within the ranges script.h documents.
#include "viewer/script.h"

#include <standin/package.h>

#include <cmath>
#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    // `set` checks its values against every representation's run-time options, as the viewer does
    static const std::vector<standin::OptionSpec> options = [] {
        std::vector<standin::OptionSpec> all;
        for (const standin::Representation& r : standin::representations())
            all.insert(all.end(), r.render_options.begin(), r.render_options.end());
        return all;
    }();
    std::string_view text(reinterpret_cast<const char*>(data), size);
    auto commands = standin::viewer::parse_script(text, "fuzz.script", options);
    if (!commands) {
        if (commands.status().message().find('\n') != std::string::npos) __builtin_trap(); // one line
        return 0;
    }
    for (const standin::viewer::ScriptCommand& c : *commands)
        for (float n : c.numbers)
            if (!std::isfinite(n)) __builtin_trap();
    return 0;
}
