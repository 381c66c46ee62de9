#include "balance/initial_split.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <stdexcept>
#include <string>

#include "balance/plane_spacing.h"
#include "shading.h"
#include "channel/message.h"

namespace rt {
namespace {

// The least x in [lo, hi] where `mix` x (the share of `centres` at or below
// x) + (1 - mix) x (the share of [lo, hi] below x) exceeds `share`: the
// mixed quantile, by bisection (the mix is a step function plus a ramp).
// With `entries` (sorted) and a weight `generation`: generation x their
// share below x, and the rest (1 - generation) as above.
double mixedQuantile(const std::vector<double>& centres, double mix, double lo, double hi, double share,
                     const std::vector<double>& entries = {}, double generation = 0) {
    const double g = entries.empty() ? 0.0 : generation;
    const auto shareBelow = [](const std::vector<double>& sorted, double x) {
        return double(std::upper_bound(sorted.begin(), sorted.end(), x) - sorted.begin()) / double(sorted.size());
    };
    const auto above = [&](double x) {
        return (1 - g) * (mix * shareBelow(centres, x) + (1 - mix) * (x - lo) / (hi - lo)) +
                   (g > 0 ? g * shareBelow(entries, x) : 0.0) > share;
    };
    double below = lo, at = hi;
    for (int i = 0; i < 64; ++i) {
        const double m = 0.5 * (below + at);
        (above(m) ? at : below) = m;
    }
    return at;
}

// The most object centres any box between `planes` holds (a centre on a
// plane counts in the box below it, as mixedQuantile counts it).
size_t heaviestBox(const std::vector<double>& sortedCentres, const std::vector<double>& planes) {
    const auto upTo = [&](size_t k) {
        return k + 1 == planes.size() ? sortedCentres.end()
                                      : std::upper_bound(sortedCentres.begin(), sortedCentres.end(), planes[k]);
    };
    size_t most = 0;
    for (size_t k = 0; k + 1 < planes.size(); ++k)
        most = std::max(most, size_t(upTo(k + 1) - (k == 0 ? sortedCentres.begin() : upTo(k))));
    return most;
}

// Where each object is along axis `ax`, sorted: its centre, or where its
// span along the axis starts or ends.
enum AlongAxis { kCentres, kLowerFaces, kUpperFaces };
std::vector<double> alongAxis(const std::vector<Shape>& shapes, int ax, AlongAxis which) {
    std::vector<double> c;
    for (const Shape& s : shapes) {
        const Box ob = s.bounds();
        c.push_back(which == kCentres ? 0.5 * (ob.lo[ax] + ob.hi[ax]) : which == kLowerFaces ? ob.lo[ax] : ob.hi[ax]);
    }
    std::sort(c.begin(), c.end());
    return c;
}

// The most objects any box between `planes` reaches into: an object whose
// span along the axis (`los`, `his`, each sorted) overlaps the box, as the
// box's grid holds it and its rays test it. A box thinner than its objects
// holds nearly all of those its planes cut: spheres of radius 0.02 crowded
// into 0.005 of the axis, split by their centres into boxes 0.0025 and
// 0.013 thick, left each box every sphere, and with the view across the
// axis the half start's longer boxes took sample's first frame to 1.43 of
// the unbalanced one (built-in scene, 4x4x4, 128x128; doc/balancing.md,
// "The recommended policy", and crowded.py's table there).
size_t heaviestReach(const std::vector<double>& los, const std::vector<double>& his, const std::vector<double>& planes) {
    size_t most = 0;
    for (size_t k = 0; k + 1 < planes.size(); ++k) {
        // (those starting below the box's top, less those ending at or below its bottom)
        const size_t startBelow = size_t(std::lower_bound(los.begin(), los.end(), planes[k + 1]) - los.begin());
        const size_t endBelow = size_t(std::upper_bound(his.begin(), his.end(), planes[k]) - his.begin());
        most = std::max(most, startBelow - std::min(startBelow, endBelow));
    }
    return most;
}

// Whether a box of `start` objects is lighter than one of `uniform` by more
// than chance: by kSpreadsLighter standard deviations of a box's count where
// the objects spread evenly (a count's spread, sqrt(uniform)). On Fig. 4's
// scene at f = 1, where the spheres spread evenly, the aligned half start's
// heaviest slab was 1.01 to 1.10 times lighter than the uniform split's by
// where they fell (265 against 254 spheres at N = 4, 142 against 133 at N =
// 8: under one deviation), and along the axis at N = 8 sample lost from it
// (1.037 of the unbalanced frame; 0.927 from the uniform split); the SPD
// scenes' are lighter by 6 deviations and more (balls-4 at N = 4: 3,839
// against 3,461; doc/balancing.md, "Where sample starts"). Only for the
// aligned start, which counts every object: a column's own count is a few
// dozen, and there 2 deviations took the 1987 machine's first-frame gains
// (Fig. 4 across the axis at N = 8, f = 1/4: 0.561 of the unbalanced frame
// to 0.890) where no first frame had lost by more than 1 %.
bool lighterThanChance(size_t start, size_t uniform) {
    return double(uniform) - double(start) > kSpreadsLighter * std::sqrt(double(uniform));
}

// `median` and `sample`'s start: boundary k of each column at the k/N
// quantile of the centres of the objects in the column (mix 1: the object
// median), or of mix x their share and (1 - mix) x the column's length (so
// a box holds at most 1 / (N mix) of the column's objects and 1 / (N (1 -
// mix)) of its length; doc/balancing.md, "Where sample starts"), kept inside
// the guards (every box at least the minimum thickness). `aligned`: the
// quantiles of all the objects, the same planes in every column.
// `lighterOnly` (auto's): a column whose heaviest box by objects that start
// leaves as heavy as the uniform split's keeps the uniform split: the start
// would lengthen boxes and gain nothing (tetra-3 at N = 5 to 7,
// doc/balancing.md, "Where sample starts").
void atObjectQuantiles(ColumnPlanes& planes, const ColumnGeometry& g, const Lattice& cuts, const Box& world,
                     const ObjectBins& bins, double minThickness, const StartMix& start,
                     const std::vector<std::vector<double>>& entries) {
    const double mix = start.mix;
    const bool aligned = start.aligned;
    const int ax = g.axis, n = g.length();
    const std::vector<double> everyObject = aligned ? alongAxis(bins.all(), ax, kCentres) : std::vector<double>{};
    const bool reaching = aligned && start.lighterOnly;
    const std::vector<double> everyLo = reaching ? alongAxis(bins.all(), ax, kLowerFaces) : std::vector<double>{};
    const std::vector<double> everyHi = reaching ? alongAxis(bins.all(), ax, kUpperFaces) : std::vector<double>{};
    const double m = planeSpacing(minThickness);
    const std::vector<double> noEntries;  // (a column none of whose primary rays is weighed)
    const ColumnPlanes everyUniform = planes;
    size_t reach = 0, uniformReach = 0;  // (the most objects a box reaches into, over the columns)
    for (int j = 0; j < g.dims[g.v]; ++j)
        for (int i = 0; i < g.dims[g.u]; ++i) {
            Box column = cuts.cellBox(g.cell(i, j, 0));
            column.lo[ax] = world.lo[ax];
            column.hi[ax] = world.hi[ax];
            const std::vector<Shape> mine = aligned ? std::vector<Shape>{} : bins.overlapping(column);
            const std::vector<double> centres = aligned ? everyObject : alongAxis(mine, ax, kCentres);
            std::vector<double>& b = planes[size_t(g.indexOf(i, j))];
            if (centres.empty()) continue;
            const std::vector<double> uniform = b;
            const std::vector<double>& in = entries.empty() ? noEntries : entries[size_t(g.indexOf(i, j))];
            for (int k = 1; k < n; ++k) {
                // (At 1 the centre itself, as before the mix: the bisection lands a hair past it.)
                const double q = mix == 1 && (in.empty() || !(start.generation > 0))
                                     ? centres[std::min(centres.size() - 1, centres.size() * size_t(k) / size_t(n))]
                                     : mixedQuantile(centres, mix, world.lo[ax], world.hi[ax], double(k) / n, in,
                                                     start.generation);
                const double lo = b[size_t(k - 1)] + m, hi = world.hi[ax] - (n - k) * m;
                b[size_t(k)] = std::clamp(q, lo, hi);
            }
            if (!start.lighterOnly) continue;
            // Lighter by the centres a box holds, and by the objects it reaches into.
            const size_t heaviest = heaviestBox(centres, b), uniformHeaviest = heaviestBox(centres, uniform);
            if (aligned ? !lighterThanChance(heaviest, uniformHeaviest) : heaviest >= uniformHeaviest) b = uniform;
            else if (aligned && !(heaviestReach(everyLo, everyHi, b) < heaviestReach(everyLo, everyHi, uniform)))
                b = uniform;
            else if (!aligned) {
                const std::vector<double> los = alongAxis(mine, ax, kLowerFaces), his = alongAxis(mine, ax, kUpperFaces);
                reach = std::max(reach, heaviestReach(los, his, b));
                uniformReach = std::max(uniformReach, heaviestReach(los, his, uniform));
            }
        }
    // A column's own count of the objects its boxes reach into is a few
    // dozen, and a column that starts uniform beside columns that start by
    // their objects made a frame slower than either (the 1987 machine,
    // across the axis, N = 8, f = 0.05, 128x128: 1.60 of the unbalanced
    // frame, where every column from the half start took 0.68 and from the
    // uniform split 0.88): the columns that start by their objects keep it
    // only where the machine's heaviest box by that count is lighter.
    if (start.lighterOnly && !aligned && !(reach < uniformReach)) planes = everyUniform;
}

// Each primary ray the host hands out (`stride`: assignPrimaryRays), with
// the cell of the uniform split where it enters the world, or none.
template <class Each>
void forEachPrimary(const Camera& camera, const Box& world, const Lattice& cuts, int stride, Each&& each) {
    for (int y = stride / 2; y < camera.height(); y += stride)
        for (int x = stride / 2; x < camera.width(); x += stride) {
            const RayJob j = primaryJob(camera, x, y, world);
            each(j, cuts.locate(j.ray, j.t0));
        }
}

}  // namespace

ColumnPlanes withInnerPlanes(const char* what, ColumnPlanes planes, const std::vector<std::vector<double>>& inner,
                             double minThickness, double slack) {
    const std::string w = what;
    if (inner.size() != planes.size())
        throw SplitError(w + ": " + std::to_string(inner.size()) + " columns, the mesh has " + std::to_string(planes.size()));
    for (size_t c = 0; c < planes.size(); ++c) {
        const size_t n = planes[c].size() - 1;
        if (inner[c].size() != n - 1)
            throw SplitError(w + ": column " + std::to_string(c) + " has " + std::to_string(inner[c].size()) +
                                        " planes, not " + std::to_string(n - 1));
        std::copy(inner[c].begin(), inner[c].end(), planes[c].begin() + 1);
        for (size_t k = 0; k < n; ++k)
            if (!(planes[c][k + 1] - planes[c][k] >= minThickness * (1 - slack)))
                throw SplitError(w + ": column " + std::to_string(c) + ", box " + std::to_string(k) +
                                            " is thinner than the minimum thickness");
    }
    return planes;
}

double minThicknessOf(const MachineConfig& cfg, const Box& world) {
    const int ax = cfg.balance.axis;
    return cfg.balance.minThickness * world.extent()[ax] / cfg.dims[ax];
}

TestAgainstHop testAgainstHop(const MachineConfig& cfg, const std::vector<Shape>& objects) {
    double test = 0;
    for (const Shape& s : objects) test += double(cfg.costs.test[size_t(s.kind())]);
    test = objects.empty() ? 0 : test / double(objects.size()) / cfg.speed;
    // A ray's share of a ray message (--ray-batch rays): its handling on the
    // processors at both ends, or the sender's on the link's engine (as
    // meshLinkOf and processorCostsOf charge them, without per-node
    // overrides), and its time on the wire.
    LinkParams link = cfg.link;
    if (cfg.hopsByLinks) link.engine = cfg.costs.send;
    const double handling = cfg.hopsByLinks ? 0 : double(cfg.costs.send + cfg.costs.recv) / cfg.speed;
    const double wire = wirePicos(link, kHeaderBytes + uint32_t(cfg.rayBatch) * kRayBytes);
    const double hop = (handling + wire) / cfg.rayBatch;
    // Measured on Fig. 4's scene (sample's first frames at f = 1/N, N = 2 to
    // 8, both views; doc/balancing.md, "Where sample starts"): 0.5 the better
    // start up to a test of 0.24 of a hop, 1 from 0.47 on.
    constexpr double kHopsPerTest = 3;  // the objects are the work from a test of a third of a hop
    TestAgainstHop t{test, hop, kHopsPerTest * test >= hop, false, "", wire / cfg.rayBatch, handling / cfg.rayBatch};
    // In line below a tenth of a hop: measured on the modern machine (0.05
    // of a hop) and the 1987 one (0.13), where an aligned start made sample's
    // first frames at f = 1/N slower (across the axis, N = 4: 0.558 of the
    // unbalanced frame against 0.530).
    constexpr double kHopsPerTestAligned = 10;
    t.cheap = !t.testsAreTheWork && kHopsPerTestAligned * test < hop;
    t.costs = "a test (" + formatTime(Picos(std::llround(test))) + ") costs " +
              (t.testsAreTheWork ? "at least" : t.cheap ? "less than a tenth of" : "less than a third of") +
              " a ray's hop (" + formatTime(Picos(std::llround(hop))) + ")";
    return t;
}

StartMix startMixFor(const MachineConfig& cfg, const std::vector<Shape>& objects) {
    if (cfg.balance.policy != "sample") return {1, false, "auto: " + cfg.balance.policy + " is the object median"};
    const TestAgainstHop t = testAgainstHop(cfg, objects);
    const bool aligned = t.cheap;
    const std::string& costs = t.costs;
    // A ray's tests do not grow with the boxes it crosses; its hops do. Up to
    // 8 boxes a column (Fig. 4's N = 2 to 8, the SPD scenes at N = 4 to 8)
    // the start by the objects paid; at 16 and 32, and on columns of 33 and
    // 64 boxes, it made the scenes with few objects a box slower than the
    // uniform split, in boxes it made long whose sides the rays crossed
    // (the half start where the hops are the work: gears-2, rings-2, tetra-3
    // by up to 79 %, and the sample's move did not take it back), or in
    // boxes it made thin, each of which a ray pays a hop in (the object
    // median where the tests are the work: on the paper's machine, whose hop
    // takes 111.5 us, tetra-3 at N = 32 2.40 times the unbalanced frame,
    // gears-2 1.29; doc/balancing.md, "At 16 and 32 boxes a column" and "On
    // the paper's machine at 16 and 32 boxes a column").
    // (kLongestColumnStartedByObjects: config/start_constants.h, with the help text)
    const int length = cfg.dims[size_t(cfg.balance.axis)];
    if (length > kLongestColumnStartedByObjects)
        return {0, false, "auto: " + costs + ", and a column has " + std::to_string(length) +
                              " boxes (more than " + std::to_string(kLongestColumnStartedByObjects) + "): the uniform split"};
    if (t.testsAreTheWork) {
        const double gen = generationWeight(cfg, t.test);
        char weight[32];
        std::snprintf(weight, sizeof weight, "%.2g", gen);
        return {1, false,
                "auto: " + costs + ": the object median, weighing where the primary rays enter at " + weight +
                    " (a ray's generation against it and " + formatNumber(kTestsPerGeneration) + " tests)",
                false, gen};
    }
    // Where a hop's wire time is kWirePerHandling of its handlings or more,
    // the links set the frame: the half start evens the nodes' work and can
    // crowd the rays' crossings onto fewer links. rings-2 on 4x4x4 lost from
    // it at 100 and 150 MB/s (1.142 and 1.143 of the unbalanced frame; wire
    // 16.5 and 11 handlings) and gained from 200 MB/s (8.3) on; from the
    // uniform split no point at 100 MB/s lost by its move (N = 4 to 8, the
    // SPD scenes). The 1987 machine's hop is 5 handlings on the wire
    // (doc/balancing.md, "Where sample starts").
    if (t.wirePerHandling() >= kWirePerHandling) {
        char times[32];
        std::snprintf(times, sizeof times, "%.3g", t.wirePerHandling());
        return {0, false, "auto: " + costs + ", and its wire time is " + times +
                              " times its handling (at least " + std::to_string(kWirePerHandling) +
                              "): the uniform split"};
    }
    // Where that start takes no object off a column's heaviest box it only
    // lengthens boxes, whose sides the rays cross: tetra-3's 64 triangles
    // fill each slab alike, and from the half start sample lost at N = 5 to 7
    // (up to 1.528 of the unbalanced frame at N = 7, 100 MB/s; 1.096 at 1
    // GB/s), where every other SPD scene's heaviest box is 1.11 to 3.7 times
    // lighter (doc/balancing.md, "Where sample starts").
    return {0.5, aligned,
            "auto: " + costs + ": half by the objects, half by the length" +
                (aligned ? ", the same planes in every column (the uniform split where that does not lighten the "
                           "heaviest box by more than " + std::to_string(kSpreadsLighter) + " deviations of an even spread"
                         : " (the uniform split in a column where that leaves the heaviest box as heavy") +
                ", or leaves the heaviest box reaching into as many objects)",
            true};
}

double generationWeight(const MachineConfig& cfg, double test) {
    const double gen = double(cfg.costs.rayGen) / cfg.speed;
    const double all = gen + kTestsPerGeneration * test;
    return all > 0 ? gen / all : 0.0;
}

void chooseStartMix(MachineConfig& cfg, const std::vector<Shape>& objects) {
    if (cfg.balance.startMix != kStartMixAuto || !cfg.balance.startsAtObjects() || !cfg.startBoundaries.empty()) return;
    StartMix m = startMixFor(cfg, objects);
    cfg.balance.startMix = m.mix;
    cfg.balance.startAligned = m.aligned;
    cfg.balance.startLighterOnly = m.lighterOnly;
    cfg.balance.startGeneration = m.generation;
    cfg.balance.startMixWhy = std::move(m.why);
}

ColumnPlanes initialPlanes(const MachineConfig& cfg, const Lattice& cuts, const Box& world, const ObjectBins& bins,
                           double minThickness, const Camera* camera) {
    const ColumnGeometry g(cfg.balance.axis, cfg.dims);
    ColumnPlanes planes(size_t(g.count()), cuts.planes(g.axis));
    // (the minimum less a report's rounding of its decimals)
    if (!cfg.startBoundaries.empty()) planes = withInnerPlanes("start boundaries", planes, cfg.startBoundaries, minThickness, 1e-9);
    else if (cfg.balance.startsAtObjects()) {
        const StartMix m = cfg.balance.startMix == kStartMixAuto
                               ? startMixFor(cfg, bins.all())
                               : StartMix{cfg.balance.startMix, cfg.balance.startAligned, "", cfg.balance.startLighterOnly,
                                          cfg.balance.startGeneration};
        std::vector<std::vector<double>> entries;
        if (camera && m.generation > 0) entries = primaryEntries(*camera, world, cuts, g, cfg.pixelStride);
        atObjectQuantiles(planes, g, cuts, world, bins, minThickness, m, entries);
    }
    return planes;
}

Box nodeBox(const Cell& c, const Lattice& cuts, const ColumnGeometry& g, const ColumnPlanes& planes) {
    Box b = cuts.cellBox(c);
    const std::vector<double>& p = planes[size_t(g.columnOf(c))];
    b.lo[g.axis] = p[size_t(c[g.axis])];
    b.hi[g.axis] = p[size_t(c[g.axis] + 1)];
    return b;
}

PrimaryRays assignPrimaryRays(const Camera& camera, const Box& world, const Lattice& cuts, const ColumnGeometry& g,
                              const ColumnPlanes& planes, int stride) {
    PrimaryRays r;
    r.perNode.resize(size_t(g.dims[0] * g.dims[1] * g.dims[2]));
    const int ax = g.axis;
    forEachPrimary(camera, world, cuts, stride, [&](const RayJob& j, std::optional<Cell> c) {
        if (!c) {
            r.misses.push_back(j);
            return;
        }
        // Along the axis, the column's own planes decide.
        const std::vector<double>& b = planes[size_t(g.columnOf(*c))];
        for (int k = 0; k < g.length(); ++k) {
            const Interval s = slabInterval(j.ray, ax, b[size_t(k)], b[size_t(k + 1)]);
            if (s.lo <= j.t0 && j.t0 < s.hi) (*c)[ax] = k;
        }
        r.perNode[nodeIndex(*c, g.dims)].push_back(j.pixel);
    });
    return r;
}

std::vector<std::vector<double>> primaryEntries(const Camera& camera, const Box& world, const Lattice& cuts,
                                                const ColumnGeometry& g, int stride) {
    std::vector<std::vector<double>> at(size_t(g.count()));
    forEachPrimary(camera, world, cuts, stride, [&](const RayJob& j, std::optional<Cell> c) {
        if (c) at[size_t(g.columnOf(*c))].push_back(j.ray.at(j.t0)[g.axis]);
    });
    for (std::vector<double>& column : at) std::sort(column.begin(), column.end());
    return at;
}

CreditShares shareCredit(const std::vector<std::vector<uint32_t>>& perNode, int maxExp) {
    size_t busyNodes = 0;
    for (const auto& p : perNode) busyNodes += !p.empty();
    const int hostExp = ceilLog2(busyNodes);
    CreditShares s;
    for (const auto& pixels : perNode) {
        Credit remainder(maxExp);
        int exp = 0;
        if (!pixels.empty()) {
            const uint64_t p = pixels.size();
            const int c = ceilLog2(p);
            exp = hostExp + c;
            remainder.add(exp, (uint64_t(1) << c) - p);
        }
        s.exp.push_back(exp);
        s.remainder.push_back(std::move(remainder));
    }
    // 1 - busyNodes * 2^-hostExp stays with the host (unit 0).
    s.host = Credit(maxExp);
    s.host.add(hostExp, (uint64_t(1) << hostExp) - busyNodes);
    return s;
}

}  // namespace rt
