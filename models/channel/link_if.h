// The interfaces a link offers its two ends: the sender's (LinkSendIf) and
// the receiver's (LinkRecvIf), and how a link tells its receiver that its
// oldest message changed (ArrivalListener, arrival_queue.h). The link that
// implements them: link.h.
#pragma once
#include <cstdint>

#include <systemc>

#include "channel/link_params.h"
#include "channel/message.h"

namespace rt {

class LinkSendIf : public virtual sc_core::sc_interface {
public:
    // Sends at the sender's time `t` (its local time, >= the kernel's).
    virtual void send(Message&& m, Picos t) = 0;
    virtual const LinkParams& params() const = 0;
    // When message `m` (its lane's buffer) sent at `t` or later finds room in the
    // output buffer: `t` if it has room then; a later time if that is known
    // already (a message leaves for a slot then); kRoomUnknown if it waits
    // for the receiver to consume (roomEvent() tells when that happened).
    // The sender's times must not decrease from one call to the next.
    static constexpr Picos kRoomUnknown = ~Picos(0);
    virtual Picos roomAt(const Message& m, Picos t) = 0;
    virtual const sc_core::sc_event& roomEvent() const = 0;
    // How long the link is kept busy by every message sent so far (those
    // waiting for a slot too), by the narrower of its two limits: its wire
    // (their time on it), or its slots when those are the narrower: a
    // message holds a slot from its start on the wire until the receiver's
    // credit is back (its transfer and the latency there and back, at the
    // least), so d slots carry a message every (transfer + 2 latency) / d.
    // With 2 slots and 450 us of latency a ray message of 132 bytes holds
    // the link 505 us per message at 1.2 MB/s, against 110 us on the wire.
    virtual Picos occupied() const = 0;
};

// Told by a link when its oldest unconsumed message changes: a message lands
// in an empty link, the oldest is consumed, or a control message goes ahead;
// `arrival` is the new oldest one's arrival, ~0 if none (arrival_queue.h).
class ArrivalListener {
public:
    virtual ~ArrivalListener() = default;
    virtual void headChanged(int port, Picos arrival) = 0;
    // Messages on the links it listens to (on the wire or arrived), not yet
    // consumed: counted by the links as they go on the wire and are taken.
    // A node reads it every step, and asking each link touched a link
    // object per port that was out of cache (on the 16x16x16 mesh, half of
    // Node::step's own time).
    size_t buffered = 0;
};

class LinkRecvIf : public virtual sc_core::sc_interface {
public:
    // Arrival time of the oldest unconsumed message, if any has been sent.
    virtual bool peekArrival(Picos& arrival) const = 0;
    // Takes the oldest message; it must have arrived by `t`.
    virtual Message consume(Picos t) = 0;
    // Tells `l` (as its input `port`) whenever the oldest message changes,
    // and at once what it is now.
    virtual void setListener(ArrivalListener* l, int port) = 0;
    // Messages that have arrived by `t` and are not yet consumed.
    virtual size_t arrivedBy(Picos t) const = 0;
    // Messages on the link or arrived, not yet consumed (at least arrivedBy).
    virtual size_t unconsumed() const = 0;
    // The control lane: whether its oldest message has arrived by `t`, and
    // taking it (ahead of data that arrived earlier).
    virtual bool controlArrivedBy(Picos t) const = 0;
    virtual Message consumeControl(Picos t) = 0;
    // Rays, contributions and credit sent on it and not yet consumed
    // (balancing messages not counted): for the watchdog's message.
    virtual uint64_t workInFlight() const = 0;
};

}  // namespace rt
