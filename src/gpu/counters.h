// GPU counters a renderer keeps while counting (render.h Counter; shaders/common/counters.glsl):
// one SSBO of uints at BINDING_COUNTERS_SSBO, the shared counters first (debug_views.h), then any
// the renderer keeps of its own.
#pragma once

#include "gpu/gl.h"

#include <cstdint>

namespace standin::gpu {

class Counters {
public:
    // `count`: at least COUNTER_SHARED_COUNT. Needs a current context.
    explicit Counters(int count = 2);
    void set_counting(bool on); // clears the counters
    bool counting() const { return counting_; }
    void bind() const;          // at BINDING_COUNTERS_SSBO
    std::uint64_t read(int index) const;

private:
    Buffer buffer_;
    int count_ = 0;
    bool counting_ = false;
};

} // namespace standin::gpu
