// The express relay (--fidelity express; channel/express.h): the process
// that moves express rays through the boxes they skip, in simulated time.
// One for the machine; its events are the rays' hops, in a heap, not the
// nodes' processes and links.
#pragma once
#include <vector>

#include <boost/container/small_vector.hpp>
#include <systemc>

#include "base/radix_heap.h"
#include "channel/express.h"

namespace rt {

class ExpressRelay : public sc_core::sc_module {
public:
    SC_HAS_PROCESS(ExpressRelay);
    ExpressRelay(sc_core::sc_module_name name, ExpressRoutes& routes);
    // A ray node `from` sends towards `dir` at its time `t` on route `r`
    // (its skipped boxes: hops[r.first..]), its `order`-th express ray: on
    // the sender's link now, then from box to box.
    void send(size_t from, int dir, const ExpressRoutes::Route& r, const std::vector<ExpressHop>& hops, Message&& m, Picos t,
              uint64_t order);
    // Rays on their way (none once a frame completed).
    size_t inFlight() const { return rays_.size() - free_.size(); }
    // The next frame of a sequence: its process, as the nodes' (spawn.h).
    sc_core::sc_process_handle restart(int frame);
    void quiet() { wake_.cancel(); }

private:
    void run();
    void hop(uint32_t slot, Picos t);  // ray `slot` reaches its next box at `t`
    // Ray `slot`, ready at `ready`, on link `l` (`first`: its sender's, the
    // machine's wire) once it has a slot (`queued`: it waited for this one).
    void launch(uint32_t slot, ExpressLink& l, Picos ready, bool first, bool queued = false);
    struct Ray {
        Message m;
        boost::container::small_vector<ExpressHop, 12> hops;  // (a path across 32 boxes has at most 94)
        uint32_t next = 0;  // the hop it reaches next
        uint32_t sender = 0;
        uint64_t order = 0;
        ExpressLink* on = nullptr;  // the link it is on, and its number there (its slot's)
        uint64_t number = 0;
        bool first = true;          // on its sender's link
    };
    uint32_t slotFor();  // a free slot of rays_
    ExpressRoutes& routes_;
    RadixHeap<uint32_t> events_;  // (time, slot): when a ray reaches its next box
    std::vector<uint32_t> ties_;  // the slots of one time, in order
    std::vector<Ray> rays_;
    std::vector<uint32_t> free_;  // slots of rays_ to reuse
    sc_core::sc_event wake_;
    Picos wakeAt_ = ~Picos(0);
};

}  // namespace rt
