// One computer of the mesh: a SystemC module with one tracer process, six
// link ports (+x -x +y -y +z -z; unbound on the mesh faces) and an output
// port to each frame-buffer unit. It owns one box of space, only the objects that
// overlap it and a grid over them (sw/Region), and it knows the camera,
// lights and materials (the job's configuration), nothing else of the scene.
//
// The tracer runs one step at a time: take a ray (local work first, then the
// oldest arrived message, then a new primary ray), trace it through the box
// (sw/Region::trace), and send what comes out: a ray leaving the box to the
// neighbour it enters (Node::route), contributions to the frame-buffer unit
// that holds their pixel (pixel mod units; Node::queueContribution). A
// step's time is its operation counts times their costs, divided by the
// node's speed (Node::stepCost); see doc/machine.md.
#pragma once
#include <array>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <systemc>

#include "arrival_queue.h"
#include "balance_agent.h"
#include "camera.h"
#include "counters.h"
#include "credit.h"
#include "link.h"
#include "machine_config.h"
#include "node_trace.h"
#include "region.h"
#include "shading.h"
#include "time_keeper.h"

namespace rt {

// One boundary move, seen by the node that gave the slab.
struct SlideEvent {
    Picos t;
    int side;           // +1: the node's upper face along the axis, -1: its lower face
    double boundary;    // the face's new coordinate
    size_t objects;     // objects sent with the slab
};

struct NodeStats {
    Picos busy = 0, wait = 0;
    Counters counters;             // operations, as sw counts them
    uint64_t raysTraced = 0;       // ray segments traced in this box
    uint64_t raysGenerated = 0;    // primary rays generated here
    uint64_t raysCreated = 0;      // generated + spawned here
    uint64_t raysTerminated = 0;   // ended here (hit, blocked, or left the world / reached its light)
    uint64_t raysForwarded = 0;    // sent to a neighbour
    // Of those, sent on without a segment traced here: the box did not own
    // where the ray was when it took it (a face moved since the ray was
    // sent or held, or a neighbouring column's face along the axis is
    // elsewhere). Each costs a send, and a receive if it came over a link,
    // for no tracing.
    uint64_t raysPassed = 0;
    // Of those, rays that came from a neighbouring column (a link across
    // the axis) to a box whose faces along the axis are not where that
    // column's are.
    uint64_t raysPassedBetweenColumns = 0;
    uint64_t messagesSent = 0, messagesReceived = 0;
    uint64_t contributionsSent = 0;
    size_t queueHighWater = 0;     // local work + input messages arrived and not yet taken
    Picos lastActive = 0;          // end of the last busy step
    bool waiting = false;          // waiting for work when the frame ended
    Picos waitingSince = 0;
    // Blocked on a full output buffer (--link-out-depth): part of `wait`.
    Picos blocked = 0;
    bool blocking = false;         // blocked when the frame ended
    Picos blockedSince = 0;
    int blockedOn = -1;            // the output it was blocked on (a direction, or kDirs + unit)
    std::vector<SlideEvent> slides;        // slabs given
    uint64_t slidesTaken = 0, acks = 0;
    uint64_t objectsSent = 0, objectsReceived = 0;
    BalanceStats balance;                  // intervals, decisions and their loads' ages (dynamic policies)
};

// What every node of a machine shares: the job, the costs' context and the
// machine's settings.
struct NodeParams {
    const Shader& shader;
    const Camera& camera;
    Box world;
    int fbUnits = 1, fbBatch = 1, rayBatch = 1;
    const BalanceConfig& balance;
    int columnLength = 1;   // nodes along the balancing axis
    double minThickness;    // absolute, along the balancing axis
    Picos quantum = 0;
    IdealLayerFaces* layerFaces = nullptr;  // --faces ideal-layer (the machine's)
    // The quantum is the node's lookahead and no dynamic policy runs: the
    // node synchronises only when it must read its input beyond what it
    // sees (Node::takeWork), not after every step that takes it a lookahead
    // ahead; a traced node does not (its queue is recorded at each step).
    bool runAhead = false;
};

class Node : public sc_core::sc_module, private BalanceHost {
public:
    SC_HAS_PROCESS(Node);
    Node(sc_core::sc_module_name name, const Cell& cell, const Box& box, std::vector<Shape> objects,
         const NodeParams& params, const Costs& costs, double speed);

    sc_core::sc_vector<sc_core::sc_port<LinkSendIf, 1, sc_core::SC_ZERO_OR_MORE_BOUND>> out;
    sc_core::sc_vector<sc_core::sc_port<LinkRecvIf, 1, sc_core::SC_ZERO_OR_MORE_BOUND>> in;
    // Bound once per frame-buffer unit, in unit order (a multiport: one
    // object, not one per unit, since a big mesh has tens of thousands).
    sc_core::sc_port<LinkSendIf, 0> fb;

