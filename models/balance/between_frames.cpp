#include "balance/between_frames.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "balance/frame_forecast.h"
#include "balance/move_forecast.h"
#include "balance/plane_spacing.h"
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
    double uniformNs;  // the unbalanced frame's: the uniform split held
    struct Move {
        const char* what;
        InnerPlanes planes;
        double ns;
        bool linkBound;  // the links are its frame, and it passes rays on between columns
        double inPlaceNs;  // its frame, each node starting when its faces are in place (facesInPlaceNs)
    };
    std::vector<Move> moves;
};

Moves forecastMoves(const FrameState& r, const MachineConfig& m, const std::vector<Shape>* objects) {
    Moves out;
    out.now = lastBoundaries(r, m);
    const FrameForecast f(r, m, averagedBoundaries(r, m), objects);
    out.heldNs = f.forecast(out.now).frameNs;
    out.uniformNs = f.forecast(uniformBoundaries(r, m)).frameNs;
    const FrameForecast::Splits s = f.splits();
    const std::pair<const char*, InnerPlanes> candidates[] = {{"aligned", s.aligned}, {"per column", s.perColumn}};
    for (const auto& [what, planes] : candidates) {
        const FrameForecast::Forecast t = f.forecast(planes);
        const bool linkBound = t.passes > 0 && t.linkNs >= t.nodeNs;
        const double ns = t.frameNs + moveNs(r, m, out.now, planes);  // and getting there (move_forecast.h)
        double inPlaceNs = 0;
        if (ns < (1 - std::min(kMinForecastGain, kTryGain)) * out.heldNs) {  // (only where choose() can take it)
            const InnerPlanes start = facesInPlaceNs(r, m, out.now, planes, objects);
            inPlaceNs = f.forecast(planes, &start).frameNs;
        }
        out.moves.push_back({what, planes, ns, linkBound, inPlaceNs});
    }
    return out;
}

// The planes of the shortest forecast frame, moving only for `gain` over
// holding, and only where the move would not lose against not balancing.
ResplitChoice choose(const Moves& f, double gain) {
    ResplitChoice c{"held", f.now, f.heldNs, f.heldNs};
    const Moves::Move* refused = nullptr;
    // Columns' own planes pass rays on between columns, which the
    // forecast counts short where the links are the frame: there they
    // must beat the aligned planes by the margin a move needs to beat
    // holding (the case that showed it: doc/history.md, "Figures behind
    // the code's comments").
    for (const Moves::Move& k : f.moves) {
        const double beat = k.linkBound ? (1 - kMinForecastGain) * c.forecastNs : c.forecastNs;
        if (!(k.ns < beat && k.ns < (1 - gain) * c.heldNs)) continue;
        // A move whose frame, its handovers followed one by one, is
        // forecast more than kMinForecastGain slower than the uniform
        // split's is refused (ResplitChoice).
        if (k.inPlaceNs > (1 + kMinForecastGain) * f.uniformNs) {
            refused = &k;
            continue;
        }
        c = {k.what, k.planes, k.ns, c.heldNs, k.inPlaceNs};
    }
    if (refused) {
        c.refused = refused->what;
        c.refusedNs = refused->ns;
        c.refusedInPlaceNs = refused->inPlaceNs;
    }
    if (c.inPlaceNs > 0 || refused) c.uniformNs = f.uniformNs;
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
        const ResplitChoice held = c;
        c = choose(moves, kTryGain);
        if (std::string(c.what) != "held") {
            tried_ = true;
            what = std::string("one try: ") + c.what;
        }
        if (!c.refused && held.refused) {  // (what the margin's choice refused, said)
            c.refused = held.refused;
            c.refusedNs = held.refusedNs;
            c.refusedInPlaceNs = held.refusedInPlaceNs;
            c.uniformNs = held.uniformNs;
        }
    }
    said_ = {{"next", what}, {"forecast_ns", c.forecastNs}, {"held_forecast_ns", c.heldNs}};
    if (c.inPlaceNs > 0) said_["faces_in_place_forecast_ns"] = c.inPlaceNs;
    if (c.refused)
        said_["refused"] = {{"what", c.refused}, {"forecast_ns", c.refusedNs}, {"faces_in_place_forecast_ns", c.refusedInPlaceNs}};
    if (c.uniformNs > 0) said_["unbalanced_forecast_ns"] = c.uniformNs;
    return c.planes;
}

