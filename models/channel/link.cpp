#include "channel/link.h"

#include <cmath>
#include <mutex>
#include <set>
#include <stdexcept>

namespace rt {

const char* msgTypeName(MsgType t) {
    switch (t) {
        case MsgType::Ray: return "ray";
        case MsgType::Contributions: return "contributions";
        case MsgType::Credit: return "credit";
        case MsgType::LoadReport: return "load_report";
        case MsgType::Slide: return "slide";
        case MsgType::Ack: return "ack";
        case MsgType::FbExpect: return "fb_expect";
        case MsgType::FbDone: return "fb_done";
        case MsgType::Sample: return "sample";
        case MsgType::Planes: return "planes";
    }
    return "?";
}

uint32_t objectBytes(const Shape& s) {
    const uint32_t head = 4 + 4 + 1;  // id, material, kind
    if (std::holds_alternative<Sphere>(s.geometry)) return head + 4 * 8 + 1;
    if (const auto* p = std::get_if<Polygon>(&s.geometry)) return head + 4 + uint32_t(p->vertices.size()) * 3 * 8;
    return head + 8 * 8 + 1;  // cone: two centres, two radii, inside flag
}

Link::Link(const std::string& name, const LinkParams& params, uint32_t smallest)
    : params_(&sharedParams(params)), smallest_(smallest), name_(new char[name.size() + 1]) {
    std::copy(name.c_str(), name.c_str() + name.size() + 1, name_.get());
    if (params.outDepth > 0) room_ = std::make_unique<sc_core::sc_event>();
}

const LinkParams& sharedParams(const LinkParams& p) {
    static std::mutex lock;
    static std::set<LinkParams> all;  // (a set's elements stay where they are)
    const std::lock_guard<std::mutex> hold(lock);
    return *all.insert(p).first;
}

const Link::Carried Link::kNothingCarried{};
const Link::Lane Link::kNoLane{};

Link::Carried& Link::startCarrying() {
    carried_ = std::make_unique<Carried>();
    if (entry_) {  // its entry's figures (flowInto), made by the first wire to carry
        if (!*entry_) *entry_ = std::make_unique<LinkStats>();
        flow_ = entry_->get();
    } else {  // no entry: its own
        carried_->own = std::make_unique<LinkFlow>();
        flow_ = carried_->own.get();
    }
    carried_->data.slots = uint32_t(params_->depth);
    if (params_->controlDepth > 0) {
        carried_->control = std::make_unique<Lane>();
        carried_->control->slots = uint32_t(params_->controlDepth);
    }
    if (params_->outDepth > 0)
        carried_->leaving = std::make_unique<std::array<Fifo<Picos>, 2>>();
    return *carried_;
}

void Link::restart() {
    lastBytes_ = 0;
    lastTransfer_ = 0;
    owedWire_ = wireFree_ = controlFree_ = saturatedUntil_ = 0;
    // (Its listener stays: the receiver's queue restarts with no heads, as
    // this link restarts empty.)
    trace_ = {};
    flow_ = nullptr;  // (its entry's owner empties it, Machine::nextFrame; the next frame's first message finds it)
    carried_.reset();
    quiet();
}

Picos Link::newTransferTime(uint32_t bytes) const {
    // (A message of a size the configuration did not bound: a slab of many
    // objects at a low bandwidth; machine_config.h checks the rest.)
    if (!(wirePicos(*params_, bytes) <= double(kMaxTimeValue)))
        throw std::runtime_error(name() + ": a message of " + std::to_string(bytes) + " bytes would take more than 1,000 s on the wire at " +
                                 formatRate(params_->bandwidth) + " (--link-bandwidth, --link-set)");
    lastBytes_ = bytes;
    lastTransfer_ = wireTime(*params_, bytes);
    return lastTransfer_;
}

// A message's changes on the link's signals, each recorded at a time no
// earlier than the kernel's (VcdStream's horizon): sent (by the sender, at
// its time), on the wire (when its slot is free: at or after the receiver
// consumed the message before it), consumed (by the receiver, at its time).
// With a control lane a data message's start may still move when a control
// message goes ahead: then all but its consumption are recorded when it is
// consumed (and the horizon waits for the link's oldest message).
void Link::traceStart(Picos start, Picos transfer) {
    VcdStream& v = *trace_.vcd;
    v.step(start, trace_.backlog, -1);
    v.step(start, trace_.wire, 1);
    v.step(start + transfer, trace_.wire, -1);
    v.step(start, trace_.buffered, 1);
}

void Link::send(Message&& m, Picos t) {
    const int type = int(m.type);
    const uint32_t bytes = m.bytes();
    // The receiver runs ahead by its lookahead, which counts on no message
    // arriving sooner than the smallest one would.
    if (bytes < smallest_)
        throw std::logic_error(name() + ": a " + msgTypeName(m.type) + " message of " + std::to_string(bytes) +
                               " bytes, smaller than the " + std::to_string(smallest_) + " its receiver's lookahead counts on");
    if (trace_.vcd && params_->controlDepth == 0) trace_.vcd->step(t, trace_.backlog, 1);
    Carried& c = carry();
    TypeCounts& counts = c.byType[size_t(type)];
    ++counts.messages;
    counts.bytes += bytes;
    ++counts.inFlight;
    const int lane = laneOf(m);
    Lane& l = c.lane(lane);
    {  // what the link owes for it (occupied())
        const Picos transfer = transferTime(bytes);
        owedWire_ += transfer;
        l.held += transfer + 2 * params_->latency;
    }
    if (progress_ && !isControl(m.type)) progress_->mark(t);  // work moves; load reports alone are no progress
    const Waiting w(t, bytes, m.type);
    l.messages.emplace_back(std::move(m));
    if (l.waiting() == 0 && l.slotFree()) {
        // The usual case: a slot is free and nothing waits before it: on
        // the wire without a record in the backlog (a cache line fewer a
        // message where every link's state is cold: doc/benchmarks/misses.md).
        putOnWire(lane, slotTime(l), w);
        return;
    }
    l.backlog.push_back(w);
    startWaiting(lane);
}

void Link::countExpress(uint32_t bytes, uint64_t count) {
    const Picos transfer = transferTime(bytes);
    TypeCounts& counts = carry().byType[size_t(MsgType::Ray)];
    counts.messages += count;
    counts.bytes += count * bytes;
    counts.wire += count * transfer;
    owedWire_ += count * transfer;
}

Picos Link::expressStart(uint32_t bytes, Picos t) {
    countExpress(bytes);
    const Picos start = std::max(t, wireFree_);
    wireFree_ = start + transferTime(bytes);
    if (progress_) progress_->mark(t);
    return start;
}

void Link::deliverExpress(Message&& m, Picos arrival) {
    Carried& c = carry();
    Lane& l = c.lane(kData);
    if (l.waiting() > 0) throw std::logic_error(name() + ": an express ray delivered behind messages waiting for a slot");
    const uint32_t bytes = m.bytes();
    const Picos transfer = transferTime(bytes), start = arrival - transfer - params_->latency;
    ++c.byType[size_t(m.type)].inFlight;
    if (progress_) progress_->mark(arrival);
    l.messages.emplace_back(std::move(m));
    recordOnWire(l, Timed(Waiting(start, bytes, MsgType::Ray), arrival, start, start, transfer));
}

Picos Link::slotTime(const Lane& l) const {
    if (l.wired < l.slots) return 0;  // a slot not used yet
    return l.takenAt(l.wired - l.slots) + params_->latency;  // the credit travelled back
}

void Link::startWaiting(int lane) {
    Lane& l = carried_->lane(lane);
    while (l.waiting() > 0 && l.slotFree()) {
        const Picos slot = slotTime(l);
        if (params_->outDepth > 0) {  // a sender blocked on the full buffer has room from then
            const Picos room = std::max(l.firstWaiting().sent, slot), k = frameClock();
            room_->notify(sc_core::sc_time::from_value(room > k ? room - k : 0));
        }
        putOnWire(lane, slot, l.firstWaiting());
        l.backlog.pop_front();
    }
}

Picos Link::roomAt(const Message& m, Picos t) {
    if (params_->outDepth <= 0 || !carried_) return t;
    const int lane = laneOf(m);
    const Lane& l = carried_->lane(lane);
    Fifo<Picos>& leaving = (*carried_->leaving)[size_t(lane)];
    while (!leaving.empty() && leaving.front() <= t) leaving.pop_front();
    // Held at `t`: the backlog, and those that leave it later than `t`
    // (in the order they leave: slots come back in order).
    const size_t held = l.waiting() + leaving.size(), cap = size_t(params_->outDepth);
    if (held < cap) return t;
    const size_t mustLeave = held - cap + 1;
    return leaving.size() >= mustLeave ? leaving[mustLeave - 1] : kRoomUnknown;
}

void Link::putOnWire(int lane, Picos slot, const Waiting& w) {
    Carried& c = *carried_;
    Lane& l = c.lane(lane);
    const Picos sent = w.sent;
    const Picos transfer = transferTime(w.bytes);
    const Picos ready = std::max(sent, slot);
    // Until its slot is free it is in the sender's output buffer. (With a
    // quantum the slot may be known before the message is sent, when the
    // receiver runs ahead: it waits all the same, without a backlog.)
    if (params_->outDepth > 0 && ready > sent) (*c.leaving)[size_t(lane)].push_back(ready);
    Picos start;
    if (lane == kData) {
        start = std::max(ready, wireFree_);
        wireFree_ = start + transfer;
    } else {
        start = scheduleControl(ready, transfer);
    }
    const Picos arrival = start + transfer + params_->latency;
    checkSimTime(arrival, [this] { return name_.get(); });  // (a backlog of long messages can pass the counter)
    // Messages sent before this one and still off the wire when it was sent.
    if (distributions_) {
        while (!l.waitedUntil.empty() && l.waitedUntil.front() <= sent) l.waitedUntil.pop_front();
        if (start > sent) l.waitedUntil.push_back(start);
        l.backlogMark = std::max(l.backlogMark, uint32_t(l.waitedUntil.size()));  // (foldTaken)
    }
    c.byType[size_t(w.type)].wire += transfer;
    if (trace_.vcd && params_->controlDepth == 0) traceStart(start, transfer);
    recordOnWire(l, Timed(w, arrival, start, ready, transfer));
}

void Link::recordOnWire(Lane& l, const Timed& m) {
    // The ring keeps the records of the messages taken and not yet folded
    // as well: folded now rather than the ring grown for them.
    if (l.unfolded > 0 && l.wired + 1 - (l.taken - l.unfolded) > l.onWire_.mask + 1) foldTaken();
    l.onWire_.fit(l.taken - l.unfolded, l.wired);
    l.onWire_[l.wired] = m;
    ++l.wired;
    if (listener_) ++listener_->buffered;
    if (l.buffered() == 1) headChanged();
}

Picos Link::occupied() const {
    const Carried& c = carried();
    Picos slots = c.lane(kData).held / Picos(params_->depth);
    if (params_->controlDepth > 0) slots = std::max(slots, c.lane(kControl).held / Picos(params_->controlDepth));
    return std::max(owedWire_, slots);
}

void Link::endFrame(Picos end) {
    if (!carried_) return;
    foldTaken();  // (those taken first, as counted at their takes)
    Carried& c = *carried_;
    const bool late = tracesLate();  // a lane's messages are traced when consumed: these never were
    for (int k = 0; k < c.lanes(); ++k) {
        const Lane& l = c.lane(k);
        for (size_t i = 0; i < l.buffered(); ++i) {
            const Timed& m = l.onWire(i);
            const Picos done = m.start + m.transfer;
            if (done > end) c.byType[size_t(m.type)].wire -= done - std::max(m.start, end);
            if (m.ready < end) countSaturation(m.ready, std::min(m.start, end), std::min(done, end));
            if (m.sent < end) countWaits(m, end);  // up to the end, as its backlog signal shows them
            if (late) {
                trace_.vcd->step(m.sent, trace_.backlog, 1);
                traceStart(m.start, m.transfer);
            }
        }
        for (size_t i = 0; i < l.waiting(); ++i) {
            if (l.backlog[i].sent < end) flow().slotWait += end - l.backlog[i].sent;  // still waiting for a slot
            if (late) trace_.vcd->step(l.backlog[i].sent, trace_.backlog, 1);
        }
    }
}

void Link::countWaits(const Timed& m, Picos upTo) const {
    LinkFlow& f = *flow_;
    f.slotWait += std::min(m.ready, upTo) - m.sent;
    f.wireWait += std::min(m.start, upTo) - std::min(m.ready, upTo);
}

// (Messages are counted in the order they are consumed, in which their wire
// waits end in order on each lane: the union is counted as it grows. A
// control message overtaking data ones may end its wait before the last
// counted: its overlap is not counted twice.)
void Link::countSaturation(Picos ready, Picos start, Picos end) const {
    LinkFlow& f = *flow_;
    if (distributions_) f.windows.add(start, end);  // (--link-stats full)
    const Picos from = std::max(ready, saturatedUntil_);
    if (start > from) f.saturated += start - from;
    saturatedUntil_ = std::max(saturatedUntil_, start);
}

void Link::foldTaken() const {
    if (!carried_) return;
    Carried& c = *carried_;
    LinkFlow& f = *flow_;
    for (int k = 0; k < c.lanes(); ++k) {  // (the data lane first: a control message is folded as it is taken)
        Lane& l = c.lane(k);
        for (uint64_t j = l.taken - l.unfolded; j < l.taken; ++j) {
            const Timed& m = l.onWire_[j];  // (m.t: its take)
            countWaits(m, m.t);  // (taken after its arrival: its whole waits)
            countSaturation(m.ready, m.start, m.start + m.transfer);
            if (distributions_) (isControl(m.type) ? f.controlLatency : f.latency).add(m.t - m.sent);
        }
        f.consumed += l.unfolded;
        l.unfolded = 0;
        f.bufferHighWater = std::max(f.bufferHighWater, size_t(l.bufferMark));
        l.bufferMark = uint32_t(std::min(f.bufferHighWater, size_t(l.slots)));  // (the mark is at most the slots)
        f.backlogHighWater = std::max(f.backlogHighWater, size_t(l.backlogMark));
    }
}

Picos Link::scheduleControl(Picos ready, Picos transfer) {
    Lane& data = carried_->data;  // on the wire in the order they went on it
    const size_t onWire = data.buffered();
    size_t first = 0;  // the first data message not started by `ready`
    while (first < onWire && data.onWire(first).start < ready) ++first;
    if (first < onWire && data.onWire(first).owed) ++first;  // its turn: it goes first (round-robin)
    Picos start = std::max(ready, controlFree_);
    if (first > 0) start = std::max(start, data.onWire(first - 1).start + data.onWire(first - 1).transfer);  // on the wire then
    controlFree_ = start + transfer;
    Picos end = controlFree_;
    if (first < onWire && data.onWire(first).ready < end) data.onWire(first).owed = true;  // it waits for this one
    for (size_t i = first; i < onWire; ++i) {
        Timed& d = data.onWire(i);
        d.start = std::max(d.ready, end);
        end = d.start + d.transfer;
        d.t = end + params_->latency;
    }
    wireFree_ = std::max(wireFree_, end);
    if (first == 0 && onWire > 0) headChanged();  // the data head moved
    return start;
}

bool Link::peekArrival(Picos& arrival) const {
    arrival = headArrival();
    return arrival != ~Picos(0);
}

size_t Link::arrivedBy(Picos t) const {
    size_t n = 0;
    for (int k = 0; k < carried().lanes(); ++k) {
        const Lane& l = carried().lane(k);
        for (size_t i = 0; i < l.buffered() && l.onWire(i).t <= t; ++i) ++n;  // buffers are in arrival order
    }
    return n;
}

bool Link::controlArrivedBy(Picos t) const {
    const Lane& c = carried().lane(kControl);
    return c.buffered() && c.head().t <= t;
}

Message Link::consumeControl(Picos t) { return take(kControl, t); }

Message Link::consume(Picos t) {
    const Lane &d = carried().lane(kData), &c = carried().lane(kControl);
    const bool control = c.buffered() && (!d.buffered() || c.head().t <= d.head().t);  // ties to control
    return take(control ? kControl : kData, t);
}

Message Link::take(int lane, Picos t) {
    if (!carried_) throw std::logic_error(name() + ": consumed before arrival");
    Carried& c = *carried_;
    Lane& l = c.lane(lane);
    if (!l.buffered() || l.head().t > t) throw std::logic_error(name() + ": consumed before arrival");
    const uint64_t j = l.taken;  // its number
    Timed& head = l.head();
    // Messages on the lane when it went on the wire: those before it taken
    // after that (take times do not decrease), and itself. They held a slot
    // each then, so they are the last `slots` at most (its own slot came
    // back after message j - slots was taken).
    if (keepsBufferMark(l)) {
        if (j + 1 > l.slots) l.markFrom = std::max(l.markFrom, j + 1 - l.slots);
        while (l.markFrom < j && l.takenAt(l.markFrom) <= head.start) ++l.markFrom;
        l.bufferMark = std::max(l.bufferMark, uint32_t(j - l.markFrom + 1));  // (foldTaken)
    }
    // Its take time, beside those the next slots need (message n's slot is
    // message n - slots's) and those the mark may still read (from markFrom,
    // which the mark's count above keeps at most `slots` back).
    uint64_t from = l.wired >= l.slots ? l.wired - l.slots : 0;
    if (keepsBufferMark(l)) from = std::min(from, l.markFrom);
    l.takenAt_.fit(std::min(from, j), j);
    l.takenAt_[j] = t;
    head.t = t;  // (its figures: foldTaken)
    if (trace_.vcd) {
        VcdStream& v = *trace_.vcd;
        if (params_->controlDepth > 0) {  // (its start may have moved: recorded now, when final)
            v.step(head.sent, trace_.backlog, 1);
            traceStart(head.start, head.transfer);
        }
        v.step(t, trace_.buffered, -1);
    }
    Message m = std::move(l.messages.front());
    l.messages.pop_front();
    ++l.taken;
    ++l.unfolded;
    if (lane == kControl) foldTaken();  // (the union of the wire waits in the order of the takes)
    if (!l.messages.empty()) {  // the next one, written long ago by the sender: on its way to the cache
        const char* next = reinterpret_cast<const char*>(&l.messages.front());
        for (size_t b = 0; b < sizeof(Message); b += 64) __builtin_prefetch(next + b);
    }
    if (listener_) --listener_->buffered;
    --c.byType[size_t(m.type)].inFlight;
    headChanged();
    startWaiting(lane);
    return m;
}

}  // namespace rt
