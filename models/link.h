// A one-way link between two nodes (or a node and the frame buffer): a FIFO
// channel with a latency, a bandwidth and a depth.
//
// Timing: a message sent at (sender) time t starts on the wire at
//   start = max(t, wire free, a credit slot free)
// takes ceil(bytes / bandwidth) (at least 1 ps) on the wire, and arrives
// latency later. The link holds at most `depth` messages that the receiver
// has not consumed; a consumed message's slot comes back to the sender one
// latency later (credit-based flow control). Messages that find no slot wait
// in the sender's own memory (the link's backlog), so a sender never blocks:
// back-pressure delays messages but cannot deadlock the machine.
//
// Every time is computed from the others when it becomes known, never by
// polling, so the outcome does not depend on the order in which the kernel
// runs processes at one instant; it also lets senders and receivers run
// ahead of the kernel (temporal decoupling).
#pragma once
#include <algorithm>
#include <array>
#include <string>

#include <systemc>

#include "fifo.h"
#include "machine_config.h"
#include "message.h"

namespace rt {

struct LinkStats {
    std::array<uint64_t, kMsgTypes> messages{}, bytes{};
    // High-water marks in simulated time (so the same in every exact mode,
    // whatever order the kernel runs the processes in):
    size_t backlogHighWater = 0;  // messages sent and not yet on the wire, at once
    size_t bufferHighWater = 0;   // messages on the wire or arrived and not consumed, at once
};

// Adds one channel's figures to a port's: counts summed, high-water marks the
// larger of the two (each channel has its own slots).
inline void mergeChannel(LinkStats& into, const LinkStats& s) {
    for (size_t t = 0; t < s.messages.size(); ++t) {
        into.messages[t] += s.messages[t];
        into.bytes[t] += s.bytes[t];
    }
    into.backlogHighWater = std::max(into.backlogHighWater, s.backlogHighWater);
    into.bufferHighWater = std::max(into.bufferHighWater, s.bufferHighWater);
}

class LinkSendIf : public virtual sc_core::sc_interface {
public:
    // Sends at the sender's time `t` (its local time, >= the kernel's).
    virtual void send(Message m, Picos t) = 0;
};

// Told by a link when its oldest unconsumed message changes: a message lands
// in an empty link, or the oldest is consumed (arrival_queue.h).
class ArrivalListener {
public:
    virtual ~ArrivalListener() = default;
    virtual void headChanged(int port) = 0;
};

class LinkRecvIf : public virtual sc_core::sc_interface {
public:
    // Arrival time of the oldest unconsumed message, if any has been sent.
    virtual bool peekArrival(Picos& arrival) const = 0;
    // Takes the oldest message; it must have arrived by `t`.
    virtual Message consume(Picos t) = 0;
    // Tells `l` (as its input `port`) whenever the oldest message changes.
    virtual void setListener(ArrivalListener* l, int port) = 0;
    // Messages that have arrived by `t` and are not yet consumed.
    virtual size_t arrivedBy(Picos t) const = 0;
    // Messages on the link or arrived, not yet consumed (at least arrivedBy).
    virtual size_t unconsumed() const = 0;
};

// A channel, but not an sc_object: ports bind to its interfaces, and a
// machine has tens of thousands of links (a frame-buffer port from every node
// to every unit), which SystemC's object hierarchy registers by name and
// unregisters one linear search at a time.
class Link : public LinkSendIf, public LinkRecvIf {
public:
    Link(std::string name, const LinkParams& params);

    void send(Message m, Picos t) override;
    bool peekArrival(Picos& arrival) const override;
    Message consume(Picos t) override;
    void setListener(ArrivalListener* l, int port) override {
        listener_ = l;
        listenerPort_ = port;
    }

    const LinkParams& params() const { return params_; }
    const LinkStats& stats() const { return stats_; }
    size_t backlog() const { return backlog_.size(); }
    // Messages of this type sent and not yet consumed.
    uint64_t inFlight(MsgType t) const { return inFlight_[int(t)]; }
    size_t arrivedBy(Picos t) const override;
    size_t unconsumed() const override { return buffer_.size(); }
    const std::string& name() const { return name_; }

private:
    void startWaiting();  // puts backlog messages on the wire while slots allow
    bool slotFree() const { return unusedSlots_ > 0 || !slotFree_.empty(); }
    Picos takeSlot();     // a free slot (one must be), and when it became free
    void putOnWire(Picos sent, Message&& m, Picos slot);
    Picos transferTime(uint32_t bytes) const;

    std::string name_;
    LinkParams params_;
    struct Timed {
        Picos t;
        Message m;
        Picos start = 0;  // in buffer_: when it went on the wire
    };
    Fifo<Timed> backlog_;     // sent, waiting for a slot (t: when sent)
    Fifo<Timed> buffer_;      // on the wire or arrived, not consumed (t: arrival)
    int unusedSlots_;            // slots never used yet (free since time 0)
    Fifo<Picos> slotFree_;      // slots returned by the receiver, free from these times
    Picos wireFree_ = 0;
    // For the high-water marks: when the messages that waited for the wire
    // started, and when the last messages were consumed (both in FIFO order,
    // so both sorted).
    Fifo<Picos> waitedUntil_, consumedAt_;
    ArrivalListener* listener_ = nullptr;
    int listenerPort_ = 0;
    LinkStats stats_;
    std::array<uint64_t, kMsgTypes> inFlight_{};
};

}  // namespace rt
