// Screen-door cross-fade between two renderers drawn into one frame (issue #14; DrawParams::fade,
// CrossFade in render.h). Every pixel gets a fixed threshold from an 8x8 ordered-dither (Bayer 1973)
// matrix: t = (rank + 0.5) / 64. At fade amount f the outgoing renderer keeps the pixels with
// t >= f and the incoming one the pixels with t < f, so two draws at the same f cover every pixel
// exactly once: no blending, no sorting, and both keep writing true depth and casting shadows (a
// discarded fragment writes nothing). Coverage moves in steps of 1/64, exact over every aligned 8x8
// tile. Departures: a temporal variant (offset the matrix per frame, or interleaved gradient noise,
// Jimenez 2014, rotated per frame, resolved by TAA) would hide the pattern but makes frames differ
// with the frame index; renders here are single and must be repeatable, so the pattern is fixed
// in screen space. Alpha-to-coverage needs MSAA, which the exact offscreen targets do not have.
// Fragment stages; include after frame.glsl. Call fade_discards() at the top of main().

// The rank 0..63 of a pixel in the 8x8 Bayer matrix: the bits of (x xor y) and y interleaved
// and reversed (the recursive construction written out).
uint fade_bayer_rank(uvec2 pixel)
{
    uint x = pixel.x & 7u, y = pixel.y & 7u, d = x ^ y;
    return ((d & 1u) << 5) | ((y & 1u) << 4) | ((d & 2u) << 2) | ((y & 2u) << 1) | ((d & 4u) >> 1) | ((y & 4u) >> 2);
}

// Whether this fragment belongs to the other renderer of the cross-fade. Never true without a
// fade (amount 0, outgoing), so the draw is exactly what it is without one.
bool fade_discards()
{
    float t = (float(fade_bayer_rank(uvec2(gl_FragCoord.xy))) + 0.5) / 64.0;
    bool incoming = frame.fade.y > 0.5;
    return incoming ? !(t < frame.fade.x) : !(t >= frame.fade.x);
}
