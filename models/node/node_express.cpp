// The node's side of the express rung (--fidelity express; channel/express.h).
#include "node/node.h"

namespace rt {

// --fidelity express: a ray whose next boxes hold no objects goes past them
// in one message, to the node its route reaches (channel/express.h).
bool Node::sendExpress(const Work& w, int dir) {
    ExpressRoutes::Route r;
    RayJob j = w.job;
    if (!params_.express->route(cell_, dir, j, now_, r, expressHops_)) return false;
    expressOut_.push_back(ExpressSend{dir, r, Message(j, w.creditExp)});
    ++stats_.raysExpressed;
    stats_.boxesSkipped += r.skipped;
    return true;
}

// The step's express rays, sent with its outbox: to the relay, which puts
// each on the wire of the link it leaves by and then moves it past the
// empty boxes.
void Node::postExpress() {
    if (expressOut_.empty()) return;
    const size_t self = params_.express->indexOf(cell_);
    for (ExpressSend& e : expressOut_) params_.relay->send(self, e.dir, e.route, expressHops_, std::move(e.m), now_, expressSent_++);
}

// A node that rays may skip has work of its own now and then (a ray that
// ends in its box or leaves the world there). Its processor is the one the
// relay books the skipping rays' passes on: the step starts once the
// passes booked so far are done (busy time, handling rays), and its end
// holds back the passes booked after it (chargeAndSend).
void Node::awaitExpressPasses() {
    const Picos free = expressSelf_->processorFree;
    if (free <= now_) return;
    const Picos gap = free - now_;
    BusyParts parts{};
    parts[kReceive] = gap / 2;
    parts[kSend] = gap - gap / 2;
    now_ = free;
    ledger_.charge(parts, now_, [this] { return kernel(); });
}

}  // namespace rt
