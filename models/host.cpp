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
            time_.catchUp(now);
            inputOrder_.waitForInput(now);
            now = sc_core::sc_time_stamp().value();
            continue;
        }
        Message m = in[best]->consume(now);
        Picos cost = 0;
        if (m.type == MsgType::Contributions) {
            ++stats_.contributionMessages;
            stats_.contributions += m.contributions.size();
            cost = cost_ * m.contributions.size();
            contributions_.insert(contributions_.end(), m.contributions.begin(), m.contributions.end());
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
    std::sort(contributions_.begin(), contributions_.end(),
              [](const Contribution& a, const Contribution& b) { return a.pixel < b.pixel; });
    std::vector<Contribution> pixel;
    for (size_t i = 0; i < contributions_.size();) {
        size_t j = i;
        while (j < contributions_.size() && contributions_[j].pixel == contributions_[i].pixel) ++j;
        pixel.assign(contributions_.begin() + i, contributions_.begin() + j);
        img.pixels[contributions_[i].pixel] = sumInKeyOrder(pixel);
        i = j;
    }
    return img;
}

}  // namespace rt
