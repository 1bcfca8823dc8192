// Binding points, record layout and constants shared by the displaced-mesh renderer's C++
// (renderer.cpp includes this file) and its shaders. Plain #defines only: both languages parse it.
#ifndef STANDIN_DISPLACED_LAYOUT_GLSL
#define STANDIN_DISPLACED_LAYOUT_GLSL

#include "gpu/shaders/common/bindings.h"
#include "gpu/shaders/common/debug_views.h"

// uniform blocks (BINDING_FRAME_UBO = 0 is the frame's)
#define DM_REFINE_UBO (BINDING_FRAME_UBO + 1) // RefineBlock: tolerance, projection, capacities

// shader storage blocks, from the first slot the GPU layer leaves to renderers
#define DM_VERTICES_SSBO (BINDING_FIRST_RENDERER_SSBO + 0)   // vec4 position, vec4 normal per control vertex
#define DM_FACES_SSBO (BINDING_FIRST_RENDERER_SSBO + 1)      // FaceData per control face
#define DM_ELEVATIONS_SSBO (BINDING_FIRST_RENDERER_SSBO + 2) // float per sample, every level, face-major
#define DM_SHADING_SSBO (BINDING_FIRST_RENDERER_SSBO + 3)    // uvec2 per finest sample: octahedral normal, RGBA8 albedo
#define DM_LIST_IN_SSBO (BINDING_FIRST_RENDERER_SSBO + 4)    // Record[]: the triangles this pass tests
#define DM_LIST_OUT_SSBO (BINDING_FIRST_RENDERER_SSBO + 5)   // Record[]: their children
#define DM_FINAL_SSBO (BINDING_FIRST_RENDERER_SSBO + 6)      // Record[]: triangles to draw
#define DM_SCAN_SSBO (BINDING_FIRST_RENDERER_SSBO + 7)       // per element of the current list: decision, local prefix sums
#define DM_GROUPS_SSBO (BINDING_FIRST_RENDERER_SSBO + 8)     // per workgroup: sums, then their exclusive prefix
#define DM_STATE_SSBO (BINDING_FIRST_RENDERER_SSBO + 9)      // refinement state and indirect arguments (DM_STATE_*)
#define DM_PBR_SSBO (BINDING_FIRST_RENDERER_SSBO + 10)       // uvec2 per finest sample: RGBA8 ORM, RGBA8 emission (PBR packages)
#define DM_FACE_TEXTURE_SSBO (BINDING_FIRST_RENDERER_SSBO + 11) // FaceTexture per control face (source_textures.h; packages with them)
#define DM_DISPLACED_SSBO (BINDING_FIRST_RENDERER_SSBO + 12)    // vec4 world position per final-list vertex (displace.comp)

// texture units
#define DM_SOURCE_TEXTURE_UNIT (BINDING_FIRST_RENDERER_TEXTURE + 0) // the source textures' arrays, one layer each, units +0..+3
#define DM_SOURCE_ARRAY_SHIFT 24 // a face record's layer: its array << DM_SOURCE_ARRAY_SHIFT | its layer there

// the renderer's own counters (gpu/counters.h), after the shared ones
#define DM_COUNTER_ERROR_SUM (COUNTER_SHARED_COUNT + 0) // over fragments, the distance to the finest surface, 1/DM_ERROR_UNITS px
#define DM_COUNTER_ERROR_MAX (COUNTER_SHARED_COUNT + 1) // its maximum, 1/DM_ERROR_UNITS px
#define DM_COUNTER_COUNT (COUNTER_SHARED_COUNT + 2)
#define DM_ERROR_UNITS 64.0 // counter units per pixel of error

// DM_STATE_SSBO layout, in uints. Passes alternate between two slots (parity p % 2) for the
// current list's count and dispatch arguments: a pass reads its own and writes the next one's.
#define DM_STATE_COUNT 0         // 2 uints: records in the current list, by parity
#define DM_STATE_DISPATCH 2      // 2 x 3 uints: glDispatchComputeIndirect arguments over it, by parity
#define DM_STATE_FINAL 8         // records in the final list
#define DM_STATE_FINAL_BASE 9    // the final list's size before this pass (where its finals go)
#define DM_STATE_OVERFLOW 10     // 1: this pass's children would not fit, every record becomes final
#define DM_STATE_PROCESSED 11    // records tested over all passes (the paper's "processed")
#define DM_STATE_CAPPED 12       // records that wanted to split when passes or lists ran out
#define DM_STATE_VISIBLE 13      // control faces (x instances) that passed culling
#define DM_STATE_DROPPED 14      // final records that did not fit the final list (drawn: none)
#define DM_STATE_OVERFLOWED 15   // records made final because their children did not fit the list
#define DM_STATE_DRAW 16         // 4 uints: glDrawArraysIndirect arguments (3 x final, 1, 0, 0)
#define DM_STATE_UINTS 20

#define DM_GROUP_SIZE 256        // invocations per workgroup of every compute pass
#define DM_RECORD_UINTS 9        // face, instance, q1 q2 of three corners, depth

#define DM_BARY_BITS 30          // face_point.h k_bary_bits

// split criteria (refine.h Criterion)
#define DM_CRITERION_WEIGHTED 0
#define DM_CRITERION_LENGTH 1
#define DM_CRITERION_SEED 2
#define DM_CRITERION_ERROR 3
// the error criterion (refine.cpp says why)
#define DM_CHORD_ERROR (1.0 / 6.0) // a chord's error over curvature x length^2
#define DM_MIN_VISIBLE 0.2        // least share of a normal deviation counted on screen
#define DM_SILHOUETTE_COS 0.15    // |cos| of the view angle below which a segment is on the outline

// debug views (debug_views.h): parts = control face, level = bisection depth (heat over 0..3m+6),
// error = distance to the finest surface at the pixel in pixels (heat over 0..tau; the paper's
// Fig. 11c), depth, normal

#endif
