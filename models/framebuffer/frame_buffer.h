// The frame buffer: K units, pixel-interleaved (pixel p belongs to unit
// p mod K), each with an input port from every node (a Link with its own
// latency, bandwidth and depth) and a cost per contribution accumulated.
// K = 1 is the single host of the first machine; K > 1 spreads the
// accumulation, which is serial within a unit, over K units working at once
// (doc/machine.md, "The frame buffer").
//
// Unit 0 is also the host that ends the frame, in two steps:
//  1. Weight throwing (credit.h): it has handed out credit 1 and gets it back
//     from the nodes, on their ports to it, behind their contributions to it.
//     When the sum is exactly 1 every ray has ended and every contribution
//     has been sent; unit 0 has accumulated its own (each port is FIFO).
//  2. With K > 1, the credit messages also carried how many contributions
//     each node sent to each other unit; unit 0 sends each unit its total
//     (fb_expect), and the unit answers (fb_done) once it has accumulated
//     that many. The render time is when the last answer is in: the image is
//     complete, and the machine itself knows it.
#pragma once
#include <chrono>
#include <functional>
#include <optional>
#include <vector>

#include <systemc>

#include "channel/arrival_queue.h"
#include "channel/credit.h"
#include "trace/vcd_stream.h"
#include "image.h"
#include "pixel_sum.h"
#include "channel/link.h"
#include "process/time_keeper.h"

namespace rt {

struct FrameBufferStats {
    Picos busy = 0;                 // accumulating contributions
    Picos lastActive = 0;           // end of its last accumulation
    uint64_t contributions = 0, contributionMessages = 0, creditMessages = 0;
    uint64_t own = 0;               // contributions it made itself (background of missed primaries)
    uint64_t digest = 0;            // of every contribution it holds (contributionDigest): conservation
};

class FrameBufferUnit : public sc_core::sc_module {
public:
    SC_HAS_PROCESS(FrameBufferUnit);
    // pixels: the image's (the unit sums those that are its own).
    FrameBufferUnit(sc_core::sc_module_name name, int index, int units, size_t pixels, Picos costPerContribution,
                    int maxExp, bool progress, Picos quantum);

    // The links from the nodes, in node order, given before the start. Not
    // bound to a port: a multiport checks each new binding against every
    // one before it, quadratic in the nodes.
    void addNodeLink(Link& l) {
        inLinks_.push_back(&l);
        inputOrder_.listen(int(inLinks_.size() - 1), &l);
    }
    // Then (unit 0) the links from units 1..K-1, or (the others) from unit 0.
    sc_core::sc_port<LinkRecvIf, 0, sc_core::SC_ZERO_OR_MORE_BOUND> in;
    // Units 1..K-1: the port to unit 0 (unbound on unit 0).
    sc_core::sc_port<LinkSendIf, 1, sc_core::SC_ZERO_OR_MORE_BOUND> toController;
    // Unit 0: bound to units 1..K-1, in order.
    sc_core::sc_port<LinkSendIf, 0, sc_core::SC_ZERO_OR_MORE_BOUND> toUnits;

    // Unit 0, `sample` under --sample-end credit: a link to the lowest node
    // of each column, in column order, given before the start (bound to the
    // node's port below it, which has no neighbour).
    void addColumnLink(Link& l) { toColumns_.push_back(&l); }
    // Unit 0, before the first frame's start: the credit the sample's primary
    // rays carry, and which columns gather a sample. Once that much of the
    // sample's credit is back (the credit messages carry it apart), every
    // ray of the sample has ended: it tells those columns' lowest nodes, in
    // a Sample message with no values (doc/balancing.md, "When the sample
    // is done").
    void expectSample(const Credit& total, std::vector<bool> columns) {
        sampleTotal_ = total;
        sampleBack_ = total;
        sampleBack_.clear();
        tellColumns_ = std::move(columns);
        sampleDue_ = true;
    }
    // Before the start: how far it may run ahead of the kernel (its lookahead).
    void setQuantum(Picos q) { time_.setQuantum(q); }
    // Before the start, a unit other than 0, exact (lookahead) mode: it may
    // take the nodes' contributions up to `late` after they arrive (still
    // at the times they would be taken; unit 0's fb_expect at once), so
    // that one activation takes many. Exact because nothing reads a unit
    // but its own input links, whose times it computes as before: a message
    // that arrived by the kernel's time plus the lookahead is in its links
    // however late it looks, and taking it later on the kernel's clock
    // changes no simulated time (the slot it frees comes back to its sender
    // at the same time: Link::take). Not with waveforms (they are recorded
    // no earlier than the kernel's time) nor with a bounded output buffer
    // on the ports (a blocked node goes on at the kernel's time).
    void setLate(Picos late);
    // Before the start: credit unit 0 keeps (not handed to nodes), and
    // contributions the unit makes itself (primary rays that miss the world
    // box: the background of its pixels).
    void keep(const Credit& c) { credit_.add(c); }
    void addOwn(const Contribution& c) {
        accumulate(c);
        ++stats_.own;
    }