    // Setup by the host's job description, before the simulation starts.
    void assignPrimaries(std::vector<uint32_t> pixels, int primaryExp, const Credit& remainder);
    // Its signals in the VCD (busy, wait, queue; boundaries it moves).
    void enableTrace(const NodeTrace& t) { trace_ = t; }
    void setProgress(Progress* p) { progress_ = p; }
    // Before the start: how far it may run ahead of the kernel (its lookahead).
    void setQuantum(Picos q) { time_.setQuantum(q); }
    // What the node still holds (rays in hand or in its input links, rays
    // in partial batches, contributions, credit), for the watchdog's
    // message; empty if nothing.
    std::string holding() const;
    // `resplit` with a frame before: where the box's faces along the axis
    // go at the frame's start (NaN: that face stays); BalanceAgent::startAt.
    void setStartTargets(double lo, double hi) { startTargets_ = {lo, hi}; }
    // The frame ended at `end`: the node's busy and wait time up to then
    // (busy + wait = end). A step still running then counts as busy only up
    // to `end`; a node still waiting then waited until then. A node running
    // ahead of the kernel may have gone past `end` (steps, or idling to a
    // known arrival): its time after `end` is not the frame's.
    void endFrame(Picos end, bool complete = true);

    const Cell& cell() const { return cell_; }
    const Region& region() const { return *region_; }
    const NodeStats& stats() const { return stats_; }

private:
    struct Work {
        RayJob job;
        uint16_t creditExp;
        bool fromLink;
        bool generated;
        int8_t from;  // the link direction it arrived on (-1: made here)
        // A ray taken from a link message.
        void take(const RayItem& r, bool first, int8_t dir) {
            r.fill(job);
            creditExp = r.creditExp;
            fromLink = first;
            generated = false;
            from = dir;
        }
    };

    void run();      // the method process: one activation
    void start();    // its first
    void proceed();  // one turn of the node's loop
    // Where the process goes on when it runs next: its start, after letting
    // the kernel catch up, after waiting for input (endWait), after waiting
    // for room in an output buffer (sendOutbox, then endSend).
    enum class Resume : uint8_t { Start, Synced, Input, Room };
    void suspend(Resume r);  // the process returns; its next activation is armed
    // Takes the next ray (or control message, into `control`); false if none.
    bool takeWork(Work& w, std::optional<Message>& control, int& controlDir);
    void step(Work& w);
    // The balancing protocol (doc/balancing.md): the node's side of it. The
    // agent (balance_agent.h) runs the rounds and decides; the node measures,
    // carries the messages and hands over slabs.
    bool takeControl(std::optional<Message>& control, int& controlDir);  // control messages first
    void control(Message& m, int fromDir);
    void closeInterval();
    const Box& box() const override { return region_->box(); }
    void sendReport(int side, Message m) override;
    void giveSlab(int side, double boundary) override;
    Picos slabCost(int side, double boundary) const override;
    Picos hopTime(int side) const override;
    Picos rayWire(int side) const;  // a ray message's time on the wire
    Picos rayOccupies(int side) const override;
    Picos reportTime(int side) const override;  // 0 on the rays' FIFO: not paced
    Picos linkOccupied(int side) const override;
    Box slabOf(int side, double boundary) const;  // between the face on `side` and `boundary`
    void takeSlab(int side, double boundary, std::vector<Shape> objects);
    void rebuild(const Box& box, std::vector<Shape> objects);
    void finishControlStep(const Counters& before, uint64_t recvs, size_t movedObjects);
    // Advances the node's time by a step's cost, sends what the step made,
    // and lets the kernel catch up as the quantum asks (with a ray step that
    // leaves nothing to do, by waiting for work at once: mayWaitForWork).
    // The node may be suspended when it returns: nothing may follow it in a
    // turn that reads the input or acts on the machine.
    void chargeAndSend(Picos cost, bool mayWaitForWork = false);
    bool sendOutbox();  // false: suspended, waiting for room
    void endSend();
    void waitForWork();
    void endWait();
    bool nothingToDo() const;
    bool owesFrameBuffer() const { return pendingCount_ || !credit_.isZero(); }  // contributions or credit not yet sent
    int sideDir(int side) const { return dirOf(bal_.axis, side); }  // side -1 / +1 -> link direction
    uint64_t waitingWork() const { return ownWork() + inputOrder_.arrivedBy(now_); }
    // The link direction towards the owner of job.t0, or -1 if it is ours;
    // box: boxSlabs(job.ray, our box).
    int route(const RayJob& job, const BoxSlabs& box) const;
    void terminate(const Work& w, std::vector<RayJob>& spawned);
    void flushToFrameBuffer();
    // A contribution into the batch of its pixel's unit, which leaves as one
    // message when full.
    void queueContribution(const Contribution& c);
    void sendContributions(int unit);  // the unit's batch, now
    static int fbTarget(int unit) { return kDirs + unit; }  // outbox destination of a frame-buffer unit
    int unitOf(const Contribution& c) const { return int(c.pixel % uint32_t(pending_.size())); }
    bool flushRays();  // sends every partial ray batch; false if there was none
    void queueRay(int dir, const Work& w);
    void sendBatch(int dir);
    void recycle(RayList& rays);
    Picos stepCost(const Counters& before, uint64_t sends, uint64_t recvs, uint64_t generated) const;
    size_t queueDepth(Picos at) const;  // rays in hand and input arrived by `at`, not yet taken
    // Rays in hand: spawned here, or the rest of a batch received.
    size_t ownWork() const { return local_.size() + (received_.size() - receivedNext_); }
    void traceState(bool busy, bool waiting);  // at now_

