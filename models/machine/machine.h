// The machine: an X x Y x Z mesh of nodes (sc_vector), a link per direction
// between face neighbours, the frame-buffer units (sc_vector) and a port from
// every node to every unit, and its watchdog. Built from a scene and a
// MachineConfig; a MachineSession elaborates it once and simulates its
// frames one after another (runMachine: one frame), returning each one's
// image and every statistic.
//
//   machine.cpp        building it, collecting a frame's results
//   machine_session.cpp a sequence of frames: the host phase between two, running each
//   machine_trace.cpp  its VCD: which signals, and when a change is final
//   machine_checks.cpp the conservation laws, checked at the end of a run
//   initial_split.h    where the frame starts (boxes, primary rays, credit)
//   watchdog.h         stopping a run that is stuck, too long or interrupted
#pragma once
#include <array>
#include <chrono>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <systemc>

#include "framebuffer/frame_buffer.h"
#include "balance/initial_split.h"
#include "lattice.h"
#include "machine/module_array.h"
#include "node/node.h"
#include "trace/vcd_stream.h"
#include "process/frame_processes.h"
#include "process/watchdog.h"

namespace rt {

// One link of the report: a mesh link, or a node's port to the frame buffer
// (its channels to the K units together: counts summed, high-water marks the
// largest channel's).
struct LinkReport {
    std::string name;
    Cell from;
    int dir;  // -1: the node's frame-buffer port
    LinkParams params;
    int channels = 1;  // wires merged into it: a frame-buffer port has one per unit
    // Its figures, made when one of its wires first carries (Link::flowInto):
    // most links of a large mesh carry nothing in a frame (what that saves:
    // doc/history.md, "At 32x32x32"). None reads as all zero.
    std::unique_ptr<LinkStats> figures;
    const LinkStats& stats() const { return figures ? *figures : kNoFigures; }
    LinkStats& fill() {
        if (!figures) figures = std::make_unique<LinkStats>();
        return *figures;
    }

    LinkReport(std::string name_, Cell from_, int dir_, LinkParams params_, int channels_)
        : name(std::move(name_)), from(from_), dir(dir_), params(params_), channels(channels_) {}
    LinkReport(const LinkReport& o) : name(o.name), from(o.from), dir(o.dir), params(o.params), channels(o.channels) {
        if (o.figures) figures = std::make_unique<LinkStats>(*o.figures);
    }
    LinkReport(LinkReport&&) = default;
    LinkReport& operator=(LinkReport o) {
        name = std::move(o.name);
        from = o.from;
        dir = o.dir;
        params = o.params;
        channels = o.channels;
        figures = std::move(o.figures);
        return *this;
    }
    ~LinkReport() = default;

private:
    static const LinkStats kNoFigures;
};

struct FrameBufferUnitReport {
    FrameBufferStats stats;
};

// One boundary between two nodes of a column along the progress axis.
struct BoundaryHistory {
    std::array<int, 2> column;  // the column's coordinates on the other two axes (in axis order)
    int index;                  // 1 .. N-1: between nodes index-1 and index along the axis
    std::vector<std::pair<Picos, double>> positions;  // (time, coordinate), from the start
};

// The slides a frame made: each history's moves after its first position.
inline size_t slideCount(const std::vector<BoundaryHistory>& boundaries) {
    size_t slides = 0;
    for (const BoundaryHistory& h : boundaries) slides += h.positions.size() - 1;
    return slides;
}

struct MachineResult {
    Image image;
    Picos renderTime = 0;
    Picos frameStart = 0;  // on the kernel's clock: 0, or (a later frame of a sequence) where the one before ended
    std::vector<NodeStats> nodes;  // x fastest, then y, then z
    std::vector<Cell> cells;
    std::vector<Box> boxes;
    std::vector<size_t> objectsPerNode;
    std::vector<uint64_t> objectBytesPerNode;  // their bytes on a link (objectBytes), summed
    struct Grid {
        std::array<int, 3> cells{};
        Box span;  // the part of the box it covers
    };
    std::vector<std::optional<Grid>> grids;  // per node: its grid, if it holds objects
    std::vector<LinkReport> links;
    std::vector<FrameBufferUnitReport> frameBuffer;  // per unit
    uint64_t primaryMisses = 0;   // primary rays that miss the world box (the host fills them in)
    bool express = false;         // --fidelity express: the nodes' express figures are in the report
    std::vector<BoundaryHistory> boundaries;
    Box worldBox;
    uint64_t deltaCycles = 0;
    double wallSeconds = 0;
    // Of it, building the machine until the first simulated event; and the
    // process's wall time up to that event (reading the scene included).
    double wallElaborationSeconds = 0, wallStartupSeconds = 0;
    // The VCD's GTKWave save file (trace_writer.h), if it was traced.
    std::string gtkw;
    // Empty for a run that ended; otherwise why the watchdog stopped it
    // (renderTime is then when it stopped, and every figure is up to then).
    std::string incomplete;
};

class Machine : public sc_core::sc_module {
public:
    Machine(sc_core::sc_module_name name, const Scene& scene, const MachineConfig& config);
    ~Machine() override;

