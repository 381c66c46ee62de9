// The node at a frame's end (its figures, what it still holds), its flushes
// (partial ray batches, what it owes the frame buffer), and at the next
// frame's start in a sequence (machine.h, MachineSession).
#include <cstring>

#include "node/node.h"
#include "process/spawn.h"

namespace rt {

void Node::endFrame(Picos end, bool complete) {
    marks_.settle(input_.arrivals());  // (the run is over: every message is in the links)
    if (balance_) stats_.balance = balance_->finalStats();
    ledger_.endFrame(end, complete, name());
}

sc_core::sc_process_handle Node::restart(const Box& box, const ObjectBins& bins, int frame) {
    stats_ = NodeStats{};
    ledger_.restart();
    marks_.restart();
    input_.restart();
    batcher_ = RayBatcher(params_.rayBatch);
    fbOut_ = FrameBufferOutbox(params_.fbUnits, params_.fbBatch);
    outbox_ = Outbox{};
    balance_.reset();
    startTargets_.reset();
    sample_.reset();  // (before the box: rebuild notes where a sample's objects are)
    occupied_ = {};
    trace_ = NodeTrace{};
    resume_ = Resume::Start;
    suspended_ = intervalClosed_ = false;
    now_ = 0;
    outboxNext_ = 0;
    sendCost_ = sendBlocked_ = 0;
    sendMayWait_ = false;
    runAhead_ = params_.runAhead;
    mustSee_ = false;
    work_ = Work{};
    control_.reset();
    spawned_.clear();
    contributions_.clear();
    mailbox_ = Mailbox{};
    expressSent_ = 0;
    if (std::memcmp(&region_->box(), &box, sizeof(Box)) != 0) rebuild(box, bins.overlapping(box));  // (to the bit: -0 is not 0)
    return spawnMethod([this] { run(); }, *this, frame);
}

std::string Node::holding() const {
    std::string s;
    auto add = [&](const std::string& what) { s += (s.empty() ? "" : ", ") + what; };
    auto count = [&](uint64_t n, const char* what) {
        if (n) add(std::to_string(n) + " " + what);
    };
    count(input_.inHand() + input_.primariesLeft(), "rays in hand");
    count(input_.onTheirWay(), "ray messages on their way to it");
    count(batcher_.held(), "rays in partial batches");
    count(fbOut_.contributions(), "contributions");
    if (fbOut_.holdsCredit()) add("credit");
    if (stats_.blocking)
        add("blocked on its full output to " + (stats_.blockedOn >= kDirs
                                                    ? "frame-buffer unit " + std::to_string(stats_.blockedOn - kDirs)
                                                    : std::string(dirName(stats_.blockedOn))));
    return s;
}

bool Node::flushRays() {
    if (batchesRays()) batcher_.flush(outbox_);
    if (outbox_.empty()) return false;
    traceState(true, false);
    finishControlStep(0, 0, false);
    return true;
}

// The node hands the frame buffer what it owes (fb_outbox.h).
void Node::flushToFrameBuffer() {
    traceState(true, false);
    fbOut_.flush(outbox_, [this] { return name(); });
    finishControlStep(0, 0, false);
}

}  // namespace rt
