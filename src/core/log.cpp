#include <standin/log.h>

#include <mutex>

namespace standin {

static std::mutex g_log_mutex;
static LogSink g_log_sink;

void set_log_sink(LogSink sink)
{
    std::lock_guard lock(g_log_mutex);
    g_log_sink = std::move(sink);
}

void log_message(LogLevel level, const std::string& message)
{
    std::lock_guard lock(g_log_mutex);
    if (g_log_sink) g_log_sink(level, message);
}

} // namespace standin
