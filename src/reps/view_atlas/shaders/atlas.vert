#version 450 core
// View atlas: one quad per instance. Style seed (seed 003 §3): the crop rectangle of the nearest
// view on the plane through the sphere's centre, turned to face the camera. Other styles: a quad
// facing the camera that covers the bounding sphere (the fragment stage casts rays), or the whole
// screen when the eye is inside the sphere.
#include "gpu/shaders/common/frame.glsl"
#include "reps/view_atlas/shaders/atlas.glsl"

uniform int style;

flat out ivec3 v_views;
flat out vec3 v_weights;
flat out int v_instance;
out vec2 v_atlas_texel; // seed: atlas texel position (level 0) on the nearest view's page

void main()
{
    mat4 world_from_object = instances.world_from_object[gl_InstanceID];
    mat4 object_from_world = inverse(world_from_object);
    vec3 eye_object = (object_from_world * vec4(frame.eye_world.xyz, 1.0)).xyz;
    vec3 e = frame.forward_world.w > 0.5 ? -normalize(mat3(object_from_world) * frame.forward_world.xyz)
                                         : normalize(eye_object - atlas_center);
    vec2 corner = vec2(gl_VertexID & 1, (gl_VertexID >> 1) & 1);
    v_instance = gl_InstanceID;

    if (style == STYLE_SEED) {
        int k = nearest_view(e);
        ViewData view = views.items[k];
        v_views = ivec3(k, 0, 0);
        v_weights = vec3(1.0, 0.0, 0.0);
        vec2 pixel = vec2(view.crop.xy) + corner * vec2(view.crop.zw);
        vec2 plane = plane_from_capture(pixel);
        mat3 turn = rotation_between(view.direction.xyz, e);
        vec3 p = atlas_center + turn * (plane.x * view.axis_u.xyz + plane.y * view.axis_v.xyz);
        v_atlas_texel = vec2(view.atlas.yz) + corner * vec2(view.crop.zw);
        gl_Position = frame.clip_from_world * (world_from_object * vec4(p, 1.0));
        return;
    }

    blend_views(e, v_views, v_weights);
    v_atlas_texel = vec2(0.0);
    float distance_to_center = length(eye_object - atlas_center);
    bool ortho = frame.forward_world.w > 0.5;
    if (!ortho && distance_to_center < atlas_radius * 1.01) {
        gl_Position = vec4(corner * 2.0 - 1.0, -1.0, 1.0); // inside the sphere: the whole screen
        return;
    }
    // the square around the sphere's outline on the centre plane
    float r = atlas_radius * 1.001;
    float half_size = ortho ? r : r * distance_to_center / sqrt(distance_to_center * distance_to_center - r * r);
    vec3 side = normalize(cross(abs(e.y) < 0.9 ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0), e));
    vec3 up = cross(e, side);
    vec3 p = atlas_center + half_size * ((corner.x * 2.0 - 1.0) * side + (corner.y * 2.0 - 1.0) * up);
    gl_Position = frame.clip_from_world * (world_from_object * vec4(p, 1.0));
}
