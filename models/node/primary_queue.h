// The primary rays a node still has to generate, and in what order: the
// host's pixels in the host's order; under `sample` (sample_split.h) the
// sample's pixels first, then the rest. Rays handed over with a slab
// (`sample`: they start in the slab) join the part of their pixel.
#pragma once
#include <cstdint>
#include <functional>
#include <vector>

#include "channel/message.h"

namespace rt {

class PrimaryQueue {
public:
    // `sampleWidth`: the image's width, to put the sample first (0: the host's order).
    void assign(const std::vector<uint32_t>& pixels, uint16_t exp, uint32_t sampleWidth);
    bool next(Primary& p);
    size_t left() const { return parts_[0].size() - next_[0] + parts_[1].size() - next_[1]; }
    size_t sampleLeft() const { return parts_[0].size() - next_[0]; }
    // Those not yet generated for which `goes` holds, taken out.
    HandedPrimaries handOver(const std::function<bool(uint32_t)>& goes);
    void take(const HandedPrimaries& h);

private:
    size_t partOf(uint32_t pixel) const { return sampleWidth_ && inSample(pixel) ? 0 : 1; }
    bool inSample(uint32_t pixel) const;
    uint32_t sampleWidth_ = 0;
    std::vector<Primary> parts_[2];  // the sample's, then the rest
    size_t next_[2] = {0, 0};
};

}  // namespace rt
