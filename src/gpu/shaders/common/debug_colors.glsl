// Colours of the renderers' debug views, shared so that every representation's pictures read alike.
#ifndef STANDIN_DEBUG_COLORS_GLSL
#define STANDIN_DEBUG_COLORS_GLSL

// A heat map, blue (0) through green and yellow to red (1).
vec3 heat(float x)
{
    x = clamp(x, 0.0, 1.0);
    return clamp(vec3(1.5 - abs(4.0 * x - 3.0), 1.5 - abs(4.0 * x - 2.0), 1.5 - abs(4.0 * x - 1.0)), 0.0, 1.0);
}

// A stable, distinguishable colour per index (billboard, view): a multiplicative hash.
vec3 index_color(int index)
{
    uint h = uint(index) * 2654435761u;
    return vec3(float(h & 255u), float((h >> 8) & 255u), float((h >> 16) & 255u)) / 255.0 * 0.8 + 0.2;
}

#endif
