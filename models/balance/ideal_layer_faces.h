// Faces shared by a whole layer, agreed at no cost: a measuring device, not
// a machine (`--faces ideal-layer`; doc/fig4.md, "Faces in line").
//
// Under `slide` each column moves its own faces, so the faces of
// neighbouring columns drift apart and rays crossing from one column into
// the next are passed on untraced. Would faces that stay in line (one plane
// per layer boundary, as the paper may have meant) balance without that
// cost? To measure it without building the layer's agreement protocol
// first, this object sums each layer's execution and wait time per
// interval directly (no messages, no delay) and applies the paper's rule to
// the layers: face k moves into the heavier of layers k and k + 1 by
// gain x (load difference) x that layer's thickness, if the loads differ by
// more than the dead band, the layer kept at least the minimum thick. Every
// column's pair then moves its own face to that plane, with the protocol's
// usual slides, rounds and guard. What it gives is an optimistic bound on
// any layer agreement built from messages, which would add its own traffic
// and delay.
#pragma once
#include <map>
#include <utility>
#include <vector>

#include "config/machine_config.h"

namespace rt {

class IdealLayerFaces {
public:
    // `faces`: the count - 1 inner planes along the axis at the start (the
    // same in every column), between the world's `lo` and `hi`.
    IdealLayerFaces(std::vector<double> faces, double lo, double hi, double deadband, double gain,
                    double minThickness);

    // Layer `layer`'s node spent `exec` tracing and `wait` waiting in interval `interval` (0-based).
    void add(int layer, long interval, Picos exec, Picos wait);
    // Plane k (between layers k and k + 1) after the rule has been applied
    // for intervals 0 .. through - 1 (the start's plane for 0). Fixed the
    // first time it is asked for, from the loads summed by then, so both
    // nodes of a face, asking at different times, get the same plane.
    double face(int k, long through);

private:
    double load(int layer, long interval) const;

    double lo_, hi_, deadband_, gain_, minThickness_;
    std::vector<std::vector<double>> planes_;  // [t]: the planes after t intervals
    std::map<std::pair<int, long>, std::pair<double, double>> sums_;  // (layer, interval): exec, wait
};

}  // namespace rt