namespace {

Busiest busiestOf(const FrameState& r, int axis) {
    const NodeFrameState* most = &r.nodes.at(0);
    for (const NodeFrameState& n : r.nodes)
        if (n.busyNs > most->busyNs) most = &n;
    Busiest b{most->cell};
    for (const NodeFrameState& n : r.nodes) {
        Cell c = n.cell;
        const int d = c[size_t(axis)] - most->cell[size_t(axis)];
        c[size_t(axis)] = most->cell[size_t(axis)];
        if (c != most->cell) continue;
        if (d == -1) b.belowNs = n.busyNs;
        if (d == 1) b.aboveNs = n.busyNs;
    }
    return b;
}

}  // namespace

std::optional<InnerPlanes> ResplitSequence::hold(const InnerPlanes& planes, double ns, const Busiest& busiest,
                                                 const FrameState& r) {
    if (m_.balance.polishTries <= 0) {
        held_ = planes;
        return held_;
    }
    polishing_ = true;  // (from here on polish() says what the next frame holds)
    polishLeft_ = m_.balance.polishTries;
    base_ = planes;
    baseNs_ = ns;
    baseBusiest_ = busiest;
    if (std::optional<InnerPlanes> next = tryMove(r)) return next;
    return base_;
}

InnerPlanes ResplitSequence::moved(int kind) const {
    const ColumnGeometry g(m_.balance.axis, m_.dims);
    const int n = g.length(), k = baseBusiest_.cell[size_t(g.axis)], col = g.columnOf(baseBusiest_.cell);
    InnerPlanes out = base_;
    if (kind == 0) {  // the busiest node's box, on the side of its less busy neighbour
        const std::vector<double>& own = base_.at(size_t(col));
        auto face = [&](int i) { return edge(own, i); };
        const bool down = baseBusiest_.belowNs >= 0 && (baseBusiest_.aboveNs < 0 || baseBusiest_.belowNs <= baseBusiest_.aboveNs);
        const double t = face(k) - face(k - 1);
        // Aligned planes stay aligned (a column's own would pass rays on
        // between columns); a column's own planes move alone.
        const bool aligned = std::all_of(base_.begin(), base_.end(), [&](const std::vector<double>& c) { return c == base_[0]; });
        for (size_t c = 0; c < out.size(); ++c) {
            if (!aligned && c != size_t(col)) continue;
            if (down) out[c][size_t(k - 1)] += shrink_ * std::min(t, face(k - 1) - face(k - 2));
            else if (k < n - 1) out[c][size_t(k)] -= shrink_ * std::min(t, face(k + 1) - face(k));
        }
        return out;
    }
    const double sign = kind == 1 ? -1 : 1;  // every plane towards the axis's start, or its end
    for (std::vector<double>& c : out)
        for (size_t i = 0; i < c.size(); ++i) {
            const int j = int(i);
            c[i] += sign * shrink_ * std::min(c[i] - edge(c, j - 1), edge(c, j + 1) - c[i]);
        }
    return out;
}

std::optional<InnerPlanes> ResplitSequence::tryMove(const FrameState& r) {
    const int n = m_.dims[size_t(m_.balance.axis)];
    const double least = planeSpacing(m_.balance.minThickness * (worldHi_ - worldLo_) / n);  // (plane_spacing.h)
    auto fits = [&](const InnerPlanes& planes) {
        for (const std::vector<double>& c : planes)
            for (int i = 0; i <= int(c.size()); ++i)
                if (!(edge(c, i) - edge(c, i - 1) >= least)) return false;
        return true;
    };
    // Each frame forecast from the last, with getting there: none tried
    // that is not kPolishRoom faster than the unbalanced frame, forecast
    // the same way (a move not tried spends its try all the same).
    std::optional<FrameForecast> f;
    InnerPlanes now;
    double roomNs = 0;
    while (polishLeft_ > 0) {
        --polishLeft_;
        const InnerPlanes next = moved(moveKind_ % 3);
        if (++moveKind_ % 3 == 0) shrink_ /= 2;
        if (next == base_ || !fits(next)) continue;
        if (!f) {
            f.emplace(r, m_, averagedBoundaries(r, m_), objects_);
            now = lastBoundaries(r, m_);
            roomNs = (1 - kPolishRoom) * f->forecast(start_).frameNs;
        }
        if (f->forecast(next).frameNs + moveNs(r, m_, now, next) > roomNs) continue;
        trying_ = true;
        said_["next"] = "a move tried";
        said_["held_ns"] = baseNs_;
        return next;
    }
    return std::nullopt;
}

