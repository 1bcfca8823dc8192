// Depth batches: an early depth test for stand-ins that write their own depth, on software
// rasterisers (issue #17, crowds).
//
// Image-based stand-ins draw a proxy (a box, a hull) and write the depth of the surface their
// shader finds behind it (layout(depth_greater)). A GPU tests such a fragment's proxy depth before
// the shader, so proxies drawn front to back behind nearer surfaces cost nothing. llvmpipe tests
// after the shader whatever the layout says, and every fragment of every proxy runs the whole
// shader: on a crowd of 1,000 view-atlas instances 5.7 fragments per covered pixel, 3.8 of them
// behind what is already drawn (docs/RESULTS.md "Depth batches"). A 2026 engine would draw a
// depth pre-pass or build a hierarchical depth buffer; neither applies where the depth is the
// shader's own result. What does, on a rasteriser that shades a pixel's fragments one at a time
// in the order of their primitives:
//  1. the instances, sorted front to back, are drawn in batches (8, then 24, 96, 384, ...: each
//     ends at four times the end of the one before); the first batch draws as before, writing its
//     depth. Instances, not proxies, as a rule: one instance's proxies in batches (a scan's 519
//     billboard boxes) stopped 3% of its fragments and cost 10% more CPU on llvmpipe (the resolves);
//     the boxes of one stand-in are sorted by their centres, and most lie over and behind each
//     other's hits only in the batch they share. Where one instance's boxes lie deep behind each
//     other (nested parts, foliage), the billboards batch its boxes (renderer.cpp, box_overdraw:
//     a 108k-face assembly 45% less CPU);
//  2. every later batch is drawn by the program compiled with DEPTH_BATCHES
//     (shaders/depth_batches.glsl): the depth test runs before the shader (early_fragment_tests),
//     against the depths of the batches before it, with depth and colour writes off; a fragment
//     whose depth is the nearest so far at its pixel (an atomic-minimum record: the renderer's own,
//     or depth_batch_nearer's) stores its colour and depth in two images, with the batch's stamp;
//  3. a resolve pass (one triangle, scissored to the batch's proxies' screen rectangle) writes the
//     pixels stamped by that batch through the ordinary depth test: the next batch's early test sees
//     them.
// The picture and depth buffer are those of the single late-tested draw: the proxy's depth is at
// or before the fragment's, so a fragment the early test drops would have failed the late one;
// within a batch the record keeps the nearest (ties to the first drawn, as GL_LESS); and the
// resolve's test keeps what other draws put nearer. It relies on in-order shading within a batch
// (a GPU runs a pixel's fragments concurrently), so renderers use it only where
// gpu::software_rasteriser() says so, and only for a GL_LESS test with depth writes into a target
// of one sample per pixel. Checked byte for byte (picture and depth buffer) on the view atlas's walk
// and the billboards' front pass (their renderer_gpu_test.cpp); the atlas's cheaper levels, which
// write their proxy's own depth, drew 7 of 8,700 pixels of a test crowd differently under the
// early test (cause not found), so they keep the late test.
#pragma once

#include "gpu/gl.h"

#include <standin/camera.h>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace standin::reps {

class DepthBatches {
public:
    // Compiles the resolve program; call with a current context.
    Status create();
    // The end of each batch of a run of `count` proxies (or instances) sorted front to back: 8, 32,
    // 128, ... up to count. The first batch is drawn the ordinary way.
    static std::vector<std::size_t> batch_ends(std::size_t count);
    // Before a frame's batches: the images sized to the viewport (grown, never shrunk), the nearest
    // depth cleared, the images bound, the caller's depth and colour write masks saved. False (draw
    // as usual) unless
    // the depth test is GL_LESS with depth writes into one sample per pixel, and for no viewport.
    bool begin_frame();
    // Before a DEPTH_BATCHES draw: depth and colour writes off. Returns the stamp to set as the
    // program's depth_batch uniform.
    std::uint32_t begin_batch();
    // After that draw: its pixels within `rect` (pixels x0, y0, x1, y1, the last two past the end:
    // where the batch's proxies lie, sphere_rect) through the depth test, with the caller's masks.
    // Leaves the resolve program and an empty vertex array bound: the caller binds its own again.
    void resolve(std::uint32_t stamp, glm::ivec4 rect);
    // The pixels of a viewport that an instance's bounding sphere (object space, under its
    // transform's largest axis scale) may cover: the projected box around it, or the whole viewport
    // where the box reaches behind the near plane. Empty (x0 >= x1) when off screen.
    static glm::ivec4 sphere_rect(const Camera& camera, glm::ivec2 viewport, const glm::mat4& world_from_object,
                                  glm::vec3 centre_object, float radius_object);
    // The smallest rectangle holding both (either may be empty).
    static glm::ivec4 rect_union(glm::ivec4 a, glm::ivec4 b);
    // After the frame's batches: the caller's write masks, as begin_frame found them.
    void end_frame();

private:
    gpu::Program resolve_;
    GLint resolve_stamp_at_ = -1;
    gpu::VertexArray empty_vertex_array_;
    gpu::Texture nearest_, color_, stamp_;
    int width_ = 0, height_ = 0;
    std::uint32_t next_stamp_ = 0; // stamps are never reused while the images live (0: none)
    GLboolean depth_mask_ = GL_TRUE;
    GLboolean color_mask_[4] = {GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE};
};

} // namespace standin::reps
