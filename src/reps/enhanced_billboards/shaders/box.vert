#version 450 core
// Enhanced billboards: every proxy box (one per occupied tile of a billboard, or one per billboard
// for instances far away) of every instance is one instance of a 36-vertex box (Vichitvejpaisal 2005 §3.3:
// the box's faces towards the eye, at most three; back faces are culled by GL). The draw list,
// built on the CPU each frame, names (instance, tile) per box, front to back, and is split in two:
// boxes that may cross the near plane, drawn first by the INSIDE_PASS variant from their back
// faces, so that views from inside a box see it, and the boxes beyond it (front faces).
#include "gpu/shaders/common/frame.glsl"
#include "reps/enhanced_billboards/shaders/billboard.glsl"

layout(std430, binding = BINDING_DRAW_LIST_SSBO) readonly buffer DrawListBlock {
    uvec2 entries[]; // instance, tile
} draw_list;

uniform int first_entry; // of this pass in the draw list

flat out int v_tile;
flat out int v_instance;
flat out mat4 v_box_from_world;
flat out mat4 v_world_from_box;

vec3 corner_position(int corner) { return vec3(corner & 1, (corner >> 1) & 1, (corner >> 2) & 1); }

void main()
{
    uvec2 entry = draw_list.entries[first_entry + gl_InstanceID];
    int instance = int(entry.x), tile = int(entry.y);
    TileData box = tiles.items[tile];
    BillboardData data = billboards.items[box.info.x];
    mat4 world_from_object = instances.world_from_object[instance];
    mat4 world_from_box = world_from_object * data.object_from_box;
    vec3 box_min = box.box_min.xyz, box_size = box.box_max.xyz - box.box_min.xyz;

    // the corner (bit 0: x, bit 1: y, bit 2: z) this index names (renderer.cpp box_indices: 12
    // triangles counter-clockwise seen from outside, drawn indexed so that each corner is shaded
    // once). A mirroring transform reverses their winding; the box mirrored along x in its own
    // space is the same box, and reverses it back: each triangle lands on the mirrored face
    int corner = gl_VertexID;
    if (determinant(mat3(world_from_box)) < 0.0) corner ^= 1;
    vec3 p = box_min + corner_position(corner) * box_size;
    p.z += box.box_min.w * p.x + box.box_max.w * p.y; // the tile's shear (TileData)
    vec4 world = world_from_box * vec4(p, 1.0);

    v_tile = tile;
    v_instance = instance;
    v_world_from_box = world_from_box;
    v_box_from_world = data.box_from_object * inverse(world_from_object);
    gl_Position = frame.clip_from_world * world;
}
