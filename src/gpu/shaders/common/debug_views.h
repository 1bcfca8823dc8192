// Debug views and GPU counters, one vocabulary for every renderer: included by GLSL and by C++
// (src/gpu/debug_views.cpp checks these numbers against include/standin/render.h's DebugView and
// Counter). Plain #defines only: both languages must parse this file.
#ifndef STANDIN_DEBUG_VIEWS_H
#define STANDIN_DEBUG_VIEWS_H

#define DEBUG_VIEW_NONE 0
#define DEBUG_VIEW_PARTS 1   // colour by part (index_color in debug_colors.glsl)
#define DEBUG_VIEW_DEPTH 2   // window depth, near white
#define DEBUG_VIEW_NORMAL 3  // shading normal, world space, n * 0.5 + 0.5
#define DEBUG_VIEW_FETCHES 4 // texture reads per pixel: heat(fetches / FETCHES_HEAT_MAX)
#define DEBUG_VIEW_PROXIES 5 // proxy geometry as lines over the shaded picture
#define DEBUG_VIEW_LEVEL 6   // level of detail: heat(level / levels)
#define DEBUG_VIEW_ERROR 7   // approximation error: heat(error / tolerance)
#define DEBUG_VIEW_COUNT 8

// The fetch count shown red in DEBUG_VIEW_FETCHES (render.h k_fetches_heat_max).
#define FETCHES_HEAT_MAX 64.0

// counters[] of the BINDING_COUNTERS_SSBO block: the shared ones first; a representation may keep
// more of its own from COUNTER_SHARED_COUNT on
#define COUNTER_FRAGMENTS 0 // fragment-stage invocations while counting
#define COUNTER_FETCHES 1   // texture reads of the stand-in's maps
#define COUNTER_SHARED_COUNT 2

#endif
