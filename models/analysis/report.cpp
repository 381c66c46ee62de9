#include "analysis/report.h"

#include <algorithm>
#include <tuple>
#include <vector>

#include "analysis/bounds.h"
#include "counters_json.h"
#include "analysis/stability.h"
#include "machine/frame_state_of.h"

namespace rt {
namespace {

nlohmann::json cellJson(const Cell& c) { return {c[0], c[1], c[2]}; }

// Each row of a parameter table with an echo, at its place in `j`, in the
// report's units (base/param.h).
template <class S>
void echoParams(nlohmann::json& j, const std::vector<Param<S>>& rows, const S& s) {
    for (const Param<S>& p : rows) {
        if (!p.echo) continue;
        nlohmann::json& at = j[nlohmann::json::json_pointer(p.echo)];
        switch (p.kind) {
            case ParamKind::Time: at = inNs(fieldOf<Picos>(p, s)); break;
            case ParamKind::Rate: at = fieldOf<double>(p, s); break;
            case ParamKind::Real:
                if (p.word && fieldOf<double>(p, s) == p.wordValue) at = p.word;  // (not chosen: unused)
                else at = fieldOf<double>(p, s);
                break;
            case ParamKind::Count:
                if (p.word && fieldOf<int>(p, s) == p.wordValue) at = p.word;  // (not chosen: unused)
                else at = fieldOf<int>(p, s);
                break;
            case ParamKind::Choice: at = fieldOf<bool>(p, s) ? p.on : p.off; break;
            default: break;
        }
    }
}

nlohmann::json costsJson(const Costs& c) {
    nlohmann::json j = nlohmann::json::object();
    echoParams(j, costParams(), c);
    return j;
}

nlohmann::json linkJson(const LinkParams& l) {
    nlohmann::json j = nlohmann::json::object();
    echoParams(j, linkParams(), l);
    if (l.engine) j["engine_ns"] = inNs(l.engine);  // --hop-handling link: the sending engine's time per message
    return j;
}

// Latencies in ps: p50, p95 and max in ns (histogram.h: exact for a few
// distinct values, within 0.8 % beyond).
nlohmann::json percentilesJson(const Histogram& h) {
    return {{"p50", h.percentile(0.5) / 1000.0}, {"p95", h.percentile(0.95) / 1000.0}, {"max", inNs(Picos(h.max()))}};
}

}  // namespace

nlohmann::json machineConfigJson(const MachineConfig& cfg, int width, int height) {
    nlohmann::json c;
    c["mesh"] = {cfg.dims[0], cfg.dims[1], cfg.dims[2]};
    c["image"] = {width, height};
    // The machine's parameters (config/machine_config.h), then what the
    // special flags set and what the machine derives.
    echoParams(c, machineParams(), cfg);
    c["costs"] = costsJson(cfg.costs);
    c["link"] = linkJson(cfg.link);
    c["fb_port"] = linkJson(cfg.fbPort);
    const BalanceConfig& bc = cfg.balance;
    c["balance"] = nlohmann::json::object();
    echoParams(c["balance"], balanceParams(), bc);
    c["balance"]["policy"] = bc.policy;
    c["balance"]["axis"] = std::string(1, "xyz"[bc.axis]);
    c["balance"]["gain"] = bc.gainOf();
    c["balance"]["guard"] = bc.guard;
    if (!bc.recommendedWhy.empty()) c["balance"]["recommended"] = bc.recommendedWhy;  // how --balance recommended chose
    if (!bc.startMixWhy.empty()) c["balance"]["start_mix_auto"] = bc.startMixWhy;  // how --start-mix auto chose
    if (!bc.sampleEndWhy.empty()) c["balance"]["sample_end_auto"] = bc.sampleEndWhy;  // how --sample-end auto chose
    for (const auto& [cell, s] : cfg.nodeSpeed) c["node_speed"].push_back({{"node", cellJson(cell)}, {"speed", s}});
    for (const auto& [cell, k] : cfg.nodeCosts) c["node_costs"].push_back({{"node", cellJson(cell)}, {"costs", costsJson(k)}});
    for (const auto& [key, l] : cfg.linkOverride)
        c["link_overrides"].push_back({{"node", cellJson(key.first)}, {"dir", dirName(key.second)}, {"link", linkJson(l)}});
    c["quantum_ns"] = inNs(cfg.lookaheadQuantum ? cfg.lookahead() : cfg.quantum);
    c["quantum"] = cfg.lookaheadQuantum ? "lookahead" : "fixed";  // lookahead: each process its own, quantum_ns the smallest
    auto& tr = c["trace"];
    tr["nodes"] = nlohmann::json::array();
    for (const Cell& n : cfg.traceNodes) tr["nodes"].push_back(cellJson(n));
    tr["links"] = nlohmann::json::array();
    for (const auto& [n, d] : cfg.traceLinks)
        tr["links"].push_back({{"node", cellJson(n)}, {"dir", d < 0 ? "all" : d == kDirs ? "fb" : dirName(d)}});
    tr["window_ns"] = cfg.traceTo == ~Picos(0) ? nlohmann::json{inNs(cfg.traceFrom), nullptr}  // (to the end)
                                                : nlohmann::json{inNs(cfg.traceFrom), inNs(cfg.traceTo)};
    return c;
}

namespace {

nlohmann::json busyPartsJson(const BusyParts& p) {
    nlohmann::json j = nlohmann::json::object();
    for (int k = 0; k < kBusyKinds; ++k) j[busyKindName(k)] = inNs(p[size_t(k)]);
    return j;
}

nlohmann::json binnedJson(const Binned& b, const char* values) {
    return {{"first_bin", b.firstBin}, {values, b.values}};
}

// Where along the axis the node's work happened (`resplit`'s forecast,
// frame_forecast.h): bin k is axis_from + [k, k + 1) x bin_width.
nlohmann::json workByPositionJson(const WorkAlongAxis& w) {
    nlohmann::json wj;
    wj["axis_from"] = w.axisFrom;
    wj["bin_width"] = w.binWidth;
    wj["first_bin"] = w.ns.firstBin;
    wj["ns"] = w.ns.values;
    if (w.within) wj["within"] = binnedJson(*w.within, "ns");
    wj["face_handling_ns"] = w.faceHandlingNs;
    wj["face_crossings"] = w.faceCrossings;
    wj["cuts_up"] = binnedJson(w.cuts[0], "rays");
    wj["cuts_down"] = binnedJson(w.cuts[1], "rays");
    for (int d = 0; d < 6; ++d)
        if (w.lateral[size_t(d)]) wj["lateral"][linkSuffix(d)] = binnedJson(*w.lateral[size_t(d)], "rays");
    return wj;
}

// Per node: its box, time, counts and (`full`) balancing intervals.
nlohmann::json nodeJson(const MachineResult& r, const NodeFrameState& st, size_t i, bool full) {
    const NodeStats& s = r.nodes[i];
    nlohmann::json n;
    n["node"] = cellJson(r.cells[i]);
    n["box"] = {{r.boxes[i].lo.x, r.boxes[i].lo.y, r.boxes[i].lo.z}, {r.boxes[i].hi.x, r.boxes[i].hi.y, r.boxes[i].hi.z}};
    n["objects"] = r.objectsPerNode[i];
    n["object_bytes"] = r.objectBytesPerNode[i];
    if (i < r.grids.size() && r.grids[i]) {
        const Box& b = r.grids[i]->span;
        n["grid"] = {{"cells", r.grids[i]->cells}, {"span", {{b.lo.x, b.lo.y, b.lo.z}, {b.hi.x, b.hi.y, b.hi.z}}}};
    }
    n["busy_ns"] = inNs(s.busy);
    n["wait_ns"] = inNs(s.wait);  // busy + wait = render time (checked at the end of every run)
    n["blocked_ns"] = inNs(s.blocked);  // of the wait: on a full output buffer (--link-out-depth)
    n["busy_by_category"] = busyPartsJson(s.busyBy);  // sums to busy_ns (in whole ps)
    n["load"] = loadOf(s);
    n["rays_traced"] = s.raysTraced;
    n["rays_generated"] = s.raysGenerated;
    n["rays_forwarded"] = s.raysForwarded;
    n["rays_passed"] = s.raysPassed;  // of those, sent on without tracing (a face elsewhere)
    n["rays_passed_between_columns"] = s.raysPassedBetweenColumns;  // of those, from another column
    if (r.express) {  // --fidelity express: of rays_forwarded, sent past empty boxes in one event
        n["rays_expressed"] = s.raysExpressed;
        n["boxes_skipped"] = s.boxesSkipped;
    }
    n["rays_created"] = s.raysCreated;
    n["rays_terminated"] = s.raysTerminated;
    n["messages_sent"] = s.messagesSent;
    n["messages_received"] = s.messagesReceived;
    n["contributions_sent"] = s.contributionsSent;
    n["queue_high_water"] = s.queueHighWater;
    n["last_active_ns"] = inNs(s.lastActive);
    n["counters"] = countersJson(s.counters);
    n["slides_given"] = s.slides.size();
    n["slides_taken"] = s.slidesTaken;
    n["objects_sent"] = s.objectsSent;
    n["objects_received"] = s.objectsReceived;
    if (st.work) n["work_by_position"] = workByPositionJson(*st.work);
    if (full && !s.balance.intervals.empty()) {
        auto& iv = n["intervals"];
        iv["intervals_per_record"] = s.balance.intervalsPerRecord;  // > 1: merged to bound the report
        for (const IntervalRecord& x : s.balance.intervals) {
            iv["end_ns"].push_back(inNs(x.end));
            iv["busy_ns"].push_back(inNs(x.busy));
            iv["wait_ns"].push_back(inNs(x.wait));
        }
    }
    return n;
}

// The wire's busy time over the frame (a port's channels are wires side by
// side: their busy time over the frame's as many).
double utilisationOf(const LinkReport& l, Picos renderTime) {
    return renderTime ? double(l.stats().wireBusy()) / (double(renderTime) * l.channels) : 0.0;
}

// Per link: messages, bytes and wire time by type, utilisation, waits and
// (--link-stats full) latency percentiles and high-water marks.
nlohmann::json linkJsonOf(const LinkReport& l, Picos renderTime, bool distributions, bool full) {
    const LinkStats& st = l.stats();
    nlohmann::json lj;
    lj["name"] = l.name;
    lj["from"] = cellJson(l.from);
    lj["to"] = l.dir < 0 ? "fb" : dirName(l.dir);
    if (full) lj["params"] = linkJson(l.params);
    for (int t = 0; full && t < kMsgTypes; ++t) {
        const char* name = msgTypeName(MsgType(t));
        lj["messages"][name] = st.messages[size_t(t)];
        lj["bytes"][name] = st.bytes[size_t(t)];
        lj["wire_ns"][name] = inNs(st.wire[size_t(t)]);
    }
    lj["wire_busy_ns"] = inNs(st.wireBusy());
    lj["channels"] = l.channels;
    lj["utilisation"] = utilisationOf(l, renderTime);
    lj["saturated_ns"] = inNs(st.saturated);  // busy with a backlog waiting for the wire
    if (distributions) lj["peak_utilisation"] = st.windows.peak(renderTime, l.channels);
    if (!full) return lj;
    lj["consumed"] = st.consumed;
    lj["slot_wait_ns"] = inNs(st.slotWait);
    lj["wire_wait_ns"] = inNs(st.wireWait);
    if (distributions) {  // (--link-stats counts: not kept)
        if (st.latency.count()) lj["latency_ns"] = percentilesJson(st.latency);
        if (st.controlLatency.count()) lj["control_latency_ns"] = percentilesJson(st.controlLatency);
        lj["backlog_high_water"] = st.backlogHighWater;
        lj["peak_window_ns"] = inNs(st.windows.width());
        lj["buffer_high_water"] = st.bufferHighWater;
    }
    return lj;
}

// The links' entries, made as the report is written.
class LinkEntries final : public ReportEntries {
public:
    LinkEntries(const MachineResult& r, bool distributions, bool full) : r_(r), distributions_(distributions), full_(full) {}
    size_t size() const override { return r_.links.size(); }
    nlohmann::json operator[](size_t i) const override {
        return linkJsonOf(r_.links[i], r_.renderTime, distributions_, full_);
    }

private:
    const MachineResult& r_;
    bool distributions_, full_;
};

// The nodes' entries, made as the report is written.
class NodeEntries final : public ReportEntries {
public:
    NodeEntries(const MachineResult& r, FrameState st, bool full) : r_(r), st_(std::move(st)), full_(full) {}
    size_t size() const override { return r_.nodes.size(); }
    nlohmann::json operator[](size_t i) const override { return nodeJson(r_, st_.nodes[i], i, full_); }

private:
    const MachineResult& r_;
    const FrameState st_;
    bool full_;
};

// An array of `entries` at top-level `key`: made as written, or null
// where it has none (as a tree that was never pushed to).
void addMade(Report& rep, const char* key, std::shared_ptr<const ReportEntries> entries) {
    if (entries->size() == 0) {
        rep.json[key] = nullptr;
        return;
    }
    rep.json[key] = nlohmann::json::array();
    rep.made.emplace_back(key, std::move(entries));
}

// The links (made as the report is written: LinkEntries), the three
// busiest wires (ties: the first in the list) and the totals by message
// type.
void addLinks(Report& rep, const MachineResult& r, const MachineConfig& cfg, const FrameState& st, bool full) {
    nlohmann::json& j = rep.json;
    std::array<uint64_t, kMsgTypes> msgs{}, bytes{};
    std::vector<std::pair<double, double>> key;  // (saturated_ns, utilisation), as each entry has them
    key.reserve(r.links.size());
    for (const LinkReport& l : r.links) {
        const LinkStats& st = l.stats();
        for (size_t t = 0; t < size_t(kMsgTypes); ++t) {
            msgs[t] += st.messages[t];
            bytes[t] += st.bytes[t];
        }
        key.push_back({inNs(st.saturated), utilisationOf(l, r.renderTime)});
    }
    addMade(rep, "links", std::make_shared<LinkEntries>(r, cfg.linkDistributions, full));
    const std::vector<size_t> busiest = rankedByBacklog(key);
    j["busiest_links"] = nlohmann::json::array();
    for (size_t i = 0; i < std::min<size_t>(3, busiest.size()); ++i) {
        const LinkReport& l = r.links[busiest[i]];
        nlohmann::json b = {{"name", l.name}, {"utilisation", key[busiest[i]].second}, {"saturated_ns", key[busiest[i]].first}};
        if (cfg.linkDistributions) b["peak_utilisation"] = l.stats().windows.peak(r.renderTime, l.channels);
        j["busiest_links"].push_back(std::move(b));
    }
    j["totals"]["ray_wire_ns"] = st.rayWireNs;  // resplit's forecast (frame_forecast.h); a summary has no per-link wire_ns
    for (int t = 0; t < kMsgTypes; ++t) {
        j["totals"]["messages"][msgTypeName(MsgType(t))] = msgs[size_t(t)];
        j["totals"]["bytes"][msgTypeName(MsgType(t))] = bytes[size_t(t)];
    }
}

// The frame buffer: per unit, and its busiest unit's busy time (the floor
// the frame buffer puts under the frame: its bound).
nlohmann::json frameBufferJson(const MachineResult& r, const Bounds& bd) {
    nlohmann::json fb;
    Picos total = 0;
    uint64_t contributions = 0;
    for (size_t u = 0; u < r.frameBuffer.size(); ++u) {
        const FrameBufferStats& s = r.frameBuffer[u].stats;
        total += s.busy;
        contributions += s.contributions;
        fb["units"].push_back({{"unit", u},
                               {"busy_ns", inNs(s.busy)},
                               {"last_active_ns", inNs(s.lastActive)},
                               {"contributions", s.contributions},
                               {"contribution_messages", s.contributionMessages},
                               {"credit_messages", s.creditMessages}});
    }
    fb["busy_ns"] = inNs(bd.frameBuffer);
    fb["busy_total_ns"] = inNs(total);
    fb["contributions"] = contributions;
    return fb;
}

// Balancing: the number of slides, how even the loads are (max / mean)
// over the whole frame, whether the boundaries settled, the decisions,
// what the guard stopped, and how old the loads they used were (the older
// of the two, in intervals).
nlohmann::json balanceJson(const MachineResult& r, const MachineConfig& cfg) {
    const size_t slides = slideCount(r.boundaries);
    double maxLoad = 0, sumLoad = 0;
    for (const NodeStats& n : r.nodes) {
        maxLoad = std::max(maxLoad, loadOf(n));
        sumLoad += loadOf(n);
    }
    nlohmann::json b = {{"slides", slides},
                        {"max_over_mean_load", sumLoad > 0 ? maxLoad / (sumLoad / double(r.nodes.size())) : 0.0}};
    const int ax = cfg.balance.axis;
    const StabilityVerdict st = judgeStability(r.boundaries, r.renderTime, r.worldBox.extent()[ax] / cfg.dims[ax]);
    b["stability"] = stabilityName(st.overall);
    b["boundaries_converged"] = st.converged;
    b["boundaries_oscillating"] = st.oscillating;
    b["boundaries_diverging"] = st.diverging;
    BalanceStats all;
    for (const NodeStats& s : r.nodes) {
        all.decisions += s.balance.decisions;
        all.skippedStale += s.balance.skippedStale;
        all.skippedLatency += s.balance.skippedLatency;
        all.skippedCost += s.balance.skippedCost;
        all.skippedBusyLink += s.balance.skippedBusyLink;
        all.ages.merge(s.balance.ages);
    }
    b["decisions"] = all.decisions;
    b["guard_stale"] = all.skippedStale;
    b["guard_latency"] = all.skippedLatency;
    b["guard_cost"] = all.skippedCost;
    b["guard_busy_link"] = all.skippedBusyLink;
    if (all.ages.count() > 0)
        b["load_age_intervals"] = {{"median", all.ages.percentile(0.5) / BalanceStats::kAgeUnits},
                                   {"p95", all.ages.percentile(0.95) / BalanceStats::kAgeUnits},
                                   {"max", double(all.ages.max()) / BalanceStats::kAgeUnits}};
    return b;
}

nlohmann::json boundariesJson(const FrameState& st) {
    nlohmann::json out = nlohmann::json::array();  // empty, not missing, with one node along the axis
    for (const BoundaryState& h : st.boundaries) {
        nlohmann::json bj;
        bj["column"] = {h.column[0], h.column[1]};
        bj["index"] = h.index;
        for (const auto& [t, x] : h.history) bj["history"].push_back({t, x});
        out.push_back(bj);
    }
    return out;
}

}  // namespace

std::vector<size_t> rankedByBacklog(const std::vector<std::pair<double, double>>& key) {
    std::vector<size_t> idx(key.size());
    for (size_t i = 0; i < idx.size(); ++i) idx[i] = i;
    std::stable_sort(idx.begin(), idx.end(), [&](size_t a, size_t b) { return key[a] > key[b]; });
    return idx;
}

std::vector<size_t> linksByBacklog(const nlohmann::json& links) {
    std::vector<std::pair<double, double>> key;  // (saturated_ns, utilisation)
    for (const auto& l : links) key.push_back({l.at("saturated_ns").get<double>(), l.at("utilisation").get<double>()});
    return rankedByBacklog(key);
}

double loadOf(const NodeStats& s) { return s.busy + s.wait ? double(s.busy) / double(s.busy + s.wait) : 0.0; }

const ReportEntries* Report::madeAt(const std::string& key) const {
    for (const auto& [k, entries] : made)
        if (k == key) return entries.get();
    return nullptr;
}

nlohmann::json Report::whole() && {
    for (const auto& [key, entries] : made) {
        nlohmann::json& to = json[key];
        for (size_t i = 0; i < entries->size(); ++i) to.push_back((*entries)[i]);
    }
    made.clear();
    return std::move(json);
}

nlohmann::json machineReport(const MachineResult& r, const MachineConfig& cfg, ReportDetail detail) {
    return machineReportOf(r, cfg, detail).whole();
}

Report machineReportOf(const MachineResult& r, const MachineConfig& cfg, ReportDetail detail) {
    const bool full = detail == ReportDetail::Full;
    FrameState st = frameStateOf(r, cfg);  // what the next frame takes: serialised as it is
    Report rep;
    nlohmann::json& j = rep.json;
    j["config"] = machineConfigJson(cfg, r.image.width, r.image.height);
    j["render_time_ns"] = inNs(r.renderTime);
    if (!r.incomplete.empty()) j["incomplete"] = r.incomplete;  // stopped by the watchdog: every figure up to then
    j["wall_s"] = r.wallSeconds;
    j["wall_elaboration_s"] = r.wallElaborationSeconds;  // of wall_s: building the machine, to the first event
    j["wall_startup_s"] = r.wallStartupSeconds;  // the process, to the first event (reading the scene included)
    NodeStats total;
    for (size_t i = 0; i < r.nodes.size(); ++i) {
        const NodeStats& s = r.nodes[i];
        total.busy += s.busy;
        total.busyBy += s.busyBy;
        total.blocked += s.blocked;
        total.raysForwarded += s.raysForwarded;
        total.raysPassed += s.raysPassed;
        total.raysPassedBetweenColumns += s.raysPassedBetweenColumns;
        total.raysExpressed += s.raysExpressed;
        total.boxesSkipped += s.boxesSkipped;
    }
    addLinks(rep, r, cfg, st, full);
    j["totals"]["busy_ns"] = inNs(total.busy);
    j["totals"]["busy_by_category"] = busyPartsJson(total.busyBy);
    j["totals"]["blocked_ns"] = inNs(total.blocked);
    j["totals"]["rays_forwarded"] = total.raysForwarded;
    j["totals"]["rays_passed"] = total.raysPassed;
    j["totals"]["rays_passed_between_columns"] = total.raysPassedBetweenColumns;
    if (r.express) {
        j["totals"]["rays_expressed"] = total.raysExpressed;
        j["totals"]["boxes_skipped"] = total.boxesSkipped;
    }
    j["totals"]["primary_misses"] = r.primaryMisses;
    const Bounds bd = renderTimeBounds(r, cfg);  // bounds.h
    j["frame_buffer"] = frameBufferJson(r, bd);
    // Each bound in ns and as a fraction of the render time.
    auto bound = [&](Picos t) {
        return nlohmann::json{{"ns", inNs(t)}, {"fraction", r.renderTime ? double(t) / double(r.renderTime) : 0.0}};
    };
    j["bounds"] = {{"perfect", bound(bd.perfect)}, {"column", bound(bd.column)}, {"frame_buffer", bound(bd.frameBuffer)}};
    j["kernel"] = {{"delta_cycles", r.deltaCycles}};
    j["boundaries"] = boundariesJson(st);
    j["balance"] = balanceJson(r, cfg);
    addMade(rep, "nodes", std::make_shared<NodeEntries>(r, std::move(st), full));
    return rep;
}

}  // namespace rt
