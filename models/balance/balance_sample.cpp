// `sample`'s first frame, the protocol (balance_agent.h, startSample;
// doc/balancing.md, "One frame: sample, then split"): the column's sample
// of work gathered up the column, split at its top, the planes sent down,
// and every face moved once. Each message is a balancing message, charged as any other (its
// handling on both nodes, its bytes on the wire); the faces move by the
// slab handover of startAt.
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "balance/balance_agent.h"
#include "base/mesh_geometry.h"
#include "balance/sample_split.h"

namespace rt {

void BalanceAgent::startSample(bool gathers, double besideLo, bool sides) {
    hold_ = true;  // no load reports: the faces stay until the planes come
    Gather& g = gather_;
    g.on = gathers;  // (else the faces hold all frame)
    if (!g.on) return;
    g.below = !sides_[0].present;
    g.lo = host_.box().lo[cfg_.axis];
    g.hi = host_.box().hi[cfg_.axis];
    g.besideLo = besideLo;
    g.sum.sides = sides;
    g.own.assign(kSampleBins, 0.0);
    g.side.assign(kSampleBins, 0.0);
    host_.sampleBegins();
}

namespace {
void addToBin(std::vector<double>& bins, double lo, double hi, double where, double amount) {
    const double k = std::floor((where - lo) / (hi - lo) * kSampleBins);  // (clamped before it is an index)
    if (std::isfinite(k)) bins[size_t(std::clamp(k, 0.0, double(kSampleBins - 1)))] += amount;
}
}  // namespace

void BalanceAgent::recordSample(double where, Picos work) { addToBin(gather_.own, gather_.lo, gather_.hi, where, double(work)); }

void BalanceAgent::recordSide(double where, double passCost) { addToBin(gather_.side, gather_.lo, gather_.hi, where, passCost); }

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

// The top node moves the column only where the forecast from the sample,
// the passes against the columns that hold included, says it pays by now
// (samplePays); else the planes it sends are none, and every face holds.
void BalanceAgent::passSum(Picos now) {
    Gather& g = gather_;
    if (!g.ready || !g.below || g.passed) return;
    g.passed = true;  // (recording stops: the sum holds what was traced by now)
    if (!sides_[0].present) g.sum.startedAt = double(now);  // (the lowest node: the climb starts)
    g.sum.add(g.lo, g.hi, g.own, g.side, g.besideLo);
    g.sum.compress(g.sum.cellsWithin(kSampleValues));
    if (sides_[1].present) {
        g.up = true;
        return;
    }
    std::vector<double> planes = splitBySample(g.sum, count_, minThickness_);
    if (!planes.empty() && !samplePays(g.sum, dearestPartWithPasses(g.sum, planes), double(now))) planes.clear();
    takePlanes(std::move(planes));
}

void BalanceAgent::onPlanes(int fromDir, const Message& m) {
    const bool fromAbove = gather_.on && dirAxis(fromDir) == cfg_.axis && dirStep(fromDir) > 0;
    if (gather_.adopted || !fromAbove) throw std::logic_error("balance agent: planes twice, or not from above");
    const std::vector<double>& p = m.body().values;
    if (!p.empty() && p.size() != size_t(count_ - 1)) throw std::logic_error("balance agent: planes of another column");
    takePlanes(p);
}

// The planes are passed on down first, then the faces move: the node below
// learns them as soon as it can.
void BalanceAgent::takePlanes(std::vector<double> planes) {
    Gather& g = gather_;
    g.adopted = true;
    g.planes = std::move(planes);
    g.down = sides_[0].present;
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
    if (g.adopt) {
        g.adopt = false;
        const double nan = std::nan("");
        startAt(index_ > 0 ? g.planes[size_t(index_ - 1)] : nan, index_ < count_ - 1 ? g.planes[size_t(index_)] : nan);
    }
}

}  // namespace rt
