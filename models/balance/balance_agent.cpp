#include "balance/balance_agent.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rt {

BalanceAgent::BalanceAgent(const BalanceConfig& cfg, BalanceHost& host, const Box& world, int index, int count,
                           bool lower, bool upper, double minThickness)
    : cfg_(cfg), host_(host), index_(index), count_(count), minThickness_(minThickness), next_(cfg.interval) {
    const PolicyInfo* p = findPolicy(cfg.policy);
    if (!p || !p->make) throw std::logic_error("balance agent: '" + cfg.policy + "' is not a dynamic policy");
    policy_ = p->make();
    sides_[0].present = lower;
    sides_[1].present = upper;
    WorkProfile empty;
    empty.lo = world.lo[cfg.axis];
    empty.hi = world.hi[cfg.axis];
    empty.bins.assign(size_t(std::max(1, cfg.bins * count)), 0.0);
    for (Side& s : sides_) s.span.profile = s.sentProfile = empty;
    if (cfg.betweenFrames()) {
        stats_.work = stats_.within = WorkByPosition(empty.lo, empty.hi, count);
        stats_.spans.fill(stats_.work);
        stats_.lateral.fill(stats_.work);
    }
}

void BalanceAgent::recordStep(double where, Picos cost, const FaceCrossings& faces) {
    traced_ += cost;
    stats_.work.add(where, double(cost - faces.cost));
    if (faces.within) stats_.within.add(where, double(faces.within));
    stats_.faceCost += faces.cost;
    stats_.faceCrossings += uint64_t(faces.crossings);
    if (std::isfinite(faces.from) && std::isfinite(faces.to)) {
        WorkByPosition& spans = stats_.spans[faces.to >= faces.from ? 0 : 1];
        spans.add(std::min(faces.from, faces.to), 1.0);
        spans.add(std::max(faces.from, faces.to), -1.0);
    }
    if (faces.lateral >= 0) stats_.lateral[size_t(faces.lateral)].add(faces.to, 1.0);
    for (Side& s : sides_) {
        if (!s.present) continue;
        s.span.profile.add(where, double(cost));
        s.span.stepCost += cost;
        ++s.span.steps;
    }
}

void BalanceAgent::recordInterval(const IntervalRecord& r) {
    pending_.end = r.end;
    pending_.busy += r.busy;
    pending_.wait += r.wait;
    if (++pendingCount_ < stats_.intervalsPerRecord) return;
    std::vector<IntervalRecord>& v = stats_.intervals;
    v.push_back(pending_);
    pending_ = {0, 0, 0};
    pendingCount_ = 0;
    if (v.size() < BalanceStats::kMaxIntervalRecords) return;
    for (size_t i = 0; i < v.size() / 2; ++i)
        v[i] = {v[2 * i + 1].end, v[2 * i].busy + v[2 * i + 1].busy, v[2 * i].wait + v[2 * i + 1].wait};
    v.resize(v.size() / 2);
    stats_.intervalsPerRecord *= 2;
}

BalanceStats BalanceAgent::finalStats() const {
    BalanceStats s = stats_;
    if (pendingCount_) s.intervals.push_back(pending_);
    return s;
}

void BalanceAgent::closeInterval(Picos now, Picos busyTotal, Picos waitTotal, uint64_t waiting) {
    const Picos busy = busyTotal - busyMark_, waited = waitTotal - waitMark_;
    recordInterval({now, busy, waited});
    busyMark_ = busyTotal;
    waitMark_ = waitTotal;
    // The load's execution time is the time spent tracing in the box; time
    // handling balancing messages or passing rays through is neither
    // execution nor wait. A node with no rays of its own to trace reports
    // load 0, so slides stop when the tracing does, and a ray chasing a slab
    // that moves back and forth always catches it (doc/balancing.md).
    const Picos exec = traced_;
    traced_ = 0;
    if (layerFaces_) layerFaces_->add(index_, long(now / cfg_.interval) - 1, exec, waited);
    const Picos length = now - lastEnd_;  // an interval, or more after a long step
    lastEnd_ = now;
    waiting_ = waiting;
    // The next interval boundary after now (a long step may have spanned several).
    next_ = (now / cfg_.interval + 1) * cfg_.interval;
    for (int i : {0, 1}) {
        Side& s = sides_[i];
        if (s.present && cfg_.wireShare > 0) {  // (only the busy-link guard reads it)
            const Picos w = host_.linkOccupied(sideOf(i));
            s.wireUse = length > 0 ? double(w - s.wireMark) / double(length) : 0;
            s.wireMark = w;
        }
        s.span.busy += exec;
        s.span.wait += waited;
        s.span.end = now;
        s.fresh = true;
    }
    if (hold_) return;
    for (int i : {0, 1})
        if (sides_[i].present) advance(i, now);
}

