#version 450 core
// Microfacets drawn as quads (Yamazaki et al. 2002 §3.3.1): per selected facet (vertices_per_facet
// vertices, two triangles a square), a square through its voxel's centre, facing the eye, of side sqrt(3) W (so it
// covers the voxel), grown under perspective to cover the outline of the voxel's bounding sphere;
// or, for the Fig. 8 comparison, a square of side W across the object axis nearest the view.
// The square is drawn nearer the eye by half a voxel (scaled towards the eye under perspective):
// the fragment stage writes the depth of the stored surface, at most W/2 nearer than the facet, so
// its depth is never nearer than the rasterised one (layout(depth_greater): early depth tests
// stay on). v_position is the point on the true facet along the same eye ray.
// MF_FACET_BOX (beyond the paper, with the ray clip): the voxel's three faces towards the eye, so
// every pixel of the voxel's outline runs the fragment stage once, at the ray's entry into the voxel
// (a face the eye is level with collapses).
#include "gpu/shaders/common/frame.glsl"
#include "reps/microfacets/shaders/microfacets.glsl"

layout(std430, binding = MF_QUADS_SSBO) readonly buffer QuadBlock {
    Facet items[];
} quads;

uniform int facet_shape; // MF_FACET_*
uniform int vertices_per_facet; // 6, or 18 for MF_FACET_BOX

out vec3 v_position; // object space, on the facet's plane through the voxel centre
flat out vec3 v_center;
out vec2 v_corner; // position on the square, [-1, 1]^2 (DEBUG_VIEW_PROXIES outlines)
flat out uint v_instance;
flat out int v_level;
flat out uvec4 v_views;
flat out vec4 v_weights;
flat out uint v_node; // index of the facet's node (select.comp), for the seen bits

// The square's half side and in-plane axes for a facet at c of voxel size w.
void facet_frame(InstanceLod lod, vec3 c, float w, out vec3 side, out vec3 up, out float half_side, out float reach)
{
    vec3 e = to_eye_object(lod, c);
    if (facet_shape == MF_FACET_FIXED) {
        vec3 a = abs(e);
        int major = a.x >= a.y && a.x >= a.z ? 0 : (a.y >= a.z ? 1 : 2);
        side = vec3(0.0);
        up = vec3(0.0);
        side[(major + 1) % 3] = 1.0;
        up[(major + 2) % 3] = 1.0;
        half_side = 0.5 * w;
        reach = 0.7072 * w;
        return;
    }
    side = cross(lod.up_object.xyz, e);
    if (dot(side, side) < 1e-8) side = cross(abs(e.x) < 0.9 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0), e);
    side = normalize(side);
    up = cross(e, side);
    half_side = 0.8660254 * w;
    if (lod.forward_object.w < 0.5) {
        float d = length(lod.eye_object.xyz - c), r = 0.8660254 * w;
        if (d > 1.01 * r) half_side *= d / sqrt(d * d - r * r);
    }
    reach = 1.4143 * half_side;
}

// a corner of the face towards the eye across `axis` of the voxel at c (size w); false when the
// eye is level with the voxel along that axis (no face of that axis faces it)
bool box_corner(InstanceLod lod, vec3 c, float w, int axis, vec2 corner, out vec3 p)
{
    float towards = lod.forward_object.w > 0.5 ? -lod.forward_object[axis] : lod.eye_object[axis] - c[axis];
    if (lod.forward_object.w < 0.5 && abs(towards) <= 0.5 * w) return false;
    if (lod.forward_object.w > 0.5 && abs(towards) < 1e-6) return false;
    p = c;
    p[axis] += sign(towards) * 0.5 * w;
    p[(axis + 1) % 3] += 0.5 * w * corner.x;
    p[(axis + 2) % 3] += 0.5 * w * corner.y;
    return true;
}

void main()
{
    Facet f = quads.items[gl_VertexID / vertices_per_facet];
    uint i = facet_instance(f);
    int level = facet_level(f);
    InstanceLod lod = lods.items[i];
    vec3 c = voxel_center(f.a.y, level);
    float w = voxel_size(level);
    const int corners[6] = int[6](0, 1, 2, 2, 1, 3);
    int k = corners[gl_VertexID % 6];
    vec2 corner = vec2(float(k & 1), float(k >> 1)) * 2.0 - 1.0;
    mat4 world_from_object = instances.world_from_object[i];
    v_instance = i;
    v_level = level;
    v_views = uvec4(uint(facet_view(f, 0)), uint(facet_view(f, 1)), uint(facet_view(f, 2)), uint(facet_view(f, 3)));
    v_weights = vec4(facet_weight(f, 0), facet_weight(f, 1), facet_weight(f, 2), facet_weight(f, 3));
    v_node = f.b.w;
    v_center = c;
    v_corner = corner;
    if (facet_shape == MF_FACET_BOX) {
        vec3 p;
        if (!box_corner(lod, c, w, (gl_VertexID % vertices_per_facet) / 6, corner, p)) {
            gl_Position = vec4(2.0, 2.0, 2.0, 1.0); // collapsed: no fragments
            v_position = c;
            return;
        }
        v_position = p;
        gl_Position = frame.clip_from_world * (world_from_object * vec4(p, 1.0));
        return;
    }

    vec3 side, up;
    float half_side, reach;
    facet_frame(lod, c, w, side, up, half_side, reach);
    vec3 p = c + half_side * (corner.x * side + corner.y * up);

    v_position = p;
    vec3 p_world = (world_from_object * vec4(p, 1.0)).xyz;
    float shift = 0.5005 * w * lod.eye_object.w; // half a voxel, world units
    if (frame.forward_world.w > 0.5) {
        p_world -= frame.forward_world.xyz * shift;
    } else {
        vec3 c_world = (world_from_object * vec4(c, 1.0)).xyz;
        float nearest = dot(c_world - frame.eye_world.xyz, frame.forward_world.xyz) - reach * lod.eye_object.w;
        if (nearest > 2.0 * shift) p_world = frame.eye_world.xyz + (p_world - frame.eye_world.xyz) * (1.0 - shift / nearest);
    }
    gl_Position = frame.clip_from_world * vec4(p_world, 1.0);
}
