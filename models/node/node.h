// One computer of the mesh: a SystemC module with one tracer process, six
// link ports (+x -x +y -y +z -z; unbound on the mesh faces) and an output
// port to each frame-buffer unit. It owns one box of space, only the
// objects that overlap it and a grid over them (Region, sw/region.h), and
// it knows the camera, lights and materials (the job's configuration),
// nothing else of the scene.
//
// The process runs one step at a time: take a ray (node_input.h), trace it
// through the box (Region::trace), and send what comes out: a ray
// leaving the box to the neighbour it enters (route.h, ray_batcher.h),
// contributions to the frame-buffer unit that holds their pixel
// (fb_outbox.h). A step's time comes from cost_model.h and goes into the
// node's time ledger (time_ledger.h); the node synchronises with the
// kernel as time_keeper.h says. The balancing protocol runs in its
// BalanceAgent (balance_agent.h); the node's side of it (reports, slabs,
// link timing for the guard) is node_balance.cpp. doc/machine.md, "A node".
#pragma once
#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <systemc>

#include "balance/balance_agent.h"
#include "camera.h"
#include "node/cost_model.h"
#include "node/fb_outbox.h"
#include "channel/link.h"
#include "config/machine_config.h"
#include "node/node_input.h"
#include "node/node_stats.h"
#include "node/node_trace.h"
#include "base/frame_clock.h"
#include "base/progress.h"
#include "base/queue_marks.h"
#include "channel/ray_batcher.h"
#include "region.h"
#include "balance/sample_split.h"
#include "shading.h"
#include "process/express_relay.h"
#include "process/time_keeper.h"
#include "node/time_ledger.h"

namespace rt {

// What every node of a machine shares: the job, the balancing and the
// machine's settings (the Machine keeps it for the nodes' lifetime).
struct NodeParams {
    NodeParams(const Shader& s, const Camera& c, const BalanceConfig& b) : shader(s), camera(c), balance(b) {}
    const Shader& shader;
    const Camera& camera;
    Box world;
    int fbUnits = 1, fbBatch = 1, rayBatch = 1;
    bool spreadPrimaries = false;  // --primary-order spread (primary_queue.h)
    const BalanceConfig& balance;
    int columnLength = 1;   // nodes along the balancing axis
    double minThickness = 0;  // absolute, along the balancing axis
    Picos quantum = 0;
    IdealLayerFaces* layerFaces = nullptr;  // --faces ideal-layer (the machine's)
    ExpressRoutes* express = nullptr;  // --fidelity express (the machine's; channel/express.h)
    ExpressRelay* relay = nullptr;           // and its relay (process/express_relay.h)
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

    // The mesh links out and in: a multiport each way, bound through
    // bindOut and bindIn, which note each binding's direction (+x -x +y -y
    // +z -z; none where the mesh ends). Two objects, not an sc_vector of six
    // ports each: 32,768 nodes made 393,216 port objects, each named and
    // registered with SystemC when the machine was built and searched for
    // when it was taken down (doc/history.md, "At 32x32x32").
    // (Each held in an optional only so that releasePorts can end it.)
    std::optional<sc_core::sc_port<LinkSendIf, 0, sc_core::SC_ZERO_OR_MORE_BOUND>> out;
    std::optional<sc_core::sc_port<LinkRecvIf, 0, sc_core::SC_ZERO_OR_MORE_BOUND>> in;
    // The node keeps each link as it is bound, by direction: taking them
    // back from the ports at each frame's start, through a dynamic_cast,
    // read every link's first cache line, most of them not read again that
    // frame (doc/history.md, "At 32x32x32").
    void bindOut(int dir, Link& link) {
        out->bind(link);
        outLinks_[size_t(dir)] = &link;
    }
    void bindIn(int dir, Link& link) {
        in->bind(link);
        input_.listen(dir, link);  // (its input keeps the link, and listens to it in every frame)
    }
    void bindFrameBuffer(Link& link) {  // the next unit's
        fb->bind(link);
        fbLinks_.push_back(&link);
    }

    // Bound once per frame-buffer unit, in unit order (a multiport: one
    // object, not one per unit, since a big mesh has tens of thousands).
    std::optional<sc_core::sc_port<LinkSendIf, 0>> fb;

    // The run is over and the node is about to be deleted: its ports leave
    // SystemC now, before the nodes do (ModuleArray::clear: SystemC finds a
    // port from the back of its registry, a module from the front of its).
    void releasePorts() {
        fb.reset();
        in.reset();
        out.reset();
    }

