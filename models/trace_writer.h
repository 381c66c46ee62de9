// VCD and GTKWave save files for the traced nodes.
//
// We write the VCD ourselves rather than with sc_trace: SystemC's writer
// stamps the wall-clock date into the file (so two runs would differ), knows
// no time window, and would need a signal and a delta cycle per change; the
// node records its few value changes directly (node_trace.h) and they are
// written here, in time order, once the frame is done.
#pragma once
#include <string>
#include <vector>

#include "node_trace.h"

namespace rt {

struct TracedNode {
    std::string name;  // "node_x_y_z"
    const NodeTrace* trace;
};

// A boundary's position over time (a real signal) and its slide count.
struct TracedBoundary {
    std::string name;  // "col_u_v_b_k"
    std::vector<std::pair<Picos, double>> positions;
};

// Per node: busy and wait (1 bit), load (real: busy / (busy + wait) over
// windows of about renderTime / 200, 1 ps at least) and queue depth
// (integer), for times in [from, to].
// Per boundary: `position` (real) and `slides` (integer, counts the moves).
void writeVcd(const std::string& path, const std::vector<TracedNode>& nodes,
              const std::vector<TracedBoundary>& boundaries, Picos from, Picos to, Picos renderTime,
              const std::string& incomplete = "");  // non-empty: why the run stopped early ($comment)
// A .gtkw save file that groups each node's signals, so GTKWave opens
// straight to them: gtkwave -a FILE.gtkw (or gtkwave FILE.vcd FILE.gtkw).
// [from, to] is the traced window, which it opens zoomed to.
void writeGtkw(const std::string& path, const std::string& vcdPath, const std::vector<TracedNode>& nodes,
               const std::vector<TracedBoundary>& boundaries, Picos from, Picos to);
// FILE.vcd -> FILE.gtkw
std::string gtkwPathFor(const std::string& vcdPath);
// The load window the VCD uses for a frame of this length.
Picos loadWindow(Picos renderTime);

}  // namespace rt
