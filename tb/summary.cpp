#include "summary.h"

#include <algorithm>
#include <cstdio>
#include <string>

namespace rt {
namespace {

std::string nsTime(const nlohmann::json& ns) { return formatTime(Picos(ns.get<double>() * 1000)); }

// The smallest, mean and largest of a per-node figure of the report.
void printSpread(const nlohmann::json& nodes, const char* label, const char* key, bool time) {
    double lo = 1e300, mean = 0, hi = -1e300;
    for (const auto& n : nodes) {
        const double v = n[key].get<double>();
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
    std::printf("  busiest links   ");
    for (const auto& l : report["busiest_links"])
        std::printf(" %s %.1f %%", l["name"].get<std::string>().c_str(), 100.0 * l["utilisation"].get<double>());
    std::printf("  (wire busy, of the render time)\n");
}

// The balancing and the bounds (when it balances), the paper's Fig. 4
// quantity for this frame (with the comparison run), the frames.
void printBalancing(const RtsimOptions& o, const nlohmann::json& report) {
    const char axis = "xyz"[o.machine.balance.axis];
    if (o.machine.balance.policy != "none") {
        std::printf("  balancing        %s along %c: %zu slides; max / mean load %.2f; boundaries %s\n",
                    o.machine.balance.policy.c_str(), axis, report["balance"]["slides"].get<size_t>(),
                    report["balance"]["max_over_mean_load"].get<double>(),
                    report["balance"]["stability"].get<std::string>().c_str());
        const auto& b = report["bounds"];
        auto bound = [&](const char* k) {
            return nsTime(b[k]["ns"]) + " (" + std::to_string(b[k]["fraction"].get<double>()).substr(0, 4) + ")";
        };
        std::printf("  bounds           perfect %s, column along %c %s, frame buffer %s (fractions of the render time)\n",
                    bound("perfect").c_str(), axis, bound("column").c_str(), bound("frame_buffer").c_str());
    }
    if (report.contains("comparison")) {
        const auto& c = report["comparison"];
        const int frame = c.value("balanced_frame", 1);
        const std::string which = c["balanced_policy"].get<std::string>() + (frame > 1 ? ", frame " + std::to_string(frame) : "");
        std::printf("  with / without   %s: %s, none: %s; ratio %.2f (bound %.2f: the heaviest column along %c spread "
                    "evenly; paper about 0.2 at f = 1/N)\n",
                    which.c_str(), nsTime(c["balanced_ns"]).c_str(),
                    nsTime(c["unbalanced_ns"]).c_str(), c["ratio"].get<double>(), c["column_bound"].get<double>(), axis);
    }
    if (report.contains("frames")) {
        std::printf("  frames          ");
        for (const auto& f : report["frames"]) std::printf(" %s", nsTime(f["render_time_ns"]).c_str());
        std::printf("  (render times; the figures above are the last frame's)\n");
    }
}

}  // namespace

void printSummary(const Scene& scene, const RtsimOptions& o, const MachineResult& r, const nlohmann::json& report,
                  double baselineNs) {
    const auto& d = o.machine.dims;
    const double renderNs = report["render_time_ns"].get<double>();
    std::printf("rtsim: %s (%zu objects), %dx%dx%d mesh, %dx%d image\n", scene.name.c_str(), scene.objects.size(), d[0],
                d[1], d[2], r.image.width, r.image.height);
    std::printf("  render time      %s", formatTime(r.renderTime).c_str());
    if (baselineNs > 0)
        std::printf("   (1x1x1 with the same costs: %s, speed-up %.2f)", formatTime(Picos(baselineNs * 1000 + 0.5)).c_str(),
                    baselineNs / renderNs);
    std::printf("\n");
    const auto& nodes = report["nodes"];
    printSpread(nodes, "busy per node", "busy_ns", true);
    printSpread(nodes, "wait per node", "wait_ns", true);
    if (report["totals"]["blocked_ns"].get<double>() > 0) printSpread(nodes, "  of it blocked", "blocked_ns", true);  // full output buffers
    printSpread(nodes, "load per node", "load", false);
    printTraffic(report);
    printBalancing(o, report);
    std::printf("  wall clock       %.3f s%s\n", r.wallSeconds, o.image.empty() ? "" : ("; image " + o.image).c_str());
}

}  // namespace rt
