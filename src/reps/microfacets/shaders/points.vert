#version 450 core
// Microfacets drawn as points with one colour each (Yamazaki et al. 2002 §3.3.1, Table 1 row b),
// for facets smaller than a pixel or on request: the views' texels where the voxel centre projects,
// kept where eq. 1 passes there (A15 in docs/ARCHITECTURE.md), the colour averaged over the
// facet's footprint in the view (its mip level); a point no view passes at is dropped. Drawn half a
// voxel nearer the eye, as the quads (facets.vert), with the stored surface's depth.
#include "gpu/shaders/common/frame.glsl"
#include "reps/microfacets/shaders/microfacets.glsl"
#include "reps/microfacets/shaders/microfacets_sample.glsl"

layout(std430, binding = MF_POINTS_SSBO) readonly buffer PointBlock {
    Facet items[];
} points;

uniform float screen_pixels; // pixels per world unit (at distance 1 for perspective cameras)
uniform int coverage_rule;

flat out vec3 v_color;
flat out vec3 v_orm;      // occlusion, roughness, metallic
flat out vec3 v_emission; // sRGB-encoded
flat out vec3 v_normal_world;
flat out vec3 v_surface_world;
flat out int v_view;
flat out int v_level;
flat out uint v_fetches;

void main()
{
    Facet f = points.items[gl_VertexID];
    uint i = facet_instance(f);
    int level = facet_level(f);
    InstanceLod lod = lods.items[i];
    vec3 c = voxel_center(f.a.y, level);
    float w = voxel_size(level);

    vec3 color = vec3(0.0), normal = vec3(0.0), surface = c, orm = vec3(0.0), emission = vec3(0.0);
    float weight = 0.0, best = -1.0;
    v_view = facet_view(f, 0);
    for (int k = 0; k < MF_MAX_BLEND; ++k) {
        float wk = facet_weight(f, k);
        if (wk <= 0.0) continue;
        ViewSample s = sample_view(views.items[facet_view(f, k)], c, c, w, color_lod(1.7320508 * w));
        if (!s.passed) continue;
        color += wk * s.color;
        normal += wk * facing(s.normal, to_eye_object(lod, c));
        orm += wk * s.orm;
        emission += wk * s.emission;
        weight += wk;
        if (wk > best) {
            best = wk;
            surface = s.surface;
            v_view = facet_view(f, k);
        }
    }
    v_fetches = g_fetches;
    v_level = level;
    bool covered = coverage_rule == MF_COVERAGE_VOTE ? weight >= 0.5 : weight > 0.0;
    if (!covered) {
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0); // outside the clip volume: no fragment
        gl_PointSize = 1.0;
        return;
    }
    mat4 world_from_object = instances.world_from_object[i];
    v_color = color / weight;
    v_orm = orm / weight;
    v_emission = emission / weight;
    v_normal_world = normalize(mat3(world_from_object) * normal);
    v_surface_world = (world_from_object * vec4(surface, 1.0)).xyz;

    float w_world = w * lod.eye_object.w;
    vec3 c_world = (world_from_object * vec4(c, 1.0)).xyz;
    float pixels = screen_pixels;
    if (frame.forward_world.w > 0.5) {
        c_world -= frame.forward_world.xyz * (0.5005 * w_world);
    } else {
        float d = max(dot(c_world - frame.eye_world.xyz, frame.forward_world.xyz), 1e-6);
        pixels /= d;
        if (d > w_world) c_world = frame.eye_world.xyz + (c_world - frame.eye_world.xyz) * (1.0 - 0.5005 * w_world / d);
    }
    gl_PointSize = clamp(1.7320508 * w_world * pixels, 1.0, 64.0);
    gl_Position = frame.clip_from_world * vec4(c_world, 1.0);
}
