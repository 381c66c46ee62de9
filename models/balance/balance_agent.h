// The balancing protocol of one node (doc/balancing.md): intervals, rounds
// of load reports with each column neighbour, the policy's decision, the
// guard, and the ages of the loads decisions used. The node drives it (at
// the end of each interval, on each report) and does what it asks through
// BalanceHost: send a report, give a slab.
//
// Rounds. With each neighbour a node runs in lockstep: it sends its report
// for round r only once it has decided round r - 1, and decides round r
// once it has both reports of r. A report covers the node's intervals closed
// since its last report to that neighbour, so when reports take longer than
// an interval to cross, rounds span several intervals instead of queueing
// up behind each other: a decision always uses the newest loads.
//
// Pacing. Reports to a neighbour go at most once per period: reportTime /
// reportShare (a report's time on the wire over the share of the link's time
// that reports may take) rounded up to whole intervals, on multiples of it
// that both ends of the link count alike, so their reports leave together.
// On a slow link reports on the control lane then do not crowd out the
// rays: at 10 MB/s a 52-byte report takes 5.2 us on the wire, a quarter of a
// 20 us interval, and with the lane's priority reports every interval
// would lengthen the frame (doc/balancing.md, "The control lane"). A round then
// spans more intervals; its loads are no older for it. (On the rays' FIFO
// the host reports no wire time: reports wait their turn, unpaced.)
//
// The guard (every policy): no slide
//  - on loads older than maxAge intervals (slow or saturated links);
//  - when a ray's hop to the neighbour (latency and wire time) takes longer
//    than its mean step: a thinner box adds a hop to the rays that cross
//    it, and when hops dominate, the frame is set by the rays' paths, not
//    by the nodes' work (measured: doc/balancing.md, "The guard");
//  - (--guard-wire U, 1 by default) across a link that would be busy more
//    than U of an interval after the slide: its share of the last interval
//    plus a ray message for each ray step the slab's work took, each by the
//    link's narrower limit, its wire or its slots (LinkSendIf::occupied).
//    On a full link the rays a slide sends across it queue, and the frame
//    is set by the link, not by the nodes' work (measured:
//    doc/balancing.md, "A busy-link guard");
//  - that costs more (handling, grid updates, the slab's time on the link)
//    than the work it moves off the giver over the next `horizon` intervals
//    (a load already even, a frame about to end: little work left).
#pragma once
#include <array>
#include <cmath>
#include <map>
#include <memory>
#include <vector>

#include "box.h"
#include "base/histogram.h"
#include "balance/ideal_layer_faces.h"
#include "config/machine_config.h"
#include "channel/message.h"
#include "balance/policy.h"
#include "balance/sample_split.h"
#include "balance/work_by_position.h"

namespace rt {

// Busy and wait time of one balancing interval, ending at `end`.
struct IntervalRecord {
    Picos end, busy, wait;
};

// A traced ray segment's span along the axis, and its crossings of the
// node's faces along the axis (in from a column neighbour, out to one) with
// what handling them cost the node.
struct FaceCrossings {
    double from = std::nan(""), to = std::nan("");
    int crossings = 0;
    Picos cost = 0;
    int lateral = -1;  // the direction it left by to another column (-1: none)
    // Its intersection tests' cost if it neither entered nor left by a face
    // along the axis (a ray running across the axis inside the box): in a
    // box whose grid has one cell along the axis such a ray tests every
    // object across the box, so these tests grow with the box's thickness
    // twice over, in the rays and in the objects each tests.
    Picos within = 0;
};

struct BalanceStats {
    // Busy and wait per interval, for the report. Bounded: once a node has
    // kMaxIntervalRecords, neighbouring records are merged pairwise and each
    // record from then on spans twice as many intervals, so memory and the
    // report stay bounded however fine the interval (a 60-node run at a
    // 0.52 us interval once wrote a 419 MB report).
    static constexpr size_t kMaxIntervalRecords = 1024;
    std::vector<IntervalRecord> intervals;
    uint64_t intervalsPerRecord = 1;
    // Per decision: the age of the older of its two loads, in 1/kAgeUnits of an interval.
    static constexpr double kAgeUnits = 1024;
    Histogram ages;
    uint64_t decisions = 0, gives = 0, skippedStale = 0, skippedLatency = 0, skippedCost = 0, skippedBusyLink = 0;
    // The frame's tracing work by where it happened along the axis (each
    // traced step's cost at the middle of its segment, less its handling of
    // rays across the faces along the axis, which `faceCost` holds for
    // `faceCrossings` crossings).
    WorkByPosition work;
    WorkByPosition within;  // of it, FaceCrossings::within
    Picos faceCost = 0;
    uint64_t faceCrossings = 0;
    // The traced segments by span, of rays going up the axis and down it:
    // +1 where one starts, -1 where it stops (the running sum is how many a
    // plane there would cut).
    std::array<WorkByPosition, 2> spans;
    // Rays sent to the neighbouring columns, by where they left, per link
    // direction (those along the axis stay empty).
    std::array<WorkByPosition, 6> lateral;
};

class BalanceHost {
public:
    virtual ~BalanceHost() = default;
    virtual const Box& box() const = 0;
    // Sends a report to the column neighbour on `side` (-1 lower, +1 upper) and charges it.
    virtual void sendReport(int side, Message m) = 0;
    // Gives the slab between the face on `side` and `boundary`, with its objects.
    virtual void giveSlab(int side, double boundary) = 0;
    // What giving that slab would cost: handling and grid updates on both
    // nodes and its time on the link.
    virtual Picos slabCost(int side, double boundary) const = 0;
    // How long one ray takes to reach that neighbour: the link's latency and
    // a ray message's time on the wire.
    virtual Picos hopTime(int side) const = 0;
    // How long one ray message keeps the link to that neighbour busy, by
    // the narrower of its wire and its slots (LinkSendIf::occupied).
    virtual Picos rayOccupies(int side) const = 0;
    // A load report's time on the wire to that neighbour (its bytes at the
    // link's bandwidth); 0 when reports to it are not paced.
    virtual Picos reportTime(int side) const = 0;
    // How long every message sent so far to that neighbour keeps the link
    // busy, including what waits to go (LinkSendIf::occupied).
    virtual Picos linkOccupied(int side) const = 0;
    // Sends a balancing message on the link in direction `dir` (`sample`'s
    // planes to a neighbouring column) and charges it.
    virtual void sendOn(int dir, Message m) = 0;
    // `sample` begins (the sample's primary rays first); the host calls
    // sampleReady once its part of the sample is in.
    virtual void sampleBegins() = 0;
};

class BalanceAgent {
public:
    // `index` of `count`: the node's place along its column; `lower`/`upper`:
    // whether it has a neighbour there.
    BalanceAgent(const BalanceConfig& cfg, BalanceHost& host, const Box& world, int index, int count, bool lower,
                 bool upper, double minThickness);