    Cell cell_;
    std::unique_ptr<Region> region_;  // the box, its objects and their grid
    const Shader& shader_;
    const Camera& camera_;
    Box world_;
    Costs costs_;
    double speed_;
    int fbBatch_;
    const BalanceConfig& bal_;
    double margin_;        // object overlap margin, the same in every node (the world's)
    double minThickness_;  // absolute, along the progress axis
    TimeKeeper time_;      // when to let the kernel catch up
    int rayBatch_;         // rays per link message
    std::array<RayList, kDirs> outRays_;                // rays collected per direction, not yet sent
    RayList received_;                                    // the rest of the last batch received (FIFO)
    size_t receivedNext_ = 0;
    int8_t receivedFrom_ = -1;                           // the link it came on
    static constexpr size_t kSpareRayLists = 8;
    std::vector<RayList> spareRays_;                      // emptied ray lists, reused for sending

    // Balancing (dynamic policies); made when the process starts, once the
    // node knows which neighbours it has.
    std::unique_ptr<BalanceAgent> balance_;
    Progress* progress_ = nullptr;  // the watchdog's (machine.h)
    std::optional<std::array<double, 2>> startTargets_;
    int columnLength_;
    IdealLayerFaces* layerFaces_;

    std::vector<uint32_t> pixels_;
    size_t nextPixel_ = 0;
    int primaryExp_ = 0;
    Credit credit_;  // returned credit not yet sent to the frame buffer

    // Decoupled modes under a dynamic policy: the node's time, busy time and
    // end of its last step at the end of each step and idle stretch, kept
    // back to the last one the kernel has passed; endFrame reads the figures
    // at the frame's end off it. (Without a dynamic policy no step ends
    // after the frame: endFrame needs none, and keepsTimeline_ is false.)
    struct Checkpoint {
        Picos t, busy, lastActive;
    };
    bool keepsTimeline_ = false;
    void checkpoint();
    std::vector<Checkpoint> timeline_;  // from timelineStart_ on (the older ones are dropped in bulk)
    size_t timelineStart_ = 0;

    std::vector<Work> local_;                 // spawned rays, LIFO
    // What proceed takes, members rather than locals: a Work and an empty
    // optional Message on the stack were cleared (392 bytes) at every turn.
    Work work_;                               // the ray being stepped
    std::optional<Message> control_;          // or the control message being handled
    std::vector<std::vector<Contribution>> pending_;  // per frame-buffer unit: contributions not yet sent
    size_t pendingCount_ = 0;                         // in all of them
    std::vector<uint32_t> sentSince_;  // per unit: contributions sent since the last credit return
    std::vector<std::pair<int, Message>> outbox_;  // this step's sends: (direction, or fbTarget(unit); message)
    // The process between activations (run): how it goes on, and the step
    // whose outbox is being sent: the next message, the step's cost, whether
    // it may wait for work at once, and the time blocked so far.
    Resume resume_ = Resume::Start;
    bool suspended_ = false;
    bool intervalClosed_ = false;  // the last turn closed an interval whose actions are being taken
    size_t outboxNext_ = 0;
    Picos sendCost_ = 0, sendBlocked_ = 0;
    bool sendMayWait_ = false;
    Mailbox mailbox_;
    Picos now_ = 0;
    ArrivalQueue inputOrder_;
    std::array<Link*, kDirs> inLinks_{};   // in[d]'s link (null: none), set at the start
    std::array<Link*, kDirs> outLinks_{};  // out[d]'s
    std::vector<Link*> fbLinks_;           // fb's, by unit
    // Running ahead (NodeParams::runAhead): takeWork found it must see its
    // input as of now_ first. And the queue depths of the steps taken
    // beyond what the node saw, for the high-water mark once it sees them:
    // the step's time, its own work then and the messages it had taken by
    // then; with the arrivals of the messages taken since the first of them
    // (in arrival order, as the node takes them).
    bool runAhead_ = false, mustSee_ = false;
    struct DeferredDepth {
        Picos t;
        uint64_t own, taken;
    };
    std::vector<DeferredDepth> deferredDepths_;
    std::vector<Picos> takenArrivals_;
    uint64_t taken_ = 0, takenBase_ = 0;
    void deferDepth();
    void settleDepths();
    std::vector<RayJob> spawned_;              // step(): rays a step spawned
    std::vector<Contribution> contributions_;  // step(): contributions a step made
    NodeStats stats_;
    NodeTrace trace_;  // (signals -1: not traced)
};

}  // namespace rt
