// The primary rays a node still has to generate, and in what order: the
// host's pixels in the host's order (row by row), or with --primary-order
// spread a stride through them (spreadOrder); under `sample`
// (sample_split.h) the sample's pixels first, then the rest. Rays handed
// over with a slab (`sample`: they start in the slab) join the part of
// their pixel.
#pragma once
#include <cstdint>
#include <functional>
#include <vector>

#include "channel/message.h"

namespace rt {

// The order --primary-order spread generates `n` items in: item (i s) mod n
// at step i, s n over the golden ratio rounded, or the first whole number
// above it with no factor in common with n (a stride that visits each item
// once). Any run
// of k steps takes items from all over the list, about n / k apart, so a
// node's work arrives evenly over the frame rather than one part of its
// image after another (doc/machine.md, "The order of the primary rays").
std::vector<size_t> spreadOrder(size_t n);

class PrimaryQueue {
public:
    // `sampleWidth`: the image's width, to put the sample first (0: no
    // sample); `spread`: each part in spreadOrder, not the host's.
    void assign(const std::vector<uint32_t>& pixels, uint16_t exp, uint32_t sampleWidth, bool spread = false);
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
