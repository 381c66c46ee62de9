// Balancing between the frames of a sequence (--frames, --boundaries-from;
// doc/balancing.md, "Between frames"): where a frame's boundaries start,
// taken from what the frame before left behind (frame_state.h), and
// `resplit`'s choice of the next frame's boundaries.
#pragma once
#include <optional>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "balance/frame_forecast.h"
#include "balance/frame_state.h"
#include "config/machine_config.h"

namespace rt {

// Each column's inner planes where frame `r` ended them (their last
// positions in its boundary histories), for MachineConfig::startBoundaries;
// with `atStart`, where they stood when it began. Throws std::runtime_error
// if `r` ran on another mesh or axis, or lacks a boundary.
InnerPlanes lastBoundaries(const FrameState& r, const MachineConfig& m, bool atStart = false);
// The uniform split of the mesh `r` ran on, every column's inner planes
// (Lattice::uniform over the world its boxes cover): the unbalanced
// frame's.
InnerPlanes uniformBoundaries(const FrameState& r, const MachineConfig& m);

// The time-weighted mean position of a boundary over [0, end]: `history`
// holds (time, position) from time 0 on, in time order.
double timeAveraged(const std::vector<std::pair<double, double>>& history, double end);

// Each column's planes as they stood on average over frame `r`.
InnerPlanes averagedBoundaries(const FrameState& r, const MachineConfig& m);

// `resplit`'s planes for the frame after frame `r` (frame_forecast.h):
// of the planes where `r`'s frame ended, the best per column and the best
// for all columns, the ones of the shortest forecast frame, getting there
// included (move_forecast.h); the planes move only if that forecast is at
// least kMinForecastGain shorter than the forecast for holding them: the
// forecast misses the frames measured by some per cent, and a move that
// gains less than its miss can lose. Where the links are the frame, the
// columns' own planes must also be kMinForecastGain shorter than the
// aligned ones: the rays they pass on between columns are what the
// forecast counts short there. (Why 4 %, and the misses measured:
// doc/history.md, "Figures behind the code's comments".)
constexpr double kMinForecastGain = 0.04;
// The choice between planes prices getting there by the longest chain
// (moveNs) added to the frame. A move is then refused where, each node
// starting its frame when its faces are in place (the handovers followed
// one by one: facesInPlaceNs), the frame would be more than
// kMinForecastGain slower than the unbalanced split's (both forecast):
// there moving makes the frame lose against not balancing. On 33x1x1 (the
// paper's machine, 1,000 spheres in 5 % of the axis, across it) the planes
// moved one after another, the move took about 228 ms where the chain said
// 90.3, and frame 2 took 1.632 of the unbalanced frame; forecast so, 267.9
// ms against the unbalanced 153.1 (it took 258.7). Against the unbalanced
// frame, not the frame held: a move that costs its own frame more than
// holding can still pay in the frames after it (balls-5 on 16x16x4 on the
// paper's machine under sample: 0.644 of the unbalanced frame, then
// 0.162, where holding gave 0.614), and the choice itself keeps the
// chain's price: a move priced exactly made the columns' own planes win
// where their frame's forecast misses the latency of the rays they pass
// between columns (doc/history.md).
struct ResplitChoice {
    const char* what;  // "held", "per column" or "aligned"
    InnerPlanes planes;
    double forecastNs, heldNs;  // the next frame, forecast: with these planes; with the planes held
    double inPlaceNs = 0;  // with these planes, each node starting when its faces are in place (0: held)
    // A move the chain's price would have taken, refused: its forecasts.
    const char* refused = nullptr;
    double refusedNs = 0, refusedInPlaceNs = 0;
    double uniformNs = 0;  // the uniform split's frame, forecast (where a move was taken or refused)
};
// With the scene's `objects` the forecast counts the grids a move would
// coarsen (FrameForecast, kCoarser).
ResplitChoice resplitChoice(const FrameState& r, const MachineConfig& m, const std::vector<Shape>* objects = nullptr);
// One try (sample): the first time the forecast says hold, a re-split it
// forecasts at least this much faster is run once all the same; if that
// frame is not the fastest, the fastest frame's planes are held (kPatience).
// sample's re-splits start from a first frame whose planes moved partway
// through, and the forecast, which counts busy time and not the waiting of
// fill and drain, can miss a gain the 4 % margin hides: on Fig. 4's modern
// machine across the axis at N = 5, f = 1/5, frame 2 gave 0.516 of the
// unbalanced frame and the forecast saw under 4 % to gain; the one try gave
// 0.494 (doc/balancing.md, "The recommended policy").
constexpr double kTryGain = 0.01;
InnerPlanes resplitTargets(const FrameState& r, const MachineConfig& m, const std::vector<Shape>* objects = nullptr);

// `resplit` and `measured` over a sequence of frames: what the next frame
// does. Each frame re-splits by the forecast from the one before
// (resplitChoice), as long as that keeps making frames faster:
//  - once a re-split frame is not faster than the fastest re-split frame
//    so far, when that one beat the first frame, the boundaries return to
//    its planes and hold from then on (the forecast missed there: on
//    balls-4, N = 4, 1 GB/s, moving on after such a frame made frames of
//    0.23 and then 0.50 of the unbalanced one);
//  - if neither of the first two re-split frames beats the first frame,
//    re-splitting does not pay here (past the links' knee thinner boxes
//    cost more link time than they save). (Two tries, not one: a first
//    re-split a few per cent slower than the first frame is often followed
//    by faster ones.) `measured`'s first frame was the starting split: it is
//    held. `resplit`'s was balanced by `slide`: one frame holds the split
//    the first frame started from; where even the first frame's slides
//    lose, that one wins and is held; otherwise every later frame is the
//    first one again. `sample`'s started at a split of its objects, which
//    held for a whole frame can lose (on the paper's machine across the
//    axis at N = 8, f = 1: 1.045 of the unbalanced frame): its trial holds
//    the uniform split, the unbalanced frame itself.
// sample's trial is run only where the forecast (from the last re-split
// frame) puts it within this many times frame 1's time. Its trial, the
// uniform split, is the unbalanced frame itself: where frame 1 took 0.285
// of it (the paper's machine across the axis at N = 5, f = 1/5) the trial
// was a frame lost. The forecast misses frames by a few per cent, by up to
// a quarter in the worst cases measured (doc/balancing.md, "Between
// frames"); on the 23 Fig. 4 sequences that ran the trial it was within
// 5 % of the frame the trial then measured (doc/balancing.md, "The
// recommended policy").
constexpr double kTrialReach = 1.2;
// Polish (--polish-tries K): the forecast misses frames by a few per cent
// (a box's tests move with the objects a plane cuts and with its grid's
// cells: doc/balancing.md, "Polish"), more than is left to gain once the
// sequence holds. So the sequence then spends K frames on moves of its own
// from the planes held, each run as a frame and kept only if that frame is
// faster: the busiest node's box shrunk on the side of its less busy
// neighbour, by kPolishShrink of the thinner of the two boxes that face
// bounds; every plane shifted towards the axis's start by that share of the
// thinner box it bounds; or towards its end. In that order, the share
// halved after each round of the three. Then the fastest planes are held
// (under sample, frame 1 again if they are still slower than frame 1; and
// where no re-split frame beat frame 1, only if the fastest of them took
// at most kTrialReach times frame 1: else frame 1 again at once).
// (measured's hold of its own starting split, where re-splitting did not
// pay, is not polished: that frame 1 was the unbalanced split itself.)
constexpr double kPolishShrink = 0.08;
// A move is tried only where the forecast from the last frame puts its
// frame, with getting there, at least kPolishRoom faster than the
// unbalanced split's (the starting split of measured, the uniform split of
// sample): a try is a frame risked on what the forecast cannot see, and
// where the frame held is near the unbalanced one, a miss of a few per cent
// loses. (Without it, on Fig. 4's f = 1, where the frames held ran 0.98 to
// 1.0 of the unbalanced frame, tries ran 1.045 to 1.066 on the modern
// machine at N = 2 and 1.031 to 1.068 on the 1987 machine at N = 8.)
constexpr double kPolishRoom = 0.1;
// The busiest node of a frame, and its neighbours' busy times along the column.
struct Busiest {
    Cell cell{};
    double belowNs = -1, aboveNs = -1;  // (-1: no neighbour there)
};
class ResplitSequence {
public:
    explicit ResplitSequence(const MachineConfig& m, const std::vector<Shape>* objects = nullptr)
        : m_(m), objects_(objects), firstHolds_(m.balance.firstFrameHolds()), tries_(m.balance.triesWithinTheMargin()) {}
    // After frame `frame` (1-based), which left `r`: the next frame's
    // targets, or nothing if the next frame is to be the first one again.
    std::optional<InnerPlanes> next(const FrameState& r, int frame);
    // Whether the next frame starts where frame 1 did (the starting split's
    // trial), not where the frame before left the boundaries: in a steady
    // state the faces would be moved back once, and that frame is to show
    // the split itself.
    bool startsAfresh() const { return afresh_; }
    // What next() chose and why, for the report's frames: {"next": "per
    // column" | "aligned" | "held" | "one try: per column" | "one try:
    // aligned" | "the fastest frame's planes" | "the
    // starting split" | "the uniform split" | "frame 1 again" | "a move
    // tried"}, with the forecasts when it re-split (forecast_ns,
    // held_forecast_ns; where a move was taken or refused,
    // faces_in_place_forecast_ns, unbalanced_forecast_ns and refused:
    // {what, forecast_ns, faces_in_place_forecast_ns}), and when it tries
    // a move, the time of the frame held (held_ns).
    const nlohmann::json& said() const { return said_; }

private:
    static constexpr int kTries = 2;
    static constexpr int kPatience = 1;  // such frames in a row before the fastest one's planes are held
    const MachineConfig& m_;
    const std::vector<Shape>* objects_;  // the scene's (FrameForecast), if given
    bool firstHolds_;  // frame 1 held the starting split (measured): it needs no trial
    double firstNs_ = 0, bestNs_ = 1e300;  // the first frame's time; the fastest re-split frame's
    int resplits_ = 0;                     // re-split frames so far
    int misses_ = 0;                       // re-split frames in a row not faster than the fastest
    InnerPlanes best_;  // where the fastest re-split frame left the boundaries (not its report: K frames keep one)
    InnerPlanes start_;  // the trial's split: where frame 1's boundaries started, or the uniform split (sample)
    std::optional<InnerPlanes> held_;
    bool tries_;          // tries once within the margin (sample: triesWithinTheMargin)
    bool tried_ = false;  // and has
    bool tryingStart_ = false, again_ = false, afresh_ = false;
    nlohmann::json said_;
    std::optional<InnerPlanes> forecast(const FrameState& r);  // resplitChoice, said
    std::optional<InnerPlanes> firstFrame(const FrameState& r);    // frame 1's
    std::optional<InnerPlanes> noResplitWon(const FrameState& r);  // no re-split frame has beaten frame 1 yet
    // Holding `planes`, whose frame took `ns`: polished first (kPolishShrink).
    std::optional<InnerPlanes> hold(const InnerPlanes& planes, double ns, const Busiest& busiest, const FrameState& r);
    std::optional<InnerPlanes> polish(const FrameState& r);  // after a polish frame
    std::optional<InnerPlanes> tryMove(const FrameState& r);  // from base_, or nothing once the tries are spent
    InnerPlanes moved(int kind) const;                       // base_ with move `kind` (0 to 2), at shrink_
    // A column's box edge i along the axis: its inner plane i, and the
    // world's ends before the first (i < 0) and past the last.
    double edge(const std::vector<double>& planes, int i) const {
        return i < 0 ? worldLo_ : i >= int(planes.size()) ? worldHi_ : planes[size_t(i)];
    }
    bool polishing_ = false;
    bool trying_ = false;    // the frame being run tries a move
    bool orFirst_ = false;   // frame 1 again, unless the polish beats it
    int polishLeft_ = 0, moveKind_ = 0;
    double shrink_ = kPolishShrink;
    InnerPlanes base_;       // the fastest planes polished so far, their frame's time and busiest node
    double baseNs_ = 0;
    Busiest baseBusiest_{};
    Busiest bestBusiest_{};  // the fastest re-split frame's
    double worldLo_ = 0, worldHi_ = 0;  // the world along the axis
};

}  // namespace rt
