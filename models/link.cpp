#include "link.h"

#include <cmath>
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
    }
    return "?";
}

uint32_t objectBytes(const Shape& s) {
    const uint32_t head = 4 + 4 + 1;  // id, material, kind
    if (std::holds_alternative<Sphere>(s.geometry)) return head + 4 * 8 + 1;
    if (const auto* p = std::get_if<Polygon>(&s.geometry)) return head + 4 + uint32_t(p->vertices.size()) * 3 * 8;
    return head + 8 * 8 + 1;  // cone: two centres, two radii, inside flag
}

Link::Link(std::string name, const LinkParams& params, uint32_t smallest)
    : name_(std::move(name)), params_(params), smallest_(smallest) {
    lanes_[kData].unusedSlots = params.depth;
    lanes_[kControl].unusedSlots = params.controlDepth;
    if (params.outDepth > 0) room_ = std::make_unique<sc_core::sc_event>();
}

// (Most messages on a link are of one size: rays, or full batches.)
Picos Link::transferTime(uint32_t bytes) const {
    if (bytes != lastBytes_) {
        lastBytes_ = bytes;
        lastTransfer_ = wireTime(bytes, params_.bandwidth);
    }
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
    // The receiver runs ahead by its lookahead, which counts on no message
    // arriving sooner than the smallest one would.
    if (m.bytes() < smallest_)
        throw std::logic_error(name_ + ": a " + msgTypeName(m.type) + " message of " + std::to_string(m.bytes()) +
                               " bytes, smaller than the " + std::to_string(smallest_) + " its receiver's lookahead counts on");
    if (trace_.vcd && params_.controlDepth == 0) trace_.vcd->step(t, trace_.backlog, 1);
    ++stats_.messages[type];
    stats_.bytes[type] += m.bytes();
    ++inFlight_[type];
    {  // what the link owes for it (occupied())
        const Picos transfer = transferTime(m.bytes());
        owedWire_ += transfer;
        lanes_[laneOf(m.type)].held += transfer + 2 * params_.latency;
    }
    if (progress_ && !isControl(m.type)) progress_->mark(t);  // work moves; load reports alone are no progress
    const int lane = laneOf(m.type);
    Lane& l = lanes_[lane];
    if (l.backlog.empty() && l.slotFree_()) {
        putOnWire(lane, t, std::move(m), takeSlot(l));  // the usual case: a slot is free, nothing waits before it
        return;
    }
    l.backlog.emplace_back(t, std::move(m));
    startWaiting(lane);
}

Picos Link::takeSlot(Lane& l) {
    if (l.unusedSlots > 0) {
        --l.unusedSlots;
        return 0;
    }
    const Picos slot = l.slotFree.front();
    l.slotFree.pop_front();
    return slot;
}

void Link::startWaiting(int lane) {
    Lane& l = lanes_[lane];
    while (!l.backlog.empty() && l.slotFree_()) {
        const Picos slot = takeSlot(l);
        Timed& w = l.backlog.front();
        if (params_.outDepth > 0) {  // a sender blocked on the full buffer has room from then
            const Picos room = std::max(w.t, slot), k = sc_core::sc_time_stamp().value();
            room_->notify(sc_core::sc_time::from_value(room > k ? room - k : 0));
        }
        putOnWire(lane, w.t, std::move(w.m), slot);
        l.backlog.pop_front();
    }
}

Picos Link::roomAt(MsgType type, Picos t) {
    if (params_.outDepth <= 0) return t;
    Lane& l = lanes_[laneOf(type)];
    while (!l.leaving.empty() && l.leaving.front() <= t) l.leaving.pop_front();
    // Held at `t`: the backlog, and those that leave it later than `t`
    // (in the order they leave: slots come back in order).
    const size_t held = l.backlog.size() + l.leaving.size(), cap = size_t(params_.outDepth);
    if (held < cap) return t;
    const size_t mustLeave = held - cap + 1;
    return l.leaving.size() >= mustLeave ? l.leaving[mustLeave - 1] : kRoomUnknown;
}

void Link::putOnWire(int lane, Picos sent, Message&& m, Picos slot) {
    Lane& l = lanes_[lane];
    const Picos transfer = transferTime(m.bytes());
    const Picos ready = std::max(sent, slot);
    // Until its slot is free it is in the sender's output buffer. (With a
    // quantum the slot may be known before the message is sent, when the
    // receiver runs ahead: it waits all the same, without a backlog.)
    if (params_.outDepth > 0 && ready > sent) l.leaving.push_back(ready);
    Picos start;
    if (lane == kData) {
        start = std::max(ready, wireFree_);
        wireFree_ = start + transfer;
    } else {
        start = scheduleControl(ready, transfer);
    }
    const Picos arrival = start + transfer + params_.latency;
    // Messages sent before this one and still off the wire when it was sent.
    while (!l.waitedUntil.empty() && l.waitedUntil.front() <= sent) l.waitedUntil.pop_front();
    if (start > sent) l.waitedUntil.push_back(start);
    stats_.backlogHighWater = std::max(stats_.backlogHighWater, l.waitedUntil.size());
    stats_.wire[size_t(m.type)] += transfer;
    if (trace_.vcd && params_.controlDepth == 0) traceStart(start, transfer);
    l.buffer.emplace_back(arrival, std::move(m), sent, start, ready, transfer);
    if (l.buffer.size() == 1) headChanged();
}

