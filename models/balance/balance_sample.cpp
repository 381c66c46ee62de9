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

void BalanceAgent::startSample(bool gathers, const std::vector<int>& besideDirs, std::vector<double> faces) {
    hold_ = true;  // no load reports: the faces stay until the planes come
    Gather& g = gather_;
    g.on = gathers;  // (else the faces hold all frame)
    if (!sides_[1].present) g.besideDirs = besideDirs;  // (the top node tells the columns beside)
    g.beside.assign(g.besideDirs.size(), {});
    if (!g.on) {  // (a column that holds proposes its faces at once, and says it holds)
        g.faces = std::move(faces);
        g.proposal = g.faces;
        g.propose = g.tell = g.besideDirs.size();
        return;
    }
    // The lowest node starts the climb once its sample is generated, or
    // (--sample-end credit) once the frame buffer says the sample is done.
    g.below = !sides_[0].present && !cfg_.sampleCredit;
    g.lo = host_.box().lo[cfg_.axis];
    g.hi = host_.box().hi[cfg_.axis];
    g.sum.sides = !besideDirs.empty();
    g.own.assign(kSampleBins, 0.0);
    g.side.assign(kSampleBins, 0.0);
    // (--sample-links on: measured on columns of up to kLongestColumnSampled
    // boxes, where --balance recommended takes sample; on longer ones the
    // crossings' third value a cell left the sum too few cells: gears-2 on
    // 64x2x1 made 1.59 of the unbalanced frame, where off holds at 0.99)
    g.sum.crossings = cfg_.sampleLinks && count_ <= kLongestColumnSampled;
    if (g.sum.crossings) g.cross.assign(kSampleBins + 1, 0.0);
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

void BalanceAgent::recordCrossing(double a, double b, bool pastTop) {
    Gather& g = gather_;
    if (!g.sum.crossings) return;
    addToBin(g.cross, g.lo, g.hi, a, 1.0);
    if (pastTop) g.cross[kSampleBins] -= 1.0;
    else addToBin(g.cross, g.lo, g.hi, b, -1.0);
}

void BalanceAgent::sampleReady(Picos now) {
    if (!gather_.on || gather_.ready) return;
    gather_.ready = true;
    passSum(now);
}

void BalanceAgent::onSample(const Message& m, Picos now) {
    if (!gather_.on || gather_.below) throw std::logic_error("balance agent: a column's sample it did not wait for");
    if (m.body().values.empty()) {  // the frame buffer's word to the lowest node: the sample is done (--sample-end credit)
        if (!cfg_.sampleCredit || sides_[0].present) throw std::logic_error("balance agent: a sample's end it did not wait for");
        gather_.below = true;
        passSum(now);
        return;
    }
    gather_.sum = ColumnSample::of(m.body().values);
    if (!gather_.sum.wellFormed() || gather_.sum.hi() != gather_.lo)
        throw std::logic_error("balance agent: a column's sample that does not end where the box begins");
    gather_.below = true;
    passSum(now);
}

// The top node decides with the top nodes of the columns beside, in two
// rounds (doc/balancing.md, "Columns side by side"):
//  1. each proposes its planes where they pay by its column's work alone,
//     else its faces as they stand (a column that holds: its faces);
//  2. each says whether it would move: whether all of them moving as
//     proposed, with the passes between their planes, beats all of them
//     holding (where a scene's rays cross columns more than they work in
//     them, as tetra-3's, every column moving made the frame three times
//     the unbalanced one, though each move paid against its neighbours'
//     moving);
// and then moves where that pays against the planes beside as they will
// be (the proposals of those that said they would move, the faces of the
// rest). Deciding on the second round alone, some columns held beside
// neighbours that moved, and became the frame's busiest (Fig. 4's scene
// along the axis at N = 8, f = 7/8: 1.07 of the unbalanced frame). Where
// it does not pay the planes it sends are none, and every face holds.
void BalanceAgent::passSum(Picos now) {
    Gather& g = gather_;
    if (!g.ready || !g.below || g.passed) return;
    g.passed = true;  // (recording stops: the sum holds what was traced by now)
    if (!sides_[0].present) g.sum.startedAt = double(now);  // (the lowest node: the climb starts)
    // What passing this box's objects on to a neighbour costs: giving the
    // whole box as a slab, less giving an empty one (sampleMovePs).
    const int s = sides_[1].present ? +1 : -1;
    const Box& box = host_.box();
    const double passPs = count_ < 2 ? 0.0
                                     : double(host_.slabCost(s, s > 0 ? box.lo[cfg_.axis] : box.hi[cfg_.axis])) -
                                           double(host_.slabCost(s, s > 0 ? box.hi[cfg_.axis] : box.lo[cfg_.axis]));
    g.sum.add(g.lo, g.hi, g.own, g.side, std::max(0.0, passPs), g.cross);
    if (!g.sum.sides) g.sum.groupBoxes(kSampleGroups);
    g.sum.compress(g.sum.cellsWithin(kSampleValues));
    if (sides_[1].present) {
        g.up = true;
        return;
    }
    // (a ray's time on the wire of the column's links: each part at least its link up's)
    if (g.sum.crossings) g.sum.wirePs = count_ < 2 ? 0.0 : double(host_.rayOccupies(-1));
    g.planes = splitBySample(g.sum, count_, minThickness_);
    // (a handover's latency and handling: an empty slab's to the node below)
    g.movePs = sampleMovePs(g.sum, g.planes, count_ < 2 ? 0.0 : double(host_.slabCost(-1, host_.box().lo[cfg_.axis])));
    g.paysAlone = !g.planes.empty() &&
                  samplePays(g.sum, holdingPart(g.sum, {}), dearestPart(g.sum, g.planes), double(now), g.movePs);
    g.faces = g.sum.faces;
    g.proposal = g.paysAlone ? g.planes : g.faces;
    g.round = 1;
    g.propose = g.besideDirs.size();
    decideSample(now);
}

void BalanceAgent::decideSample(Picos now) {
    Gather& g = gather_;
    const auto heard = [&](int n) {
        return std::all_of(g.beside.begin(), g.beside.end(), [n](const Gather::Beside& b) { return b.heard >= n; });
    };
    const auto planesBeside = [&](bool asProposed) {
        std::vector<std::vector<double>> p;
        for (const Gather::Beside& b : g.beside) p.push_back(asProposed || b.verdict ? b.proposal : b.faces);
        return p;
    };
    const double t = double(now);
    if (g.round == 1 && heard(1)) {
        std::vector<std::vector<double>> faces;
        for (const Gather::Beside& b : g.beside) faces.push_back(b.faces);
        g.verdict = g.paysAlone &&
                    samplePays(g.sum, holdingPart(g.sum, faces), dearestPartWithPasses(g.sum, g.planes, planesBeside(true)), t,
                               g.movePs);
        g.round = 2;
        g.tell = g.besideDirs.size();
    }
    if (g.round != 2 || !heard(2) || g.adopted) return;
    const std::vector<std::vector<double>> beside = planesBeside(false);
    std::vector<double> planes = g.planes;
    if (!planes.empty() &&
        !samplePays(g.sum, holdingPart(g.sum, beside), dearestPartWithPasses(g.sum, planes, beside), t, g.movePs))
        planes.clear();
    takePlanes(std::move(planes));
}

void BalanceAgent::onPlanes(int fromDir, const Message& m, Picos now) {
    const std::vector<double>& p = m.body().values;
    Gather& g = gather_;
    if (dirAxis(fromDir) != cfg_.axis) {  // from a column beside: its proposal, then whether it moves
        const auto at = std::find(g.besideDirs.begin(), g.besideDirs.end(), fromDir);
        if (at == g.besideDirs.end() || g.beside[size_t(at - g.besideDirs.begin())].heard >= 2)
            throw std::logic_error("balance agent: a proposal to a node that is not a top node, or one too many");
        Gather::Beside& b = g.beside[size_t(at - g.besideDirs.begin())];
        if (b.heard++ == 0) {
            if (p.size() % 2) throw std::logic_error("balance agent: a proposal without as many faces as planes");
            const size_t half = p.size() / 2;  // (its proposal, then its faces as they stand)
            b.proposal.assign(p.begin(), p.begin() + long(half));
            b.faces.assign(p.begin() + long(half), p.end());
        } else
            b.verdict = p.size() == 1 && p[0] != 0;
        if (g.on) decideSample(now);
        return;
    }
    const bool fromAbove = g.on && dirStep(fromDir) > 0;
    if (g.adopted || !fromAbove) throw std::logic_error("balance agent: planes twice, or not from above");
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
    if (g.propose > 0) {  // (each column beside hears the proposal before the verdict: one link, in order)
        const int dir = g.besideDirs[g.besideDirs.size() - g.propose--];
        std::vector<double> both = g.proposal;
        both.insert(both.end(), g.faces.begin(), g.faces.end());
        host_.sendOn(dir, Message::planes(std::move(both)));
        return;
    }
    if (g.tell > 0) {
        const int dir = g.besideDirs[g.besideDirs.size() - g.tell--];
        host_.sendOn(dir, Message::planes({g.verdict ? 1.0 : 0.0}));
        return;
    }
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
