#include "summary.h"

#include <algorithm>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "analysis/report.h"
#include "node/busy_parts.h"
#include "trace/trace_writer.h"

namespace rt {
namespace {

std::string nsTime(const nlohmann::json& ns) { return formatTime(Picos(ns.get<double>() * 1000)); }

// The smallest, mean and largest of a per-node figure of the report (`of`
// gives it from the node's statistics, in its units there: ns, or a share).
template <class Of>
void printSpread(const std::vector<NodeStats>& nodes, const char* label, Of of, bool time) {
    double lo = 1e300, mean = 0, hi = -1e300;
    for (const NodeStats& n : nodes) {
        const double v = of(n);
        lo = std::min(lo, v);
        hi = std::max(hi, v);
        mean += v / double(nodes.size());
    }
    if (time)
        std::printf("  %-16s min %s  mean %s  max %s\n", label, formatTime(Picos(lo * 1000)).c_str(),
                    formatTime(Picos(mean * 1000)).c_str(), formatTime(Picos(hi * 1000)).c_str());
    else
        std::printf("  %-16s min %.3f  mean %.3f  max %.3f  (max / mean %.2f)\n", label, lo, mean, hi,
                    mean > 0 ? hi / mean : 0.0);
}

// The busiest node and where its busy time went (busy_by_category), largest
// kinds first, down to 1 %.
void printBusiestNode(const MachineResult& r) {
    const size_t i = size_t(std::max_element(r.nodes.begin(), r.nodes.end(), [](const NodeStats& a, const NodeStats& b) { return a.busy < b.busy; }) -
                             r.nodes.begin());
    const Cell& c = r.cells[i];
    const double busy = inNs(r.nodes[i].busy);
    std::printf("  busiest node     node_%d_%d_%d busy %s:", c[0], c[1], c[2], formatTime(Picos(busy * 1000)).c_str());
    std::vector<std::pair<double, std::string>> kinds;
    for (int k = 0; k < kBusyKinds; ++k) kinds.push_back({inNs(r.nodes[i].busyBy[size_t(k)]), busyKindName(k)});
    std::sort(kinds.begin(), kinds.end(), [](const auto& a, const auto& b) { return a.second < b.second; });  // (the report's order)
    std::stable_sort(kinds.begin(), kinds.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
    const char* sep = " ";
    for (const auto& [v, k] : kinds) {
        if (busy <= 0 || v < 0.01 * busy) break;
        std::printf("%s%s %.0f %%", sep, k.c_str(), 100.0 * v / busy);
        sep = ", ";
    }
    std::printf("\n");
}

// The frame buffer, the messages and the busiest wires.
void printTraffic(const nlohmann::json& report) {
    const auto& fb = report["frame_buffer"];
    std::printf("  frame buffer     %zu unit%s, busiest %s busy (%.1f %% of the render time)\n", fb["units"].size(),
                fb["units"].size() == 1 ? "" : "s", nsTime(fb["busy_ns"]).c_str(),
                100.0 * report["bounds"]["frame_buffer"]["fraction"].get<double>());
    const auto& t = report["totals"];
    std::printf("  messages         %llu ray, %llu contribution, %llu credit (%.3g MB on links and ports)\n",
                (unsigned long long)t["messages"]["ray"].get<uint64_t>(),
                (unsigned long long)t["messages"]["contributions"].get<uint64_t>(),
                (unsigned long long)t["messages"]["credit"].get<uint64_t>(),
                double(t["bytes"]["ray"].get<uint64_t>() + t["bytes"]["contributions"].get<uint64_t>() +
                       t["bytes"]["credit"].get<uint64_t>()) / 1e6);
    if (report["busiest_links"].empty()) return;
    const double end = report["render_time_ns"].get<double>();
    std::printf("  busiest links   ");
    for (const auto& l : report["busiest_links"]) {
        std::printf(" %s %.1f %% (", l["name"].get<std::string>().c_str(), 100.0 * l["utilisation"].get<double>());
        if (l.contains("peak_utilisation")) std::printf("peak %.0f %%, ", 100.0 * l["peak_utilisation"].get<double>());
        std::printf("backlog %.0f %%)", end > 0 ? 100.0 * l["saturated_ns"].get<double>() / end : 0.0);
    }
    std::printf("\n                   (wire busy, of the render time; peak: of the busiest window; backlog: busy with "
                "messages waiting for the wire; node_X_Y_Z_py: from node X,Y,Z towards +y, _fb: to its frame-buffer unit)\n");
}

// How the boundaries ended (stability.h), and where a balanced frame took
// longer than the unbalanced one (the comparison run's), that it did: the
// summary never calls boundaries converged over a frame that lost. (With
// --eye-step every frame has a view of its own: only the last one's
// unbalanced frame is known.)
std::string stabilityWord(const nlohmann::json& report) {
    std::string word = report["balance"]["stability"].get<std::string>();
    if (!report.contains("comparison")) return word;
    const double none = report["comparison"]["unbalanced_ns"].get<double>();
    const bool moves = !report["config"]["frames"].value("eye_step", nlohmann::json::array()).empty();
    std::vector<double> frames;
    if (report.contains("frames") && !moves)
        for (const auto& f : report["frames"]) frames.push_back(f["render_time_ns"].get<double>());
    else
        frames.push_back(report["render_time_ns"].get<double>());
    const size_t first = moves && report.contains("frames") ? report["frames"].size() : 1;
    for (size_t k = 0; k < frames.size(); ++k)
        if (none > 0 && frames[k] > none) {
            char buf[160];
            std::snprintf(buf, sizeof buf, "%s, but frame %zu took %.3f times the unbalanced frame", word.c_str(),
                          first + k, frames[k] / none);
            return buf;
        }
    return word;
}

// The polish's tries (--polish-tries; between_frames.h, "Polish"): the
// frames that tried a move of the planes held, and how many of the moves
// were kept, their frame faster than the one held. "" where none tried.
std::string polishLine(const nlohmann::json& frames, int tries) {
    int tried = 0, kept = 0;
    size_t from = 0, to = 0;
    for (size_t k = 1; k < frames.size(); ++k) {
        const nlohmann::json then = frames[k - 1].value("then", nlohmann::json::object());
        if (then.value("next", "") != "a move tried") continue;
        from = tried++ ? from : k + 1;
        to = k + 1;
        if (frames[k]["render_time_ns"].get<double>() < then["held_ns"].get<double>()) ++kept;
    }
    if (!tried) return "";
    char buf[200];
    std::snprintf(buf, sizeof buf, "frames %zu to %zu tried a move of the planes held each, %d of %d faster and kept "
                  "(--polish-tries %d)", from, to, kept, tried, tries);
    return buf;
}

// A policy as the summary names it: one --balance recommended chose says so.
std::string policyName(const std::string& policy, bool recommended) {
    return recommended ? policy + " (the recommended policy)" : policy;
}

// The balancing and the bounds of this run's frame (when it balances), the
// paper's Fig. 4 quantity for this frame (with the comparison run, and the
// unbalanced frame's bound), the frames.
void printBalancing(const RtsimOptions& o, const nlohmann::json& report) {
    const char axis = "xyz"[o.machine.balance.axis];
    const bool balances = o.machine.balance.policy != "none";
    if (!balances && !o.machine.balance.recommendedWhy.empty())  // (--balance recommended chose none: why)
        std::printf("  balancing        %s\n", o.machine.balance.recommendedWhy.c_str());
    if (balances) {
        std::printf("  balancing        %s along %c: %zu slides; max / mean load %.2f; boundaries %s\n",
                    policyName(o.machine.balance.policy, !o.machine.balance.recommendedWhy.empty()).c_str(), axis, report["balance"]["slides"].get<size_t>(),
                    report["balance"]["max_over_mean_load"].get<double>(), stabilityWord(report).c_str());
        const auto& b = report["bounds"];
        auto bound = [&](const char* k) {
            return nsTime(b[k]["ns"]) + " (" + std::to_string(b[k]["fraction"].get<double>()).substr(0, 4) + ")";
        };
        std::printf("  bounds           of this balanced frame: perfect %s, column along %c %s, frame buffer %s (fractions of "
                    "its render time)\n",
                    bound("perfect").c_str(), axis, bound("column").c_str(), bound("frame_buffer").c_str());
    }
    if (report.contains("comparison")) {
        const auto& c = report["comparison"];
        const int frame = c.value("balanced_frame", 1);
        const std::string policy = c["balanced_policy"].get<std::string>();
        const bool recommended = c.value("balanced_recommended", false);
        const std::string ofFrame = frame > 1 ? ", frame " + std::to_string(frame) : "", which = policy + ofFrame;
        std::printf("  comparison       this run: %s; the comparison run: %s\n",
                    balances ? ("balancing with " + policyName(policy, recommended)).c_str() : "no balancing (none)",
                    balances ? "no balancing (none)" : ("balancing with " + policyName(policy, recommended) + ofFrame).c_str());
        std::printf("  with / without   %s: %s, none: %s; ratio %.2f (bound %.2f: the unbalanced frame's heaviest column "
                    "along %c spread evenly; paper about 0.2 at f = 1/N)\n",
                    which.c_str(), nsTime(c["balanced_ns"]).c_str(), nsTime(c["unbalanced_ns"]).c_str(),
                    c["ratio"].get<double>(), c["column_bound"].get<double>(), axis);
    }
    if (report.contains("frames")) {
        std::printf("  frames          ");
        for (const auto& f : report["frames"]) std::printf(" %s", nsTime(f["render_time_ns"]).c_str());
        std::printf("  (render times; the figures above are the last frame's)\n");
        const std::string polish = polishLine(report["frames"], o.machine.balance.polishTries);
        if (!polish.empty()) std::printf("  polish           %s\n", polish.c_str());
    }
}

// The whole run's wall-clock time and its parts (wall_clock.h), which add up to it.
void printWallClock(const RtsimOptions& o, const WallClock& w) {
    const std::string frames = o.frames > 1 ? "frames (" + std::to_string(o.frames) + ")" : "frame";
    char calibration[64] = "";
    if (w.calibration > 0) std::snprintf(calibration, sizeof calibration, ", calibration %.3f s", w.calibration);
    std::printf("  wall clock       %.3f s in all: start-up %.3f s%s, %s %.3f s, reference runs %.3f s%s, writing %.3f s\n",
                w.total(), w.startUp, calibration, frames.c_str(), w.frames, w.referenceRuns, o.baseline ? "" : " (--no-baseline)",
                w.writing);
}

// The fidelity rung when it is not the exact model's, and how --max-error chose it.
void printFidelity(const nlohmann::json& report) {
    const auto& f = report["config"]["fidelity"];
    const std::string rung = f["rung"].get<std::string>();
    if (!report.contains("fidelity")) {
        if (rung != "exact") std::printf("  fidelity         %s (doc/fidelity.md)\n", rung.c_str());
        return;
    }
    const auto& c = report["fidelity"];
    std::printf("  fidelity         %s, chosen for --max-error %g %%", rung.c_str(), c["max_error"].get<double>() * 100);
    if (c.contains("calibration"))
        std::printf(": on a %s calibration frame its render time was %.3g %% off the exact model's",
                    c["calibration"]["size"].get<std::string>().c_str(), c["calibration_error"].get<double>() * 100);
    else
        std::printf(" (%s)", c["why"].get<std::string>().c_str());
    std::printf("\n");
}

}  // namespace

void printSummary(const Scene& scene, const RtsimOptions& o, const MachineResult& r, const nlohmann::json& report,
                  double baselineNs, const WallClock& wall) {
    const auto& d = o.machine.dims;
    const double renderNs = report["render_time_ns"].get<double>();
    std::printf("rtsim: %s (%zu objects), %dx%dx%d mesh, %dx%d image%s\n", scene.name.c_str(), scene.objects.size(), d[0],
                d[1], d[2], r.image.width, r.image.height,
                o.machine.spreadPrimaries ? ", primary rays spread (--primary-order spread)" : "");
    std::printf("  render time      %s simulated", formatTime(r.renderTime).c_str());
    if (baselineNs > 0)
        std::printf("   (1x1x1 with the same costs: %s, speed-up %.2f)", formatTime(Picos(baselineNs * 1000 + 0.5)).c_str(),
                    baselineNs / renderNs);
    std::printf("\n");
    // (From the statistics the report's nodes are made of: it holds them as it is written.)
    printSpread(r.nodes, "busy per node", [](const NodeStats& n) { return inNs(n.busy); }, true);
    printSpread(r.nodes, "wait per node", [](const NodeStats& n) { return inNs(n.wait); }, true);
    if (report["totals"]["blocked_ns"].get<double>() > 0)  // full output buffers
        printSpread(r.nodes, "  of it blocked", [](const NodeStats& n) { return inNs(n.blocked); }, true);
    printSpread(r.nodes, "load per node", loadOf, false);
    printBusiestNode(r);
    printTraffic(report);
    printBalancing(o, report);
    printFidelity(report);
    printWallClock(o, wall);
    std::string files;
    auto add = [&](const std::string& path, const char* what) {
        if (!path.empty()) files += (files.empty() ? " " : ", ") + path + " (" + what + ")";
    };
    add(o.image, "image");
    add(o.report, o.fullReport() ? "report" : "report, summary detail: --report-detail full keeps every field");
    add(o.vcd, "waveforms");
    add(o.vcd.empty() ? "" : gtkwPathFor(o.vcd), "GTKWave view");
    add(o.map, "mesh map");
    if (!files.empty()) std::printf("  wrote           %s\n", files.c_str());
}

}  // namespace rt
