// A sequence of frames in one elaboration (machine.h, MachineSession): the
// host phase between two frames, running each, and each frame's processes,
// kept as they are made and ended at the frame's end.
#include <chrono>
#include <stdexcept>

#include "machine/machine.h"

namespace rt {

namespace {

// The process's start, for the start-up wall time (set at static initialisation).
const std::chrono::steady_clock::time_point kProcessStart = std::chrono::steady_clock::now();
double secondsBetween(std::chrono::steady_clock::time_point a, std::chrono::steady_clock::time_point b) {
    return std::chrono::duration<double>(b - a).count();
}

}  // namespace

// SystemC elaborates once per simulation context: a session after another
// in the same process (a test's machines, a reference run) gets a context
// of its own. The one before is kept, not deleted: its modules went with
// its Machine, but deleting it would lose the timed events still queued in
// it (SystemC's pool of them), and SystemC's own static events belong to
// the first. What a used context keeps is small (its kernel's tables,
// emptied of the machine).
void freshContextIfUsed() {
    // (Never freed, the first included, and the list never destroyed: the
    // contexts stay reachable to the end, not a leak.)
    static auto* const kept = new std::vector<sc_core::sc_simcontext*>{sc_core::sc_get_curr_simcontext()};
    if (sc_core::sc_get_status() == sc_core::SC_ELABORATION) return;  // (nothing run in it yet)
    auto* fresh = new sc_core::sc_simcontext;
    kept->push_back(fresh);
    sc_core::sc_curr_simcontext = fresh;
    sc_core::sc_default_global_context = fresh;
}

// The first frame's processes are the modules' own (SC_METHOD), each the
// last thing its constructor makes: kept as they are made, in the order of
// the later frames' (spawned_), so that a frame's end need not look for
// them among the modules' children (ports and all, each cast to find
// whether it is a process). (SystemC's sc_get_last_created_process_handle
// gives no process during elaboration here.)
void Machine::keepProcess(const sc_core::sc_module& m) {
    const std::vector<sc_core::sc_object*>& children = m.get_child_objects();
    sc_core::sc_process_handle h(children.empty() ? nullptr : children.back());
    if (!h.valid()) throw std::logic_error(std::string(m.name()) + ": its constructor's last child is not its process");
    spawned_.add(h);
}

// Ends every process but the caller's, from within the simulation, and
// every wake still pending (a process's next input, a sender's room, the
// watchdog's): nothing is left to happen, and the simulation returns at the
// frame's end (the next frame may start there: nextFrame, below). A
// process ended here does not run in the current delta cycle. Newest
// first (frame_processes.h). The processes are held: SystemC deletes them
// at the next frame's start, not here, a search of its names each
// (doc/history.md, "Figures behind ...").
void Machine::endProcesses() {
    spawned_.endAllBut(sc_core::sc_get_current_process_handle());
    watchdog_->quiet();
    if (relay_) relay_->quiet();
    for (Node& n : nodes_) n.quiet();
    for (FrameBufferUnit& u : units_) u.quiet();
    for (Link* l : roomLinks_) l->quiet();
}

// The order is the constructor's: the units, the nodes, the links, the
// watchdog, the waveforms, then the host's job description; the processes
// are spawned in the order the modules made theirs (units, nodes,
// watchdog). What persists: the modules, their ports and links, the
// lookaheads, costs and parameters, the objects' binning.
void Machine::nextFrame(const View& view, const MachineConfig& next, int frame) {
    if (next.usesRelay() && !express_)
        throw std::logic_error("MachineSession::next: express in a machine built without its routes (MachineConfig::expressRoutes)");
    cfg_ = next;
    cfg_.validate();
    camera_ = Camera(view, width_, height_);
    columnPlanes_ = initialPlanes(cfg_, cuts_, world_, *bins_, minThickness_, &camera_);
    const ColumnPlanes targets = startTargets();
    spawned_.clear();  // (the last frame's: SystemC deletes them now)
    for (FrameBufferUnit& u : units_) spawned_.add(u.restart(cfg_.showProgress, frame));
    makeLayerFaces();
    nodeParams_->layerFaces = layerFaces_.get();
    for (Node& n : nodes_) {
        const Box b = nodeBox(n.cell(), cuts_, columns_, columnPlanes_);
        spawned_.add(n.restart(b, *bins_, frame));
    }
    aimAtTargets();
    for (auto* links : {&links_, &unitLinks_})
        for (auto& l : *links) l->restart();
    for (LinkReport& e : linkInfo_) e.figures.reset();  // (the last frame's figures went to its report)
    if (relay_) {  // (the same machine: its boxes are where they were)
        express_->restart();
        spawned_.add(relay_->restart(frame));
    }
    spawned_.add(watchdog_->restart(frame));
    if (cfg_.faultDropFirstCredit) units_[0].dropFirstCredit();
    vcd_.reset();
    tracedLinks_.clear();
    gtkw_.clear();
    if (!cfg_.vcdPath.empty()) setupTraces();
    giveOutPrimaryRays(targets);
    deltaAtStart_ = sc_core::sc_delta_count();
    started_ = std::chrono::steady_clock::now();
}

MachineSession::MachineSession(const Scene& scene, const MachineConfig& config) {
    freshContextIfUsed();
    sc_core::sc_set_time_resolution(1, sc_core::SC_PS);
    frameOrigin = 0;
    built_ = std::chrono::steady_clock::now();
    machine_ = std::make_unique<Machine>("machine", scene, config);
}

MachineSession::~MachineSession() = default;

MachineResult MachineSession::run(bool another) {
    Machine& m = *machine_;
    try {
        sc_core::sc_start();
    } catch (const sc_core::sc_report& e) {
        // An exception thrown in a process comes out wrapped in a report of
        // several lines; its own message is the one line to show.
        throw std::runtime_error(e.get_msg());
    }
    simulationRunning = 0;  // (a signal before the next frame runs is one in start-up)
    m.endFrame();
    const double wall = secondsBetween(built_, std::chrono::steady_clock::now());
    m.checkConservation();
    m.closeTraces();
    MachineResult r = m.collect(wall, !another);
    over_ = !another;
    r.wallElaborationSeconds = secondsBetween(built_, m.started());
    r.wallStartupSeconds = secondsBetween(kProcessStart, m.started());
    return r;
}

// The next frame starts where this one ended on the kernel's clock: a unit
// 0 running ahead of the kernel (a quantum) ended it later than the
// kernel's last event, which the clock first moves on to. The host phase
// takes no simulated time.
void MachineSession::next(const View& view, const MachineConfig& config) {
    if (over_) throw std::logic_error("MachineSession::next: its last frame has run (run(true) keeps it going)");
    built_ = std::chrono::steady_clock::now();
    const Picos end = frameOrigin + machine_->frameEnd(), kernel = sc_core::sc_time_stamp().value();
    if (end > kernel) sc_core::sc_start(sc_core::sc_time::from_value(end - kernel));
    frameOrigin = sc_core::sc_time_stamp().value();
    machine_->nextFrame(view, config, ++frame_);
}

MachineResult runMachine(const Scene& scene, const MachineConfig& config) { return MachineSession(scene, config).run(); }

}  // namespace rt
