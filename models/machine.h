// The machine: an X x Y x Z mesh of nodes (sc_vector), a link per direction
// between face neighbours, an output port per node to the frame buffer /
// host. Built from a scene and a MachineConfig; runMachine() elaborates,
// simulates one frame and returns the image and every statistic.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include <systemc>

#include "host.h"
#include "lattice.h"
#include "node.h"

namespace rt {

struct LinkReport {
    std::string name;
    Cell from;
    int dir;  // -1: the node's frame-buffer port
    LinkParams params;
    LinkStats stats;
};

struct MachineResult {
    Image image;
    Picos renderTime = 0;
    std::vector<NodeStats> nodes;  // x fastest, then y, then z
    std::vector<Cell> cells;
    std::vector<Box> boxes;
    std::vector<size_t> objectsPerNode;
    std::vector<LinkReport> links;
    HostStats host;
    uint64_t primaryMisses = 0;   // primary rays that miss the world box (the host fills them in)
    uint64_t deltaCycles = 0;
    double wallSeconds = 0;
};

class Machine : public sc_core::sc_module {
public:
    Machine(sc_core::sc_module_name name, const Scene& scene, const MachineConfig& config);
    ~Machine() override;

    MachineResult collect(double wallSeconds);
    // Checks the conservation laws at the end of a run; throws
    // std::runtime_error naming the first one broken.
    void checkConservation() const;
    void writeTraces(const std::string& vcdPath) const;

    size_t nodeIndex(const Cell& c) const { return (size_t(c[2]) * cfg_.dims[1] + c[1]) * cfg_.dims[0] + c[0]; }

private:
    void assignPrimaryRays();

    const Scene& scene_;
    MachineConfig cfg_;
    int width_, height_;
    Box world_;
    Lattice cuts_;
    Camera camera_;
    Shader shader_;
    int maxExp_;
    std::unique_ptr<Host> host_;
    sc_core::sc_vector<Node> nodes_;
    std::vector<std::unique_ptr<Link>> links_;
    std::vector<LinkReport> linkInfo_;
    uint64_t primaryMisses_ = 0;
};

// Elaborates the machine, runs one frame, checks conservation, writes the
// VCD (and .gtkw) if configured. Call once per process (SystemC elaborates
// once).
MachineResult runMachine(const Scene& scene, const MachineConfig& config);

}  // namespace rt
