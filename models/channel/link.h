// A one-way link between two nodes (or a node and the frame buffer): a FIFO
// channel with a latency, a bandwidth and a depth.
//
// Timing: a message sent at (sender) time t starts on the wire at
//   start = max(t, wire free, a credit slot free)
// takes ceil(bytes / bandwidth) (at least 1 ps) on the wire, and arrives
// latency later. The link holds at most `depth` messages that the receiver
// has not consumed; a consumed message's slot comes back to the sender one
// latency later (credit-based flow control). Messages that find no slot wait
// in the sender's own memory (the link's backlog, its output buffer). By
// default that buffer is unbounded and a sender never blocks: back-pressure
// delays messages but cannot deadlock the machine. With an output depth
// (LinkParams::outDepth, --link-out-depth), a buffer holds at most that many
// messages per lane, and a sender that finds it full blocks until a message
// leaves it for a slot (roomAt, roomEvent; Node::sendOutbox charges the
// blocked time). Then two nodes that fill each other's links can deadlock
// (doc/machine.md, "Finite output buffers").
//
// The control lane. Load reports, slides and acks (the balancing protocol)
// travel in a second virtual channel with its own `controlDepth` slots and
// priority on the wire: a control message goes on the wire as soon as the
// message being sent when it became ready has left, ahead of every data
// message not yet started, which moves back behind it; except the data
// message the previous control message went ahead of, which goes first. So
// while both lanes have messages ready the wire alternates between them
// (round-robin arbitration, as virtual-channel hardware does): a control
// message waits for at most one data message beyond the one on the wire,
// and a stream of control messages cannot starve the rays (a link whose
// reports alone fill the wire once held a ray back for ever). The two lanes share
// the wire's bandwidth and latency. The receiver may take a control message
// ahead of data that arrived before it (Node::takeWork does). This is what
// link hardware with virtual channels does, and it keeps the balancing's
// decisions from waiting behind rays (doc/balancing.md, "The control lane").
// Order still holds where the protocol needs it: each lane is FIFO, and a
// data message sent after a control message arrives after it.
//
// Every time is computed from the others when it becomes known, never by
// polling, so the outcome does not depend on the order in which the kernel
// runs processes at one instant; it also lets senders and receivers run
// ahead of the kernel (temporal decoupling). A control message moves back
// only data messages that have not started yet, so none that a receiver
// could have taken (their arrival is more than one latency after the
// sender's time, which is the lookahead).
#pragma once
#include <algorithm>
#include <array>
#include <memory>
#include <stdexcept>
#include <string>

#include <systemc>

#include "base/fifo.h"
#include "base/frame_clock.h"
#include "channel/link_if.h"
#include "channel/link_stats.h"
#include "channel/message.h"
#include "base/numbered_ring.h"
#include "base/progress.h"
#include "trace/vcd_stream.h"

namespace rt {

// A link's signals in the VCD: the wire busy (a bit; a frame-buffer port's
// channels share one count), messages buffered (on the wire or arrived, not
// consumed) and the backlog (sent, not yet on the wire); Link::traceStart
// says when each change is recorded.
struct LinkTrace {
    VcdStream* vcd = nullptr;
    int wire = -1, buffered = -1, backlog = -1;
};

// A channel, but not an sc_object: ports bind to its interfaces, and a
// machine has tens of thousands of links (a frame-buffer port from every node
// to every unit), which SystemC's object hierarchy registers by name and
// unregisters one linear search at a time.
// (Aligned to a cache line: the fields a message sent or taken reads are
// its first two lines, where a link of 160 bytes at any multiple of 32
// spanned two or three; 192 bytes, about 25 MB more at 32x32x32.)
class alignas(64) Link final : public LinkSendIf, public LinkRecvIf {
public:
    // `smallest`: the fewest bytes a message on it may have (message.h,
    // smallestMeshMessage); its receiver's lookahead counts on it, and send
    // refuses a smaller message.
    Link(const std::string& name, const LinkParams& params, uint32_t smallest = kHeaderBytes);
    // The soonest after its sender's time that a message sent on it arrives.
    Picos lookahead() const { return linkLookahead(*params_, smallest_); }

