#include "reference_runs.h"

#include <chrono>
#include <optional>

#include "messages.h"
#include "stops.h"
#include "subprocess.h"
#include "process/watchdog.h"

namespace rt {
namespace {

// The balanced and the unbalanced run's times, and the unbalanced run's
// bounds as fractions of its time: what the ratio could at best be.
nlohmann::json comparison(const nlohmann::json& balanced, const nlohmann::json& unbalanced) {
    const nlohmann::json& b = balanced["config"]["balance"];
    return {{"balanced_policy", b["policy"]},
            {"balanced_recommended", b.contains("recommended")},  // chosen by --balance recommended
            {"balanced_frame", balanced.contains("frames") ? balanced["frames"].size() : 1},  // of a sequence: its last
            {"balanced_ns", balanced["render_time_ns"]},
            {"unbalanced_ns", unbalanced["render_time_ns"]},
            {"ratio", balanced["render_time_ns"].get<double>() / unbalanced["render_time_ns"].get<double>()},
            {"column_bound", unbalanced["bounds"]["column"]["fraction"]},
            {"perfect_bound", unbalanced["bounds"]["perfect"]["fraction"]}};
}

}  // namespace

ReferenceRuns addReferenceRuns(nlohmann::json& report, const std::vector<std::string>& args, const RtsimOptions& o) {
    ReferenceRuns out;
    const bool single = o.machine.dims == std::array<int, 3>{1, 1, 1};
    if (single) out.baselineNs = report["render_time_ns"].get<double>();
    const std::string policy = o.machine.balance.policy;
    const bool base = o.baseline && !single, compare = o.baseline && o.machine.dims[size_t(o.machine.balance.axis)] > 1;
    out.ran = base || compare;
    if (base) msg::info("reference runs: the 1x1x1 baseline" + std::string(compare ? " and the balancing comparison" : "") + ", in child processes");
    const OrderlyStops orderly;  // a stop is passed to them; the frame's outputs are still written
    const auto t0 = std::chrono::steady_clock::now();
    std::optional<Child> baseRun, otherRun;
    // (Their reports are read for a few figures: the per-node and per-link detail of a big mesh would be
    // written and parsed for nothing.)
    if (base) baseRun.emplace(args, std::vector<std::string>{"--as-baseline", "--report-detail", "summary"});
    std::vector<std::string> otherArgs{"--as-comparison", "--report-detail", "summary", "--balance",
                                       policy == "none" ? "recommended" : "none"};
    // Where the recommended policy keeps a first frame's split and re-splits
    // from the second, a single frame is compared with its second frame.
    BalanceConfig recommended;
    recommended.policy = recommendedPolicy(o.machine.dims, o.machine.balance.axis).policy;
    if (policy == "none" && o.frames == 1 && recommended.firstFrameHolds()) otherArgs.insert(otherArgs.end(), {"--frames", "2"});
    if (compare) otherRun.emplace(args, otherArgs);
    const std::optional<nlohmann::json> baseReport = baseRun ? baseRun->report() : std::nullopt;
    const std::optional<nlohmann::json> other = otherRun ? otherRun->report() : std::nullopt;
    std::string stopped;
    for (auto& [run, what] : {std::pair{&baseRun, "the 1x1x1 baseline"}, std::pair{&otherRun, "the balancing comparison"}})
        if (*run && (*run)->stopped()) {
            stopped += (stopped.empty() ? "" : " and ") + std::string(what);
            out.stopCode = stopSignal ? 128 + int(stopSignal) : (*run)->exitCode();
        }
    if (!stopped.empty()) report["reference_runs_stopped"] = stopped + (out.stopCode == 3 ? " (the watchdog)" : " (a signal)");
    if (base) {
        report["baseline"]["wall_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (baseReport) out.baselineNs = (*baseReport)["render_time_ns"].get<double>();
        else if (!out.stopCode) msg::warning(msg::kReference, "the 1x1x1 baseline run failed; no speed-up");
    }
    if (out.baselineNs > 0) {
        report["baseline"]["render_time_ns"] = out.baselineNs;
        report["baseline"]["speedup"] = out.baselineNs / report["render_time_ns"].get<double>();
    }
    if (compare && !other && !out.stopCode) msg::warning(msg::kReference, "the balancing comparison run failed; no ratio");
    if (other) report["comparison"] = policy == "none" ? comparison(*other, report) : comparison(report, *other);
    return out;
}

}  // namespace rt