    bool due(Picos now) const { return now >= next_; }
    Picos nextClose() const { return next_; }
    // A ray step: its cost, where along the axis its work happened, and
    // its part in the faces along the axis (for `resplit`'s next planes).
    void recordStep(double where, Picos cost, const FaceCrossings& faces = {});
    // The interval ends at `now`: the node's busy and wait totals, and the
    // rays and primaries waiting in it.
    void closeInterval(Picos now, Picos busyTotal, Picos waitTotal, uint64_t waiting);
    // A neighbour's report arrived (at the node's time `now`).
    void onReport(int side, const Message& m, Picos now);

    // What closeInterval, onReport and startAt make due (reports to send,
    // rounds to decide, slabs to give) is done one host call at a time: the
    // node calls act() while pending(), and between two calls lets the
    // kernel catch up as after any step it takes (the node is a method
    // process: it cannot wait in the middle of an action). Each side's
    // actions run in lockstep order, the lower side's first.
    bool pending() const { return startLo_ || startHi_ || advancing_[0] || advancing_[1] || gather_.due(); }
    void act();

    const BalanceStats& stats() const { return stats_; }
    // At the frame's end: the stats with the intervals not yet making up a
    // whole record (after merging) as one last, shorter record.
    BalanceStats finalStats() const;

    // `resplit` with a frame before: at the frame's start, move the box's
    // faces to `lo` and `hi` (NaN: that face stays), each face by the node
    // that owns the slab between it and its target, and then hold them for
    // the frame: no reports, no decisions. Both nodes of a face know its
    // target, so exactly one of them gives.
    void startAt(double lo, double hi);
    // A neighbour's slab was taken: with startAt's targets, the box may now
    // reach one that lay beyond it (a plane that moves across several boxes
    // moves in a chain of slides, each node passing on what it took).
    void tookSlab();

    // `sample`'s first frame (balance_sample.cpp; sample_split.h): the node
    // holds its faces and records the work of the sample's rays by where it
    // happened; once its own part of the sample is in (sampleReady) and the
    // column's sum from below has come (onSample), it passes the sum on up;
    // the top node splits the column's sum (splitBySample), tells the top
    // nodes of the columns beside (`besideDirs`, the link directions to
    // them) the planes it proposes, and once it has theirs sends its planes
    // down (onPlanes), none where the move would not pay by then against
    // the planes beside (samplePays: every face holds); every node passes
    // them on and moves its faces to them as startAt does, once, and then
    // holds. Without `gathers` (a column none of whose nodes generates
    // primary rays, under --sample-end generated) the faces hold, and its
    // top node proposes them as they stand (`faces`, the column's inner
    // faces).
    void startSample(bool gathers, const std::vector<int>& besideDirs, std::vector<double> faces);
    bool sampling() const { return gather_.on && !gather_.passed; }
    void recordSample(double where, Picos work);
    // A sample ray across the column's side, to or from a column beside, at
    // `where` along the axis: `passCost` if it were passed on.
    void recordSide(double where, double passCost);
    // With --sample-links on: a sample ray's segment along the axis from
    // `a` to `b` (a <= b), `pastTop` if it crosses the box's upper face.
    void recordCrossing(double a, double b, bool pastTop);
    void sampleReady(Picos now);
    void onSample(const Message& m, Picos now);
    // Planes: from above, the column's; from a column beside (to a top
    // node), its proposal, then whether it moves (decideSample).
    void onPlanes(int fromDir, const Message& m, Picos now);