    void send(Message&& m, Picos t) override;
    Picos roomAt(const Message& m, Picos t) override;
    const sc_core::sc_event& roomEvent() const override { return *room_; }
    // An express ray (express.h) of `bytes` sent at `t`: when it goes on
    // the wire (at `t`, or once the wire is free). It is counted among the
    // link's messages, bytes and wire time, but its slot is the express
    // relay's to keep, and the relay, not this link, takes it to the far end.
    Picos expressStart(uint32_t bytes, Picos t);
    // `count` express rays of `bytes` that went past this link's sender:
    // counted as above, timed by the express relay (express.h).
    void countExpress(uint32_t bytes, uint64_t count = 1);
    // A ray the express relay brought to this link's far end at `arrival`
    // (its wire, slot and counts the relay's: express.h), into the
    // receiver's input as if it had come on this link: --fidelity through,
    // where the node the relay would pass it through has work then.
    // Only behind the messages on the wire: not while messages wait for a
    // slot (they would be taken ahead of it).
    void deliverExpress(Message&& m, Picos arrival);
    bool mayDeliverExpress() const { return carried().lane(kData).waiting() == 0; }
    // A ray the relay passes on over this link's wire at `t` (--fidelity
    // through: its sender also sends rays of its own on it): when it goes
    // on the wire, which it then holds for its transfer.
    Picos shareWire(uint32_t bytes, Picos t) {
        const Picos start = std::max(t, wireFree_);
        wireFree_ = start + transferTime(bytes);
        return start;
    }
    bool peekArrival(Picos& arrival) const override;
    Message consume(Picos t) override;
    bool controlArrivedBy(Picos t) const override;
    Message consumeControl(Picos t) override;
    void setListener(ArrivalListener* l, int port) override {
        if (listener_) listener_->buffered -= unconsumed();
        listener_ = l;
        listenerPort_ = port;
        if (listener_) listener_->buffered += unconsumed();
        headChanged();
    }