    // The frame's results; `last`: no frame follows, and the report's list of
    // links is handed over rather than copied (at 32x32x32 it is about 230,000
    // entries of 720 bytes).
    MachineResult collect(double wallSeconds, bool last);
    // The first simulated event is next: the wall clock's start-up ends.
    void start_of_simulation() override;
    std::chrono::steady_clock::time_point started() const { return started_; }
    // The frame is over (ended, or stopped): every node's and link's figures as of its end.
    void endFrame();
    // Checks the conservation laws at the end of a run; throws
    // std::runtime_error naming the first one broken (machine_checks.cpp).
    void checkConservation() const;
    // Ends the VCD (if any) at the frame's end and makes its .gtkw
    // (MachineResult::gtkw).
    void closeTraces();

    size_t nodeIndex(const Cell& c) const { return rt::nodeIndex(c, cfg_.dims); }

    // The host phase between two frames of a sequence (machine_session.cpp):
    // the eye at `view`, the nodes re-boxed at `next`'s start boundaries
    // (and aimed at its targets), every node, link, unit and the watchdog as
    // built, in new processes (frame `frame`, 1-based), the primary rays and
    // credit handed out. `next` is the same machine: only its boundaries,
    // and what it traces and shows, may differ from the first frame's; and,
    // for a calibration (tb/fidelity_choice.h), the pixels traced and
    // express, if it was built with its routes (MachineConfig::expressRoutes).
    void nextFrame(const View& view, const MachineConfig& next, int frame);
    // When the frame ended (or was stopped), on its own clock.
    Picos frameEnd() const { return stopped() ? watchdog_->stalledAt() : controller().renderTime(); }

private:
    // Building (machine.cpp).
    void buildUnits();
    void buildNodes();
    void makeLayerFaces();
    void aimAtTargets();
    ColumnPlanes startTargets() const;  // where the nodes' faces go at the frame's start
    void buildLinks();
    void linkNeighbours(Node& n, std::vector<Picos>& nodeLookahead);
    void linkToFrameBuffer(Node& n, std::vector<Picos>& unitLookahead);
    void linkUnits(std::vector<Picos>& unitLookahead);
    void linkColumnsToFrameBuffer(std::vector<Picos>& nodeLookahead);
    void startWatchdog();
    void buildExpress();  // --fidelity express, through: the routes past boxes (machine_express.cpp)
    // Whether this frame's rays take them, and past which boxes (a node
    // that generates primary rays, `perNode`, has work of its own).
    void useExpress(const std::vector<std::vector<uint32_t>>& perNode);
    std::vector<bool> prepareSample(const std::vector<std::vector<uint32_t>>& perNode, const ColumnPlanes& planes);  // which columns gather
    void expectSampleCredit(const std::vector<std::vector<uint32_t>>& perNode, const CreditShares& credit,
                            const std::vector<bool>& gathers);
    void giveOutPrimaryRays(const ColumnPlanes& planes);  // the planes the nodes are to have (the targets, if any)
    // --quantum lookahead: each process runs ahead by its own, the smallest
    // of its input links' (Link::lookahead; kNoInput: it has none).
    static constexpr Picos kNoInput = ~Picos(0);
    void setLookaheads(const std::vector<Picos>& nodes, const std::vector<Picos>& units);
    std::vector<BoundaryHistory> boundaryHistories() const;
    const FrameBufferUnit& controller() const { return units_[0]; }  // unit 0 ends the frame
    // Ends every process but the caller's, from within the simulation.
    void endProcesses();
    void keepProcess(const sc_core::sc_module& m);  // m's process, as m is made (the first frame's)
    std::string whoHolds() const;
    bool stopped() const { return !watchdog_->stall().empty(); }

