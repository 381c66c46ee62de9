// The machine: an X x Y x Z mesh of nodes (sc_vector), a link per direction
// between face neighbours, the frame-buffer units (sc_vector) and a port from
// every node to every unit. Built from a scene and a MachineConfig;
// runMachine() elaborates, simulates one frame and returns the image and
// every statistic.
#pragma once
#include <csignal>
#include <chrono>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <systemc>

#include "frame_buffer.h"
#include "lattice.h"
#include "node.h"
#include "vcd_stream.h"

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
    LinkStats stats;
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

struct MachineResult {
    Image image;
    Picos renderTime = 0;
    std::vector<NodeStats> nodes;  // x fastest, then y, then z
    std::vector<Cell> cells;
    std::vector<Box> boxes;
    std::vector<size_t> objectsPerNode;
    std::vector<LinkReport> links;
    std::vector<FrameBufferUnitReport> frameBuffer;  // per unit
    uint64_t primaryMisses = 0;   // primary rays that miss the world box (the host fills them in)
    std::vector<BoundaryHistory> boundaries;
    Box worldBox;
    uint64_t deltaCycles = 0;
    double wallSeconds = 0;
    // Empty for a run that ended; otherwise why the watchdog stopped it
    // (renderTime is then when it stopped, and every figure is up to then).
    std::string incomplete;
};

class Machine : public sc_core::sc_module {
public:
    SC_HAS_PROCESS(Machine);
    Machine(sc_core::sc_module_name name, const Scene& scene, const MachineConfig& config);
    ~Machine() override;

    MachineResult collect(double wallSeconds);
    void endFrame() {
        for (Node& n : nodes_) n.endFrame(frameEnd(), stall_.empty());
        for (auto& l : links_) l->endFrame(frameEnd());
    }
    // Checks the conservation laws at the end of a run; throws
    // std::runtime_error naming the first one broken.
    void checkConservation() const;
    // Ends the VCD (if any) at the frame's end and writes its .gtkw.
    void closeTraces();

    size_t nodeIndex(const Cell& c) const { return (size_t(c[2]) * cfg_.dims[1] + c[1]) * cfg_.dims[0] + c[0]; }

private:
    void assignPrimaryRays();
    // Initial boundaries along the progress axis of each column: uniform, or
    // at the object medians (the static baseline policy).
    std::vector<std::vector<double>> initialBoundaries(const ObjectBins& bins) const;
    int columnOf(const Cell& c) const;
    std::vector<BoundaryHistory> boundaryHistories() const;
    const FrameBufferUnit& controller() const { return units_[0]; }  // unit 0 ends the frame

    // Tracing: the VCD, written as the run goes (vcd_stream.h), and the
    // links that record into it.
    void setupTraces();
    Picos traceHorizon() const;
    std::unique_ptr<VcdStream> vcd_;
    std::vector<const Link*> tracedLinks_;

    const Scene& scene_;
    MachineConfig cfg_;
    int width_, height_;
    Box world_;
    Lattice cuts_;      // the initial uniform split; along the axis, columns have their own boundaries
    std::vector<std::vector<double>> columnBounds_;
    double minThickness_;
    std::unique_ptr<IdealLayerFaces> layerFaces_;  // --faces ideal-layer
    Camera camera_;
    Shader shader_;
    int maxExp_;
    std::unique_ptr<NodeParams> nodeParams_;  // what the nodes share (they hold a reference)
    sc_core::sc_vector<FrameBufferUnit> units_;
    sc_core::sc_vector<Node> nodes_;
    std::vector<std::unique_ptr<Link>> links_;
    std::vector<std::unique_ptr<Link>> unitLinks_;  // units 1..K-1: [2(u-1)] u -> 0, [2(u-1) + 1] 0 -> u
    std::map<std::pair<size_t, int>, Link*> meshLinks_;  // (node, direction) -> its outgoing link
    // --quantum lookahead: each process runs ahead by its own, the smallest
    // of its input links' (Link::lookahead; kNoInput: it has none).
    static constexpr Picos kNoInput = ~Picos(0);
    void setLookaheads(const std::vector<Picos>& nodes, const std::vector<Picos>& units);
    std::vector<LinkReport> linkInfo_;  // the report's links
    std::vector<size_t> reportOf_;      // per link in links_: its entry in linkInfo_
    uint64_t primaryMisses_ = 0;

    // The watchdog (MachineConfig::watchdogSpan): progress marked by the
    // nodes and links, and why and when it stopped the run (empty: it did not).
    // A method process, like the nodes: the machine has no thread process.
    void watch();
    Picos watchSpan_ = 0, watchPeriod_ = 0;  // (period 0: not started)
    std::chrono::steady_clock::time_point watchStart_;
    std::string whoHolds() const;
    void endProcesses();
    // When the frame ended, or when the watchdog stopped it.
    Picos frameEnd() const { return stall_.empty() ? controller().renderTime() : stalledAt_; }
    Progress progress_;
    std::string stall_;
    Picos stalledAt_ = 0;
};

// A signal (SIGINT, SIGTERM) asks the running machine to stop: the watchdog
// sees it at its next wake and stops the run as it would a stuck one, with
// the report and VCD so far ("interrupted by signal N"). Set from a signal
// handler (tb/rtsim.cpp), hence a plain global.
extern volatile std::sig_atomic_t stopSignal;

// Elaborates the machine, runs one frame, checks conservation, writes the
// VCD (and .gtkw) if configured. Call once per process (SystemC elaborates
// once).
MachineResult runMachine(const Scene& scene, const MachineConfig& config);

}  // namespace rt
