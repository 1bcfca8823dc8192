#version 450 core
// Debug view "boxes": the twelve edges of every billboard's box (its whole image plane, depth 0 to
// depth_range along its direction) as lines, one instance per object-to-world transform. The box
// edges take the billboard's colour of the "billboard" view; the four edges of the front plane
// (depth 0, where the images lie) are pure red, which that palette (every channel >= 0.2) never
// produces.
#include "gpu/shaders/common/frame.glsl"
#include "reps/enhanced_billboards/shaders/billboard.glsl"

layout(location = ATTRIB_POSITION) in vec3 position_object;
layout(location = ATTRIB_BOX_EDGE) in ivec2 edge; // billboard, 1 on the front plane

out vec3 v_color;

void main()
{
    v_color = edge.y != 0 ? vec3(1.0, 0.0, 0.0) : billboard_color(edge.x);
    gl_Position = frame.clip_from_world * (instances.world_from_object[gl_InstanceID] * vec4(position_object, 1.0));
}
