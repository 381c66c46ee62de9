// The frame buffer / host: one input port per node (a Link with its own
// latency, bandwidth and depth), a cost per contribution accumulated, and the
// end-of-frame protocol: it has handed out credit 1 and knows the frame is
// done when the credit returned to it sums to exactly 1 (credit.h). The render
// time is that instant, when the machine itself would know.
#pragma once
#include <deque>
#include <vector>

#include <systemc>

#include "arrival_queue.h"
#include "credit.h"
#include "image.h"
#include "link.h"
#include "time_keeper.h"

namespace rt {

struct HostStats {
    Picos busy = 0;
    uint64_t contributions = 0, contributionMessages = 0, creditMessages = 0;
    Picos renderTime = 0;
    bool done = false;
};

class Host : public sc_core::sc_module {
public:
    SC_HAS_PROCESS(Host);
    Host(sc_core::sc_module_name name, int nodes, int width, int height, Picos costPerContribution, int maxExp,
         bool progress, Picos quantum);

    sc_core::sc_vector<sc_core::sc_port<LinkRecvIf>> in;

    // Credit the host keeps (not handed to nodes) and contributions it makes
    // itself (primary rays that miss the world box), before the start.
    void keep(const Credit& c) { returned_.add(c); }
    void addOwn(const Contribution& c) { own_.push_back(c); }

    // The image: each pixel the sum of its contributions in path-key order.
    Image image();
    const HostStats& stats() const { return stats_; }

private:
    void run();

    int width_, height_;
    Picos cost_;
    bool progress_;
    TimeKeeper time_;  // when to let the kernel catch up
    Credit returned_;
    // The contributions: each message's list as it came (kept, not copied:
    // copying them into one growing array cost about 9 % of a run, most of
    // it the kernel handing out fresh pages), and the host's own.
    std::deque<std::vector<Contribution>> received_;  // (a deque: grows without copying)
    std::vector<Contribution> own_;
    ArrivalQueue inputOrder_;
    HostStats stats_;
};

}  // namespace rt