    const LinkParams& params() const override { return *params_; }
    // Its figures; with an entry (flowInto), the entry's flow (a port's:
    // every channel's).
    LinkStats stats() const {
        foldTaken();
        LinkStats s;
        addCountsTo(s);
        if (flow_) static_cast<LinkFlow&>(s) = *flow_;
        return s;
    }
    // Adds its messages, bytes and wire time by type to `into` (its entry
    // holds the rest: flowInto).
    void addCountsTo(LinkStats& into) const {
        const Carried& c = carried();
        for (size_t t = 0; t < size_t(kMsgTypes); ++t) {
            into.messages[t] += c.byType[t].messages;
            into.bytes[t] += c.byType[t].bytes;
            into.wire[t] += c.byType[t].wire;
        }
    }
    // The frame ended at `end`: the wire time after it is taken out of the
    // figures (a node running ahead of the kernel may have sent a load
    // report that goes on the wire after the last contribution arrived;
    // the frame's figures, as its waveforms, end with the frame); messages
    // not taken by then add their waits up to it (their backlog signal). A link
    // with a control lane traces a message when it is consumed; those never
    // consumed are traced now, as a link without one traced them when sent.
    void endFrame(Picos end);
    // The next frame of a sequence (MachineSession): empty, with no
    // figures, as built; its parameters, progress and distributions kept.
    void restart();
    // The frame is over: no sender waits for room (Machine::endProcesses).
    void quiet() {
        if (room_) room_->cancel();
    }
    bool waitsForRoom() const { return bool(room_); }  // (--link-out-depth: a sender may wait for its room)
    Picos occupied() const override;
    void setProgress(Progress* p) { progress_ = p; }
    // Whether it keeps its latency distributions and high-water marks
    // (MachineConfig::linkDistributions); set before the first message.
    void keepDistributions(bool keep) { distributions_ = keep; }
    // Where its waits, latencies, high-water marks and busy windows
    // (LinkFlow) go: into the figures of `entry`, its entry in the run's
    // report (Machine), which the channels side by side of a port share (a
    // node's frame-buffer port has one per unit): the same figures as each
    // channel's merged, as the report did. The first of them to carry a
    // message makes the figures, so an entry whose wires carry nothing has
    // none. Without an entry, a link makes its own at its first message.
    // So a link that carries keeps only its lanes and its counts by type
    // (512 bytes, where it kept 1,056 and the report a copy).
    void flowInto(std::unique_ptr<LinkStats>* entry) { entry_ = entry; }
    // Whether it has carried a message since it was built or restarted.
    bool hasCarried() const { return carried_ != nullptr; }
    void setTrace(const LinkTrace& t) { trace_ = t; }
    // Whether changes it records later may be earlier than the kernel's time
    // (with a control lane: Link::traceStart).
    bool tracesLate() const { return trace_.vcd && params_->controlDepth > 0; }
    // When the oldest message not yet consumed was sent (~0 if none): no
    // change this link records later is earlier (VcdStream's horizon).
    Picos oldestSent() const {
        Picos t = ~Picos(0);
        for (int i = 0; i < carried().lanes(); ++i) {  // (a lane's buffer is older than its backlog, each in the order sent)
            const Lane& l = carried().lane(i);
            if (l.buffered()) t = std::min(t, l.head().sent);
            else if (l.waiting()) t = std::min(t, l.firstWaiting().sent);
        }
        return t;
    }
    size_t backlog() const { return carried().lane(kData).waiting() + carried().lane(kControl).waiting(); }
    // Messages of this type sent and not yet consumed.
    uint64_t inFlight(MsgType t) const { return carried().byType[size_t(t)].inFlight; }
    uint64_t workInFlight() const override {
        uint64_t n = 0;
        for (int t = 0; t < kMsgTypes; ++t)
            if (!isControl(MsgType(t))) n += carried().byType[size_t(t)].inFlight;
        return n;
    }
    size_t arrivedBy(Picos t) const override;
    size_t unconsumed() const override { return carried().lane(kData).buffered() + carried().lane(kControl).buffered(); }
    std::string name() const { return name_.get(); }

private:
    // A message's times on the link, kept apart from the message itself:
    // the times are read and written several times (sent, given a slot,
    // moved back by a control message, taken), a message is written once
    // and read once. A message waiting for a slot needs only when it was
    // sent and its size; the rest is known once it has a slot. With a
    // quantum most messages wait for a slot, and some links hold many
    // thousands at once (the output buffer of the node that generates the
    // primary rays: 126,000 on balls-4 at 512x512), which the links write
    // to memory and read back long after; so a waiting message's record is
    // 16 bytes, and the records of the few on the wire (at most a slot
    // each), which every change touches, are a queue of their own.
    struct Waiting {
        Waiting(Picos sent_, uint32_t bytes_, MsgType type_) : sent(sent_), bytes(bytes_), type(type_) {}
        Picos sent;  // when the sender sent it
        uint32_t bytes;
        MsgType type;
    };
    struct Timed {
        Timed() = default;
        Timed(const Waiting& w, Picos arrival, Picos start_, Picos ready_, Picos transfer_)
            : t(arrival), sent(w.sent), start(start_), ready(ready_), transfer(transfer_), bytes(w.bytes), type(w.type) {}
        Picos t = 0;         // its arrival; once taken (until folded: foldTaken), when it was taken
        Picos sent = 0;      // when the sender sent it
        Picos start = 0;     // when it went on the wire
        Picos ready = 0;     // when it could have (sent, and a slot free)
        Picos transfer = 0;  // its time on the wire
        uint32_t bytes = 0;
        MsgType type = MsgType::Ray;
        bool owed = false;   // a data message a control message went ahead of: it goes before the next one
    };
    // One virtual channel: its slots, its buffer and its backlog.
    //
    // Messages are numbered in the order sent, from 0. The backlog (sent,
    // waiting for a slot) is `backlog`; the messages themselves, on the wire
    // or waiting, are in `messages`, in the order sent. The receiver takes
    // them in that order, and taking message j gives its slot back one
    // latency later: message n goes on the wire with the slot of message
    // n - slots (the first `slots` with unused ones, free from time 0). So
    // at most `slots` are on the wire at once (the buffer: on the wire or
    // arrived, not taken), and a slot is free while fewer are.
    //
    // By number, without moving or dropping anything as messages go on the
    // wire and are taken: the records of those on the wire (from `taken` to
    // `wired`) in `onWire_`, and when the last ones were taken (those a
    // slot or the buffer's high-water mark may still need: at most `slots`
    // before the oldest on the wire) in `takenAt_`; message n at n mod each
    // ring's size, a power of two that grows as the window does (to at most
    // slots and 2 slots).
    //
    // Its fields in the order a message sent or taken reads them, so that
    // the lane and the counts of the message's type (Carried) are three
    // cache lines, where they were four: on a large mesh every one is cold.
    struct Lane {
        Fifo<Message> messages;
        NumberedRing<Timed> onWire_;
        NumberedRing<Picos> takenAt_;
        uint64_t taken = 0;      // messages taken so far (the oldest on the wire's number)
        uint64_t wired = 0;      // messages put on the wire so far (the next one's number)
        uint64_t markFrom = 0;   // the first message that may still count towards the buffer's high-water mark
        uint32_t slots = 0;
        // The last messages taken whose figures are not yet in the flow
        // (foldTaken): their records stay in onWire_ until then.
        uint32_t unfolded = 0;
        // Every message sent: its transfer and the latency there and back,
        // summed (the slots' round trips it owes, for occupied()).
        Picos held = 0;
        // The high-water marks of messages on the lane at once (buffer) and
        // of those waiting for the wire (backlog), as the lane has seen them
        // (its own, and the flow's at its last fold): its flow gets them at
        // the next fold.
        uint32_t bufferMark = 0, backlogMark = 0;
        Fifo<Waiting> backlog;
        // For the backlog's high-water mark: when the messages that waited
        // for the wire started.
        Fifo<Picos> waitedUntil;
        size_t buffered() const { return size_t(wired - taken); }
        size_t waiting() const { return backlog.size(); }
        Timed& onWire(size_t i) { return onWire_[taken + i]; }  // i < buffered(), oldest first
        const Timed& onWire(size_t i) const { return onWire_[taken + i]; }
        Timed& head() { return onWire(0); }  // the oldest on the wire (buffered() > 0)
        const Timed& head() const { return onWire(0); }
        const Waiting& firstWaiting() const { return backlog.front(); }  // (waiting() > 0)
        bool slotFree() const { return buffered() < slots; }
        Picos takenAt(uint64_t j) const { return takenAt_[j]; }
    };
    static constexpr int kData = 0, kControl = 1;
    // Control messages, and the sample's rays under --sample-end credit (Message::priority).
    int laneOf(const Message& m) const { return params_->controlDepth > 0 && (isControl(m.type) || m.priority) ? kControl : kData; }
    void startWaiting(int lane);  // puts backlog messages on the wire while slots allow
    Picos slotTime(const Lane& l) const;  // when the slot of the lane's next message on the wire became free (one must be)
    // Messages on a lane at once (each holding a slot) are at most its
    // slots: once the buffer's high-water mark has reached that, no message
    // can raise it, and the lane stops keeping what it needs for it (most
    // messages on the 16x16x16 mesh go on links that fill their 16 slots).
    // (A port's channels have the same slots and share the mark, the
    // largest channel's: flowInto. A channel sees the shared mark at its
    // folds, foldTaken, and until then may count marks that cannot raise
    // it: the same figure, a few messages' work later.)
    bool keepsBufferMark(const Lane& l) const { return distributions_ && l.bufferMark < l.slots; }
    void putOnWire(int lane, Picos slot, const Waiting& w);  // the lane's message w: its first waiting one (the caller then drops it), or one sent to a free slot
    void recordOnWire(Lane& l, const Timed& m);  // the lane's next message on the wire: its record
    // A message's slot and wire waits (LinkFlow::slotWait, wireWait) up to
    // `upTo`: at its take, all of them; at the frame's end, those so far.
    void countWaits(const Timed& m, Picos upTo) const;
    // A message's time on the wire [start, end) and its wait for it from
    // `ready`, in the saturation figures (LinkFlow::windows, saturated).
    void countSaturation(Picos ready, Picos start, Picos end) const;
    // The messages taken since the last fold, and the lanes' marks, into
    // the figures (LinkFlow), in the order they were taken. A take writes
    // only its own record (its take time) and leaves the rest to this: the
    // figures are another block of memory, shared by a port's channels,
    // that on a large mesh is out of cache at every message (a cache line
    // or more, and the busy windows' and the latencies' one more), so they
    // gain a batch of messages at a time, from records the lane keeps in
    // its ring of those on the wire until the ring is full (recordOnWire),
    // a control message is taken (take: the saturation's union is counted
    // in the order of the takes, across the lanes), the frame ends or the
    // figures are read. Sums, maxima and a union counted in order, so the
    // figures are the same as counted message by message.
    void foldTaken() const;
    // A control message ready at `ready`: its start on the wire, after the
    // message being sent then; the data messages not started by then move
    // back behind it.
    Picos scheduleControl(Picos ready, Picos transfer);
    Message take(int lane, Picos t);
    // A message's time on the wire (most messages on a link are of one
    // size, rays or full batches: the last size's time is kept, inline).
    Picos transferTime(uint32_t bytes) const { return bytes == lastBytes_ ? lastTransfer_ : newTransferTime(bytes); }
    Picos newTransferTime(uint32_t bytes) const;
    // The oldest unconsumed message's arrival (~0 if none), and telling the listener.
    Picos headArrival() const {
        const Lane &d = carried().lane(kData), &c = carried().lane(kControl);
        return std::min(d.buffered() ? d.head().t : ~Picos(0), c.buffered() ? c.head().t : ~Picos(0));
    }
    void headChanged() {
        if (listener_) listener_->headChanged(listenerPort_, headArrival());
    }
    void traceStart(Picos start, Picos transfer);  // (trace_ set)

