#include "node/primary_queue.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "balance/sample_split.h"

namespace rt {

bool PrimaryQueue::inSample(uint32_t pixel) const { return rt::inSample(pixel, sampleWidth_); }

std::vector<size_t> spreadOrder(size_t n) {
    std::vector<size_t> order(n);
    if (n == 0) return order;
    size_t s = std::max<size_t>(1, size_t(std::llround(double(n) * (std::sqrt(5.0) - 1) / 2)));
    while (std::gcd(s, n) != 1) ++s;
    for (size_t i = 0; i < n; ++i) order[i] = size_t((uint64_t(i) * s) % n);
    return order;
}

void PrimaryQueue::assign(const std::vector<uint32_t>& pixels, uint16_t exp, uint32_t sampleWidth, bool spread) {
    sampleWidth_ = sampleWidth;
    for (int k : {0, 1}) {
        parts_[k].clear();
        next_[k] = 0;
    }
    for (uint32_t p : pixels) parts_[partOf(p)].push_back({p, exp});
    if (!spread) return;
    for (std::vector<Primary>& part : parts_) {
        std::vector<Primary> spreadOut;
        spreadOut.reserve(part.size());
        for (size_t i : spreadOrder(part.size())) spreadOut.push_back(part[i]);
        part = std::move(spreadOut);
    }
}

bool PrimaryQueue::next(Primary& p) {
    for (int k : {0, 1})
        if (next_[k] < parts_[k].size()) {
            p = parts_[k][next_[k]++];
            return true;
        }
    return false;
}

HandedPrimaries PrimaryQueue::handOver(const std::function<bool(uint32_t)>& goes) {
    HandedPrimaries give;
    for (int k : {0, 1}) {
        std::vector<Primary> keep;
        for (size_t i = next_[k]; i < parts_[k].size(); ++i) (goes(parts_[k][i].pixel) ? give : keep).push_back(parts_[k][i]);
        parts_[k] = std::move(keep);
        next_[k] = 0;
    }
    return give;
}

void PrimaryQueue::take(const HandedPrimaries& h) {
    for (const Primary& p : h) parts_[partOf(p.pixel)].push_back(p);
}

}  // namespace rt
