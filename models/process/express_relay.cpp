#include "process/express_relay.h"

#include <algorithm>

#include "base/frame_clock.h"
#include "process/spawn.h"

namespace rt {

ExpressRelay::ExpressRelay(sc_core::sc_module_name name, ExpressRoutes& routes) : sc_module(name), routes_(routes) {
    SC_METHOD(run);
}

sc_core::sc_process_handle ExpressRelay::restart(int frame) {
    quiet();
    events_.clear();
    rays_.clear();
    free_.clear();
    wakeAt_ = ~Picos(0);
    return spawnMethod([this] { run(); }, *this, frame);
}

uint32_t ExpressRelay::slotFor() {
    if (free_.empty()) {
        rays_.emplace_back();
        return uint32_t(rays_.size() - 1);
    }
    const uint32_t slot = free_.back();
    free_.pop_back();
    return slot;
}

void ExpressRelay::send(size_t from, int dir, const ExpressRoutes::Route& r, const std::vector<ExpressHop>& hops, Message&& m,
                        Picos t, uint64_t order) {
    const uint32_t slot = slotFor();
    Ray& ray = rays_[slot];
    ray.m = std::move(m);
    ray.hops.assign(hops.begin() + r.first, hops.begin() + r.first + r.skipped);
    ray.next = 0;
    ray.sender = uint32_t(from);
    ray.order = order;
    launch(slot, routes_.node(from).out[size_t(dir)], t, true);
}

void ExpressRelay::launch(uint32_t slot, ExpressLink& l, Picos ready, bool first, bool queued) {
    Ray& ray = rays_[slot];
    ray.first = first;
    const Picos free = l.slotFree();
    if (!queued && (free == ExpressLink::kUnknown || l.waitingHead < l.waiting.size())) {  // (behind the rays that wait)
        l.waiting.emplace_back(slot, ready);
        return;
    }
    Picos start;
    if (first) {
        // (Under --fidelity through a node both sends express rays of its
        // own and passes the relay's on this wire: they take it in turn.)
        start = l.link->expressStart(ray.m.bytes(), std::max({ready, free, l.free}));
        l.free = std::max(l.free, start + l.wire);
    } else {
        start = std::max({ready, free, l.free});
        if (l.shared) start = l.link->shareWire(ray.m.bytes(), start);
        l.free = start + l.wire;
        ++l.rays;
    }
    ray.on = &l;
    ray.number = l.wired;
    l.putOnWire();
    const Picos at = start + l.hop();
    checkSimTime(at, [this] { return name(); });
    events_.push(at, slot);
    if (at < wakeAt_) {  // sooner than the relay expects to run
        wakeAt_ = at;
        wake_.notify(sc_core::sc_time::from_value(at - frameClock()));
    }
}

// At the kernel's time no ray still to be sent can reach a box before it
// plus the soonest hop (its sender's time is at least the kernel's): the
// hops before then are final, and the relay takes them in order of time,
// rays that reach boxes at the same time in the order of their senders and
// of their sending.
void ExpressRelay::run() {
    const Picos now = frameClock(), horizon = now + routes_.soonestHop();
    while (!events_.empty() && events_.top() < horizon) {
        const Picos t = events_.top();
        ties_.clear();
        events_.popTies(ties_);
        if (ties_.size() > 1)
            std::sort(ties_.begin(), ties_.end(), [this](uint32_t a, uint32_t b) {
                const Ray &x = rays_[a], &y = rays_[b];
                return x.sender != y.sender ? x.sender < y.sender : x.order < y.order;
            });
        for (uint32_t slot : ties_) hop(slot, t);
    }
    wakeAt_ = events_.empty() ? ~Picos(0) : events_.top();
    if (events_.empty()) sc_core::next_trigger(wake_);
    else sc_core::next_trigger(sc_core::sc_time::from_value(wakeAt_ - now), wake_);
}

// Through the box's processor (after the passes before it and the node's
// own steps), then on its link: the last box's is the machine's own link,
// into the node that takes the ray.
void ExpressRelay::hop(uint32_t slot, Picos t) {
    Ray& ray = rays_[slot];
    const ExpressHop h = ray.hops[ray.next];
    ExpressNode& n = routes_.node(h.node);
    ExpressLink& out = n.out[size_t(h.dir)];
    // (--fidelity through) A node with work now takes the ray into its
    // input, behind the rays before it, as in the exact model.
    ExpressLink& in = *ray.on;
    const bool busy = n.through && n.busyAt(t) && in.link->mayDeliverExpress();
    const Picos taken = busy ? t : std::max(t, n.processorFree), passed = taken + h.step;
    if (!busy) n.processorFree = passed;
    // Taken from the link it came by: its slot's credit goes back, and a ray waiting for one may go.
    in.taken[ray.number] = taken;
    while (in.waitingHead < in.waiting.size() && in.slotFree() != ExpressLink::kUnknown) {
        const auto [next, ready] = in.waiting[in.waitingHead++];
        if (in.waitingHead == in.waiting.size()) {
            in.waiting.clear();
            in.waitingHead = 0;
        }
        launch(next, in, ready, rays_[next].first, true);
    }
    if (busy) {
        ray.m.ray.t0 = h.t0;
        in.link->deliverExpress(std::move(ray.m), t);
        free_.push_back(slot);
        return;
    }
    if (++ray.next == ray.hops.size()) {
        out.link->send(std::move(ray.m), passed);
        free_.push_back(slot);
        return;
    }
    launch(slot, out, passed, false);
}

}  // namespace rt
