#version 450 core
// Shading of the displaced surface: the normal and albedo sampled with the displacement (the paper
// never says where its shading normals came from), read at the fragment's place in its control
// face from the shading pattern (the finest, or 2 or 4 times finer for textures; three samples,
// barycentric), or on faces that are source triangles the albedo and cut-out from the source's
// texture (source_textures.h), lit by the shared lighting.glsl with
// the frame's shadows. True depth: the triangles are real geometry. Debug views: control faces,
// bisection depth, and the distance to the finest surface in pixels (the paper's Fig. 11c).
#include "gpu/shaders/common/frame.glsl"
#include "gpu/shaders/common/fade.glsl"
#include "gpu/shaders/common/lighting.glsl"
#include "gpu/shaders/common/counters.glsl"
#include "reps/displaced_mesh/shaders/displaced.glsl"

layout(std430, binding = DM_SHADING_SSBO) readonly buffer ShadingBlock { uvec2 shading[]; };
layout(std430, binding = DM_PBR_SSBO) readonly buffer PbrBlock { uvec2 pbr_samples[]; }; // only when has_pbr_maps
uniform int has_pbr_maps; // the package has ORM and emission (issue #14); otherwise Material's defaults
// the package stores coverage in the albedo's alpha (issue #14): interpolated across the finest
// pattern triangle and cut where it falls below 1/2, a contour halfway between covered and cut-out
// samples. Read from the finest pattern at every refinement, so a pixel far away point-samples
// the same field the truth point-samples its texture with, and the leaves keep their area.
uniform int has_coverage;
// back faces culled here, not by GL (renderer.cpp cull_in_shader_): a front face is one whose
// winding on screen, turned by its instance's mirror where it has one, is counter-clockwise
uniform int cull_in_shader;

// Counters count the fragments that pass the depth test. Early tests write depth before the shader
// runs, so a fragment a cross-fade drops, or a cut-out discards, would still write depth: the
// renderer draws faded frames and packages with coverage with a variant compiled with DM_FADED,
// where depth is tested after the shader (and the counters then also count fragments that fail
// the test).
#ifndef DM_FADED
layout(early_fragment_tests) in;
#endif

uniform int counting; // 1: add this fragment, its reads and its error to the counters

// What this program draws, compiled in by the renderer (renderer.cpp compile_draw_programs):
// llvmpipe runs every branch of a fragment program for every fragment, masked, so a branch taken
// only on some frames costs all of them. Without the defines (a program built from this file
// alone) every path is in and the uniforms choose.
#ifndef DM_MEASURE_ERROR
#define DM_MEASURE_ERROR 1 // the fragment's error in pixels, for counted frames and the error view
#endif
#ifndef DM_FOLLOW_CONTROL
#define DM_FOLLOW_CONTROL 1 // the control mesh has moved: turn the shading normals with it
#endif
#ifndef DM_PBR
#define DM_PBR 1 // the package may have ORM and emission samples (has_pbr_maps says)
#endif

#ifndef DM_SOURCE_TEXTURES
#define DM_SOURCE_TEXTURES 1 // the package has faces drawn with the source's textures (source_textures.h)
#endif
// The cut-out pre-pass of packages with coverage (renderer.cpp draw): only the tests that decide
// whether the fragment is there (cut-out, cross-fade, culling), writing depth and no colour; the
// shading pass after it shades only the fragments whose depth equals the nearest.
#ifndef DM_DEPTH_ONLY
#define DM_DEPTH_ONLY 0
#endif

#if DM_SOURCE_TEXTURES
// A control face that is a source triangle (source_textures.h FaceTexture, 48 bytes): its corners'
// UVs and colours, the layer of its texture (DM_NO_TEXTURE: none) and its alpha cutoff.
struct FaceTexture {
    vec2 uv[3];
    uint layer;
    float cutoff;
    uint color[3];
    uint reserved;
};
#define DM_NO_TEXTURE 0xffffffffu
layout(std430, binding = DM_FACE_TEXTURE_SSBO) readonly buffer FaceTextureBlock { FaceTexture face_textures[]; };
// the source textures by size class (renderer.cpp k_max_source_arrays): a record's layer names its
// array in the top bits, and every array is read, the record's kept (masked on llvmpipe anyway)
#ifndef DM_SOURCE_ARRAYS
#define DM_SOURCE_ARRAYS 1
#endif
layout(binding = DM_SOURCE_TEXTURE_UNIT) uniform sampler2DArray source_textures[DM_SOURCE_ARRAYS];
#endif

in vec3 v_position_world;
in vec2 v_face_bary;
flat in uint v_face;
flat in uint v_instance;
flat in uint v_depth;

layout(location = 0) out vec4 out_color;

vec3 decode_normal(uint bits)
{
    vec2 p = max(unpackSnorm2x16(bits), vec2(-1.0));
    vec3 n = vec3(p, 1.0 - abs(p.x) - abs(p.y));
    if (n.z < 0.0) n.xy = (1.0 - abs(n.yx)) * vec2(n.x >= 0.0 ? 1.0 : -1.0, n.y >= 0.0 ? 1.0 : -1.0);
    return normalize(n);
}

