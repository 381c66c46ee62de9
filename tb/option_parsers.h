// The values of rtsim's flags that have a syntax of their own: node
// coordinates, times and rates with units, the mesh shape, per-node speeds
// and costs, per-link settings, traced links and the trace window. Parsed
// here without CLI11, so that each can be tested alone
// (tb/tests/test_options.cpp); rtsim_cli.cpp hands them the flags' text.
// Each throws OptionError, whose message names what is wrong and which CLI11
// reports as "FLAG: message" (exit 2).
#pragma once
#include <array>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>

#include "config/machine_config.h"

namespace rt {

struct OptionError : std::invalid_argument {
    OptionError(std::string flag_, const std::string& what) : std::invalid_argument(what), flag(std::move(flag_)) {}
    std::string flag;
};

// "x,y,z" node coordinates.
Cell parseCell(const std::string& flag, const std::string& text);
// A link setting's key in --link-set: its table name with '_' for '-'
// ("control-depth": control_depth).
std::string linkSetKey(const std::string& name);
// --trace-nodes busiest[:K]: K, 1..64 (4 without it).
int parseBusiest(const std::string& text);
// --max-error: a share ("0.02") or a percentage ("2%"), above 0 and below 1.
double parseErrorShare(const std::string& text);
// A non-negative time with a unit ("20ns"), at most 1,000 s.
Picos parseTimeOf(const std::string& flag, const std::string& text);
// A positive rate with a unit ("1GB/s", "10Gb/s").
double parseRateOf(const std::string& flag, const std::string& text);
// --mesh-dims "XxYxZ".
std::array<int, 3> parseMeshDims(const std::string& text);
// --node-speed "x,y,z=SPEED".
std::pair<Cell, double> parseNodeSpeed(const std::string& spec);
// --node-cost "x,y,z:NAME=TIME": that cost in the node's set (a copy of
// `base` where the node has none yet).
void applyNodeCost(const std::string& spec, const Costs& base, std::map<Cell, Costs>& costs);
// --link-set "x,y,z,DIR:latency=T,bandwidth=R,depth=N,control_depth=N,out_depth=N"
// (any subset): the link from the node in direction DIR, and its settings
// (`base` with those given).
std::pair<std::pair<Cell, int>, LinkParams> parseLinkSet(const std::string& spec, const LinkParams& base);
// --trace-links "x,y,z" (every link of the node: direction -1), "x,y,z,DIR"
// or "x,y,z,fb" (its frame-buffer port: kDirs).
std::pair<Cell, int> parseTraceLink(const std::string& spec);
// --trace-window "FROM,TO".
std::pair<Picos, Picos> parseTraceWindow(const std::string& text);

}  // namespace rt
