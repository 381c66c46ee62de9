#include "trace_busiest.h"

#include <algorithm>
#include <numeric>

#include "messages.h"
#include "analysis/report.h"
#include "frame_sequence.h"

namespace rt {
namespace {

// The report's indices of its entries in `list`, ranked by `before` (stable).
template <class Before>
std::vector<size_t> ranked(const nlohmann::json& list, Before before) {
    std::vector<size_t> idx(list.size());
    std::iota(idx.begin(), idx.end(), 0);
    std::stable_sort(idx.begin(), idx.end(), [&](size_t a, size_t b) { return before(list[a], list[b]); });
    return idx;
}

}  // namespace

TraceChoice busiestOf(const nlohmann::json& report, int k) {
    TraceChoice c;
    const auto& nodes = report.at("nodes");
    const auto byBusy = ranked(nodes, [](const auto& a, const auto& b) {
        return a.at("busy_ns").template get<double>() > b.at("busy_ns").template get<double>();
    });
    for (size_t i = 0; i < std::min(byBusy.size(), size_t(k)); ++i) c.nodes.push_back(nodes[byBusy[i]].at("node").get<Cell>());
    const auto& links = report.at("links");
    const std::vector<size_t> byBacklog = linksByBacklog(links);  // as busiest_links
    for (size_t i = 0; i < std::min(byBacklog.size(), size_t(k)); ++i) {
        const auto& l = links[byBacklog[i]];
        const std::string to = l.at("to").get<std::string>();
        c.links.push_back({l.at("from").get<Cell>(), to == "fb" ? kDirs : dirNamed(to).value_or(kDirs)});
    }
    return c;
}

std::optional<TraceChoice> traceBusiest(EarlierFrames& earlier, const Scene& scene, RtsimOptions& o) {
    msg::info("--trace-nodes busiest: a first pass of the last frame without waveforms, to choose what to trace");
    MachineConfig pass = o.machine;
    pass.vcdPath.clear();
    pass.vcdName.clear();
    pass.showProgress = false;
    const MachineResult r = runLastFrame(earlier, scene, pass, true);
    if (!r.incomplete.empty()) {
        msg::warning(msg::kReference, "--trace-nodes busiest: the first pass did not end normally (" + r.incomplete + "); tracing every node");
        return std::nullopt;
    }
    const TraceChoice c = busiestOf(frameReport(r, pass, o).whole(), o.traceBusiest);
    o.machine.traceNodes = c.nodes;
    o.machine.traceLinks = c.links;
    return c;
}

nlohmann::json traceChoiceJson(int k, const TraceChoice& c) {
    nlohmann::json j = {{"k", k}, {"nodes", nlohmann::json::array()}, {"links", nlohmann::json::array()}};
    for (const Cell& n : c.nodes) j["nodes"].push_back(n);
    for (const auto& [n, d] : c.links) j["links"].push_back({{"node", n}, {"dir", d == kDirs ? "fb" : dirName(d)}});
    return j;
}

}  // namespace rt