    // --faces ideal-layer: the layer's faces, summed and decided without
    // messages (ideal_layer_faces.h); this node adds its loads to them and
    // moves its faces to their planes instead of asking its policy.
    void shareFaces(IdealLayerFaces* faces) { layerFaces_ = faces; }

private:
    struct Span {  // since the last report to one side
        Picos busy = 0, wait = 0, stepCost = 0, end = 0;
        uint64_t steps = 0;
        WorkProfile profile;
    };
    struct Side {
        bool present = false;
        Span span;
        bool fresh = false;           // an interval closed since the last report
        Picos nextReport = 0;         // not before (pacing)
        int reported = -1, decided = -1;
        LoadSample sent;              // this round's sample, as reported
        WorkProfile sentProfile;      // and the work behind it
        Picos sentMeanStep = 0;       // and its mean cost per ray step
        uint64_t sentSteps = 0;       // and its ray steps
        Picos sentLength = 0;         // and its length in time
        std::map<int, LoadSample> got;  // the neighbour's, by round
        double neighbourSum = 0;      // the newest column sum from that side
        Picos wireMark = 0;           // the link's busy time (linkOccupied) when the last interval began
        double wireUse = 0;           // what it grew by since, over the time since (an interval, or more)
    };
    void advance(int i, Picos now);  // marks side i's lockstep to be advanced (act)
    bool advanceStep(int i);         // one step of it; false if nothing is due
    void giveToStartTarget();        // the next face startAt moves (act)
    void report(int i);
    void decide(int i, Picos now);
    std::optional<double> towardsLayerFace(const SlideQuery& q, const LoadSample& theirs) const;
    static int sideOf(int i) { return i ? +1 : -1; }

    const BalanceConfig& cfg_;
    BalanceHost& host_;
    std::unique_ptr<BalancePolicy> policy_;
    IdealLayerFaces* layerFaces_ = nullptr;
    int index_, count_;
    double minThickness_;
    Picos next_;
    Picos busyMark_ = 0, waitMark_ = 0, lastEnd_ = 0;
    Picos traced_ = 0;  // time tracing in the box since the last interval closed
    uint64_t waiting_ = 0;
    std::array<Side, 2> sides_;  // [0]: lower neighbour, [1]: upper
    bool hold_ = false;          // the boundaries stay for the frame (startAt)
    // Due for act(): the faces startAt moves, and the sides whose lockstep
    // advances, from the time of the report or interval that made them due.
    bool startLo_ = false, startHi_ = false;
    double startTo_[2] = {std::nan(""), std::nan("")};  // (NaN: no target, as before the planes come)
    std::array<bool, 2> advancing_{};
    std::array<Picos, 2> advanceAt_{};
    void recordInterval(const IntervalRecord& r);
    // `sample`'s gather (balance_sample.cpp).
    struct Gather {
        bool on = false;  // the column gathers its own planes
        bool ready = false, below = false, passed = false, adopted = false;
        double lo = 0, hi = 1;      // the box along the axis while it samples
        std::vector<double> own;    // the sample's work here, in kSampleBins bins over [lo, hi]
        std::vector<double> side;   // its rays across the sides (recordSide), likewise
        std::vector<double> cross;  // with --sample-links on: its segments' starts and ends (recordCrossing), and one past the top
        ColumnSample sum;           // the column's, from its lowest node through this one
        std::vector<double> planes;
        double movePs = 0;  // (the top node) how long moving the faces to `planes` takes (sampleMovePs)
        // The top node: the columns beside (link directions), what it
        // proposes to them and whether it says it moves, and theirs as they
        // come (decideSample).
        struct Beside {
            std::vector<double> proposal, faces;
            bool verdict = false;
            int heard = 0;  // 1: its proposal, 2: and its verdict
        };
        std::vector<int> besideDirs;
        std::vector<Beside> beside;
        std::vector<double> proposal, faces;  // (its faces as they stand, sent with the proposal)
        bool paysAlone = false, verdict = false;
        int round = 0;  // 1: proposed, 2: said whether it moves
        bool up = false, down = false, adopt = false;  // due: the sum up, the planes down, the faces to them
        size_t propose = 0, tell = 0;  // due: the proposal, the verdict to this many more columns beside
        bool due() const { return up || down || adopt || propose > 0 || tell > 0; }
    };
    void gatherStep();      // one action of the gather (act)
    void passSum(Picos now);  // ready and the sum from below in: up, or (the top) split
    void decideSample(Picos now);  // (the top) its proposal made and those beside in: the planes down
    void takePlanes(std::vector<double> planes);
    Gather gather_;
    BalanceStats stats_;
    IntervalRecord pending_{0, 0, 0};  // intervals closed since the last record
    uint64_t pendingCount_ = 0;
};

}  // namespace rt
