// The balancing policies by name: one line each.
#include "config/policy_table.h"

#include <string>

#include "config/start_constants.h"

namespace rt {

std::unique_ptr<BalancePolicy> makeSlidePolicy();
std::unique_ptr<BalancePolicy> makeWorkPolicy();
std::unique_ptr<BalancePolicy> makeQuantilePolicy();
std::unique_ptr<BalancePolicy> makeRelayPolicy();

const std::vector<PolicyInfo>& policies() {
    static const std::string sampleHelp =
        "the first frame starts at a split of its objects and length (--start-mix: by default the object median, "
        "weighing where the primary rays enter, where an intersection test costs at least a third of a ray's hop, "
        "else half each where that lightens a column's heaviest box (by more than chance where every column starts "
        "at the same planes), or the uniform split (and "
        "where a hop's wire time is at least " + std::to_string(kWirePerHandling) + " times its handling, where the "
        "half start's longest box would keep its link longer than the uniform split's frame, and on "
        "columns of more than " + std::to_string(kLongestColumnStartedByObjects) + " boxes)), gathers "
        "where a sample of its rays (one pixel in 16, generated first) did their work up each column, and moves "
        "every plane once to where that work splits evenly; later frames re-split as resplit";
    static const std::vector<PolicyInfo> all = {
        {"none", "boundaries stay where they start", PolicyKind::None, 0.0, nullptr},
        {"slide", "the paper: the heavier node moves its face by gain x load difference x thickness", PolicyKind::Dynamic,
         0.25, makeSlidePolicy},
        {"relay",
         "the paper's rule read so that work travels down a column: load as demand (work done and waiting, it does "
         "not saturate), and a slab with no recorded work counts by its thickness, so empty slabs pass work on",
         PolicyKind::Dynamic, 0.25, makeRelayPolicy},
        {"work", "the heavier node sheds gain x half the busy-time gap from its work next to the boundary",
         PolicyKind::Dynamic, 0.25, makeWorkPolicy},
        {"quantile", "each boundary moves gain of the way to its quantile of the column's demand (work done and waiting)",
         PolicyKind::Dynamic, 0.5, makeQuantilePolicy},
        {"resplit",
         "between frames, the boundaries move to the planes a forecast from the frame before finds fastest, if 4 % "
         "faster than holding them, and stay for the frame (the first frame, with no frame before, balances as slide)",
         PolicyKind::Dynamic, 0.25, makeSlidePolicy},
        {"measured",
         "as resplit, but the first frame keeps its starting split and only measures where the work is (no slides "
         "within a frame: the first frame is never slower than without balancing)",
         PolicyKind::Dynamic, 0.25, makeSlidePolicy},
        {"sample", sampleHelp.c_str(), PolicyKind::Dynamic, 0.25, makeSlidePolicy},
        {"median", "a static split at the object-median (or --start-mix's mix of objects and length), no messages",
         PolicyKind::Static, 0.0, nullptr},
    };
    return all;
}

const PolicyInfo* findPolicy(const std::string& name) {
    for (const PolicyInfo& p : policies())
        if (name == p.name) return &p;
    return nullptr;
}

}  // namespace rt