    // By type, counted as messages are sent, go on the wire and are taken:
    // a type's four figures in one half cache line (stats() adds the first
    // three to the rest).
    struct alignas(32) TypeCounts {
        uint64_t messages = 0, bytes = 0;
        Picos wire = 0;
        uint64_t inFlight = 0;  // sent, not yet consumed
    };
    // What a link keeps once it has carried a message: its lanes and its
    // counts by type (512 bytes; its other figures are its entry's:
    // flowInto). Most links of a large mesh carry none in a
    // frame (every node has a port to every frame-buffer unit: 524,288 on
    // 32x32x32 with 16 units; and the express rung leaves the empty boxes'
    // links idle), so a link allocates them at its first message, and one
    // that has carried none reads as empty (kNothingCarried).
    // (The data lane, the control lane's pointer and the first type's
    // counts in the first three cache lines: Lane.)
    struct Carried {
        Lane data;
        // The control lane's, with one (LinkParams::controlDepth > 0): most
        // links have none, and it was a fifth of what every link that
        // carried kept (about 200 bytes).
        std::unique_ptr<Lane> control;
        std::array<TypeCounts, kMsgTypes> byType{};
        std::unique_ptr<LinkFlow> own;  // without an entry (flowInto)
        // With an output depth (only then made: startCarrying), for each
        // lane: when the messages that left its backlog (given a slot) leave
        // the sender's buffer, from the sender's time on. (Here, not in the
        // lane: a lane and its type's counts are three cache lines.)
        std::unique_ptr<std::array<Fifo<Picos>, 2>> leaving;
        int lanes() const { return control ? 2 : 1; }
        Lane& lane(int i) { return i == kData ? data : *control; }  // (kControl: one it has)
        const Lane& lane(int i) const { return i == kData ? data : control ? *control : kNoLane; }
    };
    static const Lane kNoLane;
    static const Carried kNothingCarried;
    const Carried& carried() const { return carried_ ? *carried_ : kNothingCarried; }
    Carried& carry() { return carried_ ? *carried_ : startCarrying(); }
    Carried& startCarrying();
    // Where its LinkFlow goes (once it carries): its entry's, or its own.
    LinkFlow& flow() { return *flow_; }
    const LinkFlow& flow() const { return *flow_; }

