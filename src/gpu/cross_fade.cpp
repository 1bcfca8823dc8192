// Level-of-detail transitions by screen-door cross-fade (issue #14). The idea is the dithered LOD
// fade of game engines (e.g. Unity's LOD cross-fade, Unreal's "dithered LOD transition"), itself
// screen-door transparency (Fuchs et al. 1985) with an ordered-dither threshold (Bayer 1973).
// Steps: (1) the caller maps a distance to an amount with transition_amount (a band [near, far]);
// (2) CrossFade draws `from` as outgoing and `to` as incoming at that amount; (3) each fragment
// stage drops the pixels that belong to the other (gpu/shaders/common/fade.glsl). Departure: no
// temporal jitter of the pattern (renders must be repeatable; see fade.glsl).
#include <standin/render.h>

#include <algorithm>

namespace standin {

static float sanitised_amount(float amount) { return amount > 0.0f ? std::min(amount, 1.0f) : 0.0f; }

void CrossFade::set_amount(float amount) { amount_ = sanitised_amount(amount); }

DrawStats CrossFade::draw(const DrawParams& params)
{
    // the ends draw one renderer with no fade at all: exactly what it draws alone
    DrawParams one = params;
    one.fade = {};
    if (amount_ <= 0.0f) return from_->draw(one);
    if (amount_ >= 1.0f) return to_->draw(one);
    DrawParams outgoing = params, incoming = params;
    outgoing.fade = {amount_, false};
    incoming.fade = {amount_, true};
    DrawStats a = from_->draw(outgoing);
    DrawStats b = to_->draw(incoming);
    return {a.draw_calls + b.draw_calls, a.primitives + b.primitives};
}

void CrossFade::set_counting(bool on)
{
    from_->set_counting(on);
    to_->set_counting(on);
}

std::uint64_t CrossFade::read_counter(Counter counter) { return from_->read_counter(counter) + to_->read_counter(counter); }

float transition_amount(float distance, float near, float far)
{
    if (!(distance == distance)) return 0.0f;
    if (!(far > near)) return distance >= far ? 1.0f : 0.0f;
    return sanitised_amount((distance - near) / (far - near));
}

} // namespace standin