// The shading pattern: the finest elevation pattern's segments times the package's shading detail
// (1, 2 or 4), and its samples per face.
uniform int shading_segments;
uniform uint shading_per_face;

// The shading pattern's triangle holding the fragment: its three samples and weights.
void finest_triangle(out uint index[3], out float weight[3])
{
    int n = shading_segments;
    float x = clamp(v_face_bary.x, 0.0, 1.0) * float(n), y = clamp(v_face_bary.y, 0.0, 1.0) * float(n);
    int i0 = clamp(int(floor(y)), 0, n - 1);
    int j0 = clamp(int(floor(x)), 0, n - 1 - i0);
    float fx = x - float(j0), fy = y - float(i0);
    uint face_base = v_face * shading_per_face;
    if (fx + fy <= 1.0) {
        index = uint[3](face_base + triangle_index(n, i0, j0), face_base + triangle_index(n, i0, j0 + 1),
                        face_base + triangle_index(n, i0 + 1, j0));
        weight = float[3](1.0 - fx - fy, fx, fy);
    } else {
        index = uint[3](face_base + triangle_index(n, i0, j0 + 1), face_base + triangle_index(n, i0 + 1, j0 + 1),
                        face_base + triangle_index(n, i0 + 1, j0));
        weight = float[3](1.0 - fy, fx + fy - 1.0, 1.0 - fx);
    }
}

// A vertex's frame: its normal and the direction to its reference neighbour, made orthogonal.
mat3 vertex_frame(vec3 normal, vec3 position, vec3 neighbour)
{
    vec3 n = normalize(normal);
    vec3 t = neighbour - position;
    t = normalize(t - dot(t, n) * n);
    return mat3(t, cross(n, t), n);
}

// A moved control mesh (§5.3): the maps' normals were sampled in the rest pose, so turn them as the
// corners' frames turned, blended across the face like the corners (continuous across edges).
vec3 follow_control_mesh(vec3 normal)
{
    uvec3 corner = faces[v_face].corners.xyz;
    float w[3] = float[3](1.0 - v_face_bary.x - v_face_bary.y, v_face_bary.x, v_face_bary.y);
    vec3 turned = vec3(0.0);
    for (int k = 0; k < 3; ++k) {
        ControlVertex c = control_vertices[corner[k]];
        mat3 rest = mat3(c.rest_tangent.xyz, cross(c.rest_normal.xyz, c.rest_tangent.xyz), c.rest_normal.xyz);
        mat3 now = vertex_frame(c.normal.xyz, c.position.xyz, control_position(c.reference.x));
        turned += w[k] * (now * (transpose(rest) * normal));
    }
    return turned;
}

// Distance in pixels from this fragment to the finest displaced surface at the same place of the
// face: the geometric error of the refinement (what the tolerance tau bounds).
float error_pixels(mat4 world_from_object)
{
    uint q1 = uint(clamp(v_face_bary.x, 0.0, 1.0) * float(BARY_ONE));
    uint q2 = min(uint(clamp(v_face_bary.y, 0.0, 1.0) * float(BARY_ONE)), BARY_ONE - q1);
    FacePoint point = face_point(faces[v_face].corners.xyz, q1, q2);
    vec3 finest = point.position + elevation_at(v_face, q1, q2, 0.0) * unit_direction(point.normal);
    vec3 finest_world = (world_from_object * vec4(finest, 1.0)).xyz;
    float d = length(finest_world - v_position_world) * refine.view_terms.y;
    if (refine.view_terms.w < 0.5) d /= max(refine.view_terms.z, -(frame.view_from_world * vec4(v_position_world, 1.0)).z);
    return d;
}

