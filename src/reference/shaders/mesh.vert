#version 450 core
// Ground-truth mesh renderer: per-vertex transform, per-pixel shading in mesh.frag.
#include "gpu/shaders/common/frame.glsl"

layout(location = ATTRIB_POSITION) in vec3 position_object;
layout(location = ATTRIB_NORMAL) in vec3 normal_object;
layout(location = ATTRIB_COLOR) in vec4 color;
layout(location = ATTRIB_UV) in vec2 uv;

out vec3 v_position_world;
out vec3 v_normal_world;
out vec4 v_color;
out vec2 v_uv;
flat out float v_handedness; // -1 for a mirroring instance transform (mesh.frag)

void main()
{
    mat4 world_from_object = instances.world_from_object[gl_InstanceID];
    vec4 world = world_from_object * vec4(position_object, 1.0);
    v_position_world = world.xyz;
    // Instance transforms are similarity transforms (rotation, uniform scale, translation).
    v_normal_world = mat3(world_from_object) * normal_object;
    v_color = color;
    v_uv = uv;
    v_handedness = determinant(mat3(world_from_object)) < 0.0 ? -1.0 : 1.0;
    gl_Position = frame.clip_from_world * world;
}
