#include "node.h"

#include <cmath>

namespace rt {

Node::Node(sc_core::sc_module_name name, const Cell& cell, const Box& box, const Scene& scene, const Shader& shader,
           const Camera& camera, const Box& world, const Costs& costs, double speed, int fbBatch)
    : sc_module(name),
      out("out", kDirs),
      in("in", kDirs),
      fb("fb"),
      cell_(cell),
      region_(box, objectsOverlapping(scene.objects, box), AccelKind::Grid),
      shader_(shader),
      camera_(camera),
      world_(world),
      costs_(costs),
      speed_(speed),
      fbBatch_(fbBatch) {
    SC_THREAD(run);
}

void Node::assignPrimaries(std::vector<uint32_t> pixels, int primaryExp, const Credit& remainder) {
    pixels_ = std::move(pixels);
    primaryExp_ = primaryExp;
    credit_ = remainder;
}

size_t Node::queueDepth() const {
    size_t n = local_.size();
    for (int d = 0; d < kDirs; ++d)
        if (in[d].size()) n += in[d]->unconsumed();
    return n;
}

void Node::traceState(bool busy, bool waiting) {
    if (!trace_) return;
    NodeTrace::record(trace_->busy, now_, busy);
    NodeTrace::record(trace_->wait, now_, waiting);
    NodeTrace::record(trace_->queue, now_, int64_t(queueDepth()));
}

void Node::run() {
    for (int d = 0; d < kDirs; ++d)
        if (in[d].size()) in[d]->setArrivalEvent(&arrived_);
    now_ = sc_core::sc_time_stamp().value();
    Work w;
    for (;;) {
        if (takeWork(w)) {
            step(w);
            continue;
        }
        // Nothing to trace: hand the host what it is owed before waiting, so
        // that the credit of every ray ended here follows its contributions.
        if (!pending_.empty() || !credit_.isZero()) {
            flushToHost();
            continue;
        }
        traceState(false, true);
        Picos next = ~Picos(0);
        for (int d = 0; d < kDirs; ++d) {
            Picos a;
            if (in[d].size() && in[d]->peekArrival(a)) next = std::min(next, a);
        }
        const Picos start = now_;
        if (next != ~Picos(0)) wait(sc_core::sc_time::from_value(next - now_), arrived_);
        else wait(arrived_);
        now_ = sc_core::sc_time_stamp().value();
        stats_.wait += now_ - start;
    }
}

bool Node::takeWork(Work& w) {
    if (!local_.empty()) {
        w = local_.back();
        local_.pop_back();
        return true;
    }
    // The oldest message that has arrived; ties go to the lower direction.
    int best = -1;
    Picos bestT = 0;
    for (int d = 0; d < kDirs; ++d) {
        Picos a;
        if (in[d].size() && in[d]->peekArrival(a) && a <= now_ && (best < 0 || a < bestT)) {
            best = d;
            bestT = a;
        }
    }
    if (best >= 0) {
        Message m = in[best]->consume(now_);
        ++stats_.messagesReceived;
        w = Work{m.ray, m.creditExp, true, false};
        return true;
    }
    if (nextPixel_ < pixels_.size()) {
        const uint32_t p = pixels_[nextPixel_++];
        w = Work{primaryJob(camera_, int(p % uint32_t(camera_.width())), int(p / uint32_t(camera_.width())), world_),
                 uint16_t(primaryExp_), false, true};
        ++stats_.raysGenerated;
        ++stats_.raysCreated;
        ++stats_.counters.primaryRays;
        return true;
    }
    return false;
}

int Node::route(const RayJob& job) const {
    const Box& b = region_.box();
    for (int a = 0; a < 3; ++a) {
        if (job.ray.d[a] == 0) {
            const double o = job.ray.o[a];
            if (o < b.lo[a]) return dirOf(a, -1);
            if (o >= b.hi[a]) return dirOf(a, +1);
            continue;
        }
        const Interval s = slabInterval(job.ray, a, b.lo[a], b.hi[a]);
        const int forward = job.ray.d[a] > 0 ? +1 : -1;  // moving along the ray moves this way on axis a
        if (job.t0 < s.lo) return dirOf(a, -forward);
        if (job.t0 >= s.hi) return dirOf(a, forward);
    }
    return -1;
}

void Node::terminate(const Work& w, std::vector<RayJob>& spawned) {
    ++stats_.raysTerminated;
    // The ray's credit goes to its children in equal powers of two; what is
    // left over comes back to this node, to be returned to the host.
    const uint64_t m = spawned.size();
    if (m == 0) {
        credit_.add(w.creditExp);
        return;
    }
    const int c = ceilLog2(m);
    credit_.add(w.creditExp + c, (uint64_t(1) << c) - m);
    for (RayJob& j : spawned) {
        local_.push_back(Work{j, uint16_t(w.creditExp + c), false, false});
        ++stats_.raysCreated;
    }
}

void Node::step(Work& w) {
    const Counters before = stats_.counters;
    traceState(true, false);
    std::vector<RayJob> spawned;
    std::vector<Contribution> contributions;
    int dir = route(w.job);
    if (dir < 0) {
        ++stats_.raysTraced;
        if (region_.trace(w.job, shader_, mailbox_, stats_.counters, spawned, contributions) ==
            Region::Step::Terminated) {
            terminate(w, spawned);
            dir = -2;
        } else {
            dir = route(w.job);  // it left the box at job.t0
        }
    }
    if (dir >= 0) {
        if (out[dir].size()) {
            Message m;
            m.type = MsgType::Ray;
            m.ray = w.job;
            m.creditExp = w.creditExp;
            outbox_.push_back({dir, std::move(m)});
            ++stats_.raysForwarded;
        } else {  // no neighbour that way: the ray leaves the world
            contributions.push_back(shader_.miss(w.job, stats_.counters));
            ++stats_.raysTerminated;
            credit_.add(w.creditExp);
        }
    }
    for (const Contribution& c : contributions) pending_.push_back(c);
    stats_.contributionsSent += contributions.size();
    if (pending_.size() >= size_t(fbBatch_)) {
        Message m;
        m.type = MsgType::Contributions;
        m.contributions.swap(pending_);
        outbox_.push_back({-1, std::move(m)});
    }
    const Picos cost = stepCost(before, outbox_.size(), w.fromLink ? 1 : 0, w.generated ? 1 : 0);
    now_ += cost;
    stats_.busy += cost;
    stats_.lastActive = now_;
    for (auto& [d, m] : outbox_) {
        if (d < 0) fb->send(std::move(m), now_);
        else out[d]->send(std::move(m), now_);
    }
    stats_.messagesSent += outbox_.size();
    outbox_.clear();
    stats_.queueHighWater = std::max(stats_.queueHighWater, queueDepth());
    wait(sc_core::sc_time::from_value(cost));
}

void Node::flushToHost() {
    traceState(true, false);
    if (!pending_.empty()) {
        Message m;
        m.type = MsgType::Contributions;
        m.contributions.swap(pending_);
        outbox_.push_back({-1, std::move(m)});
    }
    if (!credit_.isZero()) {
        Message m;
        m.type = MsgType::Credit;
        m.credit = credit_;
        credit_.clear();
        outbox_.push_back({-1, std::move(m)});
    }
    const Picos cost = stepCost(stats_.counters, outbox_.size(), 0, 0);
    now_ += cost;
    stats_.busy += cost;
    stats_.lastActive = now_;
    for (auto& [d, m] : outbox_) fb->send(std::move(m), now_);
    stats_.messagesSent += outbox_.size();
    outbox_.clear();
    wait(sc_core::sc_time::from_value(cost));
}

// Where a cost is charged: a step's operation counts times their costs,
// divided by the node's speed factor (exact when the speed is 1).
Picos Node::stepCost(const Counters& before, uint64_t sends, uint64_t recvs, uint64_t generated) const {
    const Counters& c = stats_.counters;
    Picos ps = sends * costs_.send + recvs * costs_.recv + generated * costs_.rayGen;
    for (int k = 0; k < kPrimitiveKinds; ++k) ps += (c.tests[k] - before.tests[k]) * costs_.test[k];
    ps += (c.voxelSteps - before.voxelSteps) * costs_.voxelStep;
    ps += (c.shadings - before.shadings) * costs_.shade;
    if (speed_ == 1.0) return ps;
    return Picos(std::llround(double(ps) / speed_));
}

}  // namespace rt
