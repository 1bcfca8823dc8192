#version 450 core
// Tessellation baseline: a generated vertex is a point of the control face (gl_TessCoord are its
// barycentric weights on corners 0, 1, 2), displaced exactly as the bisection path displaces its
// vertices (displaced_position), so the two paths differ only in where the vertices fall.
#include "gpu/shaders/common/frame.glsl"
#include "reps/displaced_mesh/shaders/displaced.glsl"

layout(triangles, equal_spacing, ccw) in;

flat in uint tc_face[];
flat in uint tc_instance[];

out vec3 v_position_world;
out vec2 v_face_bary;
flat out uint v_face;
flat out uint v_instance;
flat out uint v_depth;

void main()
{
    uint face = tc_face[0], instance = tc_instance[0];
    uint q1 = uint(round(gl_TessCoord.y * float(BARY_ONE)));
    uint q2 = min(uint(round(gl_TessCoord.z * float(BARY_ONE))), BARY_ONE - q1);
    mat4 world_from_object = instances.world_from_object[instance];
    vec3 direction;
    vec3 p = displaced_position(face, q1, q2, frame.view_from_world * world_from_object, direction);
    vec4 world = world_from_object * vec4(p, 1.0);
    v_position_world = world.xyz;
    v_face_bary = vec2(float(q1), float(q2)) / float(BARY_ONE);
    v_face = face;
    v_instance = instance;
    v_depth = uint(log2(max(gl_TessLevelInner[0], 1.0)));
    gl_Position = frame.clip_from_world * world;
}