    // Before the start: the host's job description (its primary rays, and
    // the credit it keeps of its share), its signals in the VCD, the
    // watchdog's progress, how far it may run ahead of the kernel (its
    // lookahead), and (`resplit` with a frame before) where its faces along
    // the axis go at the frame's start (NaN: that face stays).
    void assignPrimaries(const std::vector<uint32_t>& pixels, int primaryExp, const Credit& remainder) {
        input_.assignPrimaries(pixels, primaryExp, sample_ ? uint32_t(params_.camera.width()) : 0, params_.spreadPrimaries);
        fbOut_.setCredit(remainder);
    }
    void enableTrace(const NodeTrace& t) { trace_ = t; }
    void setProgress(Progress* p) { progress_ = p; }
    void setQuantum(Picos q) { time_.setQuantum(q); }
    void setStartTargets(double lo, double hi) { startTargets_ = {lo, hi}; }
    // `sample`'s first frame (balance_sample.cpp), before its primary rays:
    // the direction its column takes its planes from (-1: its own gather;
    // -2: none, it holds); the neighbouring columns it passes them to.
    // `sample`'s setup: whether the column gathers; the link directions to
    // the columns beside (none where the sum has no room for the sides);
    // for the top node, the column's inner faces as they start.
    void setSample(bool gathers, std::vector<int> beside, std::vector<double> faces);

    // What the node still holds (rays in hand or in its input links, rays
    // in partial batches, contributions, credit), for the watchdog's
    // message; empty if nothing.
    std::string holding() const;
    // The frame ended at `end` (`complete`: it was not stopped): the node's
    // figures as of then (time_ledger.h).
    void endFrame(Picos end, bool complete = true);
    // The next frame of a sequence (machine.h, MachineSession): the node as
    // built, owning `box` and the scene's objects in it (from `bins`), with
    // no figures, in a new process named after `frame`; its costs,
    // lookahead, links and progress kept. Then, as before the first frame,
    // its primary rays and the rest. A box where the last frame left it
    // keeps its region: the same objects, the same grid (a region does not
    // change as it traces), without binning and building them again.
    sc_core::sc_process_handle restart(const Box& box, const ObjectBins& bins, int frame);
    void quiet() { input_.arrivals().quiet(); }  // the frame is over: no wake still to come

    const Cell& cell() const { return cell_; }
    const Region& region() const { return *region_; }
    const NodeStats& stats() const { return stats_; }
    const CostModel& costs() const { return costs_; }

private:
    // ---- The process (node.cpp) ----
    void run();      // the method process: one activation
    void start();    // its first
    void proceed();  // one turn of the node's loop
    // Where the process goes on when it runs next: its start, after letting
    // the kernel catch up, after waiting for input (endWait), after waiting
    // for room in an output buffer (sendOutbox, then endSend).
    enum class Resume : uint8_t { Start, Synced, Input, Room };
    void suspend(Resume r);  // the process returns; its next activation is armed
    // Takes the next ray (or control message, into `control`, and its link's
    // direction into `controlDir`, which a ray leaves as it was); false if none.
    bool takeWork(Work& w, std::optional<Message>& control, int& controlDir);
    bool generatePrimary(Work& w);
    bool takeControl(std::optional<Message>& control, int& controlDir);  // control messages first
    void takeMessage(int dir, Picos arrival, Work& w, std::optional<Message>& control, int& controlDir);
    void step(Work& w);
    // A traced segment along the progress axis: the middle (where its work
    // is), its ends, and the face it left by (-1: it ended in the box).
    struct TracedSpan {
        double where = std::nan(""), from = std::nan(""), to = std::nan("");
        int exit = -1;
    };
    bool holdsPrimaries();
    int traceInBox(Work& w, const BoxSlabs& box, TracedSpan& span);  // -2: ended here; else the exit's direction
    FaceCrossings axialFaces(const Work& w, const BusyParts& parts, const TracedSpan& span) const;
    void forward(const Work& w, int dir, bool passing);
    bool sendExpress(const Work& w, int dir);  // --fidelity express: false if the neighbour takes it
    void postExpress();                        // (node_express.cpp)
    void awaitExpressPasses();                 // a node rays may skip: its step waits for the relay's passes
    void terminate(const Work& w, std::vector<RayJob>& spawned);
    void giveBack(const Work& w, int e, uint64_t k = 1);
    // `sample`'s first frame under --sample-end credit (its rays first, their credit apart).
    // (The shared flag first: the node's sample_ is a cache line of its own,
    // which most steps need not read.)
    bool sampleCredit() const { return params_.balance.sampleCredit && sample_; }
    // Whether rays travel in batches (--ray-batch above 1). Asked of the
    // shared parameters, not the batcher: with a message per ray it holds
    // none, and on a large mesh its batches are a cold line or three.
    bool batchesRays() const { return params_.rayBatch > 1; }
    // A ray of a sample pixel, or spawned by one (sample_split.h, inSample).
    bool sampleRay(const RayJob& j) const { return inSample(j.pixel, uint32_t(params_.camera.width())); }
    void markQueueDepth();
    void recordSample(const BusyParts& parts, const TracedSpan& span, int from);  // (from: the link it came in by)
    double passCost() const;
    void noteOccupied();  // occupied_, from the box and its objects
    // Advances the node's time by a step's cost, sends what the step made,
    // and lets the kernel catch up as the quantum asks (with a ray step that
    // leaves nothing to do, by waiting for work at once: mayWaitForWork).
    // The node may be suspended when it returns: nothing may follow it in a
    // turn that reads the input or acts on the machine.
    void chargeAndSend(const BusyParts& parts, bool mayWaitForWork = false);
    // A step of messages alone (flushes, balancing): sends and receives
    // handled, and the grid updated for the objects that moved in or out.
    // `balancing`: its messages are balancing's (busy_by_category), not a flush of rays or contributions.
    void finishControlStep(uint64_t recvs, size_t movedObjects, bool balancing = true);
    bool sendOutbox();  // false: suspended, waiting for room
    void endSend();
    void waitForWork();
    void endWait();
    bool nothingToDo() const;
    bool flushRays();  // sends every partial ray batch; false if there was none
    void flushToFrameBuffer();
    void traceState(bool busy, bool waiting);  // at now_
    Picos kernel() const { return frameClock(); }

