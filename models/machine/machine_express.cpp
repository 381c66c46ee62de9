// The express and through rungs (--fidelity express, through; channel/express.h): what each
// node's box and links add to a ray that crosses it, and the relay that
// moves such rays, built with the machine (its boxes hold still:
// MachineConfig::validate allows the rung only with --balance none or median).
#include "machine/machine.h"

namespace rt {
namespace {

// --fidelity through: a box's node traces the ray as its step would
// (Node::traceInBox), into scratch lists; a ray crossing without a hit
// leaves them empty. Its step: a receive, the trace, a send (Node::step).
class NodesTraceThrough : public ThroughBoxes {
public:
    NodesTraceThrough(const ModuleArray<Node>& nodes, const Shader& shader) : nodes_(nodes), shader_(shader) {}
    bool passes(size_t node, RayJob& job, double tOut, Picos& step) const override {
        const Node& n = nodes_[node];
        RayJob traced = job;
        Counters c;
        spawned_.clear();
        contributions_.clear();
        if (n.region().trace(traced, tOut, shader_, mailbox_, c, spawned_, contributions_) != Region::Step::Forward) return false;
        job = traced;
        step = n.costs().step(Counters{}, c, 1, 1, 0);
        return true;
    }

private:
    const ModuleArray<Node>& nodes_;
    const Shader& shader_;
    // (One route at a time: the nodes' processes run one at a time.)
    mutable Mailbox mailbox_;
    mutable std::vector<RayJob> spawned_;
    mutable std::vector<Contribution> contributions_;
};

}  // namespace

void Machine::buildExpress() {
    if (!cfg_.usesRelay() && !cfg_.expressRoutes) return;
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
    through_ = std::make_unique<NodesTraceThrough>(nodes_, shader_);
    express_->passThrough(through_.get());
    relay_ = std::make_unique<ExpressRelay>("express_relay", *express_);
    keepProcess(*relay_);
}

// Whether this frame's rays take the express routes: the nodes see them
// only if so (a frame without express, in a session built with them, is
// the exact model's: no ray goes to the relay, whose process only waits).
// A box is skipped whole if it holds no object and generates no primary
// ray; under --fidelity through, one with objects and no primary ray is
// passed ray by ray (where the ray crosses it without a hit).
void Machine::useExpress(const std::vector<std::vector<uint32_t>>& perNode) {
    if (express_)
        for (size_t i = 0; i < nodes_.size(); ++i) {
            ExpressNode& e = express_->node(i);
            const bool holds = !nodes_[i].region().objects().empty(), generates = !perNode[i].empty();
            e.empty = !holds && !generates;
            e.through = cfg_.through && holds && !generates;
            for (ExpressLink& l : e.out) l.shared = e.through;
        }
    nodeParams_->express = cfg_.usesRelay() ? express_.get() : nullptr;
    nodeParams_->relay = cfg_.usesRelay() ? relay_.get() : nullptr;
}

}  // namespace rt
