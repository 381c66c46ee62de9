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

Link::Link(std::string name, const LinkParams& params)
    : name_(std::move(name)), params_(params), unusedSlots_(params.depth) {}

Picos Link::transferTime(uint32_t bytes) const {
    const double ps = std::ceil(double(bytes) * 1e12 / params_.bandwidth);
    return std::max<Picos>(1, Picos(ps));
}

void Link::send(Message m, Picos t) {
    const int type = int(m.type);
    ++stats_.messages[type];
    stats_.bytes[type] += m.bytes();
    ++inFlight_[type];
    if (backlog_.empty() && slotFree()) {
        putOnWire(t, std::move(m), takeSlot());  // the usual case: a slot is free, nothing waits before it
        return;
    }
    backlog_.push_back({t, std::move(m)});
    startWaiting();
}

Picos Link::takeSlot() {
    if (unusedSlots_ > 0) {
        --unusedSlots_;
        return 0;
    }
    const Picos slot = slotFree_.front();
    slotFree_.pop_front();
    return slot;
}

void Link::startWaiting() {
    while (!backlog_.empty() && slotFree()) {
        const Picos slot = takeSlot();
        Timed& w = backlog_.front();
        putOnWire(w.t, std::move(w.m), slot);
        backlog_.pop_front();
    }
}

void Link::putOnWire(Picos sent, Message&& m, Picos slot) {
    const Picos start = std::max({sent, slot, wireFree_});
    wireFree_ = start + transferTime(m.bytes());
    const Picos arrival = wireFree_ + params_.latency;
    // Messages sent before this one and still off the wire when it was sent.
    while (!waitedUntil_.empty() && waitedUntil_.front() <= sent) waitedUntil_.pop_front();
    if (start > sent) waitedUntil_.push_back(start);
    stats_.backlogHighWater = std::max(stats_.backlogHighWater, waitedUntil_.size());
    buffer_.push_back({arrival, std::move(m), start});
    if (listener_ && buffer_.size() == 1) listener_->headChanged(listenerPort_);
}

bool Link::peekArrival(Picos& arrival) const {
    if (buffer_.empty()) return false;
    arrival = buffer_.front().t;
    return true;
}

size_t Link::arrivedBy(Picos t) const {
    size_t n = 0;
    while (n < buffer_.size() && buffer_[n].t <= t) ++n;  // buffer_ is in arrival order
    return n;
}

Message Link::consume(Picos t) {
    if (buffer_.empty() || buffer_.front().t > t) throw std::logic_error(name_ + ": consumed before arrival");
    // Messages on the link when this one went on the wire: those before it
    // not consumed by then, and itself.
    while (!consumedAt_.empty() && consumedAt_.front() <= buffer_.front().start) consumedAt_.pop_front();
    consumedAt_.push_back(t);
    stats_.bufferHighWater = std::max(stats_.bufferHighWater, consumedAt_.size());
    Message m = std::move(buffer_.front().m);
    buffer_.pop_front();
    --inFlight_[int(m.type)];
    slotFree_.push_back(t + params_.latency);  // the credit travels back
    if (listener_ && !buffer_.empty()) listener_->headChanged(listenerPort_);
    startWaiting();
    return m;
}

}  // namespace rt
