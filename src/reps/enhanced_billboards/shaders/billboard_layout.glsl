// Constants shared by the enhanced-billboard renderer's C++ (renderer.cpp includes this file) and
// its shaders. Plain #defines only: both languages must parse this file.
#ifndef STANDIN_BILLBOARD_LAYOUT_GLSL
#define STANDIN_BILLBOARD_LAYOUT_GLSL

// shader storage blocks of this renderer (beside gpu/shaders/common/bindings.h's 0..2)
#define BINDING_TILES_SSBO 3     // TileData: the proxy boxes drawn, one per occupied tile
#define BINDING_DRAW_LIST_SSBO 4 // uvec2 (instance, tile) per drawn box, sorted front to back
#define BINDING_COARSE_LIST_SSBO 5 // uint instance index per coarse-mesh instance drawn

// image unit of the per-pixel flags the coarse mesh reads (r32ui)
#define IMAGE_PIXEL_FLAGS 0
// image unit of the nearest hit so far per pixel (r32ui: floatBitsToUint of its window depth with
// the lowest bit replaced by PIXEL_DEPTH_BACK for the back of a sheet; cleared to 1.0), so that rays
// behind it stop early (a depth test the shader does itself; see march.frag), and so that the
// coarse mesh knows whether the nearest billboard surface is a front hit it must not cover
#define IMAGE_PIXEL_DEPTH 1
#define PIXEL_DEPTH_BACK 1u
#define PIXEL_HIT 1u       // some billboard ray hit here
#define PIXEL_NEAR_MISS 2u // a ray came within a texel of a billboard surface and missed

// counters[] of the BINDING_COUNTERS_SSBO block
#define COUNTER_FETCHES 0     // height-field fetches (surface, pyramid and wall-neighbour texels)
#define COUNTER_HITS 1        // fragments that hit
#define COUNTER_FRAGMENTS 2   // fragments marched
#define COUNTER_NEAR_MISSES 3
#define COUNTER_COUNT 4

// march modes
#define MARCH_EXACT 0
#define MARCH_SEED 1

// debug views
#define DEBUG_NONE 0
#define DEBUG_BILLBOARD 1
#define DEBUG_DEPTH 2
#define DEBUG_NORMAL 3
#define DEBUG_FETCHES 4
// debug view "boxes" is the shaded picture (DEBUG_NONE in the march) with box lines drawn over it
// (boxes.vert): the vertex attribute of a line vertex's ivec2 (billboard, 1 on the front plane)
#define ATTRIB_BOX_EDGE 1

// surface texel flags (acceleration.h)
#define TEXEL_COVERED 1u
#define LINK_MINUS_U 2u
#define LINK_PLUS_U 4u
#define LINK_MINUS_V 8u
#define LINK_PLUS_V 16u

#endif
