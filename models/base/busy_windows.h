// A wire's busy time over windows of the frame, to see saturation in time
// that the frame's average hides (the report's links[].peak_utilisation;
// doc/report.md). The windows are equal, [k w, (k + 1) w), and w is chosen
// as the frame goes: it starts at 1 ns and doubles, adding neighbouring
// windows pairwise, whenever busy time lands past the last of kMaxWindows,
// so a frame ends cut in between kMaxWindows / 2 and kMaxWindows windows
// (fewer for a link last used early). Windows are kept only up to the last
// one used: an idle link holds none. A window's busy time takes 32 bits
// while every window's fits (up to 4.29 ms: most frames' windows), 64 bits
// from the first that does not on: every link that carried keeps up to
// 128 windows, half a KB where it took 1 KB (at 32x32x32, 190,000 links).
#pragma once
#include <algorithm>
#include <cstddef>
#include <cstdint>
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
            addTo(size_t(k), hi - lo);
        }
    }
    // Another channel's windows added to these (a port's wires side by side).
    void merge(BusyWindows o) {
        while (width_ < o.width_) widen();
        while (o.width_ < width_) o.widen();
        for (size_t k = 0; k < o.size(); ++k) addTo(k, o.at(k));
    }
    // The largest share of a window the wire was busy, over the windows
    // that end by `end` (the frame's end), for `channels` wires side by
    // side; a frame shorter than one window is that one window, up to `end`.
    double peak(Picos end, int channels = 1) const {
        if (end == 0 || size() == 0) return 0.0;
        const size_t whole = size_t(end / width_);
        if (whole == 0) return double(at(0)) / (double(end) * channels);
        Picos most = 0;
        for (size_t k = 0; k < std::min(whole, size()); ++k) most = std::max(most, at(k));
        return double(most) / (double(width_) * channels);
    }
    Picos width() const { return width_; }
    std::vector<Picos> busy() const {
        std::vector<Picos> b(size());
        for (size_t k = 0; k < b.size(); ++k) b[k] = at(k);
        return b;
    }

private:
    size_t size() const { return wide_ ? wideBusy_.size() : narrowBusy_.size(); }
    Picos at(size_t k) const { return wide_ ? wideBusy_[k] : narrowBusy_[k]; }
    // Window k gains `d` (the windows up to it kept, empty ones 0).
    void addTo(size_t k, Picos d) {
        if (!wide_) {
            if (narrowBusy_.size() <= k) narrowBusy_.resize(k + 1, 0);
            if (narrowBusy_[k] + d <= UINT32_MAX) {
                narrowBusy_[k] += uint32_t(d);
                return;
            }
            goWide();
        }
        if (wideBusy_.size() <= k) wideBusy_.resize(k + 1, 0);
        wideBusy_[k] += d;
    }
    void goWide() {
        wideBusy_.assign(narrowBusy_.begin(), narrowBusy_.end());
        narrowBusy_ = {};
        wide_ = true;
    }
    void widen() {
        if (!wide_)
            for (size_t k = 0; 2 * k + 1 < narrowBusy_.size(); ++k)
                if (Picos(narrowBusy_[2 * k]) + narrowBusy_[2 * k + 1] > UINT32_MAX) {
                    goWide();
                    break;
                }
        if (wide_) pairUp(wideBusy_);
        else pairUp(narrowBusy_);
        width_ *= 2;
    }
    template <class V>
    static void pairUp(V& busy) {
        for (size_t k = 0; 2 * k < busy.size(); ++k) busy[k] = busy[2 * k] + (2 * k + 1 < busy.size() ? busy[2 * k + 1] : 0);
        busy.resize((busy.size() + 1) / 2);
    }

    Picos width_ = kFirstWidth;
    bool wide_ = false;
    std::vector<uint32_t> narrowBusy_;  // while not wide_
    std::vector<Picos> wideBusy_;       // once wide_
};

}  // namespace rt
