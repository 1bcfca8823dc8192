// The displaced control mesh on the GPU (Bauman, Livny & El-Sana §3.3, §3.4): buffers, the points
// of a control face, the split test, culling on the prism and the displaced position. Mirrors
// refine.cpp and face_point.h line for line; include after frame.glsl.
#include "reps/displaced_mesh/shaders/displaced_layout.glsl"

#define BARY_ONE (1u << DM_BARY_BITS)

layout(std140, binding = DM_REFINE_UBO) uniform RefineBlock {
    mat4 clip_from_view;
    vec4 view_terms;   // x: tau (px), y: pixels per world unit at depth 1, z: near plane, w: 1 orthographic
    uvec4 counts;      // x: control faces, y: instances, z: pattern segments n, w: exponent m
    uvec4 options;     // x: criterion, y: mip (1/0), z: cull (1/0), w: debug view
    uvec4 capacities;  // x: list capacity (records), y: final capacity, z: samples per face, w: finest samples
    vec4 error_terms;  // x: full scale of the error view (px); y: 1 when the control mesh moved (§5.3);
                       // z: the error criterion's weight near the outline
} refine;

struct ControlVertex {
    vec4 position;
    vec4 normal;
    // the frame the maps were sampled in (moved control meshes, §5.3): normal, and the direction
    // to a neighbour (`reference`) made orthogonal to it
    vec4 rest_normal;
    vec4 rest_tangent;
    uvec4 reference;
};
layout(std430, binding = DM_VERTICES_SSBO) readonly buffer VertexBlock { ControlVertex control_vertices[]; };

struct FaceData {
    uvec4 corners;  // c0, c1, c2, bit k: the face walks its edge k against the edge's canonical direction
    vec4 weights;   // edges 0, 1, 2 (corner k -> k + 1), inside
    vec4 range;     // h_min, h_max, cone half-angle (radians), normal shrink
    vec4 extra;     // x: finest grid length inside the face
    vec4 curvature; // edges 0, 1, 2, inside: 1 / world units (the error criterion)
};
layout(std430, binding = DM_FACES_SSBO) readonly buffer FaceBlock { FaceData faces[]; };
layout(std430, binding = DM_ELEVATIONS_SSBO) readonly buffer ElevationBlock { float elevations[]; };

vec3 control_position(uint v) { return control_vertices[v].position.xyz; }
vec3 control_normal(uint v) { return control_vertices[v].normal.xyz; }

// ---------------------------------------------------------------------------------------------
// Points of a face (face_point.h): corners are the vertices, points on an edge come from the edge
// alone in its canonical direction, so both faces compute the same bits.

struct FacePoint {
    vec3 position;
    vec3 normal;
};

FacePoint face_point(uvec3 corner, uint q1, uint q2)
{
    uint q[3] = uint[3](BARY_ONE - q1 - q2, q1, q2);
    for (int k = 0; k < 3; ++k)
        if (q[k] == BARY_ONE) return FacePoint(control_position(corner[k]), control_normal(corner[k]));
    for (int k = 0; k < 3; ++k) {
        if (q[k] != 0u) continue;
        int a = (k + 1) % 3, b = (k + 2) % 3;
        int lo = corner[a] < corner[b] ? a : b, hi = lo == a ? b : a;
        precise float t = float(q[hi]) / float(BARY_ONE);
        vec3 p_lo = control_position(corner[lo]), n_lo = control_normal(corner[lo]);
        precise vec3 p = p_lo + t * (control_position(corner[hi]) - p_lo);
        precise vec3 n = n_lo + t * (control_normal(corner[hi]) - n_lo);
        return FacePoint(p, n);
    }
    precise float w0 = float(q[0]) / float(BARY_ONE), w1 = float(q[1]) / float(BARY_ONE), w2 = float(q[2]) / float(BARY_ONE);
    precise vec3 p = w0 * control_position(corner[0]) + w1 * control_position(corner[1]) + w2 * control_position(corner[2]);
    precise vec3 n = w0 * control_normal(corner[0]) + w1 * control_normal(corner[1]) + w2 * control_normal(corner[2]);
    return FacePoint(p, n);
}

vec3 unit_direction(vec3 n)
{
    float length_n = length(n);
    return length_n > 0.0 ? n / length_n : vec3(0.0, 0.0, 1.0);
}

