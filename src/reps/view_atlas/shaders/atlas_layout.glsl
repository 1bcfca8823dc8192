// Constants shared by the view-atlas renderer's C++ (renderer.cpp includes this file) and its
// shaders. Plain #defines only: both languages must parse this file.
#ifndef STANDIN_ATLAS_LAYOUT_GLSL
#define STANDIN_ATLAS_LAYOUT_GLSL

#include "gpu/shaders/common/bindings.h"
#include "gpu/shaders/common/debug_views.h"
#include "reps/common/shaders/height_field.h"

// shader storage blocks of this renderer (gpu/shaders/common/bindings.h)
#define ATLAS_VIEWS_SSBO (BINDING_FIRST_RENDERER_SSBO + 0) // ViewData[]
#define ATLAS_INDEX_SSBO (BINDING_FIRST_RENDERER_SSBO + 1) // int[]: the direction lookup cube, then NEIGHBOURS per view
#define ATLAS_HULL_SSBO (BINDING_FIRST_RENDERER_SSBO + 2)  // vec4[]: the proxy hull's vertices (hull.h proxy_polytope)

// texture units: each map's pages lie in up to ATLAS_MAX_ARRAYS texture arrays (units
// ATLAS_COLOR_TEXTURE + i and ATLAS_NORMAL_DEPTH_TEXTURE + i hold array i); a view's array is
// ViewData.atlas.w, its layer ViewData.atlas.x
#define ATLAS_MAX_ARRAYS 8
#define ATLAS_COLOR_TEXTURE (BINDING_FIRST_RENDERER_TEXTURE + 0)        // colour (lit or albedo), premultiplied by coverage; A: coverage
#define ATLAS_NORMAL_DEPTH_TEXTURE (BINDING_FIRST_RENDERER_TEXTURE + 8) // normal * 0.5 + 0.5 and depth, premultiplied by coverage
#define ATLAS_CELL_TEXTURE (BINDING_FIRST_RENDERER_TEXTURE + 16)        // one array, layer = global page: per ATLAS_CELL x ATLAS_CELL texel
                                     // cell, the nearest depth code of its covered texels (R8;
                                     // 255 when empty), so the corrected walk skips cells it passes over
#define ATLAS_ORM_TEXTURE (BINDING_FIRST_RENDERER_TEXTURE + 17)      // PBR packages (ATLAS_PBR): occlusion, roughness,
                                                                    // metallic, premultiplied by coverage
#define ATLAS_EMISSION_TEXTURE (BINDING_FIRST_RENDERER_TEXTURE + 25) // PBR packages: emission (sRGB), premultiplied by coverage
// image units (gpu/shaders/common/bindings.h)
#define ATLAS_NEAREST_IMAGE (BINDING_FIRST_RENDERER_IMAGE + 0) // R32UI, viewport-sized: the nearest depth this draw
                                     // wrote per pixel (float bits), so later fragments behind it stop before the walk
// the corrected walk's texel tops tilt by their stored normal up to this slope (height per plane
// unit: reps/common/shaders/height_field.h)
#define ATLAS_TOP_MAX_SLOPE HF_TOP_MAX_SLOPE
#define ATLAS_CELL 16                // texels per cell side: view_atlas.h k_cell, crops sit on cells

// styles (the run-time option "style")
#define STYLE_SEED 0       // the paper: the nearest view on a camera-facing quad, no correction
#define STYLE_BASELINE 1   // impostor bakers: 3 views blended, one parallax offset step
#define STYLE_CORRECTED 2  // 3 views blended, each intersected per pixel with its depth

// levels of detail of a corrected-style instance (atlas.vert: v_lod, by its size in pixels)
#define ATLAS_LOD_CORRECTED 0 // the walk on the cut-out hull
#define ATLAS_LOD_BASELINE 1  // the baseline's blend and parallax step on the cut-out hull
#define ATLAS_LOD_SEED 2      // the seed's nearest view on its quad

#define LOOKUP_SIDE 32     // cells per side of each face of the direction lookup cube
#define NEIGHBOURS 12      // nearest other views kept per view
#define MAX_LOD 4          // mip levels that never mix two views (crops sit on 16-texel cells)

#endif
