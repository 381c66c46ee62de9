// A rectilinear lattice: per axis a sorted list of plane coordinates, cutting
// a box into cells. It serves both the voxel grid of one region (uniform
// planes) and the partition of the world into regions (any planes).
//
// Cell membership is defined in ray-parameter space, with one half-open rule
// used everywhere: along an axis where the ray moves, cell i owns the
// parameters t in [t(entry plane), t(exit plane)); along an axis where it does
// not move, cell i owns the ray if p[i] <= o < p[i+1]. A ray's segment in a
// cell is the intersection of the three axis intervals. Because all crossings
// come from Ray::tAt on the same plane values, consecutive cells share their
// boundary parameter exactly and a ray's parameter line is cut into disjoint
// pieces, with no gaps and no overlaps, whatever the rounding.
#pragma once
#include <array>
#include <utility>
#include <optional>
#include <vector>

#include "box.h"

namespace rt {

using Cell = std::array<int, 3>;

struct Interval {
    double lo, hi;  // half-open [lo, hi)
    bool empty() const { return !(lo < hi); }
};

// The slab rule for one axis of a box [lo, hi]; used by Lattice and for a
// region's own box, so both give the same doubles.
Interval slabInterval(const Ray& r, int axis, double lo, double hi);
// The ray's parameters owned by box b (the intersection of its three slabs).
Interval boxInterval(const Ray& r, const Box& b);
// The three slabs of box b and their intersection, for a caller that asks
// both whether it owns a parameter and which face the ray leaves by.
struct BoxSlabs {
    std::array<Interval, 3> slab;
    Interval span;  // boxInterval(r, b), to the bit
    // The face by which a ray that starts inside the box leaves it at
    // span.hi: the first axis (x, y, z) whose slab ends there, and +1 or -1
    // as the ray moves along it; axis -1 if none (the span is unbounded).
    // It is the face a ray at parameter span.hi is outside of first, axis
    // by axis: the rule Node::route applies to it. (Found as the slabs are
    // intersected: the first axis to lower span.hi to its final value.)
    std::pair<int, int> exitFace(const Ray& r) const {
        if (exitAxis < 0) return {-1, 0};
        return {exitAxis, r.d[exitAxis] > 0 ? +1 : -1};
    }
    int exitAxis = -1;
};
BoxSlabs boxSlabs(const Ray& r, const Box& b);

class Lattice {
public:
    Lattice() = default;
    // planes[a] must be strictly increasing with at least two entries.
    explicit Lattice(std::array<std::vector<double>, 3> planes);
    // n[a] equal cells per axis over the box; the outer planes are exactly
    // box.lo and box.hi.
    static Lattice uniform(const Box& box, const std::array<int, 3>& n);

    int cells(int axis) const { return static_cast<int>(planes_[axis].size()) - 1; }
    long cellCount() const { return long(cells(0)) * cells(1) * cells(2); }
    double plane(int axis, int i) const { return planes_[axis][i]; }
    const std::vector<double>& planes(int axis) const& { return planes_[axis]; }
    // Not on a temporary: the reference would outlive it (uniformBoundaries
    // read a freed Lattice::uniform(...) so; AddressSanitizer caught it).
    const std::vector<double>& planes(int axis) const&& = delete;
    Box bounds() const;
    Box cellBox(const Cell& c) const;

    // The parameters of the ray that the slab [plane i, plane i+1] of this
    // axis owns (see the rule above).
    Interval slab(const Ray& r, int axis, int i) const;
    // The ray's segment in cell c, clipped to [t0, t1).
    Interval segment(const Ray& r, const Cell& c, double t0, double t1) const;
    // The cell that owns parameter t of the ray, if any.
    std::optional<Cell> locate(const Ray& r, double t) const;
    // Cells whose closed box overlaps the closed box b, as index ranges.
    void overlapRange(const Box& b, Cell& first, Cell& last) const;

    // 3D-DDA (Amanatides & Woo) over [t0, t1) clipped to the lattice's box: calls visit(cell, segment) for
    // each cell with a non-empty segment, in ray order; stops early when visit
    // returns false. Ties between axes step all tied axes at once, so a ray
    // through an edge or corner never visits a cell for zero length.
    template <class Visit>
    void walk(const Ray& r, double t0, double t1, Visit&& visit) const;

private:
    std::array<std::vector<double>, 3> planes_;
    // Per axis, cells per unit length as if the planes were evenly spaced
    // (they are, in a region's voxel grid): locate's first guess.
    std::array<double, 3> perLength_{};
};

template <class Visit>
void Lattice::walk(const Ray& r, double t0, double t1, Visit&& visit) const {
    const Interval inside = boxInterval(r, bounds());  // same planes, same doubles
    t0 = std::max(t0, inside.lo);
    t1 = std::min(t1, inside.hi);
    if (!(t0 < t1)) return;
    std::optional<Cell> start = locate(r, t0);
    if (!start) return;
    Cell c = *start;
    constexpr double inf = std::numeric_limits<double>::infinity();
    std::array<int, 3> step{};
    std::array<double, 3> tNext{};
    for (int a = 0; a < 3; ++a) {
        if (r.d[a] > 0) {
            step[a] = 1;
            tNext[a] = r.tAt(a, planes_[a][c[a] + 1]);
        } else if (r.d[a] < 0) {
            step[a] = -1;
            tNext[a] = r.tAt(a, planes_[a][c[a]]);
        } else {
            step[a] = 0;
            tNext[a] = inf;
        }
    }
    double tEntry = t0;
    for (;;) {
        const double tExit = std::min({tNext[0], tNext[1], tNext[2]});
        const double end = std::min(tExit, t1);
        if (tEntry < end && !visit(static_cast<const Cell&>(c), Interval{tEntry, end})) return;
        if (tExit >= t1) return;
        for (int a = 0; a < 3; ++a) {
            if (tNext[a] != tExit) continue;
            c[a] += step[a];
            if (c[a] < 0 || c[a] >= cells(a)) return;
            tNext[a] = r.tAt(a, planes_[a][step[a] > 0 ? c[a] + 1 : c[a]]);
        }
        tEntry = tExit;
    }
}

}  // namespace rt
