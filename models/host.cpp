#include "host.h"

#include <algorithm>
#include <chrono>
#include <cstdio>

namespace rt {

Host::Host(sc_core::sc_module_name name, int nodes, int width, int height, Picos costPerContribution, int maxExp,
           bool progress, Picos quantum)
    : sc_module(name), in("in", nodes), width_(width), height_(height), cost_(costPerContribution),
      progress_(progress), time_(quantum), returned_(maxExp) {
    SC_THREAD(run);
}

void Host::run() {
    inputOrder_.listen(in);
    Picos now = sc_core::sc_time_stamp().value();
    auto lastPrint = std::chrono::steady_clock::now();
    if (returned_.isOne()) {  // nothing to trace at all
        stats_.done = true;
        stats_.renderTime = now;
        sc_core::sc_stop();
        return;
    }
    for (;;) {
        Picos next;
        const int best = inputOrder_.oldest(now, next);  // ties go to the lower node
        if (best < 0) {
            if (time_.mayIdleUntil(next)) {  // the next arrival is known and within the quantum
                now = next;
                continue;
            }
            inputOrder_.waitForInput(now);  // also lets the kernel catch up with `now`
            now = sc_core::sc_time_stamp().value();
            continue;
        }
        Message m = in[best]->consume(now);
        Picos cost = 0;
        if (m.type == MsgType::Contributions) {
            ++stats_.contributionMessages;
            stats_.contributions += m.contributions.size();
            cost = cost_ * m.contributions.size();
            received_.push_back(std::move(m.contributions));
        } else if (m.type == MsgType::Credit) {
            ++stats_.creditMessages;
            returned_.add(m.credit);
        }
        now += cost;
        stats_.busy += cost;
        time_.afterStep(now, cost);
        if (returned_.isOne()) {
            stats_.done = true;
            stats_.renderTime = now;
            if (progress_) std::fprintf(stderr, "\r%-60s\r", "");
            sc_core::sc_stop();
            return;
        }
        if (progress_) {
            const auto t = std::chrono::steady_clock::now();
            if (t - lastPrint > std::chrono::milliseconds(500)) {
                lastPrint = t;
                std::fprintf(stderr, "\rrtsim: %5.1f%% of the frame's rays done", 100.0 * returned_.value());
            }
        }
    }
}

Image Host::image() {
    Image img(width_, height_);
    // Group the contributions by pixel (a counting sort, by reference), then
    // sum each pixel's in path-key order.
    const size_t pixels = size_t(width_) * size_t(height_);
    auto forEach = [&](auto&& f) {
        for (const std::vector<Contribution>& batch : received_)
            for (const Contribution& c : batch) f(c);
        for (const Contribution& c : own_) f(c);
    };
    std::vector<size_t> first(pixels + 1, 0);  // pixel p's contributions: byPixel[first[p] .. first[p + 1])
    forEach([&](const Contribution& c) { ++first[c.pixel + 1]; });
    for (size_t p = 0; p < pixels; ++p) first[p + 1] += first[p];
    std::vector<const Contribution*> byPixel(first[pixels]);
    std::vector<size_t> next(first.begin(), first.end() - 1);
    forEach([&](const Contribution& c) { byPixel[next[c.pixel]++] = &c; });
    std::vector<Contribution> pixel;
    for (size_t p = 0; p < pixels; ++p) {
        if (first[p] == first[p + 1]) continue;
        pixel.clear();
        for (size_t k = first[p]; k < first[p + 1]; ++k) pixel.push_back(*byPixel[k]);
        img.pixels[p] = sumInKeyOrder(pixel);
    }
    return img;
}

}  // namespace rt
