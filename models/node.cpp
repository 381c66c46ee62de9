#include "node.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <unordered_set>

namespace rt {

Node::Node(sc_core::sc_module_name name, const Cell& cell, const Box& box, std::vector<Shape> objects,
           const NodeParams& params, const Costs& costs, double speed)
    : sc_module(name),
      out("out", kDirs),
      in("in", kDirs),
      fb("fb"),
      cell_(cell),
      shader_(params.shader),
      camera_(params.camera),
      world_(params.world),
      costs_(costs),
      speed_(speed),
      fbBatch_(params.fbBatch),
      bal_(params.balance),
      margin_(roundingMargin(params.world)),
      minThickness_(params.minThickness),
      time_(params.quantum),
      rayBatch_(params.rayBatch),
      columnLength_(params.columnLength),
      layerFaces_(params.layerFaces),
      pending_(size_t(params.fbUnits)),
      sentSince_(size_t(params.fbUnits), 0) {
    rebuild(box, std::move(objects));
    runAhead_ = params.runAhead;
    SC_METHOD(run);
}

void Node::rebuild(const Box& box, std::vector<Shape> objects) {
    for (int a = 0; a < 3; ++a)
        if (!(box.lo[a] < box.hi[a])) {
            char buf[256];
            std::snprintf(buf, sizeof buf, "%s: empty box on axis %d: [%.17g, %.17g] at %llu ps", name(), a, box.lo[a],
                          box.hi[a], (unsigned long long)now_);
            throw std::logic_error(buf);
        }
    std::sort(objects.begin(), objects.end(), [](const Shape& a, const Shape& b) { return a.id < b.id; });
    region_ = std::make_unique<Region>(box, std::move(objects), AccelKind::Grid);
}

void Node::assignPrimaries(std::vector<uint32_t> pixels, int primaryExp, const Credit& remainder) {
    pixels_ = std::move(pixels);
    primaryExp_ = primaryExp;
    credit_ = remainder;
}

void Node::checkpoint() {
    if (!keepsTimeline_) return;
    const Picos k = sc_core::sc_time_stamp().value();
    while (timelineStart_ + 1 < timeline_.size() && timeline_[timelineStart_ + 1].t <= k) ++timelineStart_;
    if (timelineStart_ > 64 && timelineStart_ * 2 > timeline_.size()) {
        timeline_.erase(timeline_.begin(), timeline_.begin() + std::ptrdiff_t(timelineStart_));
        timelineStart_ = 0;
    }
    timeline_.push_back({now_, stats_.busy, stats_.lastActive});
}

void Node::endFrame(Picos end, bool complete) {
    settleDepths();  // (the run is over: every message is in the links)
    if (balance_) stats_.balance = balance_->finalStats();
    if (stats_.blocking && stats_.blockedSince <= end) {  // blocked on a full output since then
        stats_.blocking = false;
        stats_.blocked += end - stats_.blockedSince;
        stats_.wait += end - stats_.blockedSince;
        return;
    }
    if (stats_.waiting) {
        stats_.waiting = false;
        if (stats_.waitingSince <= end) {  // waiting for input since then
            stats_.wait += end - stats_.waitingSince;
            return;
        }
        // Otherwise it was waiting for the kernel to catch up with it, from
        // past the end: ahead of the end, below.
    }
    if (!time_.decoupled()) {  // lockstep: at most the last step runs past the end
        if (stats_.lastActive > end) {
            stats_.busy -= stats_.lastActive - end;
            stats_.lastActive = end;
        }
        return;
    }
    const Picos local = stats_.busy + stats_.wait;  // the node's local time: every picosecond is one or the other
    if (local <= end) {  // idle from its local time until the end (asleep while the kernel caught up)
        stats_.wait += end - local;
        return;
    }
    if (!keepsTimeline_) {
        // Without a dynamic policy every step moves credit (a ray's, or the
        // frame buffer's share), which reaches unit 0 after the step ends
        // (in any mode: a message never arrives before it is sent): no step
        // of a whole frame ends after it, and a node past its end got there
        // idling. So it keeps no timeline.
        if (stats_.lastActive > end) {
            if (complete)
                throw std::logic_error(std::string(name()) + ": a step ended after the frame, with no dynamic policy");
            // A run stopped midway (watchdog, signal) at the kernel's time,
            // which a node with work may have run past: its figures there
            // are not kept, so it counts as busy from the stop to the end of
            // its last step (an incomplete report's figures are the run's so
            // far; busy + wait is still the time).
            stats_.busy -= std::min(stats_.busy, stats_.lastActive - end);
            stats_.lastActive = end;
        }
        stats_.wait = end - stats_.busy;
        return;
    }
    // Ahead of the end: between two checkpoints the node waited, then ran one
    // step (or only idled), so the busy time at `end` is the earlier one's
    // plus whatever of that step lies before `end`. (The kernel stopped at or
    // before `end`, so the timeline reaches back to it.)
    Checkpoint prev{0, 0, 0};
    for (size_t i = timelineStart_; i < timeline_.size(); ++i) {
        const Checkpoint& c = timeline_[i];
        if (c.t > end) {
            const Picos stepStart = c.t - (c.busy - prev.busy);
            const bool running = end > stepStart;  // a step was running at the end
            stats_.busy = prev.busy + (running ? end - stepStart : 0);
            stats_.wait = end - stats_.busy;
            stats_.lastActive = running ? end : prev.lastActive;
            return;
        }
        prev = c;
    }
    throw std::logic_error(std::string(name()) + ": local time past the end of the frame, but no checkpoint after it");
}

std::string Node::holding() const {
    std::string s;
    auto add = [&](uint64_t n, const char* what) {
        if (!n) return;
        s += (s.empty() ? "" : ", ") + std::to_string(n) + " " + what;
    };
    add(ownWork() + (pixels_.size() - nextPixel_), "rays in hand");
    uint64_t coming = 0;
    for (int d = 0; d < kDirs; ++d)
        if (in[d].size()) coming += in[d]->workInFlight();
    add(coming, "ray messages on their way to it");
    uint64_t batched = 0;
    for (const RayList& b : outRays_) batched += b.size();
    add(batched, "rays in partial batches");
    add(pendingCount_, "contributions");
    if (!credit_.isZero()) s += std::string(s.empty() ? "" : ", ") + "credit";
    if (stats_.blocking)
        s += std::string(s.empty() ? "" : ", ") + "blocked on its full output to " +
             (stats_.blockedOn >= kDirs ? "frame-buffer unit " + std::to_string(stats_.blockedOn - kDirs)
                                        : std::string(dirName(stats_.blockedOn)));
    return s;
}

size_t Node::queueDepth(Picos at) const {
    // Counted in simulated time (messages that have arrived by `at`), so the
    // same in every exact mode.
    return ownWork() + inputOrder_.arrivedBy(at);
}

void Node::traceState(bool busy, bool waiting) {
    if (trace_.busy < 0) return;
    trace_.vcd->set(now_, trace_.busy, busy);
    trace_.vcd->set(now_, trace_.wait, waiting);
    trace_.vcd->set(now_, trace_.queue, int64_t(queueDepth(now_)));
}

// The node's process: a method process, run by the kernel whenever the node
// has let it catch up (after a step) or its input has come. Each activation
// first finishes what the last one stopped at (a wait for input, or for
// room in an output buffer), then runs the node's loop until the node must
// wait again; the waits are where the thread version of this loop called
// wait(), so the machine's timing is the same (doc/machine.md, "Local time
// and temporal decoupling").
void Node::run() {
    suspended_ = false;
    switch (resume_) {
        case Resume::Start: start(); break;
        case Resume::Synced: break;
        case Resume::Input:
            inputOrder_.woke();
            now_ = sc_core::sc_time_stamp().value();
            endWait();
            break;
        case Resume::Room:
            now_ = std::max(now_, Picos(sc_core::sc_time_stamp().value()));
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
    inputOrder_.listen(in);
    // The links themselves, read at every step: a port's interface is one
    // more pointer to follow (a cache miss on a node not run for a while).
    for (int d = 0; d < kDirs; ++d) {
        inLinks_[size_t(d)] = in[d].size() ? &asLink(*in[d].operator->()) : nullptr;
        outLinks_[size_t(d)] = out[d].size() ? &asLink(*out[d].operator->()) : nullptr;
    }
    for (int u = 0; u < fb.size(); ++u) fbLinks_.push_back(&asLink(*fb[u]));
    now_ = sc_core::sc_time_stamp().value();
    if (bal_.dynamic())
        balance_ = std::make_unique<BalanceAgent>(bal_, static_cast<BalanceHost&>(*this), world_, cell_[bal_.axis], columnLength_,
                                                  out[sideDir(-1)].size() > 0, out[sideDir(+1)].size() > 0, minThickness_);
    if (balance_) balance_->shareFaces(layerFaces_);
    if (balance_ && startTargets_) balance_->startAt((*startTargets_)[0], (*startTargets_)[1]);
    runAhead_ = runAhead_ && !balance_ && trace_.busy < 0;
    keepsTimeline_ = time_.decoupled() && balance_;
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
    int fromDir = -1;
    if (takeWork(work_, control_, fromDir)) {
        if (control_) {
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
    if (owesFrameBuffer()) {
        flushToFrameBuffer();
        return;
    }
    waitForWork();
}

// Nothing to do: the node waits from its own time on, including while the
// kernel catches up with it: until the next message arrives, or the
// balancing interval ends (to report the load).
void Node::waitForWork() {
    stats_.waiting = true;
    stats_.waitingSince = now_;
    // Traced as waiting from now. Straight after a step the kernel may not
    // have caught up yet, but a message arriving by now makes the wait last
    // no time, and the next step's state, traced at the same instant,
    // replaces this one; so the trace is the same as in lockstep.
    traceState(false, true);
    Picos next;
    inputOrder_.oldest(now_, next);
    // Only to a message: a node that idled ahead to the end of its balancing
    // interval would report itself idle while its neighbours, up to a quantum
    // behind, may still send it work for that interval.
    if (balance_ && next >= balance_->nextClose()) next = ~Picos(0);
    next = std::max(next, now_);  // (straight after a step, a message may have arrived by now)
    if (time_.mayIdleUntil(next)) {
        now_ = next;  // known to be the next thing to happen, and within the quantum
    } else if (inputOrder_.waitForInput(now_, balance_ ? balance_->nextClose() : ~Picos(0))) {
        suspend(Resume::Input);  // endWait when it wakes
        return;
    } else {
        now_ = sc_core::sc_time_stamp().value();
    }
    endWait();
}

void Node::endWait() {
    stats_.wait += now_ - stats_.waitingSince;
    stats_.waiting = false;
    checkpoint();
}

// What the node will do next without input: rays in hand or still to
// generate, rays in partial batches, contributions or credit owed.
bool Node::nothingToDo() const {
    if (ownWork() || nextPixel_ < pixels_.size() || owesFrameBuffer()) return false;
    for (const RayList& b : outRays_)
        if (!b.empty()) return false;
    return true;
}

// The control lane's messages are handled before any ray (link.h), as an
// interrupt-driven link controller would.
bool Node::takeControl(std::optional<Message>& control, int& controlDir) {
    for (int side : {-1, +1}) {
        const int d = sideDir(side);
        if (inLinks_[size_t(d)] && inLinks_[size_t(d)]->controlArrivedBy(now_)) {
            control = inLinks_[size_t(d)]->consumeControl(now_);
            ++stats_.messagesReceived;
            controlDir = d;
            return true;
        }
    }
    return false;
}

bool Node::takeWork(Work& w, std::optional<Message>& control, int& controlDir) {
    if (balance_ && takeControl(control, controlDir)) return true;
    if (!local_.empty()) {
        w = local_.back();
        local_.pop_back();
        return true;
    }
    if (receivedNext_ < received_.size()) {  // the rest of a batch: its message was handled already
        const RayItem& r = received_[receivedNext_++];
        w.take(r, false, receivedFrom_);
        return true;
    }
    Picos next;
    const int best = inputOrder_.oldest(now_, next);  // ties go to the lower direction
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
        Message m = inLinks_[size_t(best)]->consume(now_);
        ++stats_.messagesReceived;
        ++taken_;
        if (!deferredDepths_.empty()) takenArrivals_.push_back(next);
        if (m.type == MsgType::Ray) {
            // The first ray carries the message's handling cost.
            w.take(m.rayAt(0), true, int8_t(best));
            receivedFrom_ = int8_t(best);
            if (m.rayCount() > 1) {  // a batch: the rest waits in received_
                recycle(received_);
                received_ = m.takeBatch();
                receivedNext_ = 1;
            } else {
                if (m.batched()) {  // a batch of one (a partial flush): its list is reused
                    RayList one = m.takeBatch();
                    recycle(one);
                }
                received_.clear();
                receivedNext_ = 0;
            }
        } else {
            controlDir = best;
            control = std::move(m);
        }
        return true;
    }
    if (nextPixel_ < pixels_.size()) {
        const uint32_t p = pixels_[nextPixel_++];
        w = Work{primaryJob(camera_, int(p % uint32_t(camera_.width())), int(p / uint32_t(camera_.width())), world_),
                 uint16_t(primaryExp_), false, true, -1};
        ++stats_.raysGenerated;
        ++stats_.raysCreated;
        ++stats_.counters.primaryRays;
        return true;
    }
    return false;
}

// Where a ray is forwarded: the link direction towards the owner of job.t0,
// or -1 if this box owns it. The first axis whose slab does not own t0 picks
// the direction; a neighbour that does not own it either forwards it on, so
// a ray always reaches its owner, also when the columns' boundaries along the
// progress axis do not line up.
int Node::route(const RayJob& job, const BoxSlabs& box) const {
    // Owned when every slab holds t0: when their intersection does (the usual case).
    if (box.span.lo <= job.t0 && job.t0 < box.span.hi) return -1;
    const Box& b = region_->box();
    for (int a = 0; a < 3; ++a) {
        if (job.ray.d[a] == 0) {
            const double o = job.ray.o[a];
            if (o < b.lo[a]) return dirOf(a, -1);
            if (o >= b.hi[a]) return dirOf(a, +1);
            continue;
        }
        const Interval s = box.slab[size_t(a)];
        const int forward = job.ray.d[a] > 0 ? +1 : -1;  // moving along the ray moves this way on axis a
        if (job.t0 < s.lo) return dirOf(a, -forward);
        if (job.t0 >= s.hi) return dirOf(a, forward);
    }
    return -1;
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
        credit_.add(w.creditExp);
        return;
    }
    const int c = ceilLog2(m + 1);
    credit_.add(w.creditExp + c, (uint64_t(1) << c) - m);
    for (RayJob& j : spawned) {
        local_.push_back(Work{j, uint16_t(w.creditExp + c), false, false, -1});
        ++stats_.raysCreated;
    }
}

void Node::step(Work& w) {
    if (progress_) progress_->mark(now_);
    const Counters before = stats_.counters;
    traceState(true, false);
    // Scratch lists kept between steps, so a step allocates nothing.
    std::vector<RayJob>& spawned = spawned_;
    std::vector<Contribution>& contributions = contributions_;
    spawned.clear();
    contributions.clear();
    // The box's slabs for this ray, computed once: whether the box owns
    // job.t0, where the ray leaves it, and by which face.
    const BoxSlabs box = boxSlabs(w.job.ray, region_->box());
    int dir = route(w.job, box);
    const bool passing = dir >= 0;  // not this box's: sent on without tracing
    double where = std::nan("");  // where along the axis the work happened (work histogram)
    if (dir < 0) {
        ++stats_.raysTraced;
        if (balance_) {  // the middle of the segment traced stands for where its work is
            const double end = std::min(w.job.tEnd, box.span.hi);
            where = w.job.ray.at(0.5 * (w.job.t0 + end))[bal_.axis];
        }
        const Region::Step s = region_->trace(w.job, box.span.hi, shader_, mailbox_, stats_.counters, spawned, contributions);
        if (s == Region::Step::Terminated) {
            terminate(w, spawned);
            dir = -2;
        } else {  // it left the box at job.t0 = box.span.hi: by the face route() would pick there
            const auto [axis, step] = box.exitFace(w.job.ray);
            if (axis < 0) throw std::logic_error(std::string(name()) + ": a ray left its box by no face");
            dir = dirOf(axis, step);
        }
    }
    if (dir >= 0) {
        if (outLinks_[size_t(dir)]) {
            if (passing) {
                ++stats_.raysPassed;
                if (w.from >= 0 && dirAxis(w.from) != bal_.axis) ++stats_.raysPassedBetweenColumns;
            }
            queueRay(dir, w);
        } else {  // no neighbour that way: the ray leaves the world
            contributions.push_back(shader_.miss(w.job, stats_.counters));
            ++stats_.raysTerminated;
            credit_.add(w.creditExp);
        }
    }
    for (const Contribution& c : contributions) queueContribution(c);
    stats_.contributionsSent += contributions.size();
    for (const Contribution& c : contributions) {  // full batches leave at the end of the step
        const int u = unitOf(c);
        if (pending_[size_t(u)].size() >= size_t(fbBatch_)) sendContributions(u);
    }
    const Picos cost = stepCost(before, outbox_.size(), w.fromLink ? 1 : 0, w.generated ? 1 : 0);
    if (balance_ && std::isfinite(where)) balance_->recordStep(where, cost);
    // The exact depth (a scan of the input links) only when it could set a
    // new high-water mark: it is at most the local work plus all unconsumed.
    // A node running ahead counts it once it sees its input as of now_.
    if (runAhead_ && !time_.sees(now_)) {
        deferDepth();
    } else {
        if (!deferredDepths_.empty()) settleDepths();  // (it sees now_, so every earlier one)
        if (ownWork() + inputOrder_.unconsumed() > stats_.queueHighWater)
            stats_.queueHighWater = std::max(stats_.queueHighWater, queueDepth(now_));
    }
    chargeAndSend(cost, true);
}

void Node::deferDepth() {
    if (deferredDepths_.empty()) takenBase_ = taken_;
    deferredDepths_.push_back({now_, ownWork(), taken_});
}

// The deferred depths, once every message that arrived by each is in the
// links: its own work, the messages taken since that had arrived by it
// (taken in arrival order), and those arrived by it still not taken.
void Node::settleDepths() {
    const size_t unconsumed = inputOrder_.unconsumed();
    for (const DeferredDepth& d : deferredDepths_) {
        const auto from = takenArrivals_.begin() + std::ptrdiff_t(d.taken - takenBase_);
        const auto takenSince = uint64_t(std::upper_bound(from, takenArrivals_.end(), d.t) - from);
        // (the scan of the links only when the depth could set a new mark, as in step)
        if (d.own + takenSince + unconsumed > stats_.queueHighWater)
            stats_.queueHighWater = std::max(stats_.queueHighWater, size_t(d.own + takenSince + inputOrder_.arrivedBy(d.t)));
    }
    deferredDepths_.clear();
    takenArrivals_.clear();
}

// A step takes `cost`: the node is busy until then, and what it produced
// leaves at the end of it.
void Node::chargeAndSend(Picos cost, bool mayWaitForWork) {
    now_ += cost;
    checkSimTime(now_, name());
    stats_.busy += cost;
    stats_.lastActive = now_;
    checkpoint();
    sendCost_ = cost;
    sendMayWait_ = mayWaitForWork;
    sendBlocked_ = 0;
    if (sendOutbox()) endSend();
}

// The step's messages are sent, each after any wait for room: the step, then
// the wait, each between two checkpoints (endFrame); then the kernel catches
// up as the quantum asks. A step that leaves the node with nothing to do and
// must let the kernel catch up anyway goes straight into waiting for input,
// which includes the catching up: one kernel wait instead of two. The node
// takes its input at the same times either way.
void Node::endSend() {
    stats_.messagesSent += outbox_.size();
    outbox_.clear();
    outboxNext_ = 0;
    Picos cost = sendCost_;
    if (sendBlocked_) {
        checkpoint();
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
        for (Picos room; (room = link.roomAt(m.type, now_)) != now_;) {
            if (!stats_.blocking) {
                // It records the blocked state with its queue (messages
                // arrived by now): beyond what it may run ahead to, the
                // kernel catches up first, so that the queue is complete.
                if (now_ > sc_core::sc_time_stamp().value() && !time_.mayIdleUntil(now_)) {
                    time_.syncTo(now_);
                    suspend(Resume::Room);
                    return false;
                }
                stats_.blocking = true;
                stats_.blockedSince = now_;
                stats_.blockedOn = d;
                traceState(false, true);
            }
            if (room == LinkSendIf::kRoomUnknown) {
                sc_core::next_trigger(link.roomEvent());  // until the receiver consumes
                suspend(Resume::Room);
                return false;
            }
            now_ = room;  // known: a message leaves for a slot then
        }
        if (stats_.blocking) {
            const Picos blocked = now_ - stats_.blockedSince;
            stats_.blocking = false;
            stats_.blocked += blocked;
            stats_.wait += blocked;
            sendBlocked_ += blocked;
            traceState(true, false);
        }
        link.send(std::move(m), now_);
    }
    return true;
}

// Where a ray is forwarded: into the batch for its direction, which leaves
// as one message when full.
void Node::queueRay(int dir, const Work& w) {
    ++stats_.raysForwarded;
    RayList& batch = outRays_[dir];
    if (rayBatch_ <= 1) {  // a message per ray: written straight into the message (a ray is most of its bytes)
        outbox_.emplace_back(std::piecewise_construct, std::forward_as_tuple(dir), std::forward_as_tuple(w.job, w.creditExp));
        return;
    }
    if (batch.capacity() == 0 && !spareRays_.empty()) {
        batch = std::move(spareRays_.back());
        spareRays_.pop_back();
    }
    batch.emplace_back(w.job, w.creditExp);
    if (batch.size() >= size_t(rayBatch_)) sendBatch(dir);
}

// The rays collected for `dir` leave as one message (their list moves into it).
void Node::sendBatch(int dir) {
    Message& m = outbox_.emplace_back(dir, Message{}).second;
    m.body().batch = std::move(outRays_[dir]);
    outRays_[dir].clear();
}

// A ray list this node is done with becomes the next one it sends: nodes
// receive about as many ray messages as they send, so most messages reuse a
// list instead of allocating one (and the receiver freeing it).
void Node::recycle(RayList& rays) {
    if (rays.capacity() == 0 || spareRays_.size() >= kSpareRayLists) return;  // (no heap block to reuse)
    rays.clear();
    spareRays_.push_back(std::move(rays));
}

bool Node::flushRays() {
    for (int d = 0; d < kDirs; ++d) {
        if (!outRays_[d].empty()) sendBatch(d);
    }
    if (outbox_.empty()) return false;
    traceState(true, false);
    finishControlStep(stats_.counters, 0, 0);
    return true;
}

void Node::queueContribution(const Contribution& c) {
    pending_[size_t(unitOf(c))].push_back(c);
    ++pendingCount_;
}

void Node::sendContributions(int unit) {
    std::vector<Contribution>& p = pending_[size_t(unit)];
    Message m;
    m.type = MsgType::Contributions;
    if (p.size() >= size_t(fbBatch_)) {  // a full batch: hand over the list itself
        m.body().contributions.swap(p);
        p.reserve(size_t(fbBatch_));     // the unit keeps the list: it should hold no spare room
    } else {
        m.body().contributions.assign(p.begin(), p.end());  // a part batch: a list of its size
        p.clear();
    }
    pendingCount_ -= m.body().contributions.size();
    sentSince_[size_t(unit)] += uint32_t(m.body().contributions.size());
    outbox_.push_back({fbTarget(unit), std::move(m)});
}

// The node hands the frame buffer what it owes: every part batch, then its
// returned credit, to unit 0 (the host), with how many contributions it has
// sent to each other unit since it last returned credit. Unit 0's own
// contributions travel ahead of the credit on the same FIFO port; for the
// others, unit 0 checks the counts with each unit once the credit is whole
// (frame_buffer.h).
void Node::flushToFrameBuffer() {
    traceState(true, false);
    for (size_t u = 0; u < pending_.size(); ++u)
        if (!pending_[u].empty()) sendContributions(int(u));
    if (!credit_.isZero()) {
        Message m;
        m.type = MsgType::Credit;
        m.body().credit = credit_;
        credit_.clear();
        for (size_t u = 1; u < sentSince_.size(); ++u)
            if (sentSince_[u]) m.body().unitCounts.push_back({uint16_t(u), sentSince_[u]});
        std::fill(sentSince_.begin(), sentSince_.end(), 0);
        outbox_.push_back({fbTarget(0), std::move(m)});
    } else if (std::any_of(sentSince_.begin(), sentSince_.end(), [](uint32_t n) { return n != 0; })) {
        // A contribution is made with credit kept for it (terminate), so this cannot happen.
        throw std::logic_error(std::string(name()) + ": contributions sent without credit to cover them");
    }
    finishControlStep(stats_.counters, 0, 0);
}

// Where a cost is charged: a step's operation counts times their costs,
// divided by the node's speed factor (exact when the speed is 1).
Picos Node::stepCost(const Counters& before, uint64_t sends, uint64_t recvs, uint64_t generated) const {
    const Counters& c = stats_.counters;
    Picos ps = sends * costs_.send + recvs * costs_.recv + generated * costs_.rayGen;
    for (int k = 0; k < kPrimitiveKinds; ++k) ps += (c.tests[k] - before.tests[k]) * costs_.test[k];
    ps += (c.voxelSteps - before.voxelSteps) * costs_.voxelStep;
    ps += (c.shadings - before.shadings) * costs_.shade;
    if (speed_ == 1.0) return ps;
    return Picos(std::llround(double(ps) / speed_));
}

// Sends this step's outbox and charges its time: messages handled plus the
// grid update for the objects that moved in or out.
void Node::finishControlStep(const Counters& before, uint64_t recvs, size_t movedObjects) {
    const Picos cost = stepCost(before, outbox_.size(), recvs, 0) +
                       Picos(std::llround(double(movedObjects * bal_.rebuildCost) / speed_));
    chargeAndSend(cost);
}

// ---- The balancing protocol (doc/balancing.md): the node's side ----

// At the end of each interval: the agent records the node's load over it,
// and reports and decides with each neighbour as far as the lockstep allows.
void Node::closeInterval() {
    balance_->closeInterval(now_, stats_.busy, stats_.wait, waitingWork());
}

void Node::sendReport(int side, Message m) {
    outbox_.push_back({sideDir(side), std::move(m)});
    traceState(true, false);
    finishControlStep(stats_.counters, 0, 0);
}

void Node::control(Message& m, int fromDir) {
    const int side = dirStep(fromDir);  // the neighbour is below (-1) or above (+1) along the axis
    traceState(true, false);
    if (dirAxis(fromDir) != bal_.axis) throw std::logic_error(std::string(name()) + ": control message off the progress axis");
    if (m.type == MsgType::LoadReport) {
        finishControlStep(stats_.counters, 1, 0);
        balance_->onReport(side, m, now_);
    } else if (m.type == MsgType::Slide) {
        takeSlab(side, m.body().boundary, std::move(m.body().objects));
    } else if (m.type == MsgType::Ack) {
        ++stats_.acks;
        finishControlStep(stats_.counters, 1, 0);
    }
}

Box Node::slabOf(int side, double boundary) const {
    Box slab = region_->box();
    if (side > 0) slab.lo[bal_.axis] = boundary;
    else slab.hi[bal_.axis] = boundary;
    return slab;
}

// The time `bytes` take on the wire of a link with parameters `l`, in ps.
// A message's time on the wire, unrounded: for the guard's estimates.
static double wirePicos(const LinkParams& l, uint32_t bytes) { return double(bytes) * 1e12 / l.bandwidth; }

Picos Node::rayWire(int side) const { return Picos(wirePicos(out[sideDir(side)]->params(), kHeaderBytes + kRayBytes)); }

Picos Node::hopTime(int side) const { return out[sideDir(side)]->params().latency + rayWire(side); }

// Only a report on a control lane is paced: it goes ahead of the rays, so
// without pacing reports could take the wire from them. On the rays' FIFO
// a report waits its turn behind them (0: no pacing).
Picos Node::reportTime(int side) const {
    const LinkParams& l = out[sideDir(side)]->params();
    if (l.controlDepth == 0) return 0;
    return Picos(wirePicos(l, kHeaderBytes + kLoadReportBytes));
}

Picos Node::linkOccupied(int side) const { return out[sideDir(side)]->occupied(); }

// As LinkSendIf::occupied counts it: its wire time, or its share of the
// slots' round trip when that is longer.
Picos Node::rayOccupies(int side) const {
    const LinkParams& l = out[sideDir(side)]->params();
    const double wire = wirePicos(l, kHeaderBytes + kRayBytes);
    return Picos(std::max(wire, (wire + 2 * double(l.latency)) / l.depth));
}

// What giving the slab would cost: both nodes handle a message and update
// their grids for its objects (rebuild cost per object moved, on each), and
// the slab crosses the link (latency and its bytes at the link's bandwidth).
Picos Node::slabCost(int side, double boundary) const {
    const Box slab = slabOf(side, boundary);
    Message m;
    m.type = MsgType::Slide;
    size_t objects = 0;
    uint32_t bytes = m.bytes();
    for (const Shape& s : region_->objects())
        if (overlapsBox(s, slab, margin_)) {
            ++objects;
            bytes += objectBytes(s);
        }
    const LinkParams& l = out[sideDir(side)]->params();
    const double handling = double(costs_.send + costs_.recv + 2 * objects * bal_.rebuildCost) / speed_;
    return Picos(handling + double(l.latency) + wirePicos(l, bytes));
}

// The heavier node gives the slab between the boundary and `boundary` on
// `side`, with the objects that overlap it, in one message. From now on rays
// that reach it for the slab are forwarded to the neighbour (route()); the
// link is FIFO, so they arrive after the slide.
void Node::giveSlab(int side, double boundary) {
    Box own = region_->box();
    const Box slab = slabOf(side, boundary);
    if (side > 0) own.hi[bal_.axis] = boundary;
    else own.lo[bal_.axis] = boundary;
    Message m;
    m.type = MsgType::Slide;
    m.body().boundary = boundary;
    std::vector<Shape> keep;
    for (const Shape& s : region_->objects()) {
        if (overlapsBox(s, slab, margin_)) m.body().objects.push_back(s);
        if (overlapsBox(s, own, margin_)) keep.push_back(s);
    }
    stats_.slides.push_back({now_, side, boundary, m.body().objects.size()});
    const size_t face = side > 0 ? 1 : 0;
    if (trace_.position[face] >= 0) {  // the boundary's signals, if traced
        trace_.vcd->setReal(now_, trace_.position[face], boundary);
        trace_.vcd->step(now_, trace_.slides[face], 1);
    }
    stats_.objectsSent += m.body().objects.size();
    outbox_.push_back({sideDir(side), std::move(m)});
    const size_t moved = stats_.slides.back().objects;
    rebuild(own, std::move(keep));
    finishControlStep(stats_.counters, 0, moved);
}

// The lighter node takes the slab: its box grows to `boundary` on `side`, its
// objects become the union of its own and the slab's, and it acknowledges.
void Node::takeSlab(int side, double boundary, std::vector<Shape> objects) {
    Box own = region_->box();
    if (side > 0) own.hi[bal_.axis] = boundary;
    else own.lo[bal_.axis] = boundary;
    std::vector<Shape> all = region_->objects();
    std::unordered_set<uint32_t> have;
    for (const Shape& s : all) have.insert(s.id);
    stats_.objectsReceived += objects.size();
    const size_t moved = objects.size();
    for (Shape& s : objects)
        if (have.insert(s.id).second) all.push_back(std::move(s));
    ++stats_.slidesTaken;
    Message ack;
    ack.type = MsgType::Ack;
    ack.body().boundary = boundary;
    outbox_.push_back({sideDir(side), std::move(ack)});
    rebuild(own, std::move(all));
    finishControlStep(stats_.counters, 1, moved);
}

}  // namespace rt
