// Constants shared by the microfacet renderer's C++ (renderer.cpp includes this file) and its
// shaders. Plain #defines only: both languages must parse this file.
#ifndef STANDIN_MICROFACETS_LAYOUT_GLSL
#define STANDIN_MICROFACETS_LAYOUT_GLSL

#include "gpu/shaders/common/bindings.h"
#include "gpu/shaders/common/debug_views.h"

// shader storage blocks: the frame's instances and the shared counters are the GPU layer's
// (bindings.h); this renderer's start at BINDING_FIRST_RENDERER_SSBO
#define MF_VIEWS_SSBO (BINDING_FIRST_RENDERER_SSBO + 0)     // ViewData[]
#define MF_LOOKUP_SSBO (BINDING_FIRST_RENDERER_SSBO + 1)    // uint[]: per lookup cell (first << 8 | count),
                                                            // the candidates, then the per-draw list of
                                                            // MF_SELECT_CONE / MF_SELECT_ALL (count, views)
#define MF_NODES_SSBO (BINDING_FIRST_RENDERER_SSBO + 2)     // uint[]: the octree's codes, levels min..max
#define MF_INSTANCES_SSBO (BINDING_FIRST_RENDERER_SSBO + 3) // InstanceLod[]: eye, axes, work range, levels
#define MF_SELECTED_SSBO (BINDING_FIRST_RENDERER_SSBO + 4)  // Facet[] per work item, with its rank in its group
#define MF_GROUPS_SSBO (BINDING_FIRST_RENDERER_SSBO + 5)    // uvec2[] per work group: quads and points kept,
                                                            // then their offsets
#define MF_QUADS_SSBO (BINDING_FIRST_RENDERER_SSBO + 6)     // Facet[]: drawn as quads, in work order
#define MF_POINTS_SSBO (BINDING_FIRST_RENDERER_SSBO + 7)    // Facet[]: drawn as points, in work order
#define MF_COMMANDS_SSBO (BINDING_FIRST_RENDERER_SSBO + 8)  // two DrawArraysIndirectCommand (quads, points)
#define MF_SEEN_SSBO (BINDING_FIRST_RENDERER_SSBO + 9)      // uint[]: per node (nodes' order), a bit per view
                                                            // that saw surface in it (visibility.cpp)

// texture units (the shadow map is BINDING_SHADOW_TEXTURE)
#define MF_COLOR_TEXTURE (BINDING_FIRST_RENDERER_TEXTURE + 0)        // albedo premultiplied by coverage, mip-mapped
#define MF_NORMAL_DEPTH_TEXTURE (BINDING_FIRST_RENDERER_TEXTURE + 1) // normal * 0.5 + 0.5 and depth, 16-bit
#define MF_ORM_TEXTURE (BINDING_FIRST_RENDERER_TEXTURE + 2)      // PBR packages (MF_PBR): occlusion, roughness, metallic; mip-mapped
#define MF_EMISSION_TEXTURE (BINDING_FIRST_RENDERER_TEXTURE + 3) // PBR packages: emission (sRGB); mip-mapped

#define MF_GROUP_SIZE 256      // select.comp / scatter.comp work group; ranks in a group fit 16 bits
#define MF_SCAN_SIZE 1024      // scan.comp: one group over every group's counts
#define MF_MAX_LEVELS 11       // levels 0..10 (voxels.h k_max_grid_level)
#define MF_LOOKUP_SIDE 32      // view_lookup.h k_lookup_side
#define MF_MAX_BLEND 4         // view_lookup.h k_max_blend

// Facet kinds in a selected record (Facet.a.x bits 28..29)
#define MF_KIND_NONE 0
#define MF_KIND_QUAD 1
#define MF_KIND_POINT 2

// run-time options (renderer.cpp)
#define MF_SELECT_LOOKUP 0 // candidates from the direction lookup (default)
#define MF_SELECT_CONE 1   // the seed's cone of candidates, per draw (Table 1 row c)
#define MF_SELECT_ALL 2    // every view for every facet (Table 1 row a)
#define MF_FACET_BILLBOARD 0 // squares of side sqrt(3) W facing the eye (the seed)
#define MF_FACET_FIXED 1     // squares of side W across the object axis nearest the view (Fig. 8)
#define MF_FACET_BOX 2       // the voxel's faces towards the eye: its exact outline, each pixel once
                             // (for MF_CLIP_RAY, which walks the ray inside the voxel)
#define MF_VERTICES_PER_FACET 18 // quads: 6 vertices (two triangles) per square, 3 squares for a box
#define MF_PRIMITIVE_AUTO 0   // quads, points where a facet is smaller than a pixel
#define MF_PRIMITIVE_QUADS 1
#define MF_PRIMITIVE_POINTS 2 // one colour per facet (Table 1 row b)
#define MF_COVERAGE_ANY 0  // a pixel is covered where any blended view passes eq. 1
#define MF_COVERAGE_VOTE 1 // where the passing views hold at least half the weight
#define MF_CLIP_SEED 0     // eq. 1: the view's surface within W/2 of the facet, along the view
#define MF_CLIP_VOXEL 1    // and inside the facet's voxel (grown by a texel)
#define MF_CLIP_RAY 2      // the pixel's ray inside the voxel intersected with the view's depth

#endif
