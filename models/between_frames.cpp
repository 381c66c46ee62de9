#include "between_frames.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "resplit.h"

namespace rt {
namespace {

// The report is of this mesh and progress axis.
void checkSameMachine(const nlohmann::json& r, const MachineConfig& m) {
    const auto dims = r.at("config").at("mesh").get<std::array<int, 3>>();
    const std::string axis = r.at("config").at("balance").at("axis").get<std::string>();
    if (dims != m.dims || axis != std::string(1, "xyz"[m.balance.axis]))
        throw std::runtime_error("its run is of another mesh or progress axis");
}

// A JSON error in a report, said as one line.
template <class F>
auto readReport(F f) -> decltype(f()) {
    try {
        return f();
    } catch (const nlohmann::json::exception& e) {
        throw std::runtime_error(std::string("not an rtsim report (") + e.what() + ")");
    }
}

// A node's busy time in the frame of its report entry `node`, where it
// happened: its tracing work by position (work_by_position, bins fixed in
// the world), the rest spread evenly over [boxLo, boxHi].
void addNodeWork(const nlohmann::json& node, double boxLo, double boxHi, std::vector<WorkPiece>& pieces) {
    double rest = node.at("busy_ns").get<double>();
    if (node.contains("work_by_position")) {
        const auto& w = node.at("work_by_position");
        const double from = w.at("axis_from").get<double>(), width = w.at("bin_width").get<double>();
        double k = w.at("first_bin").get<double>();
        for (const auto& v : w.at("ns")) {
            const double work = v.get<double>();
            pieces.push_back({from + k * width, from + (k + 1) * width, work});
            rest -= work;
            ++k;
        }
    }
    pieces.push_back({boxLo, boxHi, std::max(0.0, rest)});
}

}  // namespace

InnerPlanes lastBoundaries(const nlohmann::json& r, const MachineConfig& m, bool atStart) {
    const ColumnGeometry g(m.balance.axis, m.dims);
    return readReport([&] {
        checkSameMachine(r, m);
        InnerPlanes b(size_t(g.count()), std::vector<double>(size_t(g.length() - 1), std::nan("")));
        for (const auto& h : r.at("boundaries")) {
            const auto col = h.at("column").get<std::array<int, 2>>();
            const int k = h.at("index").get<int>();
            if (!g.isColumn(col[0], col[1]) || k < 1 || k >= g.length())
                throw std::runtime_error("a boundary outside the mesh");
            const auto& history = h.at("history");
            b[size_t(g.indexOf(col[0], col[1]))][size_t(k - 1)] = (atStart ? history.front() : history.back()).at(1).get<double>();
        }
        for (const auto& c : b)
            for (double x : c)
                if (!std::isfinite(x)) throw std::runtime_error("a boundary missing from its history");
        return b;
    });
}

InnerPlanes resplitTargets(const nlohmann::json& r, const MachineConfig& m, double step) {
    const InnerPlanes check = lastBoundaries(r, m);  // the same mesh and axis
    const ColumnGeometry g(m.balance.axis, m.dims);
    const int ax = g.axis, n = g.length();
    return readReport([&] {
        const double end = r.at("render_time_ns").get<double>();
        double lo = 1e300, hi = -1e300;
        for (const auto& node : r.at("nodes")) {
            const auto box = node.at("box").get<std::array<std::array<double, 3>, 2>>();
            lo = std::min(lo, box[0][size_t(ax)]);
            hi = std::max(hi, box[1][size_t(ax)]);
        }
        // Each column's planes as they stood on average over the frame.
        std::vector<std::vector<double>> edges(check.size(), std::vector<double>(size_t(n + 1), 0.0));
        for (auto& e : edges) {
            e.front() = lo;
            e.back() = hi;
        }
        for (const auto& h : r.at("boundaries")) {
            const auto col = h.at("column").get<std::array<int, 2>>();
            std::vector<std::pair<double, double>> history;
            for (const auto& p : h.at("history")) history.push_back({p.at(0).get<double>(), p.at(1).get<double>()});
            edges[size_t(g.indexOf(col[0], col[1]))][size_t(h.at("index").get<int>())] = timeAveraged(history, end);
        }
        std::vector<std::vector<WorkPiece>> pieces(check.size());
        for (const auto& node : r.at("nodes")) {
            const auto c = node.at("node").get<std::array<int, 3>>();
            const size_t col = size_t(g.columnOf(c)), k = size_t(c[size_t(ax)]);
            addNodeWork(node, edges.at(col).at(k), edges.at(col).at(k + 1), pieces[col]);
        }
        const double minThickness = m.balance.minThickness * (hi - lo) / n;
        InnerPlanes targets;
        for (size_t c = 0; c < edges.size(); ++c) {
            const std::vector<double> now(edges[c].begin() + 1, edges[c].end() - 1);
            std::vector<double> t = resplitPlanes(pieces[c], lo, hi, n, minThickness, now);
            if (step < 1)  // from where they ended
                for (size_t k = 0; k < t.size(); ++k) t[k] = check[c][k] + step * (t[k] - check[c][k]);
            targets.push_back(std::move(t));
        }
        return targets;
    });
}

std::optional<InnerPlanes> ResplitSequence::next(const nlohmann::json& r, int frame) {
    afresh_ = false;
    if (again_) return std::nullopt;
    if (held_) return held_;
    const double t = r.at("render_time_ns").get<double>();
    if (frame == 1) {
        firstNs_ = t;
        start_ = lastBoundaries(r, m_, true);
        return resplitTargets(r, m_);
    }
    if (tryingStart_) {  // the frame just run held the starting split
        if (t < firstNs_) {
            held_ = start_;
            return held_;
        }
        again_ = true;
        return std::nullopt;
    }
    ++resplits_;
    const bool faster = t <= bestNs_;
    misses_ = faster ? 0 : misses_ + 1;
    if (faster) {
        bestNs_ = t;
        best_ = lastBoundaries(r, m_);
    }
    if (bestNs_ > firstNs_) {  // no re-split frame has beaten the first yet
        if (resplits_ >= kTries) {
            if (firstHolds_) {  // frame 1 was the starting split: hold it
                held_ = start_;
                return held_;
            }
            tryingStart_ = afresh_ = true;
            return start_;
        }
        return resplitTargets(r, m_, kStep);
    }
    if (misses_ >= kPatience) {
        held_ = best_;
        return held_;
    }
    return resplitTargets(r, m_, kStep);
}

}  // namespace rt
