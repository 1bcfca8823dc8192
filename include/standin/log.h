// The library's diagnostics go to a sink the application installs; by default they go nowhere,
// because a library never prints on its own.
#pragma once

#include <functional>
#include <string>

namespace standin {

enum class LogLevel { debug, info, warning, error };
using LogSink = std::function<void(LogLevel, const std::string&)>;

void set_log_sink(LogSink sink);
void log_message(LogLevel level, const std::string& message);

} // namespace standin