    // ---- Balancing: the node's side (node_balance.cpp) ----
    void control(Message& m, int fromDir);
    void closeInterval();
    const Box& box() const override { return region_->box(); }
    void sendReport(int side, Message m) override;
    void giveSlab(int side, double boundary) override;
    Picos slabCost(int side, double boundary) const override;
    Picos hopTime(int side) const override;
    Picos rayOccupies(int side) const override;
    Picos reportTime(int side) const override;  // 0 on the rays' FIFO: not paced
    Picos linkOccupied(int side) const override;
    void sendOn(int dir, Message m) override;
    void sampleBegins() override;
    void sampleGenerated();  // a primary ray generated: the gather may start
    void takeSlab(int side, double boundary, std::vector<Shape> objects);
    void rebuild(const Box& box, std::vector<Shape> objects);
    int sideDir(int side) const { return dirOf(params_.balance.axis, side); }  // side -1 / +1 -> link direction
    const LinkParams& linkTo(int side) const { return outLinks_[size_t(sideDir(side))]->params(); }

    // The fields in the order a step reads them, the hot ones first: on a
    // large mesh a node is cold whenever it runs, and each of its cache
    // lines that a step reads is a miss (doc/history.md, "Figures behind
    // the code's comments").
    const NodeParams& params_;
    std::unique_ptr<Region> region_;  // the box, its objects and their grid
    Progress* progress_ = nullptr;  // the watchdog's (watchdog.h)
    ExpressNode* expressSelf_ = nullptr;  // its own entry, if rays may skip it (its steps keep the relay's rays waiting)
    std::unique_ptr<BalanceAgent> balance_;  // dynamic policies; made at the start

    // The process between activations (run): how it goes on, its local
    // time, and the step whose outbox is being sent: the next message, the
    // step's cost, whether it may wait for work at once, and the time
    // blocked so far.
    Resume resume_ = Resume::Start;
    bool suspended_ = false;
    bool intervalClosed_ = false;  // the last turn closed an interval whose actions are being taken
    bool sendMayWait_ = false;
    // Running ahead (NodeParams::runAhead): takeWork found it must see its
    // input as of now_ first.
    bool runAhead_ = false, mustSee_ = false;
    Picos now_ = 0;
    size_t outboxNext_ = 0;
    Picos sendCost_ = 0, sendBlocked_ = 0;
    NodeTrace trace_;  // (signals -1: not traced)
    std::array<Link*, kDirs> outLinks_{};  // the link out towards d (null: none), set when bound
    Outbox outbox_;    // this step's sends
    // This step's express rays (--fidelity express): sent with the outbox,
    // each to the express relay, which takes it past the boxes it skips.
    struct ExpressSend {
        int dir;  // the link it leaves by
        ExpressRoutes::Route route;
        Message m;
    };
    std::vector<ExpressSend> expressOut_;
    TimeKeeper time_;  // when to let the kernel catch up
    CostModel costs_;
    // What proceed and step work on, members rather than locals: as locals a
    // Work and an empty optional Message would be cleared at every turn, and
    // the scratch lists would allocate at every step.
    Work work_;
    std::vector<RayJob> spawned_;
    std::vector<Contribution> contributions_;
    Mailbox mailbox_;
    NodeInput input_;
    FrameBufferOutbox fbOut_;
    std::vector<Link*> fbLinks_;           // fb's, by unit, set when bound
    RayBatcher batcher_;
    NodeStats stats_;
    TimeLedger ledger_{stats_};
    QueueDepthMarks marks_{stats_.queueHighWater};

    // Read at the start, or with balancing, express or `sample` alone.
    Cell cell_;
    double margin_;                   // object overlap margin, the same in every node (the world's)
    std::optional<Message> control_;
    std::vector<ExpressHop> expressHops_;  // the boxes they skip (ExpressSend::route.first on)
    uint64_t expressSent_ = 0;  // express rays sent so far (their order among this node's)
    std::optional<std::array<double, 2>> startTargets_;
    struct SampleSetup {
        bool gathers = true;  // its column gathers its sample (Machine::prepareSample; else its faces hold)
        std::vector<int> beside;    // the link directions to the columns beside (none: the sum carries no sides)
        std::vector<double> faces;  // its column's inner faces as they start (what a top node proposes if it holds)
        uint64_t trigger = 0;  // the gather starts once the node has generated this many primary rays
        bool armed = false;
    };
    std::optional<SampleSetup> sample_;
    std::array<double, 2> occupied_{};  // along the axis, the part of the box its objects occupy (recordSample)
};

}  // namespace rt
