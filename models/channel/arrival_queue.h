// The order in which a process takes its input: of the messages at the heads
// of its input links, the one that arrived first, ties to the lower port.
// Nodes and the host take their input in this order, which is what makes a
// run independent of the order in which the kernel runs processes.
//
// The links tell the queue when their oldest unconsumed message changes (a
// message lands in an empty link, the oldest is consumed, or a control
// message goes ahead), with its arrival, and the queue keeps each port's
// head. With a few ports (a node has six) a choice scans those heads, which
// sit in the queue itself. With many (a frame-buffer unit has one port per
// node: 4,096 on a 16x16x16 mesh) it also keeps a min-heap of (arrival,
// port); entries are checked against the port's head when they reach the
// top and dropped if it has moved on, so a choice costs O(log ports). Either
// way a choice touches no link.
//
// It also wakes its process: a process with nothing to do waits until its
// next known arrival (waitForInput), and only a message that lands in an
// empty link and arrives sooner than that notifies it. A message behind
// another in its link, or sent to a busy process, costs the kernel nothing.
#pragma once
#include <algorithm>
#include <functional>
#include <queue>
#include <vector>

#include <boost/container/small_vector.hpp>
#include <systemc>

#include "base/frame_clock.h"
#include "channel/link.h"

namespace rt {

class ArrivalQueue : public ArrivalListener {
public:
    // Listens to `link` as its port `port` (ports with no link stay empty),
    // in every frame: a link keeps its listener when a frame restarts it
    // (Link::restart), so a frame's start touches none of them. The machine
    // has each process listen as it builds the links, while their memory is
    // being written anyway (at 32x32x32 the frame-buffer units listen to
    // 524,288 links, most of which never carry a message).
    void listen(int port, LinkRecvIf* link) {
        if (links_.size() <= size_t(port)) {
            if (head_.capacity() <= size_t(port)) {  // (grown by doubling: a unit's ports come one at a time)
                head_.reserve(std::max(size_t(port) + 1, 2 * head_.capacity()));
                links_.reserve(head_.capacity());
            }
            links_.resize(size_t(port) + 1, nullptr);
            head_.resize(size_t(port) + 1, kNone);
        }
        links_[size_t(port)] = link;
        if (link) link->setListener(this, port);  // (it tells the head it has now)
    }

    // A process that may take its input late (a frame-buffer unit other
    // than 0: FrameBufferUnit::setLate) is woken up to `late` after a message
    // on ports below `punctualFrom` arrives, and at once by one on the others.
    void setLate(Picos late, size_t punctualFrom) {
        late_ = late;
        punctualFrom_ = punctualFrom;
    }

    void headChanged(int port, Picos arrival) override {
        head_[size_t(port)] = arrival;
        if (arrival == kNone) return;
        if (heaped()) heap_.push({arrival, port});
        const Picos w = std::max(arrival, notBefore_) + (size_t(port) < punctualFrom_ ? late_ : 0);
        if (waiting_ && w < wakeAt_) {  // sooner than the waiting process expects
            wakeAt_ = w;
            arrived_.notify(sc_core::sc_time::from_value(w - frameClock()));
        }
    }

    // In the calling (method) process, at local time `now` (at or ahead of
    // the kernel's): if a message has arrived by `now`, whether the kernel
    // must still catch up with `now`; otherwise, until the next message
    // arrives or `deadline`, whichever is first. Arms the process's next
    // activation for then and returns true, or returns false if no wait is
    // needed. One wait, however far ahead `now` is: the process looks at its
    // input only once the kernel is there, so nothing that arrives by then
    // can be missed. The process calls woke() when it runs again.
    bool waitForInput(Picos now, Picos deadline = ~Picos(0)) {
        Picos next;
        oldest(now, next);
        if (late_ > 0) {  // the first message late, those on punctual ports at once
            if (next != kNone) next += late_;
            for (size_t p = punctualFrom_; p < head_.size(); ++p) next = std::min(next, head_[p]);
        }
        next = std::max(now, std::min(next, deadline));
        const Picos k = frameClock();
        if (next <= k) return false;
        waiting_ = true;
        notBefore_ = now;
        wakeAt_ = next;
        if (next != ~Picos(0)) sc_core::next_trigger(sc_core::sc_time::from_value(next - k), arrived_);
        else sc_core::next_trigger(arrived_);
        return true;
    }
    void woke() { waiting_ = false; }
    // The frame is over: no wake still to come.
    void quiet() { arrived_.cancel(); }
    // The next frame: its links, emptied too (Link::restart), still tell
    // this queue their heads; it starts with none.
    void restart() {
        quiet();
        std::fill(head_.begin(), head_.end(), kNone);
        heap_ = {};
        buffered = 0;
        waiting_ = false;
        notBefore_ = wakeAt_ = 0;
        late_ = 0;
        punctualFrom_ = ~size_t(0);
    }

    // The port whose oldest message has arrived by `now` and arrived first
    // (ties to the lower port), or -1; `next` gets the earliest arrival of any
    // unconsumed message (~0 if none).
    int oldest(Picos now, Picos& next) {
        if (!heaped()) {
            int port = -1;
            next = kNone;
            for (size_t p = 0; p < head_.size(); ++p)
                if (head_[p] < next) {  // (strictly: ties to the lower port)
                    next = head_[p];
                    port = int(p);
                }
            return next <= now ? port : -1;
        }
        while (!heap_.empty()) {
            const Entry& e = heap_.top();
            if (head_[size_t(e.port)] == e.arrival) break;
            heap_.pop();  // that message has been consumed
        }
        if (heap_.empty()) {
            next = ~Picos(0);
            return -1;
        }
        next = heap_.top().arrival;
        return next <= now ? heap_.top().port : -1;
    }

    // Messages on the listened links or arrived there, not yet taken.
    size_t unconsumed() const { return buffered; }

    // Messages that have arrived at the listened ports by `t`, not yet taken.
    // (Only the links whose oldest message has arrived by then: the others
    // have none, and are not read.)
    size_t arrivedBy(Picos t) const {
        size_t n = 0;
        for (size_t p = 0; p < links_.size(); ++p)
            if (head_[p] <= t) n += links_[p]->arrivedBy(t);
        return n;
    }

private:

    struct Entry {
        Picos arrival;
        int port;
        bool operator>(const Entry& o) const { return arrival != o.arrival ? arrival > o.arrival : port > o.port; }
    };
    static constexpr Picos kNone = ~Picos(0);
    static constexpr size_t kScanned = 8;  // ports up to which a choice scans the heads, without the heap
    bool heaped() const { return head_.size() > kScanned; }
    // What a message landing in an empty link and a choice of input read
    // first, in the queue's first cache lines (on a large mesh the sender
    // finds its receiver's queue cold): the wait's state and the heads.
    bool waiting_ = false;
    Picos notBefore_ = 0;        // while waiting: the process's local time, before which it takes nothing
    Picos wakeAt_ = 0;           // while waiting: when the process wakes anyway
    Picos late_ = 0;             // setLate
    size_t punctualFrom_ = ~size_t(0);
    // Each port's oldest unconsumed arrival, as its link last said (kNone: empty).
    boost::container::small_vector<Picos, kScanned> head_;
    std::vector<LinkRecvIf*> links_;
    std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> heap_;
    sc_core::sc_event arrived_;  // wakes the waiting process
};

}  // namespace rt
