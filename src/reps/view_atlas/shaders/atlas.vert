#version 450 core
// View atlas: one proxy per instance. Style seed (Saraiva et al. §3): the crop rectangle of the nearest
// view on the plane through the sphere's centre, turned to face the camera (a 4-vertex strip).
// Octahedral-baseline: a camera-facing quad covering the bounding sphere, as impostor bakers draw.
// Corrected: the proxy hull (hull.h proxy_polytope, issue #17: the source box cut by the baked
// planes tangent to the model; an indexed draw of its own, back faces culled, hull_pass 1), or, for
// the instances renderer.cpp keeps off it (on_hull: under --hull-above pixels, the near plane
// clipping the hull, a mirroring transform, the seed's level, no planes in the package), the
// nearest view's crop prism below (36 vertices). The fragment stage casts the rays; with the eye
// inside the prism, the whole screen.
// Level of detail (beyond the paper, for crowds), corrected style only: renderer.cpp sorts the
// instances by the radius in pixels of their bounding spheres into one draw per level (draw_lod),
// each with a fragment program of that level alone. Under --baseline-below an instance keeps its
// cut-out hull but is shaded as the octahedral baseline (three views around its direction, a few
// parallax steps: no walk); under --seed-below it is drawn as the seed's quad (the prism draw's
// first 6 vertices) and shaded as the seed. The thresholds were chosen by comparing each level's
// picture with the corrected one at the switch size (docs/RESULTS.md, "View atlas crowd: level of
// detail"): there the walk's parallax is below a pixel or two, and its hull and walk cost most of a
// crowd's frame.
#include "gpu/shaders/common/frame.glsl"
#include "reps/view_atlas/shaders/atlas.glsl"

uniform int style;
uniform int draw_lod; // corrected style: ATLAS_LOD_*, the level of this draw's instances (renderer.cpp)
// The proxy hull's vertices (object space, xyz), indexed by the hull pass's element buffer.
layout(std430, binding = ATLAS_HULL_SSBO) readonly buffer HullBlock {
    vec4 vertices[];
} hull;
uniform int hull_pass;       // 1: this draw is the proxy hull's (never the seed's level)
uniform int instance_offset; // this draw's first instance in the frame's instance block

flat out ivec3 v_views;
flat out vec3 v_weights;
flat out int v_instance;
flat out int v_lod; // ATLAS_LOD_*: the level of detail a corrected-style instance is shaded at
out vec2 v_atlas_texel; // seed: atlas texel position (level 0) on the nearest view's page

void main()
{
    int instance = gl_InstanceID + instance_offset;
    mat4 world_from_object = instances.world_from_object[instance];
    mat4 object_from_world = inverse(world_from_object);
    vec3 eye_object = (object_from_world * vec4(frame.eye_world.xyz, 1.0)).xyz;
    vec3 e = frame.forward_world.w > 0.5 ? -normalize(mat3(object_from_world) * frame.forward_world.xyz)
                                         : normalize(eye_object - atlas_center);
    vec2 corner = vec2(gl_VertexID & 1, (gl_VertexID >> 1) & 1);
    v_instance = instance;
    v_lod = style == STYLE_CORRECTED ? draw_lod : ATLAS_LOD_CORRECTED;
    bool lod_seed = v_lod == ATLAS_LOD_SEED;
    bool ortho = frame.forward_world.w > 0.5;
    if (hull_pass != 0) { // every vertex may be a triangle's provoking one: each writes the views
        gl_Position = frame.clip_from_world * (world_from_object * vec4(hull.vertices[gl_VertexID].xyz, 1.0));
        v_atlas_texel = vec2(0.0);
        if (v_lod == ATLAS_LOD_BASELINE) {
            blend_views(e, v_views, v_weights);
        } else {
            v_views = ivec3(nearest_view(e), 0, 0);
            v_weights = vec3(1.0, 0.0, 0.0);
        }
        return;
    }
    if (lod_seed) {
        const int strip_corner[6] = int[6](0, 1, 3, 0, 3, 2); // the strip's quad as two triangles
        int c = strip_corner[min(gl_VertexID, 5)];
        corner = vec2(c & 1, (c >> 1) & 1);
    }

    if (style == STYLE_SEED || lod_seed) {
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

    v_atlas_texel = vec2(0.0);
    float distance_to_center = length(eye_object - atlas_center);

    if (style == STYLE_CORRECTED) {
        // The cut-out hull: the prism of the nearest view's crop, from its nearest stored height down
        // to the back of the sphere. Every point of the model projects into every view's crop, so
        // this prism holds the whole model; drawn as its faces towards the eye (36 vertices, the
        // others collapsed), each covered pixel runs the fragment stage once.
        // the baseline level blends the views around the instance's direction (the nearest first);
        // the corrected fragment stage picks its own per pixel
        if (v_lod == ATLAS_LOD_BASELINE) {
            blend_views(e, v_views, v_weights);
        } else {
            v_views = ivec3(nearest_view(e), 0, 0);
            v_weights = vec3(1.0, 0.0, 0.0);
        }
        int k = v_views.x;
        ViewData view = views.items[k];
        vec3 lo = vec3(plane_from_capture(vec2(view.crop.xy)), -atlas_radius);
        vec3 hi = vec3(plane_from_capture(vec2(view.crop.xy + view.crop.zw)),
                       min(view.depth_range.x + 2.0 * atlas_radius / 255.0, atlas_radius));
        mat3 view_to_object = mat3(view.axis_u.xyz, view.axis_v.xyz, view.direction.xyz);
        vec3 eye_view = transpose(view_to_object) * (eye_object - atlas_center);
        int face = gl_VertexID / 6, axis = face >> 1;
        float side = (face & 1) == 0 ? 1.0 : -1.0;
        const int quad_corner[6] = int[6](0, 1, 2, 0, 2, 3);
        int q = quad_corner[gl_VertexID % 6];
        vec2 ab = vec2(q == 1 || q == 2 ? 1.0 : 0.0, q >= 2 ? 1.0 : 0.0);
        vec3 at;
        at[axis] = side > 0.0 ? hi[axis] : lo[axis];
        at[(axis + 1) % 3] = mix(lo[(axis + 1) % 3], hi[(axis + 1) % 3], ab.x);
        at[(axis + 2) % 3] = mix(lo[(axis + 2) % 3], hi[(axis + 2) % 3], ab.y);
        vec3 normal = vec3(0.0);
        normal[axis] = side;
        vec3 e_view = transpose(view_to_object) * e;
        bool faces_eye = ortho ? dot(normal, e_view) > 0.0 : dot(normal, eye_view - at) > 0.0;
        bool inside = !ortho && all(greaterThan(eye_view, lo)) && all(lessThan(eye_view, hi));
        if (view.crop.z == 0 || view.depth_range.x < view.depth_range.y) {
            gl_Position = vec4(2.0, 2.0, 2.0, 1.0); // nothing seen: no fragments
        } else if (inside) {
            gl_Position = face == 0 ? vec4(ab * 2.0 - 1.0, -1.0, 1.0) : vec4(2.0, 2.0, 2.0, 1.0);
        } else if (!faces_eye) {
            gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
        } else {
            vec3 p = atlas_center + view_to_object * at;
            gl_Position = frame.clip_from_world * (world_from_object * vec4(p, 1.0));
        }
        return;
    }

    blend_views(e, v_views, v_weights);
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
