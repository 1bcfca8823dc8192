// The material channels of a GPU capture (issue #14): bakers that capture views by rendering the
// ground-truth mesh (view atlas, microfacets) also need the surface's occlusion, roughness, metallic
// and emission per pixel, aligned with their colour and normal captures, to relight PBR models.
#pragma once

#include <standin/camera.h>
#include <standin/render.h>
#include <standin/status.h>

namespace standin::reps {

struct MaterialImages {
    // RGB: occlusion, perceptual roughness, metallic (linear); A: 255 where the mesh was drawn
    ImageRGBA8 orm;
    // RGB: emission, sRGB-encoded and clamped to [0, 1]; A: 255 where the mesh was drawn
    ImageRGBA8 emission;
};

// Draws `truth` (make_mesh_renderer) twice into `target` with the draw parameters of a colour
// capture, in the capture modes ShadingModel::capture_orm and capture_emission. Those modes are
// mesh.frag itself (same vertex stage, same material binding, factors x maps, alpha test and face
// culling) returning its inputs to shade_pbr instead of a colour, so pixel (x, y) of both images is
// the surface the colour capture's pixel (x, y) shows, with exactly the ORM and emission the truth
// shades it with. Only params.light's shading model is replaced. Leaves the default framebuffer bound.
Result<MaterialImages> capture_material(Renderer& truth, const RenderTarget& target, DrawParams params);

// The texel packing of write_pbr_texel for a captured pixel (the capture already quantised it).
inline void copy_material_texel(const MaterialImages& capture, int sx, int sy, ImageRGBA8& orm, ImageRGBA8& emission,
                                int x, int y)
{
    const std::uint8_t* o = capture.orm.at(sx, sy);
    const std::uint8_t* e = capture.emission.at(sx, sy);
    std::uint8_t* to = orm.at(x, y);
    std::uint8_t* te = emission.at(x, y);
    to[0] = o[0], to[1] = o[1], to[2] = o[2], to[3] = 255;
    te[0] = e[0], te[1] = e[1], te[2] = e[2], te[3] = 255;
}

} // namespace standin::reps
