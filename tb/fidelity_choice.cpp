#include "fidelity_choice.h"

#include <chrono>
#include <cmath>
#include <sstream>

#include "balance/initial_split.h"
#include "machine/machine.h"
#include "messages.h"

namespace rt {
namespace {

constexpr Picos kCoarseQuantum = 10000000;  // 10 us: the quantum rungs'
constexpr double kMargin = 0.5;             // a rung's calibration error must be within this share of E
// A calibration frame has at least this many pixels (16 x 16) and this
// share of the frame's: the calibration is then at most a few per cent of
// the frame's work (with the exact run and two rungs, 3/256), which a rung
// that gains 10 % pays for (balls-4 at 256x256 on 8x8x8: calibrating on a
// 16th of the pixels, a 32x32 frame, made --max-error 1% 0.85x the exact
// run's speed, express having gained 1.2x).
constexpr int kLeastPixels = 256;
constexpr int kShare = 256;
// Below this many nodes a calibration does not tell where express gains
// too little to pay for it: on 8x8x8 at 256x256 --max-error 1% took
// balls-4 1.12x faster than the exact run, but balls-5 0.96x, its
// calibration frames' events cut as much as balls-4's (doc/fidelity.md).
constexpr int kLeastNodes = 4096;
// Below this many pixels per node the frame is too short for a rung to win
// back its calibration (two frames of a 256th of the pixels and the host
// phases before them, in the machine that then renders the frame): a scene
// whose rays make few hops (tetra-3) gains least. Measured on the SPD
// scenes (doc/fidelity.md, "--max-error E"): at 4 pixels a node three of
// eight lost, at 16 none that chose express.
constexpr int kLeastPixelsPerNode = 16;

// What a run cost the simulator, in simulated figures (the same on every
// run): the kernel's delta cycles and every message taken.
uint64_t eventsOf(const MachineResult& r) {
    uint64_t n = r.deltaCycles;
    for (const NodeStats& s : r.nodes) n += s.messagesReceived;
    for (const auto& u : r.frameBuffer) n += u.stats.contributionMessages + u.stats.creditMessages;
    return n;
}

// The calibration frames' pixel stride: the largest power of two whose
// frames trace at least max(kLeastPixels, a kShare-th of the pixels); 1:
// too small to calibrate on less.
int calibrationDivisor(int w, int h) {
    const double least = std::max(double(kLeastPixels), double(w) * h / kShare);
    int k = 1;
    while (double(stridedCount(w, 2 * k)) * stridedCount(h, 2 * k) >= least) k *= 2;
    return k;
}

MachineConfig withRung(MachineConfig m, const FidelityRung& r) {
    m.express = r.express;
    m.through = r.through;
    m.lookaheadQuantum = r.quantum == 0;
    m.quantum = r.quantum == 0 ? m.lookahead() : r.quantum;
    return m;
}

// Whether the chooser tries the rung on this machine: express where boxes
// stay put and rays go one per message. Not the quantum rungs: their error
// on a calibration frame does not foretell the frame's (a fixed quantum
// is a larger share of a shorter frame, and the errors do not scale):
// with them, --max-error 1% chose express with a 10 us quantum on gears-2
// at 128x128 on 16x16x16 (-1.49 % on the frame) and on rings-2 on
// 32x32x32 (+13.8 %) (doc/results/speed_accuracy.md).
bool applies(const FidelityRung& r, const MachineConfig& m) {
    return (r.express || r.through) && r.quantum == 0 && m.balance.boxesStayPut() && m.rayBatch <= 1;
}

double secondsSince(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

}  // namespace

const std::vector<FidelityRung>& fidelityRungs() {
    static const std::vector<FidelityRung> rungs = {
        {"exact", false, false, 0},
        {"express", true, false, 0},
        {"through", false, true, 0},
        {"quantum 10 us", false, false, kCoarseQuantum},
        {"express, quantum 10 us", true, false, kCoarseQuantum},
    };
    return rungs;
}

std::string rungOf(const MachineConfig& m) {
    for (const FidelityRung& r : fidelityRungs())
        if (r.express == m.express && r.through == m.through && (r.quantum == 0 ? m.lookaheadQuantum : !m.lookaheadQuantum && m.quantum == r.quantum)) return r.name;
    std::ostringstream s;
    const std::string relay = m.usesRelay() ? m.relayRung() : "";
    s << (relay.empty() ? "" : relay + ", ") << "quantum " << formatTime(m.quantum);
    return m.lookaheadQuantum ? (relay.empty() ? "exact" : relay) : s.str();
}

namespace {

// What a frame of the session took, without building the machine (the
// first frame's elaboration serves the frame asked for as well).
double ownWall(const MachineResult& r) { return r.wallSeconds - r.wallElaborationSeconds; }

// The calibration: the frame `c` (every k-th pixel) run exact in a session
// built with the express routes, then at each candidate, the coarsest first,
// in the same session, until one is within kMargin of `maxError` with fewer
// events than the exact run: it (or the exact rung) into `best`, with its
// error. The session is left ready for its next frame (the one asked for).
nlohmann::json calibrate(MachineSession& session, const Scene& scene, const MachineConfig& c,
                         const std::vector<const FidelityRung*>& candidates, double maxError, const FidelityRung*& best,
                         double& bestError) {
    const auto t0 = std::chrono::steady_clock::now();
    const MachineResult ex = session.run(true);
    const int k = c.pixelStride;
    nlohmann::json cal = {{"size", std::to_string(stridedCount(c.width, k)) + "x" + std::to_string(stridedCount(c.height, k))},
                          {"pixel_stride", k},
                          {"exact", {{"render_time_ns", double(ex.renderTime) / 1000}, {"events", eventsOf(ex)}, {"wall_s", ownWall(ex)}}},
                          {"rungs", nlohmann::json::array()}};
    const uint64_t bestEvents = eventsOf(ex);
    for (const FidelityRung* r : candidates) {
        if (!ex.incomplete.empty()) break;
        session.next(scene.view, withRung(c, *r));
        const MachineResult got = session.run(true);
        if (!got.incomplete.empty()) break;
        const double error = std::fabs(double(got.renderTime) - double(ex.renderTime)) / double(ex.renderTime);
        const uint64_t events = eventsOf(got);
        const bool within = error <= kMargin * maxError;
        cal["rungs"].push_back({{"rung", r->name}, {"render_time_ns", double(got.renderTime) / 1000}, {"error", error},
                                {"events", events}, {"wall_s", ownWall(got)}, {"within", within}});
        if (within && events < bestEvents) {
            best = r;
            bestError = error;
            break;
        }
    }
    cal["wall_s"] = secondsSince(t0);  // (the machine was built before: start-up, as any run's)
    if (!ex.incomplete.empty()) cal["stopped"] = ex.incomplete;
    return cal;
}

}  // namespace

FidelityChoice chooseFidelity(const Scene& scene, RtsimOptions& o) {
    const MachineConfig& m = o.machine;
    FidelityChoice out;
    nlohmann::json& j = out.json;
    j = {{"max_error", o.maxError}};
    const FidelityRung& exact = fidelityRungs()[0];
    std::vector<const FidelityRung*> candidates;
    for (const FidelityRung& r : fidelityRungs())
        if (&r != &exact && applies(r, m)) candidates.insert(candidates.begin(), &r);  // (the coarsest first)
    const int k = calibrationDivisor(m.width, m.height);
    auto settle = [&](const FidelityRung& r, const std::string& why) {
        o.machine = withRung(o.machine, r);
        j["rung"] = r.name;
        j["why"] = why;
        msg::info("--max-error: " + r.name + " (" + why + ")");
        return std::move(out);
    };
    if (candidates.empty())
        return settle(exact, "no coarser rung applies: a policy that moves boundaries is timed exactly, since the timing steers them");
    if (k == 1) return settle(exact, "the image is too small to calibrate on a part of it");
    if (m.nodeCount() < kLeastNodes)
        return settle(exact, "a mesh of fewer than " + std::to_string(kLeastNodes) +
                                  " nodes: its coarser rungs gain less than a calibration costs");
    if (double(m.width) * m.height < double(kLeastPixelsPerNode) * m.nodeCount())
        return settle(exact, "fewer than " + std::to_string(kLeastPixelsPerNode) +
                                  " pixels per node: the frame is too short for a coarser rung to win back a calibration");

    // The calibration frames: the same machine and camera, every k-th pixel
    // of every k-th row, traced nowhere; in the machine that then renders
    // the frame asked for (built once, with the express routes).
    MachineConfig c = m;
    c.pixelStride = k;
    c.expressRoutes = true;
    c.vcdPath.clear();
    c.vcdName.clear();
    c.traceNodes.clear();
    c.traceLinks.clear();
    c.showProgress = false;
    msg::info("--max-error: calibrating on every " + std::to_string(k) + "th pixel of every " + std::to_string(k) + "th row");
    out.session = std::make_unique<MachineSession>(scene, withRung(c, exact));
    const FidelityRung* best = &exact;
    double bestError = 0;
    j["calibration"] = calibrate(*out.session, scene, c, candidates, o.maxError, best, bestError);
    j["calibration_error"] = bestError;
    if (j["calibration"].contains("stopped")) {
        out.session.reset();
        return settle(exact, "the calibration was stopped");
    }
    std::ostringstream why;
    why << "the coarsest rung within " << kMargin << " of the error asked for on calibration frames of 1/" << k * k
        << " of the pixels, with fewer simulated events than the exact model";
    return settle(*best, why.str());
}

}  // namespace rt
