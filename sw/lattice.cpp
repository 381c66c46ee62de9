#include "lattice.h"

#include <algorithm>
#include <stdexcept>

namespace rt {

Lattice::Lattice(std::array<std::vector<double>, 3> planes) : planes_(std::move(planes)) {
    for (const auto& p : planes_) {
        if (p.size() < 2) throw std::invalid_argument("lattice axis needs at least two planes");
        for (size_t i = 1; i < p.size(); ++i)
            if (!(p[i - 1] < p[i])) throw std::invalid_argument("lattice planes must be strictly increasing");
    }
    for (int a = 0; a < 3; ++a) perLength_[a] = double(cells(a)) / (planes_[a].back() - planes_[a].front());
}

Lattice Lattice::uniform(const Box& box, const std::array<int, 3>& n) {
    std::array<std::vector<double>, 3> planes;
    for (int a = 0; a < 3; ++a) {
        planes[a].resize(n[a] + 1);
        const double lo = box.lo[a], hi = box.hi[a];
        for (int i = 0; i <= n[a]; ++i) planes[a][i] = lo + (hi - lo) * (double(i) / n[a]);
        planes[a][0] = lo;  // exact outer planes: shared with the region box
        planes[a][n[a]] = hi;
    }
    return Lattice(std::move(planes));
}

Box Lattice::bounds() const {
    return Box{Vec3(planes_[0].front(), planes_[1].front(), planes_[2].front()),
               Vec3(planes_[0].back(), planes_[1].back(), planes_[2].back())};
}

Box Lattice::cellBox(const Cell& c) const {
    return Box{Vec3(planes_[0][c[0]], planes_[1][c[1]], planes_[2][c[2]]),
               Vec3(planes_[0][c[0] + 1], planes_[1][c[1] + 1], planes_[2][c[2] + 1])};
}

Interval slabInterval(const Ray& r, int axis, double lo, double hi) {
    constexpr double inf = std::numeric_limits<double>::infinity();
    if (r.d[axis] > 0) return {r.tAt(axis, lo), r.tAt(axis, hi)};
    if (r.d[axis] < 0) return {r.tAt(axis, hi), r.tAt(axis, lo)};
    const double o = r.o[axis];
    return (lo <= o && o < hi) ? Interval{-inf, inf} : Interval{inf, -inf};
}

BoxSlabs boxSlabs(const Ray& r, const Box& b) {
    constexpr double inf = std::numeric_limits<double>::infinity();
    BoxSlabs s{{}, {-inf, inf}};
    for (int a = 0; a < 3; ++a) {
        const Interval ia = slabInterval(r, a, b.lo[a], b.hi[a]);
        s.slab[size_t(a)] = ia;
        s.span.lo = std::max(s.span.lo, ia.lo);
        if (ia.hi < s.span.hi) {  // the first axis to reach the final span.hi names the exit
            s.span.hi = ia.hi;
            s.exitAxis = r.d[a] != 0 ? a : -1;  // (a parallel axis's slab is all or nothing)
        }
    }
    return s;
}

Interval boxInterval(const Ray& r, const Box& b) { return boxSlabs(r, b).span; }

Interval Lattice::slab(const Ray& r, int axis, int i) const {
    return slabInterval(r, axis, planes_[axis][i], planes_[axis][i + 1]);
}

Interval Lattice::segment(const Ray& r, const Cell& c, double t0, double t1) const {
    Interval s{t0, t1};
    for (int a = 0; a < 3; ++a) {
        Interval ia = slab(r, a, c[a]);
        s.lo = std::max(s.lo, ia.lo);
        s.hi = std::min(s.hi, ia.hi);
    }
    return s;
}

namespace {
// Of an axis's planes p_0 < ... < p_n, those on p_0's side of the ray's
// point (`below`) are a prefix p_0 .. p_i: i, or -1 if none. The guess is
// checked first (two tests; with evenly spaced planes it is nearly always
// right), then the planes are bisected: the same i either way.
template <class Below>
int lastPlaneBelow(const std::vector<double>& p, double guess, Below below) {
    const int n = int(p.size()) - 1;
    const int g = guess >= 0 ? int(std::min(guess, double(n))) : -1;  // floor, from -1 to n (NaN: -1)
    if ((g < 0 || below(p[size_t(g)])) && (g == n || !below(p[size_t(g) + 1]))) return g;
    return int(std::partition_point(p.begin(), p.end(), below) - p.begin()) - 1;
}
}  // namespace

std::optional<Cell> Lattice::locate(const Ray& r, double t) const {
    Cell c{};
    for (int a = 0; a < 3; ++a) {
        const std::vector<double>& p = planes_[a];
        // The guess: the cell of the point at t, as if the planes were even.
        const double x = r.d[a] != 0 ? r.o[a] + t * r.d[a] : r.o[a];
        const double guess = p.empty() ? -1 : (x - p.front()) * perLength_[a];  // (lastPlaneBelow truncates it)
        int i;
        if (r.d[a] > 0)  // t(p_k) grows with k: below are the planes already crossed
            i = lastPlaneBelow(p, guess, [&](double q) { return r.tAt(a, q) <= t; });
        else if (r.d[a] < 0)  // t(p_k) shrinks with k: below are those not crossed yet
            i = lastPlaneBelow(p, guess, [&](double q) { return r.tAt(a, q) > t; });
        else
            i = lastPlaneBelow(p, guess, [&](double q) { return q <= r.o[a]; });
        if (i < 0 || i >= cells(a)) return std::nullopt;
        c[a] = i;
    }
    return c;
}

void Lattice::overlapRange(const Box& b, Cell& first, Cell& last) const {
    for (int a = 0; a < 3; ++a) {
        const std::vector<double>& p = planes_[a];
        const int n = cells(a);
        // Cell i spans [p_i, p_{i+1}]; it overlaps [lo, hi] iff p_i <= hi and lo <= p_{i+1}.
        int f = int(std::lower_bound(p.begin(), p.end(), b.lo[a]) - p.begin()) - 1;
        int l = int(std::upper_bound(p.begin(), p.end(), b.hi[a]) - p.begin()) - 1;
        first[a] = std::clamp(f, 0, n - 1);
        last[a] = std::clamp(l, 0, n - 1);
    }
}

}  // namespace rt