std::optional<InnerPlanes> ResplitSequence::polish(const FrameState& r) {
    said_ = {{"next", "held"}};
    if (trying_) {
        trying_ = false;
        if (r.renderTimeNs < baseNs_) {  // the move gained: polish from there
            base_ = lastBoundaries(r, m_);
            baseNs_ = r.renderTimeNs;
            baseBusiest_ = busiestOf(r, m_.balance.axis);
        }
    }
    if (std::optional<InnerPlanes> next = tryMove(r)) return next;
    if (orFirst_ && baseNs_ >= firstNs_) {  // polished, and still not faster than frame 1
        polishing_ = false;
        again_ = true;
        said_ = {{"next", "frame 1 again"}};
        return std::nullopt;
    }
    return base_;
}

std::optional<InnerPlanes> ResplitSequence::firstFrame(const FrameState& r) {
    firstNs_ = r.renderTimeNs;
    worldLo_ = 1e300;
    worldHi_ = -1e300;
    for (const NodeFrameState& n : r.nodes) {
        worldLo_ = std::min(worldLo_, n.box.lo[m_.balance.axis]);
        worldHi_ = std::max(worldHi_, n.box.hi[m_.balance.axis]);
    }
    start_ = m_.balance.startsAtObjects() ? uniformBoundaries(r, m_) : lastBoundaries(r, m_, true);
    return forecast(r);
}

std::optional<InnerPlanes> ResplitSequence::noResplitWon(const FrameState& r) {
    if (resplits_ < kTries) return forecast(r);
    said_ = {{"next", m_.balance.startsAtObjects() ? "the uniform split" : "the starting split"}};
    if (firstHolds_) {  // frame 1 was the starting split: hold it
        held_ = start_;
        return held_;
    }
    if (m_.balance.startsAtObjects()) {  // (sample's trial, the uniform split: kTrialReach)
        const double startNs = FrameForecast(r, m_, averagedBoundaries(r, m_), objects_).forecast(start_).frameNs;
        if (std::isfinite(startNs) && startNs > kTrialReach * firstNs_) {  // it cannot beat frame 1: frame 1 again
            said_ = {{"next", "frame 1 again"}, {"start_forecast_ns", startNs}};
            // Unless polishing the fastest re-split frame's planes beats it,
            // where that frame is within reach of frame 1 too (a polish's
            // moves are small: from 1.67 times frame 1 its tries ran 1.02 of
            // the unbalanced frame before frame 1 came back at 0.625).
            if (m_.balance.polishTries > 0 && bestNs_ <= kTrialReach * firstNs_) {
                orFirst_ = true;
                return hold(best_, bestNs_, bestBusiest_, r);
            }
            again_ = true;
            return std::nullopt;
        }
        if (std::isfinite(startNs)) said_["start_forecast_ns"] = startNs;
    }
    tryingStart_ = afresh_ = true;
    return start_;
}

std::optional<InnerPlanes> ResplitSequence::next(const FrameState& r, int frame) {
    afresh_ = false;
    if (polishing_) return polish(r);
    said_ = {{"next", "frame 1 again"}};
    if (again_) return std::nullopt;
    said_ = {{"next", "held"}};
    if (held_) return held_;
    const double t = r.renderTimeNs;
    if (frame == 1) return firstFrame(r);
    if (tryingStart_) {  // the frame just run held the starting split
        if (t < firstNs_) return hold(start_, t, busiestOf(r, m_.balance.axis), r);
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
        bestBusiest_ = busiestOf(r, m_.balance.axis);
    }
    if (bestNs_ > firstNs_) return noResplitWon(r);  // no re-split frame has beaten the first yet
    if (misses_ >= kPatience) {
        said_ = {{"next", "the fastest frame's planes"}};
        return hold(best_, bestNs_, bestBusiest_, r);
    }
    std::optional<InnerPlanes> next = forecast(r);
    // The forecast holds: polish the fastest re-split frame's planes.
    if (m_.balance.polishTries > 0 && said_.value("next", "") == "held") return hold(best_, bestNs_, bestBusiest_, r);
    return next;
}

}  // namespace rt
