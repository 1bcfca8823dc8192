// The per-billboard block of the enhanced-billboard renderer (C++ side: BillboardGpu in
// renderer.cpp). Box space: x, y in texels along axis_u, axis_v; z in [0, 1] of the depth range.
#include "reps/enhanced_billboards/shaders/billboard_layout.glsl"

struct BillboardData {
    mat4 object_from_box;
    mat4 box_from_object;
    ivec4 info;    // layer, unused, width, height (texels)
    vec4 box_min;  // box space bounds of the covered texels and their depths (min > max: empty)
    vec4 box_max;
};

layout(std430, binding = BINDING_BILLBOARDS_SSBO) readonly buffer BillboardBlock {
    BillboardData items[];
} billboards;
