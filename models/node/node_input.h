// What a node has to work on, and the order in which it takes it
// (doc/machine.md, "A node"):
//  1. rays in hand: those spawned here (last in, first out: a ray tree is
//     followed depth first), then the rest of a batch received;
//  2. the message that arrived first on its links (arrival_queue.h; ties
//     to the lower port), which a node running ahead of the kernel takes
//     only once it sees it is the first (Node::takeWork);
//  3. a new primary ray of the pixels the host assigned it.
// Control messages on a link's control lane come before all of these
// (Node::takeControl).
#pragma once
#include <array>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include "channel/arrival_queue.h"
#include "camera.h"
#include "channel/link.h"
#include "node/primary_queue.h"
#include "channel/ray_batcher.h"
#include "shading.h"

namespace rt {

// A ray to step, with its credit 2^-creditExp.
struct Work {
    RayJob job;
    uint16_t creditExp;
    bool fromLink;   // the first ray of a message from a link: it carries the message's handling cost
    bool generated;  // a primary ray generated here: it carries the generation cost
    int8_t from;     // the link direction it arrived on (-1: made here)
    // A ray taken from a link message.
    void take(const RayItem& r, bool first, int8_t dir) {
        r.fill(job);
        creditExp = r.creditExp;
        fromLink = first;
        generated = false;
        from = dir;
    }
};

class NodeInput {
public:
    // As the machine is built: the node's input link from direction `dir`,
    // listened to in every frame.
    void listen(int dir, Link& in) {
        arrivals_.listen(dir, &in);
        // The links themselves, read at every step: a port's interface is
        // one more pointer to follow (a cache miss on a node not run for a while).
        links_[size_t(dir)] = &in;
    }
    // Before the start: the pixels whose primary rays this node generates,
    // each with credit 2^-exp; `sampleWidth`: `sample`'s first; `spread`:
    // --primary-order spread (primary_queue.h).
    void assignPrimaries(const std::vector<uint32_t>& pixels, int exp, uint32_t sampleWidth = 0, bool spread = false) {
        primaries_.assign(pixels, uint16_t(exp), sampleWidth, spread);
    }
    PrimaryQueue& primaries() { return primaries_; }
    // The next frame: nothing in hand, no primary rays; the same links.
    void restart() {
        arrivals_.restart();
        local_.clear();
        received_.clear();
        receivedNext_ = 0;
        receivedFrom_ = -1;
        primaries_ = PrimaryQueue{};
    }

    // A ray spawned here.
    void spawn(const RayJob& j, uint16_t creditExp) { local_.push_back(Work{j, creditExp, false, false, -1}); }
    // A ray of the sample taken from a link's control lane (--sample-end
    // credit): one ray a message; the rest of a batch in hand stays.
    void takePriorityRay(const Message& m, int dir, Work& w) {
        if (m.rayCount() != 1) throw std::logic_error("a ray message on a control lane with more than one ray");
        w.take(m.rayAt(0), true, int8_t(dir));
    }
    // Rays spawned here not yet stepped.
    bool spawnedInHand() const { return !local_.empty(); }
    // The next ray in hand, if any.
    bool takeInHand(Work& w) {
        if (!local_.empty()) {
            w = local_.back();
            local_.pop_back();
            return true;
        }
        if (receivedNext_ < received_.size()) {  // the rest of a batch: its message was handled already
            w.take(received_[receivedNext_++], false, receivedFrom_);
            return true;
        }
        return false;
    }
    // The oldest message on the links (-1 if none has arrived by `now`);
    // `next`: the earliest arrival of any not taken (~0 if none).
    int oldest(Picos now, Picos& next) { return arrivals_.oldest(now, next); }
    Message consume(int dir, Picos now) { return links_[size_t(dir)]->consume(now); }
    // A ray message taken from `dir`: its first ray into `w`, the rest in
    // hand; its list, once done with, to `batcher` for reuse.
    void takeRays(Message& m, int dir, Work& w, RayBatcher& batcher);
    // The control lane of the link from `dir`: its oldest message, if it has arrived by `now`.
    bool controlArrived(int dir, Picos now) const { return links_[size_t(dir)] && links_[size_t(dir)]->controlArrivedBy(now); }
    Message consumeControl(int dir, Picos now) { return links_[size_t(dir)]->consumeControl(now); }
    // The next primary ray, if any pixel is left.
    bool nextPrimary(Work& w, const Camera& camera, const Box& world) {
        Primary p;
        if (!primaries_.next(p)) return false;
        w = Work{primaryOf(camera, p.pixel, world), p.exp, false, true, -1};
        return true;
    }
    // `sample`: the primary rays not yet generated that start at or beyond
    // `boundary` along `axis` (below it if !upper), taken out with their
    // credit, to go with a slab (MessageBody::primaries).
    HandedPrimaries handOver(const Camera& camera, const Box& world, int axis, double boundary, bool upper);
    // The primary ray of an image pixel (its index, row by row).
    static RayJob primaryOf(const Camera& camera, uint32_t pixel, const Box& world) {
        const uint32_t width = uint32_t(camera.width());
        return primaryJob(camera, int(pixel % width), int(pixel / width), world);
    }

    size_t inHand() const { return local_.size() + (received_.size() - receivedNext_); }
    // Its queue at `at`: rays in hand and messages arrived by then, not yet
    // taken (counted in simulated time, so the same in every exact mode).
    size_t depth(Picos at) const { return inHand() + arrivals_.arrivedBy(at); }
    size_t primariesLeft() const { return primaries_.left(); }
    // Rays, contributions and credit on their way to it (for the watchdog's message).
    uint64_t onTheirWay() const;
    // Where it waits for input (arrival_queue.h).
    ArrivalQueue& arrivals() { return arrivals_; }
    const ArrivalQueue& arrivals() const { return arrivals_; }

private:
    // (What taking work reads, together, ahead of the arrival queue's
    // first fields: on a large mesh each cache line of it is a miss.)
    std::array<Link*, kDirs> links_{};  // in[d]'s link (null: none), set at the start
    std::vector<Work> local_;           // spawned rays, LIFO
    RayList received_;                  // the rest of the last batch received (FIFO)
    size_t receivedNext_ = 0;
    int8_t receivedFrom_ = -1;          // the link it came on
    PrimaryQueue primaries_;
    ArrivalQueue arrivals_;
};

}  // namespace rt
