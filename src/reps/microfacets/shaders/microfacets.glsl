// The microfacet renderer's blocks and helpers, shared by its compute and drawing stages (C++ side:
// ViewGpu, InstanceLod and the facet records in renderer.cpp).
#include "reps/microfacets/shaders/microfacets_layout.glsl"

// One captured view (microfacets.h View): orthographic, capture pixel (x, y) on the centre plane at
// centre + (-r + x 2r / res) axis_u + (-r + y 2r / res) axis_v.
struct ViewData {
    vec4 direction; // xyz: unit, from the centre towards the capture camera
    vec4 axis_u;    // xyz: image columns
    vec4 axis_v;    // xyz: image rows (down)
    ivec4 crop;     // crop x, y, width, height in capture pixels
    ivec4 atlas;    // page (texture layer), x, y (texels), unused
};

layout(std430, binding = MF_VIEWS_SSBO) readonly buffer ViewBlock {
    ViewData items[];
} views;

// What the CPU works out per instance and frame (renderer.cpp plan_instances).
struct InstanceLod {
    vec4 eye_object;     // xyz: the eye in object space; w: world units per object unit
    vec4 forward_object; // xyz: unit view direction in object space; w: 1 for orthographic cameras
    vec4 up_object;      // xyz: unit camera up in object space (turns the facets with the screen)
    uvec4 work;          // x: first work item, y: work items, z: first level, w: finest level
};

layout(std430, binding = MF_INSTANCES_SSBO) readonly buffer InstanceLodBlock {
    InstanceLod items[];
} lods;

// A selected facet. a.x: instance (bits 0..23), level (24..27), kind (28..29); a.y: Morton code;
// a.z, a.w: view ids 0|1 and 2|3 (16 bits each); b.x, b.y: their weights, unorm16 pairs; b.z: in
// MF_SELECTED_SSBO, the rank among the group's quads (0..15) and points (16..31); b.w: the node's
// index (nodes' order), whose seen bits facets.frag reads for its fallback views.
struct Facet {
    uvec4 a;
    uvec4 b;
};

uniform vec3 grid_origin;  // object space, the voxel cube's minimum corner
uniform float grid_size;   // its side
uniform vec3 mf_center;    // the capture sphere's centre (object space)
uniform float mf_radius;
uniform float capture_resolution; // capture pixels per side

// three 10-bit coordinates from every third bit (voxels.cpp morton_decode)
uint compact_bits(uint x)
{
    x &= 0x09249249u;
    x = (x | (x >> 2)) & 0x030c30c3u;
    x = (x | (x >> 4)) & 0x0300f00fu;
    x = (x | (x >> 8)) & 0x030000ffu;
    x = (x | (x >> 16)) & 0x000003ffu;
    return x;
}

float voxel_size(int level) { return grid_size / float(1u << uint(level)); }

vec3 voxel_center(uint code, int level)
{
    uvec3 cell = uvec3(compact_bits(code), compact_bits(code >> 1), compact_bits(code >> 2));
    return grid_origin + (vec3(cell) + 0.5) * voxel_size(level);
}

uint facet_instance(Facet f) { return f.a.x & 0xffffffu; }
int facet_level(Facet f) { return int((f.a.x >> 24) & 15u); }
uint facet_kind(Facet f) { return (f.a.x >> 28) & 3u; }
int facet_view(Facet f, int k)
{
    uint word = k < 2 ? f.a.z : f.a.w;
    return int((k & 1) == 0 ? (word & 0xffffu) : (word >> 16));
}
float facet_weight(Facet f, int k)
{
    vec2 pair = unpackUnorm2x16(k < 2 ? f.b.x : f.b.y);
    return (k & 1) == 0 ? pair.x : pair.y;
}

// The direction from a point towards the eye, object space.
vec3 to_eye_object(InstanceLod lod, vec3 p)
{
    return lod.forward_object.w > 0.5 ? -lod.forward_object.xyz : normalize(lod.eye_object.xyz - p);
}

// capture pixel position (continuous, y down) of an object-space point in a view
vec2 capture_pixel(ViewData view, vec3 p)
{
    vec3 local = p - mf_center;
    vec2 plane = vec2(dot(local, view.axis_u.xyz), dot(local, view.axis_v.xyz));
    return (plane + mf_radius) * (capture_resolution / (2.0 * mf_radius));
}

// height above the centre plane along the view of a stored depth code (0 nearest the camera)
float stored_height(float depth_code) { return mf_radius - 2.0 * mf_radius * depth_code; }