void BalanceAgent::startAt(double lo, double hi) {
    hold_ = true;
    startTo_[0] = lo;
    startTo_[1] = hi;
    startLo_ = sides_[0].present && std::isfinite(lo);
    startHi_ = sides_[1].present && std::isfinite(hi);
}

void BalanceAgent::tookSlab() {
    if (!hold_) return;
    const Box& b = host_.box();
    const int ax = cfg_.axis;
    startLo_ = startLo_ || (sides_[0].present && std::isfinite(startTo_[0]) && startTo_[0] > b.lo[ax]);
    startHi_ = startHi_ || (sides_[1].present && std::isfinite(startTo_[1]) && startTo_[1] < b.hi[ax]);
}

// Each give leaves the box at least the minimum thick; a target beyond the
// box (the boxes ended elsewhere than the targets assumed) is approached as
// far as that allows, and the next frame's targets start from there. The
// upper face is judged on the box as the lower face's give left it.
void BalanceAgent::giveToStartTarget() {
    const int ax = cfg_.axis;
    const Box& b = host_.box();
    if (startLo_) {
        startLo_ = false;
        const double lo = startTo_[0];
        if (lo > b.lo[ax]) {
            const double to = std::min(lo, b.hi[ax] - minThickness_);
            if (to > b.lo[ax]) {
                ++stats_.gives;
                host_.giveSlab(-1, to);
                return;
            }
        }
    }
    if (startHi_) {
        startHi_ = false;
        const double hi = startTo_[1];
        if (hi < b.hi[ax]) {
            const double to = std::max(hi, b.lo[ax] + minThickness_);
            if (to < b.hi[ax]) {
                ++stats_.gives;
                host_.giveSlab(+1, to);
            }
        }
    }
}

void BalanceAgent::act() {
    if (startLo_ || startHi_) {
        giveToStartTarget();
        return;
    }
    if (gather_.due()) {
        gatherStep();
        return;
    }
    for (int i : {0, 1}) {
        if (!advancing_[i]) continue;
        if (advanceStep(i)) return;
        advancing_[i] = false;
    }
}

void BalanceAgent::onReport(int side, const Message& m, Picos now) {
    const int i = side > 0;
    Side& s = sides_[i];
    const MessageBody& r = m.body();
    if (r.interval > s.reported + 1 || r.interval <= s.decided || s.got.count(r.interval))
        throw std::logic_error("balance agent: report for round " + std::to_string(r.interval) + " out of lockstep");
    s.got[r.interval] = LoadSample{Picos(r.end), Picos(r.busy), Picos(r.wait), Picos(r.backlog), r.sum};
    s.neighbourSum = r.sum;
    advance(i, now);
}

// Lockstep: report round r once r - 1 is decided (and an interval has closed
// since the last report), decide r once both reports of r are here. A slide
// given when deciding r leaves before the report of r + 1 on the same FIFO
// lane, so the neighbour has the slab before it decides r + 1: the two never
// give across one boundary at once, and each decides with its box up to date.
// A decision uses the time of the report or interval that made it due. A
// report waits for the first interval to close after its pacing allows it.
void BalanceAgent::advance(int i, Picos now) {
    if (advancing_[i]) throw std::logic_error("balance agent: a side advanced again before its actions were taken");
    advancing_[i] = true;
    advanceAt_[i] = now;
}

bool BalanceAgent::advanceStep(int i) {
    Side& s = sides_[i];
    if (s.reported == s.decided && s.fresh && advanceAt_[i] >= s.nextReport) {
        report(i);
        return true;
    }
    if (s.reported > s.decided && s.got.count(s.reported)) {
        decide(i, advanceAt_[i]);
        return true;
    }
    return false;
}