    // Tracing: the VCD, written as the run goes (vcd_stream.h), and the
    // links that record into it (machine_trace.cpp).
    void setupTraces();
    void traceNodes(std::vector<NodeTrace>& traces);
    void traceUnits();
    void traceBoundaries(std::vector<NodeTrace>& traces);
    Picos traceHorizon() const;
    std::unique_ptr<VcdStream> vcd_;
    std::string gtkw_;
    std::vector<const Link*> tracedLinks_;

    std::chrono::steady_clock::time_point started_;
    const Scene& scene_;
    MachineConfig cfg_;
    int width_, height_;
    Box world_;
    ColumnGeometry columns_;
    Lattice cuts_;             // the initial uniform split; along the axis, columns have their own planes
    ColumnPlanes columnPlanes_;
    double minThickness_;
    std::unique_ptr<IdealLayerFaces> layerFaces_;  // --faces ideal-layer
    Camera camera_;
    Shader shader_;
    int maxExp_;
    std::unique_ptr<NodeParams> nodeParams_;  // what the nodes share (they hold a reference)
    std::unique_ptr<ExpressRoutes> express_;   // --fidelity express (channel/express.h)
    std::unique_ptr<ExpressRelay> relay_;      // and its relay (process/express_relay.h)
    std::unique_ptr<ThroughBoxes> through_;    // --fidelity through's boxes (machine_express.cpp)
    sc_core::sc_vector<FrameBufferUnit> units_;
    ModuleArray<Node> nodes_;  // (not an sc_vector: module_array.h)
    std::vector<std::unique_ptr<Link>> links_;
    // Units 1..K-1: [2(u-1)] u -> 0, [2(u-1) + 1] 0 -> u; then (--sample-end credit) 0 -> each column's lowest node.
    std::vector<std::unique_ptr<Link>> unitLinks_;
    // The links a sender may wait on for room (--link-out-depth), which a
    // frame's end quiets: not every link, most of which have no such wait
    // (at 32x32x32, 714,000 links read, each out of cache, at every frame).
    std::vector<Link*> roomLinks_;
    std::vector<Link*> meshLinks_;  // [node * kDirs + direction]: its outgoing link (none at a mesh face)
    Link* meshLink(size_t node, int dir) const { return meshLinks_[node * kDirs + size_t(dir)]; }
    std::vector<LinkReport> linkInfo_;  // the report's links (their figures but counts by type: Link::flowInto)
    std::vector<size_t> reportOf_;      // per link in links_: its entry in linkInfo_
    uint64_t primaryMisses_ = 0;
    std::unique_ptr<Watchdog> watchdog_;
    std::unique_ptr<ObjectBins> bins_;  // the scene's objects by cell of the uniform split
    // The frame's processes (the modules' own in the first frame, then
    // spawned), in the order the modules made theirs, and the kernel's
    // delta count at its start.
    FrameProcesses spawned_;
    uint64_t deltaAtStart_ = 0;
};

// A machine that renders a sequence of frames in one elaboration, as the
// paper's machine would: frame-buffer unit 0 ends frame k, the host phase
// (next) re-boxes the nodes, and frame k + 1 starts on the kernel's clock
// where frame k ended (each frame's times count from its own start:
// base/frame_clock.h). Each session elaborates in a fresh SystemC
// simulation context (SystemC elaborates once per context), so a process
// may run any number of sessions, one after another; one at a time (a new
// session's context becomes the current one, and frameOrigin is the
// running session's).
// A simulation context of its own for what is built next, if the current
// one has been elaborated (SystemC elaborates once per context; the
// sessions and the tests' own modules call it). Not a leak: the contexts
// are kept (machine_session.cpp says why).
void freshContextIfUsed();

class MachineSession {
public:
    MachineSession(const Scene& scene, const MachineConfig& config);
    ~MachineSession();
    // Simulates the frame set up (the first, or the one next() set up),
    // checks its conservation laws, ends its VCD (and .gtkw) if it is
    // traced; its result. `another`: next() will follow (without it the
    // session is over, and next() refuses).
    MachineResult run(bool another = false);
    // The host phase after a frame (Machine::nextFrame), at its end.
    void next(const View& view, const MachineConfig& config);
    int frame() const { return frame_; }  // 1-based

private:
    std::chrono::steady_clock::time_point built_;  // the frame's set-up began (elaboration, or the host phase)
    std::unique_ptr<Machine> machine_;
    int frame_ = 1;
    bool over_ = false;  // the last frame has run
};

// One frame: a session of one.
MachineResult runMachine(const Scene& scene, const MachineConfig& config);

}  // namespace rt
