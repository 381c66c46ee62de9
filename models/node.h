// One computer of the mesh: a SystemC module with one tracer process, six
// link ports (+x -x +y -y +z -z; unbound on the mesh faces) and an output
// port to the frame buffer. It owns one box of space, only the objects that
// overlap it and a grid over them (sw/Region), and it knows the camera,
// lights and materials (the job's configuration), nothing else of the scene.
//
// The tracer runs one step at a time: take a ray (local work first, then the
// oldest arrived message, then a new primary ray), trace it through the box
// (sw/Region::trace), and send what comes out: a ray leaving the box to the
// neighbour it enters (Node::route), contributions to the frame buffer. A
// step's time is its operation counts times their costs, divided by the
// node's speed (Node::stepCost); see doc/machine.md.
#pragma once
#include <memory>
#include <optional>
#include <vector>

#include <systemc>

#include "camera.h"
#include "counters.h"
#include "credit.h"
#include "link.h"
#include "machine_config.h"
#include "node_trace.h"
#include "region.h"
#include "shading.h"

namespace rt {

struct NodeStats {
    Picos busy = 0, wait = 0;
    Counters counters;             // operations, as sw counts them
    uint64_t raysTraced = 0;       // ray segments traced in this box
    uint64_t raysGenerated = 0;    // primary rays generated here
    uint64_t raysCreated = 0;      // generated + spawned here
    uint64_t raysTerminated = 0;   // ended here (hit, blocked, or left the world / reached its light)
    uint64_t raysForwarded = 0;    // sent to a neighbour
    uint64_t messagesSent = 0, messagesReceived = 0;
    uint64_t contributionsSent = 0;
    size_t queueHighWater = 0;     // local work + unconsumed input messages
    Picos lastActive = 0;          // end of the last busy step
};

class Node : public sc_core::sc_module {
public:
    SC_HAS_PROCESS(Node);
    Node(sc_core::sc_module_name name, const Cell& cell, const Box& box, const Scene& scene, const Shader& shader,
         const Camera& camera, const Box& world, const Costs& costs, double speed, int fbBatch);

    sc_core::sc_vector<sc_core::sc_port<LinkSendIf, 1, sc_core::SC_ZERO_OR_MORE_BOUND>> out;
    sc_core::sc_vector<sc_core::sc_port<LinkRecvIf, 1, sc_core::SC_ZERO_OR_MORE_BOUND>> in;
    sc_core::sc_port<LinkSendIf> fb;

    // Setup by the host's job description, before the simulation starts.
    void assignPrimaries(std::vector<uint32_t> pixels, int primaryExp, const Credit& remainder);
    void enableTrace() { trace_ = std::make_unique<NodeTrace>(); }

    const Cell& cell() const { return cell_; }
    const Region& region() const { return region_; }
    const NodeStats& stats() const { return stats_; }
    const NodeTrace* trace() const { return trace_.get(); }

private:
    struct Work {
        RayJob job;
        uint16_t creditExp;
        bool fromLink;
        bool generated;
    };

    void run();
    bool takeWork(Work& w);
    void step(Work& w);
    // The link direction towards the owner of job.t0, or -1 if it is ours.
    int route(const RayJob& job) const;
    void terminate(const Work& w, std::vector<RayJob>& spawned);
    void flushToHost();
    Picos stepCost(const Counters& before, uint64_t sends, uint64_t recvs, uint64_t generated) const;
    size_t queueDepth() const;
    void traceState(bool busy, bool waiting);

    Cell cell_;
    Region region_;
    const Shader& shader_;
    const Camera& camera_;
    Box world_;
    Costs costs_;
    double speed_;
    int fbBatch_;

    std::vector<uint32_t> pixels_;
    size_t nextPixel_ = 0;
    int primaryExp_ = 0;
    Credit credit_;  // returned credit not yet sent to the host

    std::vector<Work> local_;                 // spawned rays, LIFO
    std::vector<Contribution> pending_;   // contributions not yet sent
    std::vector<std::pair<int, Message>> outbox_;  // this step's sends: (direction or -1 for fb, message)
    Mailbox mailbox_;
    Picos now_ = 0;
    sc_core::sc_event arrived_;
    NodeStats stats_;
    std::unique_ptr<NodeTrace> trace_;
};

}  // namespace rt