void BalanceAgent::report(int i) {
    Side& s = sides_[i];
    LoadSample l;
    l.end = s.span.end;
    s.sentLength = l.end - s.sent.end;  // (the last report's end, or the frame's start)
    l.busy = s.span.busy;
    l.wait = s.span.wait;
    l.backlog = s.span.steps ? saturatedPicos(double(waiting_) * double(s.span.stepCost) / double(s.span.steps)) : 0;
    // The column's demand from the far end through this node: what the other
    // side last said, plus this node's own.
    const Side& other = sides_[1 - i];
    l.sum = (other.present ? other.neighbourSum : 0.0) + l.demand();
    s.sent = l;
    s.sentMeanStep = s.span.steps ? Picos(s.span.stepCost / s.span.steps) : 0;
    s.sentSteps = s.span.steps;
    std::swap(s.sentProfile, s.span.profile);
    s.span.profile.clear();
    s.span.busy = s.span.wait = s.span.stepCost = 0;
    s.span.steps = 0;
    s.fresh = false;
    ++s.reported;
    // Pacing: the next report from the next multiple of the period, a whole
    // number of intervals. Both ends of a link count the same multiples, so
    // their reports leave together and neither's loads wait for the other's.
    const Picos gap = saturatedPicos(std::ceil(double(host_.reportTime(sideOf(i))) / cfg_.reportShare));
    const Picos period = std::max<Picos>(1, (gap + cfg_.interval - 1) / cfg_.interval) * cfg_.interval;
    s.nextReport = (advanceAt_[i] / period + 1) * period;
    host_.sendReport(sideOf(i), Message::loadReport(s.reported, l.end, l.busy, l.wait, l.backlog, l.sum));
}

// --faces ideal-layer: the face goes to its layer's plane after the last
// interval both samples cover (the same for both nodes of the face), and the
// node that loses volume to it gives.
std::optional<double> BalanceAgent::towardsLayerFace(const SlideQuery& q, const LoadSample& theirs) const {
    const long through = long(std::min(q.mine.end, theirs.end) / cfg_.interval);
    const double plane = layerFaces_->face(q.upper ? index_ : index_ - 1, through);
    const int ax = q.axis;
    if (q.upper && plane < q.own.hi[ax]) return clampGive(q, q.own.hi[ax] - plane);
    if (!q.upper && plane > q.own.lo[ax]) return clampGive(q, plane - q.own.lo[ax]);
    return std::nullopt;
}

void BalanceAgent::decide(int i, Picos now) {
    Side& s = sides_[i];
    const LoadSample theirs = s.got.at(s.reported);
    s.got.erase(s.reported);
    s.decided = s.reported;
    ++stats_.decisions;
    const Picos oldest = std::min(s.sent.end, theirs.end);
    const double age = double(now - std::min(now, oldest)) / double(cfg_.interval);
    stats_.ages.add(uint64_t(std::llround(age * BalanceStats::kAgeUnits)));
    SlideQuery q;
    q.own = host_.box();
    q.axis = cfg_.axis;
    q.upper = i == 1;
    q.mine = s.sent;
    q.theirs = theirs;
    q.profile = &s.sentProfile;
    q.index = index_;
    q.count = count_;
    q.minThickness = minThickness_;
    const std::optional<double> b = layerFaces_ ? towardsLayerFace(q, theirs) : policy_->decide(cfg_, q);
    if (!b) return;
    if (cfg_.guard) {
        if (age > cfg_.maxAge) {
            ++stats_.skippedStale;
            return;
        }
        if (double(host_.hopTime(sideOf(i))) > cfg_.hopRatio * double(s.sentMeanStep)) {
            ++stats_.skippedLatency;
            return;
        }
        // What the slide returns: the slab's share of this node's work (by
        // the work recorded there, or its thickness if none was, or for a
        // relaying policy none was in the slab) over the guard's horizon,
        // and of the work waiting now.
        const double lo = q.own.lo[q.axis], hi = q.own.hi[q.axis];
        const double a = q.upper ? *b : lo, z = q.upper ? hi : *b;
        const double inBox = s.sentProfile.within(lo, hi), inSlab = s.sentProfile.within(a, z);
        const bool byThickness = !(inBox > 0) || (policy_->relays() && !(inSlab > 0));
        const double share = byThickness ? (z - a) / (hi - lo) : inSlab / inBox;
        const double returns =
            share * (q.mine.load() * double(cfg_.interval) * cfg_.horizon + double(q.mine.backlog));
        if (cfg_.wireShare > 0) {
            // The link after the slide: its busy share of the last interval
            // (wire or slots, the narrower), plus a ray message for each ray
            // step the slab's work took in the span, which the giver now
            // sends across instead.
            const double across = s.sentLength > 0 ? share * double(s.sentSteps) / double(s.sentLength) : 0;  // rays per ps
            if (s.wireUse + across * double(host_.rayOccupies(sideOf(i))) > cfg_.wireShare) {
                ++stats_.skippedBusyLink;
                return;
            }
        }
        if (double(host_.slabCost(sideOf(i), *b)) > returns) {
            ++stats_.skippedCost;
            return;
        }
    }
    ++stats_.gives;
    host_.giveSlab(sideOf(i), *b);
}

}  // namespace rt
