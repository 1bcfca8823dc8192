// Constants shared by the enhanced-billboard renderer's C++ (renderer.cpp includes this file) and
// its shaders. Plain #defines only: both languages must parse this file.
#ifndef STANDIN_BILLBOARD_LAYOUT_GLSL
#define STANDIN_BILLBOARD_LAYOUT_GLSL

#include "gpu/shaders/common/bindings.h"
#include "gpu/shaders/common/debug_views.h"

// shader storage blocks and texture units of this renderer (gpu/shaders/common/bindings.h)
#define BINDING_BILLBOARDS_SSBO (BINDING_FIRST_RENDERER_SSBO + 0) // BillboardData, one per billboard
#define BINDING_TILES_SSBO (BINDING_FIRST_RENDERER_SSBO + 1)      // TileData: the proxy boxes, one per occupied tile
#define BINDING_DRAW_LIST_SSBO (BINDING_FIRST_RENDERER_SSBO + 2)  // uvec2 (instance, tile) per drawn box, front to back
#define BINDING_COARSE_LIST_SSBO (BINDING_FIRST_RENDERER_SSBO + 3) // uint instance index per coarse-mesh instance
#define BINDING_COLOR_MAPS (BINDING_FIRST_RENDERER_TEXTURE + 0)   // albedo + coverage, one layer per billboard
#define BINDING_NORMAL_MAPS (BINDING_FIRST_RENDERER_TEXTURE + 1)  // normal + depth
#define BINDING_SURFACE_MAPS (BINDING_FIRST_RENDERER_TEXTURE + 2) // depth, range, tilt, link flags (acceleration.h pack_surface)
#define BINDING_MINMAX_MAPS (BINDING_FIRST_RENDERER_TEXTURE + 3)  // the min/max pyramid above level 0
#define BINDING_ORM_MAPS (BINDING_FIRST_RENDERER_TEXTURE + 4)      // occlusion, roughness, metallic (PBR packages)
#define BINDING_EMISSION_MAPS (BINDING_FIRST_RENDERER_TEXTURE + 5) // emission, sRGB (PBR packages)
#define BINDING_COLOR_MIPS (BINDING_FIRST_RENDERER_TEXTURE + 6)   // colour of one surface over 2^k texels (build_color_pyramid)

// image unit of the per-pixel flags the coarse mesh reads (r32ui)
#define IMAGE_PIXEL_FLAGS (BINDING_FIRST_RENDERER_IMAGE + 0)
// image unit of the nearest hit so far per pixel (r32ui: floatBitsToUint of its window depth with
// the lowest bit replaced by PIXEL_DEPTH_BACK for the back of a sheet; cleared to 1.0), so that rays
// behind it stop early (a depth test the shader does itself; see march.frag), and so that the
// coarse mesh knows whether the nearest billboard surface is a front hit it must not cover
#define IMAGE_PIXEL_DEPTH (BINDING_FIRST_RENDERER_IMAGE + 1)
#define PIXEL_DEPTH_BACK 1u
#define PIXEL_HIT 1u       // some billboard ray hit here
#define PIXEL_NEAR_MISS 2u // a ray came within a texel of a billboard surface and missed

// counters of this renderer, after the shared ones (debug_views.h)
#define COUNTER_HITS (COUNTER_SHARED_COUNT + 0)        // fragments that hit
#define COUNTER_NEAR_MISSES (COUNTER_SHARED_COUNT + 1) // fragments that came near a surface and missed
#define COUNTER_BEHIND_HITS (COUNTER_SHARED_COUNT + 2) // fragments stopped before their ray: behind a hit drawn
#define COUNTER_COUNT (COUNTER_SHARED_COUNT + 3)

// march modes
#define MARCH_EXACT 0
#define MARCH_SEED 1

// debug view "proxies" is the shaded picture with every billboard's box drawn over it as lines
// (boxes.vert): the vertex attribute of a line vertex's ivec2 (billboard, 1 on the front plane)
#define ATTRIB_BOX_EDGE ATTRIB_FIRST_RENDERER

// surface texel flags (acceleration.h)
#define TEXEL_COVERED 1u
#define LINK_MINUS_U 2u
#define LINK_PLUS_U 4u
#define LINK_MINUS_V 8u
#define LINK_PLUS_V 16u
#define TEXEL_LINE_LOW_BIT 5u // with bits TEXEL_LINE_HIGH_SHIFT..15: 1 + the texel's edge line code
#define SMOOTH_MINUS_U 64u // the link continues the surface without a crease (colour is filtered across it)
#define SMOOTH_PLUS_U 128u
#define SMOOTH_MINUS_V 256u
#define SMOOTH_PLUS_V 512u
#define TEXEL_LINE_HIGH_SHIFT 10u // (acceleration.h pack_surface), 0 where the texel holds none

// sheet edge lines (issue #17, --sheet-edges clip; capture.cpp, edge_line_code): the colour alpha of
// a covered texel an open edge crosses is EDGE_LINE_FIRST_CODE + angle * EDGE_LINE_OFFSETS + offset,
// the surface being the texel's part where dot(n, p - centre) <= e, p in texel units, n the edge's
// outward normal at angle * 360 / EDGE_LINE_ANGLES degrees from +u, e = ((offset + 0.5) /
// EDGE_LINE_OFFSETS * 2 - 1) * (|n.x| + |n.y|) / 2. Codes stay at or above 128, so readers that take
// alpha >= 128 as coverage (older ones, the BC encoders, glTF export's mask) see the texel covered;
// 255 is a whole texel. The march reads the line from the surface texel's flags (TEXEL_LINE_*: the
// code's index + 1 in 7 bits), not from the colour map: no fetch of its own
#define EDGE_LINE_FIRST_CODE 128
#define EDGE_LINE_ANGLES 18
#define EDGE_LINE_OFFSETS 7

#endif
