// Microfacets: reading a captured view at a point of a facet, with the clipping rule of Yamazaki et
// al. 2002 eq. 1 (a texel is kept where the view's stored surface lies within W/2 of the facet,
// measured along the view, §3.3.3). Shared by the quads' fragment stage and the points' vertex
// stage. Include after microfacets.glsl.
layout(binding = MF_COLOR_TEXTURE) uniform sampler2DArray color_pages;
layout(binding = MF_NORMAL_DEPTH_TEXTURE) uniform sampler2DArray normal_depth_pages;

uniform float page_size;  // texels per page side
uniform int max_color_lod; // mip levels of the colour pages that never mix two crops

uint g_fetches = 0u;

struct ViewSample {
    bool passed;    // covered and within W/2 (eq. 1)
    vec3 color;     // albedo, sRGB-encoded
    vec3 normal;    // object space, unnormalised
    vec3 surface;   // the stored surface point: the facet point moved along the view to its depth
};

// The view's sample at facet point p (object space) for a facet of voxel size w; `lod` is the
// colour's mip level (<= 0: the exact texel; above: the covered texels around it, averaged through
// the pages' coverage-premultiplied mips).
ViewSample sample_view(ViewData view, vec3 p, float w, float lod)
{
    ViewSample s;
    s.passed = false;
    ivec2 texel = ivec2(floor(capture_pixel(view, p)));
    if (any(lessThan(texel, view.crop.xy)) || any(greaterThanEqual(texel, view.crop.xy + view.crop.zw))) return s;
    ivec2 at = view.atlas.yz + texel - view.crop.xy;
    vec4 nd = texelFetch(normal_depth_pages, ivec3(at, view.atlas.x), 0);
    g_fetches += 1u;
    if (nd.r + nd.g + nd.b == 0.0) return s; // empty texel
    float stored = stored_height(nd.a), here = dot(p - mf_center, view.direction.xyz);
    if (abs(stored - here) >= 0.5 * w) return s; // eq. 1
    s.passed = true;
    s.normal = nd.rgb * 2.0 - 1.0;
    s.surface = p + (stored - here) * view.direction.xyz;
    vec2 texel_center = vec2(at) + 0.5;
    if (lod > 0.0) {
        // filtered: keep the footprint inside the crop (crops sit on cells of 2^max_color_lod texels)
        lod = min(lod, float(max_color_lod));
        float margin = 0.5 * exp2(ceil(lod));
        texel_center = clamp(texel_center, vec2(view.atlas.yz) + margin, vec2(view.atlas.yz + view.crop.zw) - margin);
    }
    vec4 c = textureLod(color_pages, vec3(texel_center / page_size, float(view.atlas.x)), max(lod, 0.0));
    g_fetches += 1u;
    s.color = c.a > 0.0 ? c.rgb / c.a : c.rgb;
    return s;
}

// The colour mip level at which one texel of the capture spans `span` object units.
float color_lod(float span) { return log2(max(span * capture_resolution / (2.0 * mf_radius), 1e-6)); }
