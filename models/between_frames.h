// Balancing between the frames of a sequence (--frames, --boundaries-from;
// doc/balancing.md, "Between frames"): where a frame's boundaries start,
// read from the report of the frame before, and `resplit`'s choice of the
// next frame's boundaries. Plain C++ on reports (JSON), run by rtsim between
// the child processes that render the frames.
#pragma once
#include <optional>
#include <vector>

#include <nlohmann/json.hpp>

#include "machine_config.h"

namespace rt {

// Per column (ColumnGeometry order): its N - 1 inner planes along the axis.
using InnerPlanes = std::vector<std::vector<double>>;

// Each column's inner planes where the run of report `r` ended them (their
// last positions in its boundary histories), for MachineConfig::
// startBoundaries; with `atStart`, where they stood when it began. Throws
// std::runtime_error if `r` is not a report of this mesh and axis.
InnerPlanes lastBoundaries(const nlohmann::json& r, const MachineConfig& m, bool atStart = false);

// `resplit`: each column's inner planes at the quantiles of its nodes' busy
// time in the run of report `r` (resplit.h): the tracing work where it
// happened (work_by_position), the rest of a node's busy time spread over its
// box as it stood on average over that frame. `step`: the share of the way
// from where the planes ended to those quantiles.
InnerPlanes resplitTargets(const nlohmann::json& r, const MachineConfig& m, double step = 1);

// `resplit` and `measured` over a sequence of frames: what the next frame
// does. Each frame re-splits towards the quantiles of the one before (the
// first re-split all the way, later ones half the way), as long as that
// keeps making frames faster:
//  - once two re-split frames in a row are not faster than the fastest
//    re-split frame so far, when that one beat the first frame, the
//    boundaries return to its planes and hold from then on (equal busy
//    times are not always the fastest frame: across the axis the frame also
//    waits for work to arrive, and re-splitting to equal busy times crept
//    from 825 to 953 us over ten frames);
//  - if neither of the first two re-split frames beats the first frame,
//    re-splitting does not pay here (past the links' knee thinner boxes
//    cost more link time than they save). (Two tries, not one: a first
//    re-split a few per cent slower than the first frame is often followed
//    by faster ones.) `measured`'s first frame was the starting split: it is
//    held. `resplit`'s was balanced by `slide`: one frame holds the split
//    the first frame started from; where even the first frame's slides
//    lose, that one wins and is held; otherwise every later frame is the
//    first one again.
class ResplitSequence {
public:
    explicit ResplitSequence(const MachineConfig& m) : m_(m), firstHolds_(m.balance.firstFrameHolds()) {}
    // After frame `frame` (1-based), whose report is `r`: the next frame's
    // targets, or nothing if the next frame is to be the first one again.
    std::optional<InnerPlanes> next(const nlohmann::json& r, int frame);
    // Whether the next frame starts where frame 1 did (the starting split's
    // trial), not where the frame before left the boundaries: in a steady
    // state the faces would be moved back once, and that frame is to show
    // the split itself.
    bool startsAfresh() const { return afresh_; }

private:
    static constexpr int kTries = 2;
    // How far each re-split after the first moves the planes towards their
    // quantiles (the first goes all the way): the work moves with the
    // planes (rays cross more boxes, and cross from column to column), so
    // full steps overshoot once the planes are near; half steps settle
    // (doc/balancing.md, "Why it settles").
    static constexpr double kStep = 0.5;
    static constexpr int kPatience = 2;  // such frames in a row before the fastest one's planes are held
    const MachineConfig& m_;
    bool firstHolds_;  // frame 1 held the starting split (measured): it needs no trial
    double firstNs_ = 0, bestNs_ = 1e300;  // the first frame's time; the fastest re-split frame's
    int resplits_ = 0;                     // re-split frames so far
    int misses_ = 0;                       // re-split frames in a row not faster than the fastest
    InnerPlanes best_;  // where the fastest re-split frame left the boundaries (not its report: K frames keep one)
    InnerPlanes start_;  // where frame 1's boundaries started
    std::optional<InnerPlanes> held_;
    bool tryingStart_ = false, again_ = false, afresh_ = false;
};

}  // namespace rt
