// `sample`'s first frame, the protocol (balance_agent.h, startSample;
// doc/balancing.md, "One frame: sample, then split"): the column's sample
// of work gathered up the column, split at its top, the planes sent down
// and to the columns that generate no primary rays, and every face moved
// once. Each message is a balancing message, charged as any other (its
// handling on both nodes, its bytes on the wire); the faces move by the
// slab handover of startAt.
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "balance/balance_agent.h"
#include "base/mesh_geometry.h"
#include "balance/sample_split.h"

namespace rt {

void BalanceAgent::startSample(int feeder, const std::array<bool, 6>& floodTo) {
    hold_ = true;  // no load reports: the faces stay until the planes come
    floodTo_ = floodTo;
    feeder_ = feeder;
    Gather& g = gather_;
    g.on = feeder == -1;  // (else it takes its feeder's planes, or holds)
    if (!g.on) return;
    g.below = !sides_[0].present;
    g.lo = host_.box().lo[cfg_.axis];
    g.hi = host_.box().hi[cfg_.axis];
    g.own.assign(kSampleBins, 0.0);
    host_.sampleBegins();
}

void BalanceAgent::recordSample(double where, Picos work) {
    Gather& g = gather_;
    const double k = std::floor((where - g.lo) / (g.hi - g.lo) * kSampleBins);  // (clamped before it is an index)
    if (!std::isfinite(k)) return;
    g.own[size_t(std::clamp(k, 0.0, double(kSampleBins - 1)))] += double(work);
}

void BalanceAgent::sampleReady(Picos now) {
    if (!gather_.on || gather_.ready) return;
    gather_.ready = true;
    passSum(now);
}

void BalanceAgent::onSample(const Message& m, Picos now) {
    if (!gather_.on || gather_.below) throw std::logic_error("balance agent: a column's sample it did not wait for");
    gather_.sum = ColumnSample::of(m.body().values);
    if (!gather_.sum.wellFormed() || gather_.sum.hi() != gather_.lo)
        throw std::logic_error("balance agent: a column's sample that does not end where the box begins");
    gather_.below = true;
    passSum(now);
}

// The top node moves the column only where the forecast from the sample
// says it pays by now (samplePays); else the planes it sends are none, and
// every face holds.
void BalanceAgent::passSum(Picos now) {
    Gather& g = gather_;
    if (!g.ready || !g.below || g.passed) return;
    g.passed = true;  // (recording stops: the sum holds what was traced by now)
    if (!sides_[0].present) g.sum.startedAt = double(now);  // (the lowest node: the climb starts)
    g.sum.add(g.lo, g.hi, g.own);
    g.sum.compress(kSampleCells);
    if (sides_[1].present) {
        g.up = true;
        return;
    }
    std::vector<double> planes = splitBySample(g.sum, count_, minThickness_);
    if (!planes.empty() && !samplePays(g.sum, dearestPart(g.sum, planes), double(now))) planes.clear();
    takePlanes(std::move(planes), -1);
}

void BalanceAgent::onPlanes(int fromDir, const Message& m) {
    const bool fromAbove = gather_.on && dirAxis(fromDir) == cfg_.axis && dirStep(fromDir) > 0;
    if (gather_.adopted || !(fromAbove || fromDir == feeder_))
        throw std::logic_error("balance agent: planes twice, or from a neighbour that does not feed it");
    const std::vector<double>& p = m.body().values;
    if (!p.empty() && p.size() != size_t(count_ - 1)) throw std::logic_error("balance agent: planes of another column");
    takePlanes(p, fromDir);
}

// The planes are passed on first (down the column, to the columns it
// feeds), then the faces move: a neighbour learns them as soon as it can.
void BalanceAgent::takePlanes(std::vector<double> planes, int fromDir) {
    Gather& g = gather_;
    g.adopted = true;
    g.planes = std::move(planes);
    g.down = g.on && sides_[0].present;  // (a fed column's nodes each hear from their own neighbour)
    for (int d = 0; d < 6; ++d) g.flood[size_t(d)] = floodTo_[size_t(d)] && d != fromDir;
    g.adopt = !g.planes.empty();
}

void BalanceAgent::gatherStep() {
    Gather& g = gather_;
    if (g.up) {
        g.up = false;
        host_.sendReport(+1, Message::sample(g.sum.values()));
        return;
    }
    if (g.down) {
        g.down = false;
        host_.sendReport(-1, Message::planes(g.planes));
        return;
    }
    for (int d = 0; d < 6; ++d)
        if (g.flood[size_t(d)]) {
            g.flood[size_t(d)] = false;
            host_.sendOn(d, Message::planes(g.planes));
            return;
        }
    if (g.adopt) {
        g.adopt = false;
        const double nan = std::nan("");
        startAt(index_ > 0 ? g.planes[size_t(index_ - 1)] : nan, index_ < count_ - 1 ? g.planes[size_t(index_)] : nan);
    }
}

}  // namespace rt
