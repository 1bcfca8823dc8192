// Depth batches (depth_batches.h): batch sizes, the images and the resolve pass.
#include "reps/common/depth_batches.h"

#include "reps/common/shaders/depth_batches.h"

#include <algorithm>

namespace standin::reps {

Status DepthBatches::create()
{
    Result<gpu::Program> program = gpu::Program::create(
        {"reps/common/shaders/depth_batch_resolve.vert", "reps/common/shaders/depth_batch_resolve.frag"});
    if (!program) return program.status();
    resolve_ = std::move(*program);
    resolve_stamp_at_ = resolve_.uniform("depth_batch");
    empty_vertex_array_ = gpu::make_vertex_array();
    return Status::ok();
}

std::vector<std::size_t> DepthBatches::batch_ends(std::size_t count)
{
    // the nearest eight drawn without an early test, then batches ending at 4x the last end: each
    // resolve is a pass over the viewport, and growth 4 took the least CPU of 2, 4 and 8 with first
    // batches of 4, 8, 16 and 32 (1000 copies of a 235k-face scan at 800x600 on llvmpipe: 15-20%
    // under one late-tested draw, docs/RESULTS.md "Depth batches"; the choices within noise of each other)
    constexpr std::size_t k_first_batch = 8, k_growth = 4;
    std::vector<std::size_t> ends;
    for (std::size_t end = std::min(count, k_first_batch); end > 0; end = std::min(count, k_growth * end)) {
        ends.push_back(end);
        if (end == count) break;
    }
    return ends;
}

bool DepthBatches::begin_frame()
{
    GLint viewport[4] = {0, 0, 0, 0};
    glGetIntegerv(GL_VIEWPORT, viewport);
    const int width = viewport[0] + viewport[2], height = viewport[1] + viewport[3];
    if (width <= 0 || height <= 0) return false;
    if (width > width_ || height > height_) {
        width_ = std::max(width, width_);
        height_ = std::max(height, height_);
        color_ = gpu::make_texture_2d(GL_RGBA32F, width_, height_);
        stamp_ = gpu::make_texture_2d(GL_R32UI, width_, height_);
        const std::uint32_t none = 0; // no batch's stamp
        glClearTexImage(stamp_.get(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT, &none);
        next_stamp_ = 0;
    }
    glGetBooleanv(GL_DEPTH_WRITEMASK, &depth_mask_);
    glGetBooleanv(GL_COLOR_WRITEMASK, color_mask_);
    return true;
}

std::uint32_t DepthBatches::begin_batch()
{
    if (++next_stamp_ == 0) { // 2^32 batches with one pair of images: forget every stamp
        const std::uint32_t none = 0;
        glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT);
        glClearTexImage(stamp_.get(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT, &none);
        next_stamp_ = 1;
    }
    // the previous resolve read the images this batch writes
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    glDepthMask(GL_FALSE);
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    glBindImageTexture(DEPTH_BATCH_COLOR_IMAGE, color_.get(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
    glBindImageTexture(DEPTH_BATCH_STAMP_IMAGE, stamp_.get(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32UI);
    return next_stamp_;
}

void DepthBatches::resolve(std::uint32_t stamp)
{
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    glDepthMask(depth_mask_);
    glColorMask(color_mask_[0], color_mask_[1], color_mask_[2], color_mask_[3]);
    glProgramUniform1ui(resolve_.id(), resolve_stamp_at_, stamp);
    resolve_.use();
    glBindVertexArray(empty_vertex_array_.get());
    const GLboolean cull = glIsEnabled(GL_CULL_FACE);
    glDisable(GL_CULL_FACE);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    if (cull) glEnable(GL_CULL_FACE);
}

void DepthBatches::end_frame()
{
    glDepthMask(depth_mask_);
    glColorMask(color_mask_[0], color_mask_[1], color_mask_[2], color_mask_[3]);
}

} // namespace standin::reps
