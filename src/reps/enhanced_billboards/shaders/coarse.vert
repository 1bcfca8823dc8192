#version 450 core
// The package's coarse mesh (Vichitvejpaisal 2005 §3.4), drawn after the billboards to fill their holes.
#include "gpu/shaders/common/frame.glsl"
#include "reps/enhanced_billboards/shaders/billboard_layout.glsl"

// the instances large enough on screen to need hole filling (renderer.cpp)
layout(std430, binding = BINDING_COARSE_LIST_SSBO) readonly buffer CoarseListBlock {
    uint instance_index[];
} coarse_list;
uniform int first_coarse; // this draw's run of the list: one level of the coarse mesh (renderer.cpp)

layout(location = ATTRIB_POSITION) in vec3 position_object;
layout(location = ATTRIB_NORMAL) in vec3 normal_object;
layout(location = ATTRIB_COLOR) in vec4 color;

out vec3 v_position_world;
out vec3 v_normal_world;
out vec4 v_color;
flat out float v_handedness; // -1 for a mirroring instance transform (coarse.frag)

void main()
{
    mat4 world_from_object = instances.world_from_object[coarse_list.instance_index[first_coarse + gl_InstanceID]];
    vec4 world = world_from_object * vec4(position_object, 1.0);
    v_position_world = world.xyz;
    v_normal_world = mat3(world_from_object) * normal_object;
    v_color = color;
    v_handedness = determinant(mat3(world_from_object)) < 0.0 ? -1.0 : 1.0;
    gl_Position = frame.clip_from_world * world;
}
