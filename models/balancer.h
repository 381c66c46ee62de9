// How far a boundary slides: the policies, as pure functions of what one node
// knows (its own box, load, busy time and work histogram, and its neighbour's
// last load report), so their guards can be tested on their own.
#pragma once
#include <optional>
#include <vector>

#include "box.h"
#include "machine_config.h"

namespace rt {

struct SlideQuery {
    Box own;                    // the giver's box now
    int axis = 0;
    bool upper = true;          // the boundary is the box's upper face along the axis (else the lower)
    double ownLoad = 0, otherLoad = 0;
    Picos ownBusy = 0, otherBusy = 0;   // busy time in the interval
    std::vector<Picos> histogram;       // work policy: work per bin along the axis, low to high
    double minThickness = 0;            // absolute
};

// The boundary's new coordinate if this node, the heavier one, gives a slab
// now; nullopt if it does not (inside the dead band, or the guard leaves
// nothing to give). The result always leaves the box at least minThickness
// thick, whatever the box already gave on its other side.
std::optional<double> decideSlide(const BalanceConfig& cfg, const SlideQuery& q);

}  // namespace rt