    // Its pixel p's value so far (p one of its own: p mod units = index).
    Vec3 pixel(uint32_t p) { return sums_.value(p / uint32_t(units_)); }
    const FrameBufferStats& stats() const { return stats_; }
    int index() const { return index_; }
    bool controller() const { return index_ == 0; }
    // Unit 0: the frame is done (the returned credit is exactly 1), and when.
    bool done() const { return done_; }
    // Unit 0: the share of the frame's credit returned so far (for the
    // watchdog's message).
    double creditReturned() const { return credit_.value(); }
    void dropFirstCredit() { dropCredit_ = true; }
    // Its signals in the VCD: busy accumulating, contributions so far and
    // (unit 0) the share of the frame's credit back.
    struct Trace {
        VcdStream* vcd = nullptr;
        int busy = -1, contributions = -1, credit = -1;
    };
    void enableTrace(const Trace& t) { trace_ = t; }
    // Unit 0: called in its process when the frame is done, before the
    // simulation stops (the machine ends its other processes).
    void onFinish(std::function<void()> f) { onFinish_ = std::move(f); }  // test only (MachineConfig::faultDropFirstCredit)
    Picos renderTime() const { return renderTime_; }
    // The next frame of a sequence (machine.h, MachineSession): no
    // contribution, credit or figure, as built, in a new process named after
    // `frame`; its links, lookahead and lateness kept. The machine then
    // hands it the frame's credit and background (keep, addOwn).
    sc_core::sc_process_handle restart(bool progress, int frame);
    void quiet() { inputOrder_.quiet(); }  // the frame is over: no wake still to come

private:
    void run();  // the method process: one activation
    // Takes one message; returns the time it costs.
    Picos take(Message& m);
    // Adds a contribution to its pixel's sum (checked to be its own).
    void accumulate(const Contribution& c);
    void finish(Picos now);
    // The steps of run().
    bool begin();
    bool waitFor(Picos next);
    void traceTake(Picos cost);
    bool endOfFrame();
    void tellSampleDone();
    void reportDone();
    void showProgress();

    int index_, units_;
    Picos cost_;
    bool progress_;
    TimeKeeper time_;  // when to let the kernel catch up
    int maxExp_;       // credit's precision
    Credit credit_;  // unit 0: the credit returned so far
    // Unit 0: contributions the nodes have reported sending to each unit
    // (with their credit); fb_done answers still to come once it is whole.
    std::vector<uint64_t> expected_;
    int awaiting_ = -1;  // -1: the credit is not whole yet
    // Units 1..K-1: the count unit 0 says to expect, once it has said so.
    std::optional<uint64_t> expect_;
    // Its pixels' sums (local index p / units), accumulated as contributions
    // come: the order they come in cannot change a bit (pixel_sum.h).
    PixelSums sums_;
    ArrivalQueue inputOrder_;
    // Unit 0, --sample-end credit: the sample's credit, what is back of it,
    // the links to the columns' lowest nodes and which of them to tell.
    Credit sampleTotal_, sampleBack_;
    std::vector<Link*> toColumns_;
    std::vector<bool> tellColumns_;
    bool sampleDue_ = false;
    // The nodes' links (addNodeLink), then in's in binding order (at the
    // first frame's start: unitsListened_); its input ports, in every frame.
    std::vector<Link*> inLinks_;
    bool unitsListened_ = false;
    FrameBufferStats stats_;
    bool done_ = false;
    bool dropCredit_ = false;
    std::function<void()> onFinish_;
    Picos renderTime_ = 0;
    Trace trace_;
    // The process's state between activations.
    bool started_ = false, waiting_ = false;  // waiting: for input (ArrivalQueue::waitForInput)
    Picos late_ = 0;                          // setLate (> 0: its local time may be behind the kernel's)
    Picos now_ = 0;                           // its local time
    std::chrono::steady_clock::time_point lastPrint_;
};

// The image the units hold: each pixel the sum of its contributions
// (pixel_sum.h), as rtref sums them.
Image assembleImage(sc_core::sc_vector<FrameBufferUnit>& units, int width, int height);

}  // namespace rt
