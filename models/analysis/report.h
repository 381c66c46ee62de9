// The JSON report of a run: configuration echo, render time, per node
// busy/wait/load and counts, per link messages and bytes by type, queue
// high-water marks, host and kernel statistics. Fields whose name contains
// "wall" are wall-clock measurements; everything else is deterministic.
#pragma once
#include <memory>
#include <string>
#include <utility>
#include <vector>
#include <nlohmann/json.hpp>

#include "machine/machine.h"

namespace rt {

// How much of each node and link the report keeps (--report-detail; doc/report.md,
// "Report detail"). Summary keeps what the summary, the mesh map, the frame
// loop (a node's grid and work by position: `resplit`'s forecast) and
// scripts read, and leaves out what grows with the mesh but few read: a
// node's balancing intervals, a link's settings, counts by message type,
// latency percentiles and high-water marks. A 32x32x32 mesh's report was
// 334 MB.
enum class ReportDetail { Full, Summary };

// A top-level array of a report, its entries made one at a time as the
// report is written instead of held as a JSON tree: a 32x32x32 mesh has
// 32,768 nodes and 223,000 links, and as a tree they were the larger part
// of the process's peak memory and of the report's time (figures:
// doc/history.md, "At 32x32x32").
class ReportEntries {
public:
    virtual ~ReportEntries() = default;
    virtual size_t size() const = 0;
    virtual nlohmann::json operator[](size_t i) const = 0;
};

// A report as it is written: every field in `json`, but for the arrays in
// `made` (`json` holds an empty array at each of their keys), whose
// entries the writer asks for one at a time.
struct Report {
    nlohmann::json json;
    std::vector<std::pair<std::string, std::shared_ptr<const ReportEntries>>> made;
    // The entries at top-level `key`, if they are made as written.
    const ReportEntries* madeAt(const std::string& key) const;
    // `json` with every entry in it.
    nlohmann::json whole() &&;
};

// The report of `r`; its nodes' and links' entries read `r`, which must
// outlive it.
Report machineReportOf(const MachineResult& r, const MachineConfig& config, ReportDetail detail);
// The whole of it as one JSON tree.
nlohmann::json machineReport(const MachineResult& r, const MachineConfig& config,
                             ReportDetail detail = ReportDetail::Full);
// A node's `load`: its busy share of the frame.
double loadOf(const NodeStats& s);
// Its `config`: every machine setting, as the run used it, for an image of
// width x height.
nlohmann::json machineConfigJson(const MachineConfig& config, int width, int height);

// A report's `links` (their indices) ranked by what held the frame back:
// the time the wire was busy with messages waiting for it (saturated_ns),
// then the utilisation; ties keep the report's order. `busiest_links` and
// --trace-nodes busiest take their first.
std::vector<size_t> linksByBacklog(const nlohmann::json& links);
// The same from each link's (saturated_ns, utilisation).
std::vector<size_t> rankedByBacklog(const std::vector<std::pair<double, double>>& key);

}  // namespace rt
