// Constants shared by the view-atlas renderer's C++ (renderer.cpp includes this file) and its
// shaders. Plain #defines only: both languages must parse this file.
#ifndef STANDIN_ATLAS_LAYOUT_GLSL
#define STANDIN_ATLAS_LAYOUT_GLSL

// shader storage blocks
#define ATLAS_VIEWS_SSBO 1     // ViewData[]
#define ATLAS_INDEX_SSBO 2     // int[]: the direction lookup cube, then NEIGHBOURS per view
#define ATLAS_COUNTERS_SSBO 3  // uint[ATLAS_COUNTER_COUNT], written when counting
#define ATLAS_COUNTER_FRAGMENTS 0 // fragment invocations (overdraw = fragments / covered pixels)
#define ATLAS_COUNTER_FETCHES 1   // texture reads
#define ATLAS_COUNTER_COUNT 2

// texture units: each map's pages lie in up to ATLAS_MAX_ARRAYS texture arrays (units
// ATLAS_COLOR_TEXTURE + i and ATLAS_NORMAL_DEPTH_TEXTURE + i hold array i); a view's array is
// ViewData.atlas.w, its layer ViewData.atlas.x
#define ATLAS_MAX_ARRAYS 8
#define ATLAS_COLOR_TEXTURE 0        // colour (lit or albedo), premultiplied by coverage; A: coverage
#define ATLAS_NORMAL_DEPTH_TEXTURE 8 // normal * 0.5 + 0.5 and depth, premultiplied by coverage
#define ATLAS_CELL_TEXTURE 17        // one array, layer = global page: per ATLAS_CELL x ATLAS_CELL texel
                                     // cell, the nearest depth code of its covered texels (R8;
                                     // 255 when empty), so the corrected walk skips cells it passes over
#define ATLAS_CELL 16                // texels per cell side: view_atlas.h k_cell, crops sit on cells

// styles (RenderOptions::style)
#define STYLE_SEED 0       // the paper: the nearest view on a camera-facing quad, no correction
#define STYLE_BASELINE 1   // impostor bakers: 3 views blended, one parallax offset step
#define STYLE_CORRECTED 2  // 3 views blended, each intersected per pixel with its depth

// debug views (RenderOptions::debug_view)
#define ATLAS_DEBUG_NONE 0
#define ATLAS_DEBUG_VIEW 1    // "billboard": colour by the view contributing most
#define ATLAS_DEBUG_DEPTH 2   // window depth, near white
#define ATLAS_DEBUG_NORMAL 3  // the normal used for shading, world space
#define ATLAS_DEBUG_FETCHES 4 // texture reads of this pixel, heat map over 0..160

#define LOOKUP_SIDE 32     // cells per side of each face of the direction lookup cube
#define NEIGHBOURS 12      // nearest other views kept per view
#define MAX_LOD 4          // mip levels that never mix two views (crops sit on 16-texel cells)

#endif
