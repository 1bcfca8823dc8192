// libFuzzer harness: the viewer's script parser (apps/viewer/script.cpp), pure: text in, commands or
// one Status out. A parsed command must hold arguments within the ranges script.h documents.
#include "viewer/script.h"

#include <cmath>
#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    std::string_view text(reinterpret_cast<const char*>(data), size);
    auto commands = standin::viewer::parse_script(text, "fuzz.script");
    if (!commands) {
        if (commands.status().message().find('\n') != std::string::npos) __builtin_trap(); // one line
        return 0;
    }
    for (const standin::viewer::ScriptCommand& c : *commands)
        for (float n : c.numbers)
            if (!std::isfinite(n)) __builtin_trap();
    return 0;
}
