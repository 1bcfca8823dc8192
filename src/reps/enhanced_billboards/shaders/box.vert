#version 450 core
// Enhanced billboards: every billboard of every instance is one instance of a 36-vertex box
// (seed 000 §3.3: the box's faces towards the eye, at most three; back faces are culled by GL).
// Boxes that cross the near plane are drawn instead by the INSIDE_PASS variant from their back
// faces, so that views from inside a box see it.
#include "gpu/shaders/common/frame.glsl"
#include "reps/enhanced_billboards/shaders/billboard.glsl"

uniform int billboard_count;

flat out int v_billboard;
flat out int v_instance;
flat out mat4 v_box_from_world;
flat out mat4 v_world_from_box;

// corners (bit 0: x, bit 1: y, bit 2: z) of 12 triangles, counter-clockwise seen from outside
const int k_corners[36] = int[36](0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5, 0, 1, 5, 0, 5, 4,
                                  2, 6, 7, 2, 7, 3, 0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6);

vec3 corner_position(int corner) { return vec3(corner & 1, (corner >> 1) & 1, (corner >> 2) & 1); }

void main()
{
    int billboard = gl_InstanceID % billboard_count;
    int instance = gl_InstanceID / billboard_count;
    BillboardData data = billboards.items[billboard];
    mat4 world_from_object = instances.world_from_object[instance];
    mat4 world_from_box = world_from_object * data.object_from_box;
    vec3 box_min = data.box_min.xyz, box_size = data.box_max.xyz - data.box_min.xyz;

    // does the box reach in front of the near plane?
    bool crosses_near = false;
    for (int i = 0; i < 8; ++i) {
        vec4 clip = frame.clip_from_world * (world_from_box * vec4(box_min + corner_position(i) * box_size, 1.0));
        crosses_near = crosses_near || clip.z < -clip.w;
    }
#ifdef INSIDE_PASS
    bool drawn = crosses_near;
#else
    bool drawn = !crosses_near;
#endif
    drawn = drawn && all(greaterThanEqual(box_size, vec3(0.0)));

    // mirroring transforms flip the winding
    int vertex = gl_VertexID % 3;
    if (determinant(mat3(world_from_box)) < 0.0 && vertex != 0) vertex = 3 - vertex;
    int corner = k_corners[gl_VertexID - gl_VertexID % 3 + vertex];
    vec4 world = world_from_box * vec4(box_min + corner_position(corner) * box_size, 1.0);

    v_billboard = billboard;
    v_instance = instance;
    v_world_from_box = world_from_box;
    v_box_from_world = data.box_from_object * inverse(world_from_object);
    gl_Position = drawn ? frame.clip_from_world * world : vec4(0.0, 0.0, 2.0, 1.0);
}
