#include "node/node_input.h"

namespace rt {

void NodeInput::takeRays(Message& m, int dir, Work& w, RayBatcher& batcher) {
    // The first ray carries the message's handling cost.
    w.take(m.rayAt(0), true, int8_t(dir));
    receivedFrom_ = int8_t(dir);
    if (m.rayCount() > 1) {  // a batch: the rest waits in received_
        batcher.recycle(received_);
        received_ = m.takeBatch();
        receivedNext_ = 1;
    } else {
        if (m.batched()) {  // a batch of one (a partial flush): its list is reused
            RayList one = m.takeBatch();
            batcher.recycle(one);
        }
        received_.clear();
        receivedNext_ = 0;
    }
}

uint64_t NodeInput::onTheirWay() const {
    uint64_t n = 0;
    for (const Link* l : links_)
        if (l) n += l->workInFlight();
    return n;
}

HandedPrimaries NodeInput::handOver(const Camera& camera, const Box& world, int axis, double boundary, bool upper) {
    return primaries_.handOver([&](uint32_t p) {
        const RayJob j = primaryOf(camera, p, world);
        const double x = j.ray.at(j.t0)[axis];
        return upper ? x >= boundary : x < boundary;
    });
}

}  // namespace rt
