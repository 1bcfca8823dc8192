// Draws one frame of the viewer: each subject shown is rendered by its Renderer into an offscreen
// target at the render resolution (timed with a GPU timer query, its covered pixels counted), then
// scaled into the window: alone, split with the original, side by side, or as the holes debug view.
#pragma once

#include "viewer_state.h"

#include <standin/image.h>
#include <standin/render.h>

#include <optional>

namespace standin::viewer {

// Where images landed in the window, in window pixels from the top left (x0, y0, x1, y1).
struct FrameLayout {
    glm::vec4 left{0.0f}, right{0.0f}; // right is empty in the single layout
    float split_x = -1.0f;             // the divider of the split layout, -1 without one
    std::string left_label, right_label;
};

class FrameRenderer {
public:
    FrameRenderer();
    // Renders the subjects the state asks for and composes them into the window's framebuffer
    // (framebuffer_size pixels); fills state.stats. Needs the window's context current.
    FrameLayout draw(ViewerState& state, glm::ivec2 framebuffer_size);

private:
    struct Target {
        std::optional<RenderTarget> target;
        glm::ivec2 size{0};
        std::vector<std::uint8_t> pixels; // read back, bottom row first
        unsigned framebuffer() const { return target ? target->framebuffer() : 0u; }
    };
    void ensure(Target& target, glm::ivec2 size);
    SubjectStats render_subject(ViewerState& state, int subject, Target& target, float aspect);
    void compose_holes(ViewerState& state);

    Target targets_[3]; // left (or single), right, holes composite
    std::unique_ptr<ShadowMap> shadow_map_; // made on the first frame with shadows
    GpuTimer timer_;
};

// The window's back buffer as an image (top row first, opaque). Call before swapping buffers.
ImageRGBA8 read_window(glm::ivec2 framebuffer_size);

} // namespace standin::viewer

namespace standin::viewer {

// The statistics overlay and the labels of the images, drawn over the frame (ui_overlay.cpp).
void ui_overlay(const ViewerState& state, const FrameLayout& layout);

} // namespace standin::viewer
