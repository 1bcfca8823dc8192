// The per-billboard block of the enhanced-billboard renderer (C++ side: BillboardGpu in
// renderer.cpp). Box space: x, y in texels along axis_u, axis_v; z in [0, 1] of the depth range.
#include "gpu/shaders/common/debug_colors.glsl"
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

// One proxy box: a tile of a billboard (or a whole billboard), in that billboard's box space.
struct TileData {
    vec4 box_min;  // xy: texel rectangle, z: depth range, of the covered texels and their walls
    vec4 box_max;
    ivec4 info;    // billboard, highest pyramid level the march climbs to, unused, unused
};

layout(std430, binding = BINDING_TILES_SSBO) readonly buffer TileBlock {
    TileData items[];
} tiles;

// The colour of billboard `index` in the debug views "billboard" and "boxes".
vec3 billboard_color(int index) { return index_color(index); }
