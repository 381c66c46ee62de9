// The node's process: taking work, stepping rays, sending what a step
// made, waiting. Its balancing side: node_balance.cpp.
#include "node/node.h"

#include <algorithm>
#include <cmath>

#include "channel/route.h"

namespace rt {

Node::Node(sc_core::sc_module_name name, const Cell& cell, const Box& box, std::vector<Shape> objects,
           const NodeParams& params, const Costs& costs, double speed)
    : sc_module(name),
      out(std::in_place, "out"),
      in(std::in_place, "in"),
      fb(std::in_place, "fb"),
      params_(params),
      time_(params.quantum),
      costs_(costs, speed, params.balance.rebuildCost),
      fbOut_(params.fbUnits, params.fbBatch),
      batcher_(params.rayBatch),
      cell_(cell),
      margin_(roundingMargin(params.world)) {
    rebuild(box, std::move(objects));
    runAhead_ = params.runAhead;
    SC_METHOD(run);
}

void Node::traceState(bool busy, bool waiting) {
    if (trace_.busy < 0) return;
    trace_.vcd->set(now_, trace_.busy, busy);
    trace_.vcd->set(now_, trace_.wait, waiting);
    trace_.vcd->set(now_, trace_.queue, int64_t(input_.depth(now_)));
}

// The node's process: a method process, run by the kernel whenever the node
// has let it catch up (after a step) or its input has come. Each activation
// first finishes what the last one stopped at (a wait for input, or for
// room in an output buffer), then runs the node's loop until the node must
// wait again; the waits are where the thread version of this loop called
// wait(), so the machine's timing is the same (doc/time.md, "Local time
// and temporal decoupling").
void Node::run() {
    suspended_ = false;
    switch (resume_) {
        case Resume::Start: start(); break;
        case Resume::Synced: break;
        case Resume::Input:
            input_.arrivals().woke();
            now_ = kernel();
            endWait();
            break;
        case Resume::Room:
            now_ = std::max(now_, kernel());
            if (sendOutbox()) endSend();
            break;
    }
    while (!suspended_) proceed();
}

void Node::suspend(Resume r) {
    suspended_ = true;
    resume_ = r;
}

void Node::start() {
    expressSelf_ = nullptr;  // (a frame without express, after one with it)
    if (params_.express) {
        ExpressNode& self = params_.express->node(params_.express->indexOf(cell_));
        expressSelf_ = self.empty || self.through ? &self : nullptr;
    }
    now_ = kernel();
    const BalanceConfig& bal = params_.balance;
    if (bal.dynamic()) {
        balance_ = std::make_unique<BalanceAgent>(bal, static_cast<BalanceHost&>(*this), params_.world, cell_[bal.axis],
                                                  params_.columnLength, outLinks_[size_t(sideDir(-1))] != nullptr,
                                                  outLinks_[size_t(sideDir(+1))] != nullptr, params_.minThickness);
        balance_->shareFaces(params_.layerFaces);
        if (startTargets_) {
            balance_->startAt((*startTargets_)[0], (*startTargets_)[1]);
            sample_.reset();
        } else if (bal.firstFrameHolds()) {
            balance_->startAt(std::nan(""), std::nan(""));  // hold, and measure
        } else if (sample_) {
            balance_->startSample(sample_->gathers, sample_->beside, sample_->faces);
        }
    }
    runAhead_ = runAhead_ && !balance_ && trace_.busy < 0;
    ledger_.configure(time_.decoupled(), time_.decoupled() && balance_);
}

// One turn of the node's loop: a balancing action that is due, or the next
// ray or message, or sending what batches and the frame buffer are owed, or
// waiting for work. A turn that charges time may suspend the process.
void Node::proceed() {
    if (balance_ && balance_->pending()) {  // the rest of the last interval's or report's actions
        balance_->act();
        return;
    }
    // An interval's end is seen before the next ray is taken, and once its
    // actions are done that ray is taken before the end is looked at again.
    if (!intervalClosed_ && balance_ && balance_->due(now_)) {
        closeInterval();
        if (balance_->pending()) {
            intervalClosed_ = true;
            return;
        }
    }
    intervalClosed_ = false;
    // --sample-end credit: the sample's credit goes back once no ray spawned
    // here waits (its rays go first: its trees here are done), not when the
    // node idles (doc/balancing.md, "When the sample is done").
    if (sampleCredit() && fbOut_.holdsSampleCredit() && !input_.spawnedInHand()) {
        flushToFrameBuffer();
        return;
    }
    int fromDir = -1;  // a control message's link: -1 for a ray (control_ is a cache line of its own, not read for one)
    if (takeWork(work_, control_, fromDir)) {
        if (fromDir >= 0) {
            Message m = std::move(*control_);
            control_.reset();
            control(m, fromDir);
        } else {
            step(work_);
        }
        return;
    }
    if (mustSee_) {  // running ahead, its input as of now_ is not all there yet
        mustSee_ = false;
        time_.syncTo(now_);
        suspend(Resume::Synced);
        return;
    }
    // Nothing to trace: send the rays still collected in batches, and hand
    // the frame buffer what it is owed, before waiting; so no ray waits in a batch
    // while everyone waits, and the credit of every ray ended here
    // follows its contributions.
    if (flushRays()) return;
    if (fbOut_.owes()) {
        flushToFrameBuffer();
        return;
    }
    waitForWork();
}

// Nothing to do: the node waits from its own time on, including while the
// kernel catches up with it: until the next message arrives, or the
// balancing interval ends (to report the load).
void Node::waitForWork() {
    ledger_.startWaiting(now_);
    // Traced as waiting from now. Straight after a step the kernel may not
    // have caught up yet, but a message arriving by now makes the wait last
    // no time, and the next step's state, traced at the same instant,
    // replaces this one; so the trace is the same as in lockstep.
    traceState(false, true);
    Picos next;
    input_.oldest(now_, next);
    // Only to a message: a node that idled ahead to the end of its balancing
    // interval would report itself idle while its neighbours, up to a quantum
    // behind, may still send it work for that interval.
    if (balance_ && next >= balance_->nextClose()) next = ~Picos(0);
    next = std::max(next, now_);  // (straight after a step, a message may have arrived by now)
    if (time_.mayIdleUntil(next)) {
        now_ = next;  // known to be the next thing to happen, and within the quantum
    } else if (input_.arrivals().waitForInput(now_, balance_ ? balance_->nextClose() : ~Picos(0))) {
        suspend(Resume::Input);  // endWait when it wakes
        return;
    } else {
        now_ = kernel();
    }
    endWait();
}

void Node::endWait() {
    ledger_.endWaiting(now_, [this] { return kernel(); });
}

// What the node will do next without input: rays in hand or still to
// generate, rays in partial batches, contributions or credit owed.
bool Node::nothingToDo() const {
    return !input_.inHand() && !input_.primariesLeft() && !fbOut_.owes() && (!batchesRays() || !batcher_.held());
}

// The control lane's messages are handled before any ray (link.h), as an
// interrupt-driven link controller would.
bool Node::takeControl(std::optional<Message>& control, int& controlDir) {
    // Along the axis, the lower side first; then, for `sample`'s planes, the neighbouring columns.
    const int ax = params_.balance.axis;
    for (int k = 0; k < (sample_ ? kDirs : 2); ++k) {
        const int d = k < 2 ? sideDir(k ? +1 : -1) : k - 2 + (k - 2 >= 2 * ax ? 2 : 0);  // (laterals in order)
        if (input_.controlArrived(d, now_)) {
            control = input_.consumeControl(d, now_);
            ++stats_.messagesReceived;
            controlDir = d;
            return true;
        }
    }
    return false;
}

bool Node::takeWork(Work& w, std::optional<Message>& control, int& controlDir) {
    if (balance_ && takeControl(control, controlDir)) {
        if (control->type == MsgType::Ray) {  // a ray of the sample, on the control lane (--sample-end credit)
            input_.takePriorityRay(*control, controlDir, w);
            control.reset();
            controlDir = -1;  // (a ray: proceed steps it)
        }
        return true;
    }
    if (input_.takeInHand(w)) return true;
    // --sample-end credit: the sample's primary rays before any that arrive.
    if (sampleCredit() && input_.primaries().sampleLeft() > 0 && generatePrimary(w)) return true;
    Picos next;
    const int best = input_.oldest(now_, next);  // ties go to the lower direction
    // Running ahead, the node takes the oldest message it has only if none
    // still to be sent can arrive before it, and decides that nothing has
    // arrived by now_ only if none can arrive by then: else it lets the
    // kernel catch up first (proceed). What it takes is what it would take
    // in lockstep; it only reads its input less often.
    if (runAhead_ && !time_.sees(best >= 0 ? next : now_)) {
        mustSee_ = true;
        return false;
    }
    if (best >= 0) {
        takeMessage(best, next, w, control, controlDir);
        return true;
    }
    return generatePrimary(w);
}

// The next primary ray of the node's pixels, if any is left and its box is there.
bool Node::generatePrimary(Work& w) {
    if (holdsPrimaries() || !input_.nextPrimary(w, params_.camera, params_.world)) return false;
    ++stats_.raysGenerated;
    ++stats_.raysCreated;
    ++stats_.counters.primaryRays;
    if (sample_) sampleGenerated();
    return true;
}

// The oldest message, from `dir`, which arrived at `arrival`: a ray message's
// first ray into `w`, or a control message.
void Node::takeMessage(int dir, Picos arrival, Work& w, std::optional<Message>& control, int& controlDir) {
    Message m = input_.consume(dir, now_);
    ++stats_.messagesReceived;
    marks_.taken(arrival);
    if (m.type == MsgType::Ray) {
        input_.takeRays(m, dir, w, batcher_);
    } else {
        controlDir = dir;
        control = std::move(m);
    }
}

void Node::step(Work& w) {
    if (expressSelf_) awaitExpressPasses();
    if (progress_) progress_->mark(now_);
    const Counters before = stats_.counters;
    traceState(true, false);
    spawned_.clear();
    contributions_.clear();
    // The box's slabs for this ray, computed once: whether the box owns
    // job.t0, where the ray leaves it, and by which face.
    const BoxSlabs box = boxSlabs(w.job.ray, region_->box());
    int dir = routeRay(w.job, box, region_->box());
    const bool passing = dir >= 0;  // not this box's: sent on without tracing
    TracedSpan span;  // where along the axis the work happened (work histogram)
    if (dir < 0) dir = traceInBox(w, box, span);
    if (dir >= 0) forward(w, dir, passing);
    fbOut_.add(contributions_, outbox_);
    stats_.contributionsSent += contributions_.size();
    const size_t sends = outbox_.size() + expressOut_.size();
    const BusyParts parts = costs_.stepParts(before, stats_.counters, sends, w.fromLink ? 1 : 0, w.generated ? 1 : 0);
    const Picos cost = sumOf(parts);
    if (balance_ && std::isfinite(span.where)) {  // (the faces only for `resplit`'s forecast: not on slide's path)
        balance_->recordStep(span.where, cost, params_.balance.betweenFrames() ? axialFaces(w, parts, span) : FaceCrossings{});
        if (sample_ && balance_->sampling() && sampleRay(w.job)) recordSample(parts, span, w.from);
    }
    markQueueDepth();
    if (expressSelf_) expressSelf_->queued = uint32_t(input_.inHand() + input_.arrivals().unconsumed());  // (express.h: route)
    chargeAndSend(parts, true);
}

// Traces the ray's segment in the box: -2 if it ended here, else the link
// direction of the face it left by.
int Node::traceInBox(Work& w, const BoxSlabs& box, TracedSpan& span) {
    ++stats_.raysTraced;
    const double t0 = w.job.t0;
    double stop = t0;
    const Region::Step s =
        region_->trace(w.job, box.span.hi, params_.shader, mailbox_, stats_.counters, spawned_, contributions_, &stop);
    if (balance_) {  // the middle of the segment traced (to its hit) stands for where its work is
        const int ax = params_.balance.axis;
        span.where = w.job.ray.at(0.5 * (t0 + stop))[ax];
        span.from = w.job.ray.at(t0)[ax];
        span.to = w.job.ray.at(stop)[ax];
    }
    if (s == Region::Step::Terminated) {
        terminate(w, spawned_);
        return -2;
    }
    // It left the box at job.t0 = box.span.hi: by the face routeRay would pick there.
    const auto [axis, step] = box.exitFace(w.job.ray);
    if (axis < 0) throw std::logic_error(std::string(name()) + ": a ray left its box by no face");
    span.exit = dirOf(axis, step);
    return span.exit;
}

// Where a ray is forwarded: to the neighbour in `dir`, or, with none that
// way, out of the world (the background, through the frame buffer).
void Node::forward(const Work& w, int dir, bool passing) {
    if (!outLinks_[size_t(dir)]) {
        contributions_.push_back(params_.shader.miss(w.job, stats_.counters));
        ++stats_.raysTerminated;
        giveBack(w, w.creditExp);
        return;
    }
    if (passing) {
        ++stats_.raysPassed;
        if (w.from >= 0 && dirAxis(w.from) != params_.balance.axis) ++stats_.raysPassedBetweenColumns;
    }
    ++stats_.raysForwarded;
    if (sampleCredit() && sampleRay(w.job)) {
        // A ray of the sample: alone, on the control lane, ahead of the rest (--sample-end credit).
        outbox_.emplace_back(std::piecewise_construct, std::forward_as_tuple(dir), std::forward_as_tuple(w.job, w.creditExp));
        outbox_.back().second.priority = true;
        return;
    }
    if (params_.express && sendExpress(w, dir)) return;
    batcher_.add(dir, w.job, w.creditExp, outbox_);
}

void Node::terminate(const Work& w, std::vector<RayJob>& spawned) {
    ++stats_.raysTerminated;
    // The ray's credit goes to its children in equal powers of two, and at
    // least one share stays here: this node returns it to the frame buffer
    // only after the contributions the hit made here (flushToFrameBuffer sends
    // them first on the same FIFO ports). Otherwise the children could end
    // elsewhere and complete the credit while those contributions still wait
    // here, for instance while this node is busy with balancing messages.
    const uint64_t m = spawned.size();
    if (m == 0) {
        giveBack(w, w.creditExp);
        return;
    }
    const int c = ceilLog2(m + 1);
    giveBack(w, w.creditExp + c, (uint64_t(1) << c) - m);
    for (RayJob& j : spawned) {
        input_.spawn(j, uint16_t(w.creditExp + c));
        ++stats_.raysCreated;
    }
}

// The queue's high-water mark after a step (queue_marks.h); a node running
// ahead counts it once it sees its input as of now_.
void Node::markQueueDepth() {
    if (runAhead_ && !time_.sees(now_)) marks_.defer(now_, input_.inHand());
    else marks_.step(now_, input_.inHand(), input_.arrivals());
}

// A step takes `cost`: the node is busy until then, and what it produced
// leaves at the end of it.
void Node::chargeAndSend(const BusyParts& parts, bool mayWaitForWork) {
    const Picos cost = sumOf(parts);
    now_ += cost;
    checkSimTime(now_, [this] { return name(); });
    if (expressSelf_) expressSelf_->processorFree = std::max(expressSelf_->processorFree, now_);  // (express.h)
    ledger_.charge(parts, now_, [this] { return kernel(); });
    sendCost_ = cost;
    sendMayWait_ = mayWaitForWork;
    sendBlocked_ = 0;
    if (sendOutbox()) endSend();
}

void Node::finishControlStep(uint64_t recvs, size_t movedObjects, bool balancing) {
    chargeAndSend(costs_.messageParts(outbox_.size(), recvs, movedObjects, balancing));
}

// The step's messages are sent, each after any wait for room: the step, then
// the wait, each between two checkpoints (time_ledger.h); then the kernel
// catches up as the quantum asks. A step that leaves the node with nothing
// to do and must let the kernel catch up anyway goes straight into waiting
// for input, which includes the catching up: one kernel wait instead of
// two. The node takes its input at the same times either way.
void Node::endSend() {
    stats_.messagesSent += outbox_.size() + expressOut_.size();
    outbox_.clear();
    if (!expressOut_.empty()) {  // (their hops with them: without express, a cache line not read at every send)
        expressOut_.clear();
        expressHops_.clear();
    }
    outboxNext_ = 0;
    Picos cost = sendCost_;
    if (sendBlocked_) {
        ledger_.checkpoint(now_, [this] { return kernel(); });
        cost += sendBlocked_;
    }
    if (!time_.mustSync(now_, cost)) return;
    const bool idle = sendMayWait_ && nothingToDo();
    if (runAhead_ && !idle) return;  // it lets the kernel catch up when it must see its input (takeWork)
    if (idle) {
        waitForWork();
    } else {
        time_.syncTo(now_);
        suspend(Resume::Synced);
    }
}

// Sends the outbox from outboxNext_ on. A full output buffer blocks the node
// (link.h): no step, no input taken, until the link has room; the time is
// wait, and counted as blocked. Returns false if the node must wait for the
// receiver to consume (suspended: it goes on from the same message).
bool Node::sendOutbox() {
    for (; outboxNext_ < outbox_.size(); ++outboxNext_) {
        auto& [d, m] = outbox_[outboxNext_];
        Link& link = d >= kDirs ? *fbLinks_[size_t(d - kDirs)] : *outLinks_[size_t(d)];
        for (Picos room; (room = link.roomAt(m, now_)) != now_;) {
            if (!ledger_.blocking()) {
                // It records the blocked state with its queue (messages
                // arrived by now): beyond what it may run ahead to, the
                // kernel catches up first, so that the queue is complete.
                if (now_ > frameClock() && !time_.mayIdleUntil(now_)) {
                    time_.syncTo(now_);
                    suspend(Resume::Room);
                    return false;
                }
                ledger_.startBlocked(now_, d);
                traceState(false, true);
            }
            if (room == LinkSendIf::kRoomUnknown) {
                sc_core::next_trigger(link.roomEvent());  // until the receiver consumes
                suspend(Resume::Room);
                return false;
            }
            now_ = room;  // known: a message leaves for a slot then
        }
        if (ledger_.blocking()) {
            sendBlocked_ += ledger_.endBlocked(now_);
            traceState(true, false);
        }
        link.send(std::move(m), now_);
    }
    postExpress();
    return true;
}

}  // namespace rt
