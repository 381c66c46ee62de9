#include "reference_runs.h"

#include <chrono>
#include <optional>
#include <string>
#include <vector>

#include "messages.h"
#include "subprocess.h"

namespace rt {
namespace {

// The balanced and the unbalanced run's times, and the unbalanced run's
// bounds as fractions of its time: what the ratio could at best be.
nlohmann::json comparison(const nlohmann::json& balanced, const nlohmann::json& unbalanced) {
    return {{"balanced_policy", balanced["config"]["balance"]["policy"]},
            {"balanced_ns", balanced["render_time_ns"]},
            {"unbalanced_ns", unbalanced["render_time_ns"]},
            {"ratio", balanced["render_time_ns"].get<double>() / unbalanced["render_time_ns"].get<double>()},
            {"column_bound", unbalanced["bounds"]["column"]["fraction"]},
            {"perfect_bound", unbalanced["bounds"]["perfect"]["fraction"]}};
}

}  // namespace

double addReferenceRuns(nlohmann::json& report, int argc, char** argv, const RtsimOptions& o) {
    const bool single = o.machine.dims == std::array<int, 3>{1, 1, 1};
    double baselineNs = single ? report["render_time_ns"].get<double>() : -1;
    const std::string policy = o.machine.balance.policy;
    const bool base = o.baseline && !single, compare = o.baseline && o.machine.dims[size_t(o.machine.balance.axis)] > 1;
    if (base) msg::info("reference runs: the 1x1x1 baseline" + std::string(compare ? " and the balancing comparison" : "") + ", in child processes");
    const auto t0 = std::chrono::steady_clock::now();
    std::optional<Child> baseRun, otherRun;
    if (base) baseRun.emplace(argc, argv, std::vector<std::string>{"--as-baseline"});
    if (compare) otherRun.emplace(argc, argv, std::vector<std::string>{"--as-comparison", "--balance", policy == "none" ? "default" : "none"});
    const std::optional<nlohmann::json> baseReport = baseRun ? baseRun->report() : std::nullopt;
    const std::optional<nlohmann::json> other = otherRun ? otherRun->report() : std::nullopt;
    if (base) {
        report["baseline"]["wall_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (baseReport) baselineNs = (*baseReport)["render_time_ns"].get<double>();
        else msg::warning(msg::kReference, "the 1x1x1 baseline run failed; no speed-up");
    }
    if (baselineNs > 0) {
        report["baseline"]["render_time_ns"] = baselineNs;
        report["baseline"]["speedup"] = baselineNs / report["render_time_ns"].get<double>();
    }
    if (compare && !other) msg::warning(msg::kReference, "the balancing comparison run failed; no ratio");
    if (other) report["comparison"] = policy == "none" ? comparison(*other, report) : comparison(report, *other);
    return baselineNs;
}

}  // namespace rt
