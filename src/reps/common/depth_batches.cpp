// Depth batches (depth_batches.h): batch sizes, the images and the resolve pass.
#include "reps/common/depth_batches.h"

#include "reps/common/shaders/depth_batches.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

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
    // only where the late test is GL_LESS with depth writes into one sample per pixel: what the
    // record's "nearest so far" and the resolve stand for
    GLint func = 0, samples = 0, viewport[4] = {0, 0, 0, 0};
    GLboolean mask = GL_FALSE;
    glGetIntegerv(GL_DEPTH_FUNC, &func);
    glGetBooleanv(GL_DEPTH_WRITEMASK, &mask);
    glGetIntegerv(GL_SAMPLES, &samples);
    if (func != GL_LESS || mask != GL_TRUE || samples > 1) return false;
    glGetIntegerv(GL_VIEWPORT, viewport);
    const int width = viewport[0] + viewport[2], height = viewport[1] + viewport[3];
    if (width <= 0 || height <= 0) return false;
    if (width > width_ || height > height_) {
        width_ = std::max(width, width_);
        height_ = std::max(height, height_);
        nearest_ = gpu::make_texture_2d(GL_R32UI, width_, height_);
        color_ = gpu::make_texture_2d(GL_RGBA32F, width_, height_);
        stamp_ = gpu::make_texture_2d(GL_R32UI, width_, height_);
        const std::uint32_t none = 0; // no batch's stamp
        glClearTexImage(stamp_.get(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT, &none);
        next_stamp_ = 0;
    }
    const float far_depth = 1.0f; // no fragment of a batch yet (window depths are at most 1)
    std::uint32_t far_bits = 0;
    std::memcpy(&far_bits, &far_depth, sizeof far_bits);
    glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT); // the last frame's image writes, before the clear
    glClearTexImage(nearest_.get(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT, &far_bits);
    glBindImageTexture(DEPTH_BATCH_NEAREST_IMAGE, nearest_.get(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32UI);
    glBindImageTexture(DEPTH_BATCH_COLOR_IMAGE, color_.get(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
    glBindImageTexture(DEPTH_BATCH_STAMP_IMAGE, stamp_.get(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32UI);
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
    return next_stamp_;
}

glm::ivec4 DepthBatches::sphere_rect(const Camera& camera, glm::ivec2 viewport, const glm::mat4& world_from_object,
                                     glm::vec3 centre_object, float radius_object)
{
    const glm::mat4& m = world_from_object;
    const float radius = radius_object *
                         std::max({glm::length(glm::vec3(m[0])), glm::length(glm::vec3(m[1])), glm::length(glm::vec3(m[2]))});
    const glm::ivec4 whole(0, 0, viewport.x, viewport.y);
    const glm::vec3 centre_view = glm::vec3(camera.view_from_world * (m * glm::vec4(centre_object, 1.0f)));
    glm::vec2 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    for (int corner = 0; corner < 8; ++corner) {
        const glm::vec3 offset(corner & 1 ? radius : -radius, corner & 2 ? radius : -radius, corner & 4 ? radius : -radius);
        const glm::vec4 clip = camera.clip_from_view * glm::vec4(centre_view + offset, 1.0f);
        if (!(clip.w > 1e-6f) || !std::isfinite(clip.x) || !std::isfinite(clip.y)) return whole; // behind the eye
        const glm::vec2 ndc = glm::vec2(clip) / clip.w;
        lo = glm::min(lo, ndc);
        hi = glm::max(hi, ndc);
    }
    // window pixels, a pixel of margin for rasterisation's rounding
    const glm::vec2 size(viewport);
    const glm::vec2 a = (lo * 0.5f + 0.5f) * size - 1.0f, b = (hi * 0.5f + 0.5f) * size + 1.0f;
    glm::ivec4 rect(int(std::floor(std::max(a.x, 0.0f))), int(std::floor(std::max(a.y, 0.0f))),
                    int(std::ceil(std::min(b.x, size.x))), int(std::ceil(std::min(b.y, size.y))));
    if (rect.x >= rect.z || rect.y >= rect.w) return glm::ivec4(0);
    return rect;
}

glm::ivec4 DepthBatches::rect_union(glm::ivec4 a, glm::ivec4 b)
{
    if (a.x >= a.z || a.y >= a.w) return b;
    if (b.x >= b.z || b.y >= b.w) return a;
    return glm::ivec4(std::min(a.x, b.x), std::min(a.y, b.y), std::max(a.z, b.z), std::max(a.w, b.w));
}

void DepthBatches::resolve(std::uint32_t stamp, glm::ivec4 rect)
{
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    glDepthMask(depth_mask_);
    glColorMask(color_mask_[0], color_mask_[1], color_mask_[2], color_mask_[3]);
    if (rect.x >= rect.z || rect.y >= rect.w) return; // nothing on screen: nothing stored either
    glProgramUniform1ui(resolve_.id(), resolve_stamp_at_, stamp);
    resolve_.use();
    glBindVertexArray(empty_vertex_array_.get());
    const GLboolean cull = glIsEnabled(GL_CULL_FACE), scissor = glIsEnabled(GL_SCISSOR_TEST);
    GLint box[4] = {0, 0, 0, 0};
    glGetIntegerv(GL_SCISSOR_BOX, box);
    glDisable(GL_CULL_FACE);
    if (scissor) // within the caller's scissor box too
        rect = glm::ivec4(std::max(rect.x, box[0]), std::max(rect.y, box[1]), std::min(rect.z, box[0] + box[2]),
                          std::min(rect.w, box[1] + box[3]));
    if (rect.x < rect.z && rect.y < rect.w) {
        glEnable(GL_SCISSOR_TEST);
        glScissor(rect.x, rect.y, rect.z - rect.x, rect.w - rect.y);
        glDrawArrays(GL_TRIANGLES, 0, 3);
    }
    glScissor(box[0], box[1], box[2], box[3]);
    if (!scissor) glDisable(GL_SCISSOR_TEST);
    if (cull) glEnable(GL_CULL_FACE);
}

void DepthBatches::end_frame()
{
    glDepthMask(depth_mask_);
    glColorMask(color_mask_[0], color_mask_[1], color_mask_[2], color_mask_[3]);
}

} // namespace standin::reps
