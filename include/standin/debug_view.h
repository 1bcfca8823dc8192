// Debug views and GPU counters: one vocabulary for every renderer, the command line, the viewer and
// its script. The GLSL twin is src/gpu/shaders/common/debug_views.h (checked against this file at
// build time).
#pragma once

#include <standin/status.h>

#include <string>

namespace standin {

// Debug views, one vocabulary for every renderer (the GLSL twin is
// src/gpu/shaders/common/debug_views.h). A representation lists the ones its renderer draws.
enum class DebugView {
    none = 0,
    parts = 1,   // each pixel coloured by the part of the stand-in it came from
    depth = 2,   // window depth, near white
    normal = 3,  // the shading normal, world space
    fetches = 4, // texture reads per pixel, a heat map over 0..k_fetches_heat_max
    proxies = 5, // the proxy geometry drawn (boxes, hulls, facets) as lines over the picture
    level = 6,   // level of detail chosen per pixel, a heat map
    error = 7,   // approximation error per pixel, a heat map
};
constexpr int k_debug_view_count = 8;
// The fetch count a debug heat map shows as red: the same scale for every renderer.
constexpr int k_fetches_heat_max = 64;
const char* debug_view_name(DebugView view);       // "parts", ...; "off" for none
const char* debug_view_description(DebugView view); // one line for --help and the viewer
// "off" (or "") is none; an unknown name is an invalid_argument error listing the names.
Result<DebugView> parse_debug_view(const std::string& name);

// GPU counters a renderer may keep while counting (zero when it does not).
enum class Counter {
    fragments = 0, // fragment-stage invocations (overdraw = fragments / covered pixels)
    fetches = 1,   // texture reads of the stand-in's maps
};

} // namespace standin
