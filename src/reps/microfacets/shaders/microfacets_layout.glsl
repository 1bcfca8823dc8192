// Constants shared by the microfacet renderer's C++ (renderer.cpp includes this file) and its
// shaders. Plain #defines only: both languages must parse this file.
#ifndef STANDIN_MICROFACETS_LAYOUT_GLSL
#define STANDIN_MICROFACETS_LAYOUT_GLSL

// shader storage blocks (binding 0 is the frame's instance transforms, gpu/shaders/common/bindings.h)
#define MF_VIEWS_SSBO 1     // ViewData[]
#define MF_LOOKUP_SSBO 2    // uint[]: per lookup cell (first << 8 | count), the candidates, then the
                            // per-draw list of MF_SELECT_CONE / MF_SELECT_ALL (count, then views)
#define MF_NODES_SSBO 3     // uint[]: the octree's Morton codes, levels min..max concatenated
#define MF_INSTANCES_SSBO 4 // InstanceLod[]: per instance eye, axes, work range and levels
#define MF_SELECTED_SSBO 5  // Facet[] per work item (select.comp), with its rank in its group
#define MF_GROUPS_SSBO 6    // uvec2[] per work group: quads and points kept; then their offsets
#define MF_QUADS_SSBO 7     // Facet[]: the facets drawn as quads, in work order
#define MF_POINTS_SSBO 8    // Facet[]: the facets drawn as points, in work order
#define MF_COMMANDS_SSBO 9  // two DrawArraysIndirectCommand (quads, points)
#define MF_COUNTERS_SSBO 10 // uint[MF_COUNTER_COUNT], written when counting
#define MF_COUNTER_FRAGMENTS 0 // fragment invocations (overdraw = fragments / covered pixels)
#define MF_COUNTER_FETCHES 1   // texture reads
#define MF_COUNTER_COUNT 2

// texture units (the shadow map is BINDING_SHADOW_TEXTURE, 16)
#define MF_COLOR_TEXTURE 0        // colour pages: albedo premultiplied by coverage, mip-mapped
#define MF_NORMAL_DEPTH_TEXTURE 1 // normal * 0.5 + 0.5 and depth, 16-bit, level 0 only

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

// debug views
#define MF_DEBUG_NONE 0
#define MF_DEBUG_VIEW 1    // colour by the view with the largest weight (Fig. 13 d)
#define MF_DEBUG_DEPTH 2
#define MF_DEBUG_NORMAL 3
#define MF_DEBUG_FETCHES 4 // texture reads of this pixel, heat map over 0..16
#define MF_DEBUG_LEVEL 5   // the octree level drawn, heat map over min..max
#define MF_DEBUG_FACETS 6  // the facets themselves, untextured and unclipped, coloured by view (Fig. 2)

#endif