Picos Link::occupied() const {
    Picos slots = lanes_[kData].held / Picos(params_.depth);
    if (params_.controlDepth > 0) slots = std::max(slots, lanes_[kControl].held / Picos(params_.controlDepth));
    return std::max(owedWire_, slots);
}

void Link::endFrame(Picos end) {
    const bool late = tracesLate();  // a lane's messages are traced when consumed: these never were
    for (const Lane& l : lanes_) {
        for (size_t i = 0; i < l.buffer.size(); ++i) {
            const Timed& m = l.buffer[i];
            const Picos done = m.start + m.transfer;
            if (done > end) stats_.wire[size_t(m.m.type)] -= done - std::max(m.start, end);
            if (late) {
                trace_.vcd->step(m.sent, trace_.backlog, 1);
                traceStart(m.start, m.transfer);
            }
        }
        if (late)
            for (size_t i = 0; i < l.backlog.size(); ++i) trace_.vcd->step(l.backlog[i].t, trace_.backlog, 1);
    }
}

Picos Link::scheduleControl(Picos ready, Picos transfer) {
    Fifo<Timed>& data = lanes_[kData].buffer;  // in the order they go on the wire
    size_t first = 0;                          // the first data message not started by `ready`
    while (first < data.size() && data[first].start < ready) ++first;
    if (first < data.size() && data[first].owed) ++first;  // its turn: it goes first (round-robin)
    Picos start = std::max(ready, controlFree_);
    if (first > 0) start = std::max(start, data[first - 1].start + data[first - 1].transfer);  // on the wire then
    controlFree_ = start + transfer;
    Picos end = controlFree_;
    if (first < data.size() && data[first].ready < end) data[first].owed = true;  // it waits for this one
    for (size_t i = first; i < data.size(); ++i) {
        Timed& d = data[i];
        d.start = std::max(d.ready, end);
        end = d.start + d.transfer;
        d.t = end + params_.latency;
    }
    wireFree_ = std::max(wireFree_, end);
    if (first == 0 && !data.empty()) headChanged();  // the data head moved
    return start;
}

bool Link::peekArrival(Picos& arrival) const {
    arrival = headArrival();
    return arrival != ~Picos(0);
}

size_t Link::arrivedBy(Picos t) const {
    size_t n = 0;
    for (const Lane& l : lanes_)
        for (size_t i = 0; i < l.buffer.size() && l.buffer[i].t <= t; ++i) ++n;  // buffers are in arrival order
    return n;
}

bool Link::controlArrivedBy(Picos t) const {
    const Fifo<Timed>& c = lanes_[kControl].buffer;
    return !c.empty() && c.front().t <= t;
}

Message Link::consumeControl(Picos t) { return take(kControl, t); }

Message Link::consume(Picos t) {
    const Fifo<Timed>&d = lanes_[kData].buffer, &c = lanes_[kControl].buffer;
    const bool control = !c.empty() && (d.empty() || c.front().t <= d.front().t);  // ties to control
    return take(control ? kControl : kData, t);
}

Message Link::take(int lane, Picos t) {
    Lane& l = lanes_[lane];
    if (l.buffer.empty() || l.buffer.front().t > t) throw std::logic_error(name_ + ": consumed before arrival");
    // Messages on the lane when this one went on the wire: those before it
    // not consumed by then, and itself.
    while (!l.consumedAt.empty() && l.consumedAt.front() <= l.buffer.front().start) l.consumedAt.pop_front();
    l.consumedAt.push_back(t);
    stats_.bufferHighWater = std::max(stats_.bufferHighWater, l.consumedAt.size());
    const Timed& head = l.buffer.front();
    stats_.slotWait += head.ready - head.sent;
    stats_.wireWait += head.start - head.ready;
    ++stats_.consumed;
    (isControl(head.m.type) ? stats_.controlLatency : stats_.latency).add(t - head.sent);
    if (trace_.vcd) {
        VcdStream& v = *trace_.vcd;
        if (params_.controlDepth > 0) {  // (its start may have moved: recorded now, when final)
            v.step(head.sent, trace_.backlog, 1);
            traceStart(head.start, head.transfer);
        }
        v.step(t, trace_.buffered, -1);
    }
    Message m = std::move(l.buffer.front().m);
    l.buffer.pop_front();
    --inFlight_[int(m.type)];
    l.slotFree.push_back(t + params_.latency);  // the credit travels back
    headChanged();
    startWaiting(lane);
    return m;
}

}  // namespace rt
