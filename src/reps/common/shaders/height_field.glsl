// The height-field surface of image-based stand-ins (constants and rule: height_field.h): the
// same-surface link rule and the crossing of one texel column, shared by the enhanced billboards'
// march and the view atlas' walk. Depths grow away from the capture (into the field).
#ifndef STANDIN_HEIGHT_FIELD_GLSL
#define STANDIN_HEIGHT_FIELD_GLSL

#include "reps/common/shaders/height_field.h"

// The depth change per texel that a stored normal implies along one plane axis, capped:
// `along` and `across` are the normal's components along the axis and along the capture direction.
float hf_slope(float along, float across)
{
    along = abs(along);
    across = abs(across);
    return along >= across * HF_MAX_SLOPE ? HF_MAX_SLOPE : along / across;
}

// The largest depth step between two neighbouring texels of one surface, in depth units (the same
// units as `texel`, the texel's side, and `quantum`, one step of the stored depth).
float hf_link_tolerance(float slope_a, float slope_b, float texel, float quantum)
{
    return (HF_SLOPE_TOLERANCE * max(slope_a, slope_b) + HF_CURVATURE_TEXELS) * texel + HF_QUANTA * quantum;
}

// A ray crossing one covered texel column over [t_enter, t_exit], at depth z(t) = z_origin + t *
// z_per_t, with its top at depth `top`. `from_linked`: it came across the side at t_wall from a
// neighbour of the same surface whose top is `from_top`. The hit is that wall when the ray passes
// between the two tops there, else the top where the ray crosses it inside the column; a ray that
// entered below the top otherwise is in space the capture did not see. Returns (t, HF_*).
vec2 hf_cross_column(float t_wall, float t_enter, float t_exit, float z_origin, float z_per_t, float top,
                     bool from_linked, float from_top)
{
    if (from_linked) {
        float z_wall = z_origin + t_wall * z_per_t;
        if (z_wall >= min(from_top, top) && z_wall <= max(from_top, top)) return vec2(t_wall, HF_WALL);
    }
    float z_enter = z_origin + t_enter * z_per_t, z_exit = z_origin + t_exit * z_per_t;
    if (top >= min(z_enter, z_exit) && top <= max(z_enter, z_exit)) {
        float t_top = abs(z_per_t) > 1e-20 ? clamp((top - z_origin) / z_per_t, t_enter, t_exit) : t_enter;
        return vec2(t_top, HF_TOP);
    }
    return vec2(-1.0, z_enter > top ? HF_UNDER : HF_MISS);
}

#endif
