// The per-billboard block of the enhanced-billboard renderer (C++ side: BillboardGpu in
// renderer.cpp). Box space: x, y in texels along axis_u, axis_v; z in [0, 1] of the depth range.
#include "gpu/shaders/common/debug_colors.glsl"
#include "reps/enhanced_billboards/shaders/billboard_layout.glsl"

struct BillboardData {
    mat4 object_from_box;
    mat4 box_from_object;
    ivec4 info;    // layer, the surface map's range unit in depth codes (acceleration.h pack_surface), width, height (texels)
    vec4 box_min;  // box space bounds of the covered texels and their depths (min > max: empty)
    vec4 box_max;
    ivec4 offset;  // xy: where the billboard's texel (0, 0) lies in its layer (acceleration.h pack_layers)
};

layout(std430, binding = BINDING_BILLBOARDS_SSBO) readonly buffer BillboardBlock {
    BillboardData items[];
} billboards;

// One proxy box: a tile of a billboard (or a whole billboard), in that billboard's box space,
// sheared to follow the surface: a point (x, y, z) is inside when xy is in the texel rectangle and
// z - (slope.x * x + slope.y * y) is in the offset range (acceleration.h, TileBox).
struct TileData {
    vec4 box_min;  // xy: texel rectangle, z: offset range, of the covered texels and their walls; w: slope.x
    vec4 box_max;  // w: slope.y
    ivec4 info;    // billboard, highest pyramid level the march climbs to, 1: the walk starts at the ray footprint's level (a whole billboard's box, coarse tiles), unused
};

layout(std430, binding = BINDING_TILES_SSBO) readonly buffer TileBlock {
    TileData items[];
} tiles;

// box space of a billboard to the sheared space of one of its tiles (z measured from the tile's plane)
vec3 tile_from_box(TileData tile, vec3 p)
{
    return vec3(p.xy, p.z - tile.box_min.w * p.x - tile.box_max.w * p.y);
}
vec3 tile_from_box_direction(TileData tile, vec3 d)
{
    return vec3(d.xy, d.z - tile.box_min.w * d.x - tile.box_max.w * d.y);
}

// The colour of billboard `index` in the debug views "billboard" and "boxes".
vec3 billboard_color(int index) { return index_color(index); }