    // What a message sent or taken touches comes first, so that it shares
    // a few cache lines: on a large mesh a link is out of cache whenever it
    // is used (the 16x16x16 mesh has about 90,000 links).
    // (A large mesh has about 900,000 links: its fields are packed, and its
    // parameters are shared with the links that have the same, sharedParams.)
    const LinkParams* params_;
    std::unique_ptr<Carried> carried_;
    LinkFlow* flow_ = nullptr;  // once it carries: its entry's (flowInto), or without one its own
    std::unique_ptr<LinkStats>* entry_ = nullptr;  // its entry's figures, made by the first of its wires to carry
    mutable Picos lastTransfer_ = 0;   // transferTime's last message's time on the wire
    Picos owedWire_ = 0;     // every message sent: its time on the wire (occupied())
    Picos wireFree_ = 0;     // the end of the last transmission scheduled
    Picos controlFree_ = 0;  // the end of the last control transmission
    mutable Picos saturatedUntil_ = 0;  // LinkFlow::saturated counted up to here (foldTaken)
    ArrivalListener* listener_ = nullptr;
    Progress* progress_ = nullptr;  // the watchdog's (machine.h)
    mutable uint32_t lastBytes_ = 0;   // and its size
    uint32_t smallest_;
    int listenerPort_ = 0;
    bool distributions_ = true;  // keepDistributions
    LinkTrace trace_;
    std::unique_ptr<char[]> name_;  // (8 bytes where a string took 32 and its heap copy as many)
    // A message left a full output buffer's backlog: only with an output
    // depth (168 bytes, on each of the 16x16x16 mesh's 90,000 links).
    std::unique_ptr<sc_core::sc_event> room_;
};

// The link behind a port: every channel a node or a unit is bound to is a
// Link, and holding it as one (Link is final) makes the calls at every
// message direct instead of virtual, through the interfaces' thunks (what
// that bought: doc/history.md, "Figures behind the code's comments").
template <class If>
Link& asLink(If& i) {
    if (auto* l = dynamic_cast<Link*>(&i)) return *l;
    throw std::logic_error("a port bound to a channel that is not a Link");
}

}  // namespace rt
