// Names of the shared debug views (include/standin/debug_view.h).
#include <standin/debug_view.h>

namespace standin {

namespace {

struct Entry {
    DebugView view;
    const char* name;
    const char* description;
};

constexpr Entry k_entries[k_debug_view_count] = {
    {DebugView::none, "off", "the shaded picture"},
    {DebugView::parts, "parts", "each pixel coloured by the part of the stand-in it came from"},
    {DebugView::depth, "depth", "window depth, near white"},
    {DebugView::normal, "normal", "the shading normal, world space"},
    {DebugView::fetches, "fetches", "texture reads per pixel, heat map (red: 64 or more)"},
    {DebugView::proxies, "proxies", "the proxy geometry as lines over the picture (hidden parts dimmed)"},
    {DebugView::level, "level", "level of detail chosen, heat map"},
    {DebugView::error, "error", "approximation error, heat map"},
};

} // namespace

const char* debug_view_name(DebugView view) { return k_entries[int(view)].name; }
const char* debug_view_description(DebugView view) { return k_entries[int(view)].description; }

Result<DebugView> parse_debug_view(const std::string& name)
{
    if (name.empty()) return DebugView::none;
    for (const Entry& e : k_entries)
        if (name == e.name) return e.view;
    std::string names;
    for (const Entry& e : k_entries) names += std::string(names.empty() ? "" : ", ") + e.name;
    return error(StatusCode::invalid_argument, "--debug-view: '" + name + "' is not one of " + names);
}

} // namespace standin
