// Rays leaving a node: a message per ray by default, or collected per
// direction into messages of --ray-batch rays, sent when full or before
// the node waits (doc/machine.md, "Rays batched per message"). The ray
// lists of batches it receives come back to it, emptied, for the next
// batches it sends: nodes receive about as many ray messages as they send,
// so most batches reuse a list instead of allocating one (and the receiver
// freeing it). Plain C++.
#pragma once
#include <array>
#include <vector>

#include "base/mesh_geometry.h"
#include "channel/message.h"

namespace rt {

class RayBatcher {
public:
    explicit RayBatcher(int batch) : batch_(batch) {}

    // A ray leaving by `dir`: into the outbox (a message per ray), or into
    // its direction's batch, which goes into the outbox when full.
    void add(int dir, const RayJob& job, uint16_t creditExp, Outbox& out) {
        if (batch_ <= 1) {  // a message per ray: written straight into the message (a ray is most of its bytes)
            out.emplace_back(std::piecewise_construct, std::forward_as_tuple(dir), std::forward_as_tuple(job, creditExp));
            return;
        }
        RayList& batch = batches_[size_t(dir)];
        if (batch.capacity() == 0 && !spare_.empty()) {
            batch = std::move(spare_.back());
            spare_.pop_back();
        }
        batch.emplace_back(job, creditExp);
        if (batch.size() >= size_t(batch_)) send(dir, out);
    }
    // Every partial batch into the outbox.
    void flush(Outbox& out) {
        for (int d = 0; d < kDirs; ++d)
            if (!batches_[size_t(d)].empty()) send(d, out);
    }
    // A ray list the node is done with (a batch it received), for reuse.
    void recycle(RayList& rays) {
        if (rays.capacity() == 0 || spare_.size() >= kSpare) return;  // (no heap block to reuse)
        rays.clear();
        spare_.push_back(std::move(rays));
    }
    // Rays in partial batches.
    size_t held() const {
        size_t n = 0;
        for (const RayList& b : batches_) n += b.size();
        return n;
    }

private:
    void send(int dir, Outbox& out) {  // the batch leaves as one message (its list moves into it)
        out.emplace_back(dir, Message::rays(std::move(batches_[size_t(dir)])));
        batches_[size_t(dir)].clear();
    }

    static constexpr size_t kSpare = 8;
    int batch_;                             // rays per message
    std::array<RayList, kDirs> batches_;    // rays collected per direction, not yet sent
    std::vector<RayList> spare_;            // emptied lists, reused for sending
};

}  // namespace rt
