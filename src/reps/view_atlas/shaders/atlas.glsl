// The view atlas's per-view block and the nearest-view search (C++ side: ViewGpu and the lookup
// tables in renderer.cpp).
#include "reps/view_atlas/shaders/atlas_layout.glsl"

struct ViewData {
    vec4 direction; // xyz: unit, from the centre towards the capture camera
    vec4 axis_u;    // xyz: image columns
    vec4 axis_v;    // xyz: image rows (down)
    ivec4 crop;     // crop x, y, width, height in capture pixels
    ivec4 atlas;    // layer in its texture array, x, y (texels), texture array
    vec4 depth_range; // x: height of the nearest stored surface above the centre plane (object
                      // units, towards the capture camera), y: of the farthest; x < y when empty
};

layout(std430, binding = ATLAS_VIEWS_SSBO) readonly buffer ViewBlock {
    ViewData items[];
} views;

layout(std430, binding = ATLAS_INDEX_SSBO) readonly buffer IndexBlock {
    int entries[]; // 6 * LOOKUP_SIDE^2 lookup cells, then NEIGHBOURS per view
} index_data;

uniform vec3 atlas_center;     // object space
uniform float atlas_radius;
uniform float half_extent;     // of the captured square on the centre plane
uniform float resolution;      // capture pixels per side
uniform float capture_distance;
uniform int capture_ortho;
uniform int view_count;
uniform float page_size;

int lookup_cell(vec3 d)
{
    vec3 a = abs(d);
    int face;
    vec2 uv;
    if (a.x >= a.y && a.x >= a.z) {
        face = d.x > 0.0 ? 0 : 1;
        uv = d.yz / a.x;
    } else if (a.y >= a.z) {
        face = d.y > 0.0 ? 2 : 3;
        uv = d.xz / a.y;
    } else {
        face = d.z > 0.0 ? 4 : 5;
        uv = d.xy / a.z;
    }
    ivec2 cell = clamp(ivec2((uv * 0.5 + 0.5) * float(LOOKUP_SIDE)), ivec2(0), ivec2(LOOKUP_SIDE - 1));
    return face * LOOKUP_SIDE * LOOKUP_SIDE + cell.y * LOOKUP_SIDE + cell.x;
}

// The three views around e and their blend weights: cosine above the fourth-nearest's, so a view
// enters and leaves the blend with weight 0 (no popping). The nearest view is found by the lookup
// cube's guess, then a walk over nearest-neighbour lists while a neighbour is nearer; the walk
// and the ranking of its neighbours share one pass over each neighbour list: the ranking of the
// last list walked, where no neighbour was nearer, is the blend's. The three best neighbours are
// kept in scalars, not an array: llvmpipe runs a fragment program's every path masked, and a
// dynamically indexed local array became a ladder of selects on every fragment (the corrected
// style picks its views per pixel: the frame of a crowd of 1000 about -20%, docs/RESULTS.md "Views per
// pixel without arrays").
void blend_views(vec3 e, out ivec3 ids, out vec3 weights)
{
    int k = index_data.entries[lookup_cell(e)];
    float best = dot(views.items[k].direction.xyz, e);
    int neighbour_base = 6 * LOOKUP_SIDE * LOOKUP_SIDE;
    int b1 = -1, b2 = -1, b3 = -1;        // the nearest neighbours of k, nearest first
    float c1 = -2.0, c2 = -2.0, c3 = -2.0; // their cosines
    for (int step = 0; step < 65; ++step) {
        int next = k;
        float next_cosine = best;
        b1 = -1, b2 = -1, b3 = -1;
        c1 = -2.0, c2 = -2.0, c3 = -2.0;
        for (int i = 0; i < NEIGHBOURS; ++i) {
            int n = index_data.entries[neighbour_base + k * NEIGHBOURS + i];
            if (n < 0) continue;
            float c = dot(views.items[n].direction.xyz, e);
            if (c > next_cosine || (c == next_cosine && n < next)) {
                next_cosine = c;
                next = n;
            }
            if (c > c1) {
                c3 = c2, b3 = b2;
                c2 = c1, b2 = b1;
                c1 = c, b1 = n;
            } else if (c > c2) {
                c3 = c2, b3 = b2;
                c2 = c, b2 = n;
            } else if (c > c3) {
                c3 = c, b3 = n;
            }
        }
        // 64 steps of the walk at most: the 65th pass only ranks the neighbours of where they ended
        if (next == k || step == 64) break;
        k = next;
        best = next_cosine;
    }
    float floor_cosine = b3 >= 0 ? c3 : c2 - 1e-3;
    ids = ivec3(k, max(b1, 0), max(b2, 0));
    weights = max(vec3(best, c1, c2) - floor_cosine, vec3(0.0));
    if (b1 < 0) weights.y = 0.0;
    if (b2 < 0) weights.z = 0.0;
    float sum = weights.x + weights.y + weights.z;
    weights = sum > 0.0 ? weights / sum : vec3(1.0, 0.0, 0.0);
}

// The view nearest to direction e (largest cosine): blend_views' first.
int nearest_view(vec3 e)
{
    ivec3 ids;
    vec3 weights;
    blend_views(e, ids, weights);
    return ids.x;
}

// Rotation taking unit a onto unit b (Rodrigues).
mat3 rotation_between(vec3 a, vec3 b)
{
    vec3 axis = cross(a, b);
    float s = length(axis), c = dot(a, b);
    if (s < 1e-7) return mat3(1.0);
    axis /= s;
    mat3 k = mat3(0.0, axis.z, -axis.y, -axis.z, 0.0, axis.x, axis.y, -axis.x, 0.0);
    return mat3(1.0) + s * k + (1.0 - c) * k * k;
}

// plane coordinates (along axis_u, axis_v, object units) of a capture pixel position
vec2 plane_from_capture(vec2 pixel) { return -half_extent + pixel * (2.0 * half_extent / resolution); }
vec2 capture_from_plane(vec2 plane) { return (plane + half_extent) * (resolution / (2.0 * half_extent)); }