// ---------------------------------------------------------------------------------------------
// Elevations: a level's triangular array (pattern.h), points on an edge read that edge only.

uint triangle_index(int n, int i, int j) { return uint(i * (n + 1) - (i * (i - 1)) / 2 + j); }

uint level_offset(int level)
{
    uint offset = 0u;
    int n = int(refine.counts.z);
    for (int l = 0; l < level; ++l) offset += uint((n + 1) * (n + 2) / 2), n >>= 1;
    return offset;
}

float stored_elevation(uint face, int level, int i, int j)
{
    int n = int(refine.counts.z) >> level;
    return elevations[face * refine.capacities.z + level_offset(level) + triangle_index(n, i, j)];
}

void edge_vertex(int n, int edge, int s, out int i, out int j)
{
    if (edge == 0) {
        i = 0;
        j = s;
    } else if (edge == 1) {
        i = s;
        j = n - s;
    } else {
        i = n - s;
        j = 0;
    }
}

int edge_of_point(uint q1, uint q2)
{
    if (q2 == 0u) return 0;
    if (q1 + q2 == BARY_ONE) return 1;
    if (q1 == 0u) return 2;
    return -1;
}

float elevation_at_level(uint face, uint q1, uint q2, int level)
{
    int n = int(refine.counts.z) >> level;
    uvec3 corner = faces[face].corners.xyz;
    uint q[3] = uint[3](BARY_ONE - q1 - q2, q1, q2);
    for (int k = 0; k < 3; ++k)
        if (q[k] == BARY_ONE) {
            int i, j;
            edge_vertex(n, k, 0, i, j);
            return stored_elevation(face, level, i, j);
        }
    int edge = edge_of_point(q1, q2);
    if (edge >= 0) {
        int a = edge, b = (edge + 1) % 3;
        int hi = corner[a] < corner[b] ? b : a;
        precise float t = float(q[hi]) / float(BARY_ONE) * float(n);
        int s0 = min(int(floor(t)), n);
        precise float fraction = t - float(s0);
        bool reversed = ((faces[face].corners.w >> uint(edge)) & 1u) != 0u;
        int i, j;
        edge_vertex(n, edge, reversed ? n - s0 : s0, i, j);
        float v0 = stored_elevation(face, level, i, j);
        if (!(fraction > 0.0) || s0 >= n) return v0;
        edge_vertex(n, edge, reversed ? n - s0 - 1 : s0 + 1, i, j);
        float v1 = stored_elevation(face, level, i, j);
        precise float h = v0 + fraction * (v1 - v0);
        return h;
    }
    float x = float(q1) / float(BARY_ONE) * float(n), y = float(q2) / float(BARY_ONE) * float(n);
    int i0 = min(int(floor(y)), n - 1);
    int j0 = min(int(floor(x)), n - 1 - i0);
    float fx = x - float(j0), fy = y - float(i0);
    if (fx + fy <= 1.0)
        return (1.0 - fx - fy) * stored_elevation(face, level, i0, j0) + fx * stored_elevation(face, level, i0, j0 + 1) +
               fy * stored_elevation(face, level, i0 + 1, j0);
    return (1.0 - fy) * stored_elevation(face, level, i0, j0 + 1) + (fx + fy - 1.0) * stored_elevation(face, level, i0 + 1, j0 + 1) +
           (1.0 - fx) * stored_elevation(face, level, i0 + 1, j0);
}

float elevation_at(uint face, uint q1, uint q2, float level)
{
    int m = int(refine.counts.w);
    int l0 = clamp(int(floor(level)), 0, m);
    precise float fraction = level - float(l0);
    float h0 = elevation_at_level(face, q1, q2, l0);
    if (!(fraction > 0.0) || l0 >= m) return h0;
    float h1 = elevation_at_level(face, q1, q2, l0 + 1);
    precise float h = h0 + fraction * (h1 - h0);
    return h;
}

// ---------------------------------------------------------------------------------------------
// The view of one instance.

mat4 view_from_object(uint instance) { return frame.view_from_world * instances.world_from_object[instance]; }

float projected_length(vec3 a, vec3 b)
{
    precise float len = length(a - b) * refine.view_terms.y;
    if (refine.view_terms.w > 0.5) return len;
    precise float projected = len / max(refine.view_terms.z, min(-a.z, -b.z));
    return projected;
}