void main()
{
#if DM_SOURCE_TEXTURES
    // a face that is a source triangle reads the source's texture as the truth does (mesh.frag):
    // colour through the mip levels, the alpha test at the full-resolution level; read before any
    // discard, on every fragment (implicit derivatives want the whole quad)
    FaceTexture source = face_textures[v_face];
    const float w0 = 1.0 - v_face_bary.x - v_face_bary.y;
    const uint source_array = source.layer == DM_NO_TEXTURE ? 0u : source.layer >> DM_SOURCE_ARRAY_SHIFT;
    const uint source_layer = source.layer == DM_NO_TEXTURE ? 0u : source.layer & ((1u << DM_SOURCE_ARRAY_SHIFT) - 1u);
    const vec3 source_uv = vec3(w0 * source.uv[0] + v_face_bary.x * source.uv[1] + v_face_bary.y * source.uv[2], float(source_layer));
    // (the UV's derivatives from the barycentrics', a varying's: derived implicitly from the
    // records' storage reads, llvmpipe's came out near zero, and the minigun's texture was
    // point-sampled at level 0, Luv 0.59 -> 5.8)
#if !DM_DEPTH_ONLY
    const vec2 d_bary_x = dFdx(v_face_bary), d_bary_y = dFdy(v_face_bary);
    const mat2 uv_from_bary = mat2(source.uv[1] - source.uv[0], source.uv[2] - source.uv[0]);
    vec4 source_texel = vec4(0.0);
#endif
    float source_alpha = 0.0;
    for (int a = 0; a < DM_SOURCE_ARRAYS; ++a) {
        if (uint(a) != source_array) continue;
#if !DM_DEPTH_ONLY
        source_texel = textureGrad(source_textures[a], source_uv, uv_from_bary * d_bary_x, uv_from_bary * d_bary_y);
#endif
        source_alpha = textureLod(source_textures[a], source_uv, 0.0).a;
    }
#endif
    if (fade_discards()) discard; // a cross-fade's other renderer owns this pixel
    uint index[3];
    float weight[3];
    finest_triangle(index, weight);
    vec3 normal = vec3(0.0);
    vec4 albedo = vec4(0.0);
    for (int k = 0; k < 3; ++k) {
        uvec2 s = shading[index[k]];
#if !DM_DEPTH_ONLY
        normal += weight[k] * decode_normal(s.x);
#endif
        albedo += weight[k] * unpackUnorm4x8(s.y);
    }
    bool cut_out = has_coverage != 0 && albedo.a < 0.5;
#if DM_SOURCE_TEXTURES
    if (source.layer != DM_NO_TEXTURE) {
        vec4 corners = w0 * unpackUnorm4x8(source.color[0]) + v_face_bary.x * unpackUnorm4x8(source.color[1]) +
                       v_face_bary.y * unpackUnorm4x8(source.color[2]);
#if !DM_DEPTH_ONLY
        albedo = vec4(corners.rgb * source_texel.rgb, 1.0);
#endif
        cut_out = source.cutoff > 0.0 && corners.a * source_alpha < source.cutoff;
    }
#endif
    if (cut_out) discard;
    mat4 world_from_object = instances.world_from_object[v_instance];
    if (cull_in_shader != 0 && gl_FrontFacing == (determinant(mat3(world_from_object)) < 0.0)) discard;
#if !DM_DEPTH_ONLY // the pre-pass ends here: depth only
    if (DM_FOLLOW_CONTROL != 0 && refine.error_terms.y > 0.5) normal = follow_control_mesh(normalize(normal));
    vec3 normal_world = mat3(world_from_object) * normal; // similarity transforms
    vec3 to_eye = frame.forward_world.w > 0.5 ? -frame.forward_world.xyz : normalize(frame.eye_world.xyz - v_position_world);
    vec3 orm = SHADING_DEFAULT_ORM, emissive = vec3(0.0);
    if (DM_PBR != 0 && has_pbr_maps != 0) {
        vec4 orm_sum = vec4(0.0), emission_sum = vec4(0.0);
        for (int k = 0; k < 3; ++k) {
            uvec2 s = pbr_samples[index[k]];
            orm_sum += weight[k] * unpackUnorm4x8(s.x);
            emission_sum += weight[k] * unpackUnorm4x8(s.y);
        }
        orm = orm_sum.rgb;
        emissive = srgb_to_linear(emission_sum.rgb);
    }
    vec3 color = shade_pbr_at(albedo.rgb, orm, emissive, normal_world, to_eye, v_position_world);

    uint debug_view = refine.options.w;
    bool want_error = DM_MEASURE_ERROR != 0 && (debug_view == DEBUG_VIEW_ERROR || counting != 0);
    float error_px = want_error ? error_pixels(world_from_object) : 0.0;
#if DM_MEASURE_ERROR
    // only in the measuring program (renderer.cpp chooses it while counting): on llvmpipe this
    // branch cost every fragment of every frame whatever the uniform (the 4,000-face tree at 800 x
    // 600: 72 ms a frame with it, 39 without; docs/RESULTS.md)
    if (counting != 0) {
        count_fragment(3u);
        uint e = uint(min(error_px * DM_ERROR_UNITS, 1.0e9));
        atomicAdd(counters[DM_COUNTER_ERROR_SUM], e);
        atomicMax(counters[DM_COUNTER_ERROR_MAX], e);
    }
#endif
    if (debug_view == DEBUG_VIEW_PARTS) color = index_color(int(v_face));
    else if (debug_view == DEBUG_VIEW_LEVEL) color = heat(float(v_depth) / float(3u * refine.counts.w + 6u));
    else if (debug_view == DEBUG_VIEW_ERROR) color = heat(error_px / refine.error_terms.x);
    else if (debug_view == DEBUG_VIEW_DEPTH) color = vec3(1.0 - gl_FragCoord.z);
    else if (debug_view == DEBUG_VIEW_NORMAL) color = normalize(normal_world) * 0.5 + 0.5;
    out_color = vec4(color, 1.0);
#endif
}
