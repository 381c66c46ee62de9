// The express rung (--fidelity express; channel/express.h): what each
// node's box and links add to a ray that crosses it, and the relay that
// moves such rays, built with the machine (its boxes hold still:
// MachineConfig::validate allows the rung only with --balance none or median).
#include "machine/machine.h"

namespace rt {

void Machine::buildExpress() {
    if (!cfg_.express && !cfg_.expressRoutes) return;
    const uint32_t oneRay = kHeaderBytes + kRayBytes;
    std::vector<ExpressNode> info(nodes_.size());
    for (size_t i = 0; i < nodes_.size(); ++i) {
        Node& n = nodes_[i];
        ExpressNode& e = info[i];
        e.box = n.region().box();  // (whether rays may skip it: giveOutPrimaryRays, which knows its primary rays)
        // A ray it passes on: a step of one receive and one send (Node::step).
        const CostModel costs(cfg_.processorCostsOf(n.cell()), cfg_.speedOf(n.cell()), 0);
        e.pass = costs.step(Counters{}, Counters{}, 1, 1, 0);
        for (int d = 0; d < kDirs; ++d) {
            Link* out = meshLink(i, d);
            if (!out) continue;
            ExpressLink& l = e.out[size_t(d)];
            l.link = out;
            l.wire = wireTime(out->params(), oneRay);
            l.latency = out->params().latency;
            l.depth = uint32_t(out->params().depth);
        }
    }
    express_ = std::make_unique<ExpressRoutes>(cfg_.dims, std::move(info));
    relay_ = std::make_unique<ExpressRelay>("express_relay", *express_);
}

// Whether this frame's rays take the express routes: the nodes see them
// only if so (a frame without express, in a session built with them, is
// the exact model's: no ray goes to the relay, whose process only waits).
void Machine::useExpress() {
    nodeParams_->express = cfg_.express ? express_.get() : nullptr;
    nodeParams_->relay = cfg_.express ? relay_.get() : nullptr;
}

}  // namespace rt