// The finest spacing at a point (refine.cpp grid_spacing).
float grid_spacing(uint face, uint q1, uint q2)
{
    int edge = edge_of_point(q1, q2);
    if (edge < 0) return faces[face].extra.x;
    uvec3 corner = faces[face].corners.xyz;
    uint a = corner[edge], b = corner[(edge + 1) % 3];
    return length(control_position(max(a, b)) - control_position(min(a, b))) / float(refine.counts.z);
}

// The displaced object-space position of a refined vertex (refine.cpp displaced_position).
vec3 displaced_position(uint face, uint q1, uint q2, mat4 view_object, out vec3 direction)
{
    FacePoint point = face_point(faces[face].corners.xyz, q1, q2);
    direction = unit_direction(point.normal);
    float level = 0.0;
    if (refine.options.y != 0u) {
        float scale = length(view_object[0].xyz);
        precise float spacing = grid_spacing(face, q1, q2) * scale * refine.view_terms.y;
        if (refine.view_terms.w < 0.5) spacing /= max(refine.view_terms.z, -(view_object * vec4(point.position, 1.0)).z);
        level = spacing > 0.0 ? clamp(log2(refine.view_terms.x / spacing), 0.0, float(refine.counts.w)) : 0.0;
    }
    precise vec3 p = point.position + elevation_at(face, q1, q2, level) * direction;
    return p;
}

// ---------------------------------------------------------------------------------------------
// Culling on the prism (§3.4).

#define PI 3.14159265358979

// Whether a control face's prism (corners displaced by its lowest and highest elevation) may be
// visible: inside the frustum and not wholly back-facing (refine.cpp face_visible).
bool face_visible(uint face, mat4 view_object)
{
    FaceData d = faces[face];
    vec3 corners[6];
    for (int k = 0; k < 3; ++k) {
        vec3 p = control_position(d.corners[k]), n = control_normal(d.corners[k]);
        corners[k] = (view_object * vec4(p + d.range.x * n, 1.0)).xyz;
        corners[k + 3] = (view_object * vec4(p + d.range.y * n, 1.0)).xyz;
    }
    vec3 centre = vec3(0.0);
    for (int k = 0; k < 6; ++k) centre += corners[k] / 6.0;
    float radius = 0.0, longest = 0.0;
    for (int k = 0; k < 6; ++k) radius = max(radius, length(corners[k] - centre));
    for (int k = 0; k < 3; ++k) longest = max(longest, length(corners[k] - corners[(k + 1) % 3]));
    float scale = length(view_object[0].xyz);
    radius += 0.01 * longest + scale * max(abs(d.range.x), abs(d.range.y)) * d.range.w;

    // frustum (Gribb & Hartmann 2001) in view space
    mat4 m = refine.clip_from_view;
    for (int plane = 0; plane < 6; ++plane) {
        vec4 r3 = vec4(m[0][3], m[1][3], m[2][3], m[3][3]);
        int axis = plane / 2;
        vec4 ra = vec4(m[0][axis], m[1][axis], m[2][axis], m[3][axis]);
        vec4 e = r3 + ((plane % 2) == 1 ? -1.0 : 1.0) * ra;
        if (dot(e.xyz, centre) + e.w < -radius * length(e.xyz)) return false;
    }

    // back faces
    if (d.range.z >= 0.5 * PI) return true;
    vec3 p0 = (view_object * vec4(control_position(d.corners.x), 1.0)).xyz;
    vec3 p1 = (view_object * vec4(control_position(d.corners.y), 1.0)).xyz;
    vec3 p2 = (view_object * vec4(control_position(d.corners.z), 1.0)).xyz;
    // (a mirroring transform turns the cross product of the face's edges against its normal)
    vec3 axis = cross(p1 - p0, p2 - p0);
    if (determinant(mat3(view_object)) < 0.0) axis = -axis;
    if (!(length(axis) > 0.0)) return true;
    axis = normalize(axis);
    float sin_cone = sin(d.range.z);
    if (refine.view_terms.w > 0.5) return dot(vec3(0.0, 0.0, -1.0), axis) < sin_cone;
    float distance_c = length(centre);
    if (distance_c <= radius) return true;
    return dot(centre / distance_c, axis) < sin_cone + radius / distance_c;
}
