#include "balance/between_frames.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "balance/frame_forecast.h"
#include "balance/move_forecast.h"
#include "lattice.h"

namespace rt {
namespace {

// The frame ran on this mesh and progress axis.
void checkSameMachine(const FrameState& r, const MachineConfig& m) {
    if (r.dims != m.dims || r.axis != m.balance.axis) throw std::runtime_error("its run is of another mesh or progress axis");
}

}  // namespace

InnerPlanes lastBoundaries(const FrameState& r, const MachineConfig& m, bool atStart) {
    const ColumnGeometry g(m.balance.axis, m.dims);
    checkSameMachine(r, m);
    InnerPlanes b(size_t(g.count()), std::vector<double>(size_t(g.length() - 1), std::nan("")));
    for (const BoundaryState& h : r.boundaries) {
        const int k = h.index;
        if (!g.isColumn(h.column[0], h.column[1]) || k < 1 || k >= g.length())
            throw std::runtime_error("a boundary outside the mesh");
        if (h.history.empty()) throw std::runtime_error("a boundary with no history");
        b[size_t(g.indexOf(h.column[0], h.column[1]))][size_t(k - 1)] = (atStart ? h.history.front() : h.history.back()).second;
    }
    for (const auto& c : b)
        for (double x : c)
            if (!std::isfinite(x)) throw std::runtime_error("a boundary missing from its history");
    return b;
}

InnerPlanes uniformBoundaries(const FrameState& r, const MachineConfig& m) {
    checkSameMachine(r, m);
    const ColumnGeometry g(m.balance.axis, m.dims);
    Box world;  // the boxes cover it
    for (const NodeFrameState& s : r.nodes) world.add(s.box);
    if (world.empty()) throw std::runtime_error("a frame with no boxes");
    const Lattice uniform = Lattice::uniform(world, m.dims);  // (held: planes() refers into it)
    const std::vector<double>& p = uniform.planes(g.axis);
    return InnerPlanes(size_t(g.count()), std::vector<double>(p.begin() + 1, p.end() - 1));
}

double timeAveraged(const std::vector<std::pair<double, double>>& history, double end) {
    if (history.empty()) throw std::invalid_argument("resplit: an empty boundary history");
    if (!(end > 0)) return history.back().second;
    double sum = 0;
    for (size_t i = 0; i < history.size(); ++i) {
        const double from = i == 0 ? 0.0 : std::min(history[i].first, end);  // the first position holds from 0
        const double to = i + 1 < history.size() ? std::min(history[i + 1].first, end) : end;
        sum += history[i].second * std::max(0.0, to - from);
    }
    return sum / end;
}

InnerPlanes averagedBoundaries(const FrameState& r, const MachineConfig& m) {
    InnerPlanes planes = lastBoundaries(r, m);  // the same mesh and axis, and every plane there
    const ColumnGeometry g(m.balance.axis, m.dims);
    for (const BoundaryState& h : r.boundaries)
        planes[size_t(g.indexOf(h.column[0], h.column[1]))][size_t(h.index - 1)] = timeAveraged(h.history, r.renderTimeNs);
    return planes;
}

namespace {

// What resplitChoice weighs, forecast once: holding, and each move with
// getting there (move_forecast.h).
struct Moves {
    InnerPlanes now;
    double heldNs;
    struct Move {
        const char* what;
        InnerPlanes planes;
        double ns;
        bool linkBound;  // the links are its frame, and it passes rays on between columns
    };
    std::vector<Move> moves;
};

Moves forecastMoves(const FrameState& r, const MachineConfig& m, const std::vector<Shape>* objects) {
    Moves out;
    out.now = lastBoundaries(r, m);
    const FrameForecast f(r, m, averagedBoundaries(r, m), objects);
    out.heldNs = f.forecast(out.now).frameNs;
    const FrameForecast::Splits s = f.splits();
    const std::pair<const char*, InnerPlanes> candidates[] = {{"aligned", s.aligned}, {"per column", s.perColumn}};
    for (const auto& [what, planes] : candidates) {
        const FrameForecast::Forecast t = f.forecast(planes);
        const bool linkBound = t.passes > 0 && t.linkNs >= t.nodeNs;
        const double ns = t.frameNs + moveNs(r, m, out.now, planes);  // and getting there (move_forecast.h)
        out.moves.push_back({what, planes, ns, linkBound});
    }
    return out;
}

// The planes of the shortest forecast frame, moving only for `gain` over holding.
ResplitChoice choose(const Moves& f, double gain) {
    ResplitChoice c{"held", f.now, f.heldNs, f.heldNs};
    // Columns' own planes pass rays on between columns, which the
    // forecast counts short where the links are the frame: there they
    // must beat the aligned planes by the margin a move needs to beat
    // holding (the case that showed it: doc/history.md, "Figures behind
    // the code's comments").
    for (const Moves::Move& k : f.moves) {
        const double beat = k.linkBound ? (1 - kMinForecastGain) * c.forecastNs : c.forecastNs;
        if (k.ns < beat && k.ns < (1 - gain) * c.heldNs) c = {k.what, k.planes, k.ns, c.heldNs};
    }
    return c;
}

}  // namespace

ResplitChoice resplitChoice(const FrameState& r, const MachineConfig& m, const std::vector<Shape>* objects) {
    return choose(forecastMoves(r, m, objects), kMinForecastGain);
}

InnerPlanes resplitTargets(const FrameState& r, const MachineConfig& m, const std::vector<Shape>* objects) {
    return resplitChoice(r, m, objects).planes;
}

std::optional<InnerPlanes> ResplitSequence::forecast(const FrameState& r) {
    const Moves moves = forecastMoves(r, m_, objects_);  // (once: the try weighs the same forecasts)
    ResplitChoice c = choose(moves, kMinForecastGain);
    std::string what = c.what;
    if (tries_ && !tried_ && what == "held") {  // One try (between_frames.h)
        c = choose(moves, kTryGain);
        if (std::string(c.what) != "held") {
            tried_ = true;
            what = std::string("one try: ") + c.what;
        }
    }
    said_ = {{"next", what}, {"forecast_ns", c.forecastNs}, {"held_forecast_ns", c.heldNs}};
    return c.planes;
}

std::optional<InnerPlanes> ResplitSequence::next(const FrameState& r, int frame) {
    afresh_ = false;
    said_ = {{"next", "frame 1 again"}};
    if (again_) return std::nullopt;
    said_ = {{"next", "held"}};
    if (held_) return held_;
    const double t = r.renderTimeNs;
    if (frame == 1) {
        firstNs_ = t;
        start_ = m_.balance.startsAtObjects() ? uniformBoundaries(r, m_) : lastBoundaries(r, m_, true);
        return forecast(r);
    }
    if (tryingStart_) {  // the frame just run held the starting split
        if (t < firstNs_) {
            held_ = start_;
            return held_;
        }
        again_ = true;
        said_ = {{"next", "frame 1 again"}};
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
            said_ = {{"next", m_.balance.startsAtObjects() ? "the uniform split" : "the starting split"}};
            if (firstHolds_) {  // frame 1 was the starting split: hold it
                held_ = start_;
                return held_;
            }
            if (m_.balance.startsAtObjects()) {  // (sample's trial, the uniform split: kTrialReach)
                const double startNs = FrameForecast(r, m_, averagedBoundaries(r, m_), objects_).forecast(start_).frameNs;
                if (std::isfinite(startNs) && startNs > kTrialReach * firstNs_) {  // it cannot beat frame 1: frame 1 again
                    again_ = true;
                    said_ = {{"next", "frame 1 again"}, {"start_forecast_ns", startNs}};
                    return std::nullopt;
                }
                if (std::isfinite(startNs)) said_["start_forecast_ns"] = startNs;
            }
            tryingStart_ = afresh_ = true;
            return start_;
        }
        return forecast(r);
    }
    if (misses_ >= kPatience) {
        said_ = {{"next", "the fastest frame's planes"}};
        held_ = best_;
        return held_;
    }
    return forecast(r);
}

}  // namespace rt
