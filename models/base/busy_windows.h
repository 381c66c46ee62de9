// A wire's busy time over windows of the frame, to see saturation in time
// that the frame's average hides (the report's links[].peak_utilisation;
// doc/report.md). The windows are equal, [k w, (k + 1) w), and w is chosen
// as the frame goes: it starts at 1 ns and doubles, adding neighbouring
// windows pairwise, whenever busy time lands past the last of kMaxWindows,
// so a frame ends cut in between kMaxWindows / 2 and kMaxWindows windows
// (fewer for a link last used early). Windows are kept only up to the last
// one used: an idle link holds none.
#pragma once
#include <algorithm>
#include <cstddef>
#include <vector>

#include "base/units.h"

namespace rt {

class BusyWindows {
public:
    static constexpr size_t kMaxWindows = 128;
    static constexpr Picos kFirstWidth = 1000;  // 1 ns

    // The wire was busy over [from, to).
    void add(Picos from, Picos to) {
        if (to <= from) return;
        while ((to - 1) / width_ >= kMaxWindows) widen();
        for (Picos k = from / width_; k * width_ < to; ++k) {
            const Picos lo = std::max(from, k * width_), hi = std::min(to, (k + 1) * width_);
            if (busy_.size() <= size_t(k)) busy_.resize(size_t(k) + 1, 0);
            busy_[size_t(k)] += hi - lo;
        }
    }
    // Another channel's windows added to these (a port's wires side by side).
    void merge(BusyWindows o) {
        while (width_ < o.width_) widen();
        while (o.width_ < width_) o.widen();
        if (busy_.size() < o.busy_.size()) busy_.resize(o.busy_.size(), 0);
        for (size_t k = 0; k < o.busy_.size(); ++k) busy_[k] += o.busy_[k];
    }
    // The largest share of a window the wire was busy, over the windows
    // that end by `end` (the frame's end), for `channels` wires side by
    // side; a frame shorter than one window is that one window, up to `end`.
    double peak(Picos end, int channels = 1) const {
        if (end == 0 || busy_.empty()) return 0.0;
        const size_t whole = size_t(end / width_);
        if (whole == 0) return double(busy_[0]) / (double(end) * channels);
        Picos most = 0;
        for (size_t k = 0; k < std::min(whole, busy_.size()); ++k) most = std::max(most, busy_[k]);
        return double(most) / (double(width_) * channels);
    }
    Picos width() const { return width_; }
    const std::vector<Picos>& busy() const { return busy_; }

private:
    void widen() {
        for (size_t k = 0; 2 * k < busy_.size(); ++k) busy_[k] = busy_[2 * k] + (2 * k + 1 < busy_.size() ? busy_[2 * k + 1] : 0);
        busy_.resize((busy_.size() + 1) / 2);
        width_ *= 2;
    }

    Picos width_ = kFirstWidth;
    std::vector<Picos> busy_;
};

}  // namespace rt
