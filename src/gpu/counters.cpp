// GPU counters (counters.h).
#include "gpu/counters.h"

#include <standin/debug_view.h>

#include "gpu/shaders/common/bindings.h"
#include "gpu/shaders/common/debug_views.h"

#include <cassert>
#include <vector>

namespace standin::gpu {

// the GLSL twin of include/standin/debug_view.h
static_assert(int(DebugView::none) == DEBUG_VIEW_NONE && int(DebugView::parts) == DEBUG_VIEW_PARTS &&
              int(DebugView::depth) == DEBUG_VIEW_DEPTH && int(DebugView::normal) == DEBUG_VIEW_NORMAL &&
              int(DebugView::fetches) == DEBUG_VIEW_FETCHES && int(DebugView::proxies) == DEBUG_VIEW_PROXIES &&
              int(DebugView::level) == DEBUG_VIEW_LEVEL && int(DebugView::error) == DEBUG_VIEW_ERROR &&
              k_debug_view_count == DEBUG_VIEW_COUNT, "DebugView and debug_views.h disagree");
static_assert(int(Counter::fragments) == COUNTER_FRAGMENTS && int(Counter::fetches) == COUNTER_FETCHES,
              "Counter and debug_views.h disagree");
static_assert(k_fetches_heat_max == int(FETCHES_HEAT_MAX), "one fetch heat-map scale");

Counters::Counters(int count) : count_(count)
{
    assert(count >= COUNTER_SHARED_COUNT);
    buffer_ = make_buffer(std::vector<std::uint32_t>(std::size_t(count), 0u), GL_DYNAMIC_STORAGE_BIT);
}

void Counters::set_counting(bool on)
{
    counting_ = on;
    std::vector<std::uint32_t> zero(std::size_t(count_), 0u);
    glNamedBufferSubData(buffer_.get(), 0, GLsizeiptr(zero.size() * sizeof(std::uint32_t)), zero.data());
}

void Counters::bind() const { glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_COUNTERS_SSBO, buffer_.get()); }

std::uint64_t Counters::read(int index) const
{
    assert(index >= 0 && index < count_);
    std::uint32_t value = 0;
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glGetNamedBufferSubData(buffer_.get(), GLintptr(index * sizeof(std::uint32_t)), sizeof value, &value);
    return value;
}

} // namespace standin::gpu
