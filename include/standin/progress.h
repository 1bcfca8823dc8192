// Progress of long work, reported to whoever asked for it (the CLI prints to stderr; the library
// itself never prints).
#pragma once

#include <functional>
#include <string>

namespace standin {

class Progress {
public:
    using Callback = std::function<void(const std::string& stage, double fraction)>;
    Progress() = default;
    explicit Progress(Callback callback) : callback_(std::move(callback)) {}
    // fraction in [0,1] of `stage`; cheap to call often (throttling is the callback's business).
    void report(const std::string& stage, double fraction) const
    {
        if (callback_) callback_(stage, fraction);
    }

private:
    Callback callback_;
};

} // namespace standin
