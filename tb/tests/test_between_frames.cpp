// Between frames on their own (resplit): the minimax split, the frame
// forecast, work by position, and what getting to new planes costs,
// against values worked out by hand (no machine run).
#include <algorithm>
#include <set>
#include <string>
#include <cmath>
#include <deque>
#include <map>
#include <memory>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "frame_state_json.h"
#include "balance/balance_agent.h"
#include "base/fifo.h"
#include "balance/frame_forecast.h"
#include "channel/link.h"
#include "balance/minimax_split.h"
#include "balance/policy.h"
#include "balance/between_frames.h"
#include "balance/move_forecast.h"
#include "balance/sample_split.h"
#include "balance/work_by_position.h"

#include "policy_test.h"

using namespace rt;
using namespace rt::test;

// ---- resplit: between frames (models/balance/frame_forecast.h, minimax_split.h, between_frames.h) ----

namespace {
// Part costs on a grid of m cells: the sum of the cells' costs, and `cut`
// more for a part whose ends lie on an edge listed (not the line's ends).
PartCosts sumOfCells(const std::vector<double>& cells, const std::map<int, double>& cut = {}) {
    const int m = int(cells.size());
    PartCosts c{m, std::vector<double>(size_t(m + 1) * size_t(m + 1), 0.0)};
    for (int i = 0; i < m; ++i)
        for (int j = i + 1; j <= m; ++j) {
            double x = 0;
            for (int k = i; k < j; ++k) x += cells[size_t(k)];
            for (int e : {i, j})
                if (auto it = cut.find(e); it != cut.end()) x += it->second;
            c.at(i, j) = x;
        }
    return c;
}
}  // namespace

TEST(MinimaxSplit, EqualCellsSplitEvenly) {
    EXPECT_EQ(minimaxSplit(sumOfCells(std::vector<double>(12, 1.0)), 4, 1), (std::vector<int>{0, 3, 6, 9, 12}));
    // 3 1 1 3 in cells of 1, 1, 1, 1 each of 2: two parts of 4 each.
    EXPECT_EQ(minimaxSplit(sumOfCells({1.5, 1.5, 0.5, 0.5, 0.5, 0.5, 1.5, 1.5}), 2, 1), (std::vector<int>{0, 4, 8}));
}

TEST(MinimaxSplit, APlaneWhereManyRaysCrossCostsItsNeighbours) {
    // Ten cells of 1 in two parts: the middle, edge 5, gives 5 and 5; a
    // plane there cuts rays that cost each side 3 more (8 and 8), so the
    // plane moves to edge 4 or 6 (4 + 0 and 6, or 6 and 4): the dearest part 6.
    const std::vector<int> e = minimaxSplit(sumOfCells(std::vector<double>(10, 1.0), {{5, 3.0}}), 2, 1);
    EXPECT_TRUE(e == (std::vector<int>{0, 4, 10}) || e == (std::vector<int>{0, 6, 10})) << e[1];
    // Where the cut costs less than it saves, the plane stays.
    EXPECT_EQ(minimaxSplit(sumOfCells(std::vector<double>(10, 1.0), {{5, 0.5}}), 2, 1), (std::vector<int>{0, 5, 10}));
}

TEST(MinimaxSplit, AmongEqualDearestPartsTheRestShareEvenly) {
    // One cell of 10 dominates; the other 9 cells of 1 go to the two other
    // parts as evenly as they can (sum of squares): 4 and 5, not 1 and 8.
    std::vector<double> cells(10, 1.0);
    cells[0] = 10;
    const std::vector<int> e = minimaxSplit(sumOfCells(cells), 3, 1);
    EXPECT_EQ(e[1], 1);
    EXPECT_TRUE(e[2] == 5 || e[2] == 6) << e[2];
}

TEST(MinimaxSplit, EveryPartAtLeastTheMinimumWide) {
    std::vector<double> cells(12, 0.0);
    cells[0] = 100;  // all the work in the first cell: quarters would be one cell each
    const std::vector<int> e = minimaxSplit(sumOfCells(cells), 4, 3);
    EXPECT_EQ(e, (std::vector<int>{0, 3, 6, 9, 12}));
    EXPECT_THROW(minimaxSplit(sumOfCells(cells), 4, 4), std::invalid_argument);
    EXPECT_THROW(minimaxSplit(sumOfCells(cells), 0, 1), std::invalid_argument);
}

namespace {
// A report of an N x 1 x 2 mesh along x over [0, 1] (two columns, z = 0
// and z = 1), planes at k / N, each node busy `busy` with all of it spread
// over its box; `extra` edits it.
nlohmann::json forecastReport(int n, double busy) {
    nlohmann::json r;
    r["render_time_ns"] = 1000;
    r["config"]["mesh"] = {n, 1, 2};
    r["config"]["balance"]["axis"] = "x";
    for (int z = 0; z < 2; ++z) {
        for (int k = 1; k < n; ++k) r["boundaries"].push_back({{"column", {0, z}}, {"index", k}, {"history", {{0, double(k) / n}}}});
        for (int k = 0; k < n; ++k)
            r["nodes"].push_back({{"node", {k, 0, z}},
                                  {"box", {{double(k) / n, 0, z}, {double(k + 1) / n, 1, z + 1}}},
                                  {"busy_ns", busy}});
    }
    return r;
}
MachineConfig forecastMesh(int n) {
    MachineConfig m;
    m.dims = {n, 1, 2};
    m.balance.axis = 0;
    return m;
}
}  // namespace

TEST(FrameForecast, BusyTimesAndCutsByHand) {
    // Two nodes per column, 100 ns each spread over its half. Node 0 of
    // column z = 0 also crossed its upper face 40 times at 2 ns each (80
    // ns, not in its spread busy time), and the rays a plane would cut are
    // 10 going up at every position of [0, 1) (bins of 1/256: 128 per box).
    nlohmann::json r = forecastReport(2, 100);
    auto& w = r["nodes"][0]["work_by_position"];
    w = {{"axis_from", 0.0}, {"bin_width", 1.0 / 256}, {"first_bin", 0}, {"ns", nlohmann::json::array()},
         {"face_handling_ns", 80.0}, {"face_crossings", 40}};
    w["cuts_up"] = {{"first_bin", 0}, {"rays", std::vector<double>(255, 10.0)}};
    r["nodes"][0]["busy_ns"] = 180.0;
    const MachineConfig m = forecastMesh(2);
    const FrameForecast f(frameStateFromReport(r), m, InnerPlanes{{0.5}, {0.5}});
    // Held at 0.5: node 0 of column 0 does its 100, plus 10 cut rays at
    // 2 ns (its column's 80 ns / 40 crossings): 120; the others 100.
    EXPECT_NEAR(f.forecast({{0.5}, {0.5}}).nodeNs, 120, 1e-9);
    // At 0.25: node 1 has 50 of node 0's and its 100, and the cut: 170.
    EXPECT_NEAR(f.forecast({{0.25}, {0.5}}).nodeNs, 170, 1e-9);
    // The search evens column 0: x + 20 = (1 - x) ... busy below x is 200 x
    // for x < 0.5: 200 x + 20 = 200 - 200 x + 20 gives x = 0.5 again.
    const InnerPlanes p = f.perColumn();
    EXPECT_NEAR(p[0][0], 0.5, 1.0 / 256);
    EXPECT_NEAR(f.forecast(p).nodeNs, 120, 200.0 / 256 + 1e-9);
    // No links in the report: no wire time forecast.
    EXPECT_EQ(f.forecast(p).linkNs, 0);
}

// A node that waits for its faces (facesInPlaceNs) ends its frame's work
// that much later; one in place does not (frame_forecast.h).
TEST(FrameForecast, ANodeStartingLateEndsLate) {
    const nlohmann::json r = forecastReport(2, 100);
    const FrameForecast f(frameStateFromReport(r), forecastMesh(2), InnerPlanes{{0.5}, {0.5}});
    const InnerPlanes planes{{0.5}, {0.5}};
    const InnerPlanes none{{0, 0}, {0, 0}}, late{{0, 30}, {0, 0}}, later{{0, 30}, {45, 0}};
    EXPECT_NEAR(f.forecast(planes, &none).nodeNs, 100, 1e-9);
    EXPECT_NEAR(f.forecast(planes, &late).nodeNs, 130, 1e-9);
    EXPECT_NEAR(f.forecast(planes, &later).frameNs, 145, 1e-9);
    // At 0.25, node 1 of column 0 has 150 ns of work: started at 30, 180;
    // node 0 of column 1 ends at 145 still.
    EXPECT_NEAR(f.forecast({{0.25}, {0.5}}, &later).nodeNs, 180, 1e-9);
    EXPECT_NEAR(f.forecast({{0.25}, {0.5}}).nodeNs, 150, 1e-9);
}

TEST(FrameForecast, OneCellGrowthIsTheNewCellOverTheOld) {
    EXPECT_DOUBLE_EQ(oneCellGrowth(1.0, 1.0), 1.0);
    EXPECT_DOUBLE_EQ(oneCellGrowth(1.4, 1.0), 1.4);   // still one cell, 1.4 times as thick
    EXPECT_DOUBLE_EQ(oneCellGrowth(0.5, 1.0), 0.5);   // thinner: one cell, half as thick
    EXPECT_DOUBLE_EQ(oneCellGrowth(1.6, 1.0), 0.8);   // two cells of 0.8
    EXPECT_DOUBLE_EQ(oneCellGrowth(3.0, 1.0), 1.0);   // three cells of 1
}

TEST(FrameForecast, TestsWithinABoxOfOneCellAlongTheAxisGrowWithItsCell) {
    // Column z = 0, node 0 over [0, 0.5): 100 ns of work spread over its
    // box, 60 of it the tests of rays running across the axis inside it,
    // and its grid has one cell along x. Every other node: 100 ns spread.
    nlohmann::json r = forecastReport(2, 100);
    auto& w = r["nodes"][0]["work_by_position"];
    w = {{"axis_from", 0.0}, {"bin_width", 1.0 / 256}, {"first_bin", 0}, {"ns", std::vector<double>(128, 100.0 / 128)},
         {"face_handling_ns", 0.0}, {"face_crossings", 0}};
    w["within"] = {{"first_bin", 0}, {"ns", std::vector<double>(128, 60.0 / 128)}};
    r["nodes"][0]["grid"] = {{"cells", {1, 3, 3}}, {"span", {{0, 0, 0}, {0.5, 1, 1}}}};
    const MachineConfig m = forecastMesh(2);
    const FrameForecast one(frameStateFromReport(r), m, InnerPlanes{{0.5}, {0.5}});
    // Held: as measured.
    EXPECT_NEAR(one.forecast({{0.5}, {0.5}}).nodeNs, 100, 1e-9);
    // Node 0 to [0, 0.625), 1.25 times as thick, still one cell: its 100,
    // its 60 within 1.25 times (+15), and 25 of node 1's: 140.
    EXPECT_NEAR(one.forecast({{0.625}, {0.5}}).nodeNs, 140, 1e-9);
    // Node 0 to [0, 0.375): 75 of its own, of which 45 within at 0.75
    // (-11.25): 63.75. Node 1, [0.375, 1), 0.625 thick: node 0's last 25
    // (15 within, at 1.25 times: +3.75) and its 100: 128.75.
    EXPECT_NEAR(one.forecast({{0.375}, {0.5}}).nodeNs, 128.75, 1e-9);
    // With two cells along x the cells do not change with the box: no scaling.
    r["nodes"][0]["grid"]["cells"] = {2, 3, 3};
    const FrameForecast two(frameStateFromReport(r), m, InnerPlanes{{0.5}, {0.5}});
    EXPECT_NEAR(two.forecast({{0.625}, {0.5}}).nodeNs, 125, 1e-9);
    EXPECT_NEAR(two.forecast({{0.375}, {0.5}}).nodeNs, 125, 1e-9);
}

TEST(FrameForecast, APartWhoseGridWouldBeMuchCoarserCountsItsTestsGrown) {
    // Column z = 0: node 0, [0, 0.5), holds one big sphere (centre 0.25,
    // 0.5, 0.5, radius 0.24); node 1, [0.5, 1), a crowd of 116 spheres of
    // radius 0.005 in 8 layers along x: at 0.53 2 x 2 (y and z at 0.49 and
    // 0.51), at 0.59 ... 0.71 and 0.78 ... 0.96 4 x 4 each (0.47, 0.49,
    // 0.51, 0.53). Node 1's grid, as a node builds it: the crowd's part,
    // [0.525, 0.965] x [0.465, 0.535]^2, in 33 x 5 x 5 cells (8 cells an
    // object: 928 over 0.44 x 0.07^2 gives 75.5 a unit; 33.2, 5.29, 5.29
    // rounded), a cell's edge cbrt(0.44/33 x 0.014^2) = 0.013774. Each
    // node did 100 ns spread over its box.
    std::vector<Shape> objects{Shape{Sphere{Vec3(0.25, 0.5, 0.5), 0.24, false}, 0, 0}};
    for (double x : {0.53, 0.59, 0.65, 0.71, 0.78, 0.84, 0.90, 0.96})
        for (double y : {0.47, 0.49, 0.51, 0.53})
            for (double z : {0.47, 0.49, 0.51, 0.53})
                if (x > 0.55 || ((y == 0.49 || y == 0.51) && (z == 0.49 || z == 0.51)))
                    objects.push_back(Shape{Sphere{Vec3(x, y, z), 0.005, false}, 0, uint32_t(objects.size())});
    ASSERT_EQ(objects.size(), 117u);
    nlohmann::json r = forecastReport(2, 100);
    for (int k = 0; k < 2; ++k) {
        r["nodes"][k]["work_by_position"] = {{"axis_from", 0.0}, {"bin_width", 1.0 / 256}, {"first_bin", 128 * k},
                                             {"ns", std::vector<double>(128, 100.0 / 128)},
                                             {"face_handling_ns", 0.0}, {"face_crossings", 0}};
        r["nodes"][k]["objects"] = k == 0 ? 1 : 116;
    }
    r["nodes"][1]["grid"] = {{"cells", {33, 5, 5}}, {"span", {{0.525, 0.465, 0.465}, {0.965, 0.535, 0.535}}}};
    const MachineConfig m = forecastMesh(2);
    const FrameState state = frameStateFromReport(r);
    const FrameForecast blind(state, m, InnerPlanes{{0.5}, {0.5}});
    const FrameForecast seeing(state, m, InnerPlanes{{0.5}, {0.5}}, &objects);
    // Held: as measured, with or without the objects.
    EXPECT_NEAR(seeing.forecast({{0.5}, {0.5}}).nodeNs, 100, 1e-9);
    // The plane to 0.75: node 0's box takes the big sphere and the crowd's
    // first four layers (52 spheres). Its grid's part, [0.01, 0.715] x
    // [0.26, 0.74]^2, 53 objects: 13.77 cells a unit, 10 x 7 x 7 cells, an
    // edge of cbrt(0.0705 x (0.48/7)^2) = 0.069208, r = 5.0245 times node
    // 1's. The crowd's work there grows r^1.5 = 11.263 times, times the
    // density of centres the part keeps over the grid's own: 52 in 0.225 x
    // 0.07^2 against 116 in 0.44 x 0.07^2, 0.87663: 9.873. Node 0: its 100
    // and node 1's 50 there, of which those 50 grow: 150 + 50 x 8.873.
    EXPECT_NEAR(blind.forecast({{0.75}, {0.5}}).nodeNs, 150, 1e-9);
    EXPECT_NEAR(seeing.forecast({{0.75}, {0.5}}).nodeNs, 150 + 50 * 8.873, 0.05);
    // The plane to 0.56: the part keeps the first layer, 4 centres: fewer
    // than kLeastKept, so nothing is counted, though its grid (5 objects)
    // is far coarser (node 0: its 100 and node 1's 12).
    EXPECT_NEAR(seeing.forecast({{0.56}, {0.5}}).nodeNs, blind.forecast({{0.56}, {0.5}}).nodeNs, 1e-9);
    // The searches do not count it: both find the same planes.
    EXPECT_EQ(seeing.perColumn(), blind.perColumn());
}

TEST(FrameForecast, RaysAcrossColumnsArePassedWhereThePlanesDiffer) {
    // 30 rays left node 0 of column z = 0 for column z = 1 at x in the bin
    // [0.2, 0.2 + 1/256); a receive and a send cost 1 ns each (the column
    // handled 20 crossings for 20 ns).
    nlohmann::json r = forecastReport(2, 0);
    auto& w = r["nodes"][2]["work_by_position"];  // node 0 of column z = 1: its handling cost
    w = {{"axis_from", 0.0}, {"bin_width", 1.0 / 256}, {"first_bin", 0}, {"ns", nlohmann::json::array()},
         {"face_handling_ns", 20.0}, {"face_crossings", 20}};
    r["nodes"][0]["work_by_position"] = {{"axis_from", 0.0}, {"bin_width", 1.0 / 256}, {"first_bin", 51},
                                         {"ns", nlohmann::json::array()}};
    r["nodes"][0]["work_by_position"]["lateral"]["pz"] = {{"first_bin", 51}, {"rays", {30.0}}};
    r["links"] = nlohmann::json::array({{{"to", "+z"}, {"wire_ns", {{"ray", 300.0}}}}, {{"to", "fb"}, {"wire_ns", {{"ray", 1e6}}}}});
    const FrameForecast f(frameStateFromReport(r), forecastMesh(2), InnerPlanes{{0.5}, {0.5}});
    // Planes alike: the rays go from node 0 to node 0, owner there; none passed.
    const FrameForecast::Forecast same = f.forecast({{0.5}, {0.5}});
    EXPECT_EQ(same.passes, 0);
    EXPECT_EQ(same.nodeNs, 0);
    // Column 1's plane at 0.1: x = 0.2 is its node 1's; node 0 passes the
    // 30 rays up: 30 x (1 + 1) ns, and the link up through 0.1 carries them.
    const FrameForecast::Forecast moved = f.forecast({{0.5}, {0.1}});
    EXPECT_EQ(moved.passes, 30);
    EXPECT_NEAR(moved.nodeNs, 60, 1e-9);
    // Wire per ray: 300 ns over the rays the links carried, the frame
    // buffer's links aside: the 30 across and 20 / 2 along the axis (each
    // crossing counted by both its nodes), 7.5 ns; the busiest link (the
    // one across, and the one up through 0.1) carries 30.
    EXPECT_NEAR(moved.linkNs, 225, 1e-9);
    EXPECT_NEAR(moved.frameNs, 225, 1e-9);
}

TEST(FrameForecast, ANodesLinkToANeighbouringColumnCarriesTheRaysOfItsPart) {
    // Node 0 of column z = 0 sent 2 rays to column z = 1 from each bin of
    // [0, 0.5) (256 rays); the links' rays took 512 ns on the wire, 2 ns
    // each; no other work. Its link there carries the rays of its part:
    // 512 ns with the plane at 0.5. Both searches halve its part (the plane
    // at 0.25: 128 rays, 256 ns); a search that saw only the nodes' busy
    // times and the links along the axis would see no cost anywhere.
    nlohmann::json r = forecastReport(2, 0);
    auto& w = r["nodes"][0]["work_by_position"];
    w = {{"axis_from", 0.0}, {"bin_width", 1.0 / 256}, {"first_bin", 0}, {"ns", nlohmann::json::array()}};
    w["lateral"]["pz"] = {{"first_bin", 0}, {"rays", std::vector<double>(128, 2.0)}};
    r["links"] = nlohmann::json::array({{{"to", "+z"}, {"wire_ns", {{"ray", 512.0}}}}});
    const FrameForecast f(frameStateFromReport(r), forecastMesh(2), InnerPlanes{{0.5}, {0.5}});
    EXPECT_NEAR(f.forecast({{0.5}, {0.5}}).linkNs, 512, 1e-9);
    for (const InnerPlanes& p : {f.perColumn(), f.aligned()}) {
        EXPECT_NEAR(p[0][0], 0.25, 1.0 / 256);
        EXPECT_NEAR(f.forecast({p[0], p[0]}).linkNs, 256, 2 * 2 + 1e-9);  // (within a bin's 2 rays)
    }
}

TEST(FrameForecast, ANodeAndALinkCloseTogetherMakeALongerFrame) {
    // The setup above (node 0 of column 0's link to column 1 carries 512
    // ns of rays with the plane at 0.5), each node also busy `busy` over
    // its box. Far apart, the frame is the dearer of the two; within
    // kTandem of each other, kTandem times the cheaper: the link queues the
    // rays behind it and the nodes after it get them late.
    for (const auto& [busy, frame] : {std::pair<double, double>{100, 512}, {2000, 2000}, {500, 550}, {540, 563.2}}) {
        nlohmann::json r = forecastReport(2, busy);
        auto& w = r["nodes"][0]["work_by_position"];
        w = {{"axis_from", 0.0}, {"bin_width", 1.0 / 256}, {"first_bin", 0}, {"ns", nlohmann::json::array()}};
        w["lateral"]["pz"] = {{"first_bin", 0}, {"rays", std::vector<double>(128, 2.0)}};
        r["links"] = nlohmann::json::array({{{"to", "+z"}, {"wire_ns", {{"ray", 512.0}}}}});
        const FrameForecast::Forecast f = FrameForecast(frameStateFromReport(r), forecastMesh(2), InnerPlanes{{0.5}, {0.5}}).forecast({{0.5}, {0.5}});
        EXPECT_NEAR(f.nodeNs, busy, 1e-9);
        EXPECT_NEAR(f.linkNs, 512, 1e-9);
        EXPECT_NEAR(f.frameNs, frame, 1e-9) << busy;
    }
}

TEST(Resplit, WorkByPositionKeepsOnlyTheSpanTraced) {
    // The world [0, 4] in 2 boxes: 256 bins of 1/64. Steps at 1.001 and
    // 1.01 share bin 64; one at 0.5 (bin 32) grows the span downwards, one
    // at 3.99 (bin 255) upwards; NaN is no position.
    WorkByPosition w(0, 4, 2);
    EXPECT_DOUBLE_EQ(w.binWidth(), 1.0 / 64);
    w.add(1.001, 3);
    w.add(1.01, 4);
    EXPECT_EQ(w.firstBin(), 64);
    EXPECT_EQ(w.bins(), (std::vector<double>{7}));
    w.add(0.5, 2);
    w.add(3.99, 1);
    w.add(std::nan(""), 100);
    EXPECT_EQ(w.firstBin(), 32);
    ASSERT_EQ(w.bins().size(), size_t(255 - 32 + 1));
    EXPECT_EQ(w.bins().front(), 2);
    EXPECT_EQ(w.bins()[64 - 32], 7);
    EXPECT_EQ(w.bins().back(), 1);
    double sum = 0;
    for (double b : w.bins()) sum += b;
    EXPECT_EQ(sum, 10);
}

TEST(Resplit, TimeAveragedPosition) {
    // At 1 for 2 ns, then at 3 for 2 ns.
    EXPECT_DOUBLE_EQ(timeAveraged({{0, 1}, {2, 3}}, 4), 2.0);
    // A move after the end does not count.
    EXPECT_DOUBLE_EQ(timeAveraged({{0, 1}, {2, 3}, {9, 100}}, 4), 2.0);
    EXPECT_DOUBLE_EQ(timeAveraged({{0, 5}}, 10), 5.0);
}

namespace {
// The moves' hand-worked column: boxes [0,1], [1,2], [2,3] along x holding
// 10, 20 and 30 objects, on a 3x1x1 mesh whose links take 100 ns and 42
// GB/s (1 ns an object's 42 bytes).
FrameState threeBoxColumn() {
    FrameState r;
    const size_t objects[] = {10, 20, 30};
    for (int k = 0; k < 3; ++k) {
        NodeFrameState n;
        n.cell = {k, 0, 0};
        n.box = Box{Vec3(double(k), 0.0, 0.0), Vec3(double(k + 1), 1.0, 1.0)};
        n.objects = objects[k];
        r.nodes.push_back(n);
    }
    return r;
}
MachineConfig threeBoxMachine() {
    MachineConfig m;
    m.dims = {3, 1, 1};
    m.link.latency = 100000;
    m.link.bandwidth = 42e9;
    return m;
}
}  // namespace

// What getting to new planes costs, by hand (move_forecast.h): boxes [0,1],
// [1,2], [2,3] along x holding 10, 20 and 30 objects; links of 100 ns and
// 42 GB/s (1 ns an object's 42 bytes), handling 40 + 40 ns a slide, grid
// updates 4 ns an object on each node (9 ns an object in all). Plane 1 from
// 1 to 2.5 crosses the second box and half the third: 2 hops of 180 ns,
// and 20 + 15 objects passed on average half of the chain's 2 + 1:
// 360 + 35 x 1.5 x 9 = 832.5 ns. Plane 2 stays. With the hops on the
// links (--hop-handling link), no handling: 200 + 472.5.
TEST(Resplit, GettingToNewPlanesCostsItsChainOfSlabs) {
    FrameState r = threeBoxColumn();
    MachineConfig m = threeBoxMachine();
    m.balance.rebuildCost = 4000;
    const InnerPlanes from{{1.0, 2.0}}, to{{2.5, 2.0}};
    EXPECT_NEAR(moveNs(r, m, from, to), 832.5, 1e-9);
    EXPECT_NEAR(moveNs(r, m, to, from), 832.5, 1e-9);  // the same chain back
    EXPECT_DOUBLE_EQ(moveNs(r, m, from, from), 0.0);
    m.hopsByLinks = true;
    EXPECT_NEAR(moveNs(r, m, from, to), 672.5, 1e-9);
    // The third box's objects three times a sphere's size (126 bytes, 3 ns
    // on the wire): its 15 take 11 ns each, the second box's 20 still 9.
    m.hopsByLinks = false;
    r.nodes[2].objectBytes = 30 * 126;
    EXPECT_NEAR(moveNs(r, m, from, to), 360 + 1.5 * (20 * 9 + 15 * 11), 1e-9);
    r.nodes[1].objectBytes = 20 * 42;  // (a sphere's, said: as not said)
    EXPECT_NEAR(moveNs(r, m, from, to), 360 + 1.5 * (20 * 9 + 15 * 11), 1e-9);
    // Nodes twice as fast: the handling (40 ns a slide) and the updates (2
    // ns an object on each node) halve, the link does not: hops of 140 ns,
    // objects of 5 and 7 ns.
    m.speed = 2;
    EXPECT_NEAR(moveNs(r, m, from, to), 280 + 1.5 * (20 * 5 + 15 * 7), 1e-9);
}

// When each node's faces are in place (move_forecast.h, facesInPlaceNs),
// by hand: the handovers as the nodes make them. Boxes [0,1], [1,2], [2,3]
// along x holding 10, 20 and 30 objects; links of 100 ns and 42 GB/s (1 ns
// an object's 42 bytes); a send and a receive 40 ns each; grid updates 4
// ns an object on each node; the least thickness 0.05. Planes (1, 2) move
// to (2.4, 2.7), both up:
// - at 0, node 1 gives [1, 1.95] (as far as its box allows: 19 objects)
//   to node 0: it is free at 40 + 76 = 116, the slab arrives at 116 + 100
//   + 19 = 235; node 2 gives [2, 2.7] (21 objects) to node 1: free at 124,
//   arrives at 245. Node 2 is in place at 124;
// - node 0 takes its slab at 235 (a receive, an acknowledgement's send and
//   76 of updates: done at 391);
// - node 1 takes its slab at 245 (done at 245 + 80 + 84 = 409), its box
//   now [1.95, 2.7], and gives again towards 2.4: [1.95, 2.4], 1 + 12 =
//   13 objects, free at 409 + 40 + 52 = 501, in place; arriving at 614;
// - node 0 takes it: in place at 614 + 80 + 52 = 746 ns.
// (moveNs, plane 1's chain alone with each object passed half of it, says
// 792 ns; the handovers show node 0 waiting for its second slab until node
// 1 has taken node 2's.)
TEST(Resplit, FacesInPlaceFollowTheHandoversOneAfterAnother) {
    FrameState r = threeBoxColumn();
    MachineConfig m = threeBoxMachine();
    m.costs.send = m.costs.recv = 40000;
    m.balance.rebuildCost = 4000;
    m.balance.minThickness = 0.05;
    const InnerPlanes from{{1.0, 2.0}}, to{{2.4, 2.7}};
    auto near = [](const InnerPlanes& got, const std::vector<double>& want) {
        ASSERT_EQ(got.size(), 1u);
        ASSERT_EQ(got[0].size(), want.size());
        for (size_t i = 0; i < want.size(); ++i) EXPECT_NEAR(got[0][i], want[i], 1e-9) << "node " << i;
    };
    near(facesInPlaceNs(r, m, from, to), {746, 501, 124});
    near(facesInPlaceNs(r, m, from, from), {0, 0, 0});
    EXPECT_THROW(facesInPlaceNs(r, m, InnerPlanes{{1.0}}, to), std::invalid_argument);  // planes of another mesh
    m.dims = {2, 1, 1};
    EXPECT_THROW(facesInPlaceNs(r, m, InnerPlanes{{1.0}}, InnerPlanes{{1.5}}), std::invalid_argument);  // a frame of another
    m.dims = {3, 1, 1};
    // With the hops on the links (--hop-handling link): no sends or
    // receives on the nodes; node 1 gives 19 objects (free at 76, arriving
    // at 195), node 2 21 (in place at 84, arriving at 205); node 1 done at
    // 289, gives 13 (in place at 341, arriving at 454); node 0 in place at
    // 454 + 52 = 506.
    m.hopsByLinks = true;
    near(facesInPlaceNs(r, m, from, to), {506, 341, 84});
    m.hopsByLinks = false;
    // The third box's objects three times a sphere's size (126 bytes, 3 ns
    // on the wire): node 2's slab arrives at 124 + 100 + 63 = 287, node 1
    // is done with it at 451 and gives 1 + 12 objects of 42 and 126 bytes
    // (37 ns on the wire; in place at 543, arriving at 680); node 0 is in
    // place at 812.
    r.nodes[2].objectBytes = 30 * 126;
    near(facesInPlaceNs(r, m, from, to), {812, 543, 124});
    r.nodes[2].objectBytes = 0;  // (not known: a sphere's)
    // Nodes twice as fast: handling and updates halve, the link does not.
    // Node 1 free at 58, arriving at 177; node 2 in place at 62, arriving
    // at 183; node 1 done at 183 + 40 + 42 = 265, gives 13 (in place at
    // 311, arriving at 424); node 0 in place at 424 + 40 + 26 = 490.
    m.speed = 2;
    near(facesInPlaceNs(r, m, from, to), {490, 311, 62});
    m.speed = 1;
    // With the scene's objects, a slab carries those whose bounds reach
    // into it, once each, at their own sizes: a sphere over [1.4, 1.6], a
    // triangle over [2.1, 2.3] (85 bytes: 85 / 42 ns on the wire) and a
    // sphere over [2.85, 2.95]. The first gives carry one object each
    // (free at 44; arriving at 145 and 146 + 1 / 42); node 1 is done with
    // its slab at 230 + 1 / 42 and gives [1.95, 2.4] with the triangle
    // (in place at 274 + 1 / 42, arriving at 376 + 2 / 42); node 0 is in
    // place at 460 + 2 / 42.
    Polygon triangle;
    triangle.vertices = {Vec3(2.1, 0.4, 0.5), Vec3(2.3, 0.4, 0.5), Vec3(2.2, 0.6, 0.5)};
    ASSERT_TRUE(triangle.finish());
    const std::vector<Shape> scene{Shape{Sphere{Vec3(1.5, 0.5, 0.5), 0.1, false}, 0, 0}, Shape{triangle, 0, 1},
                                   Shape{Sphere{Vec3(2.9, 0.5, 0.5), 0.05, false}, 0, 2}};
    near(facesInPlaceNs(r, m, from, to, &scene), {460 + 2.0 / 42, 274 + 1.0 / 42, 44});
    // The planes back down, from (2.4, 2.7) to (1, 2): node 0 gives [1,
    // 2.4] with the first sphere and the triangle (in place at 48, arriving
    // at 151 + 1 / 42); node 1 gives [2.45, 2.7] (as far as its box
    // allows), empty (free at 40, arriving at 140); node 2 takes it (in
    // place at 220); node 1 is done with its slab at 239 + 1 / 42 and gives
    // [2, 2.45] with the triangle (in place at 283 + 1 / 42, arriving at
    // 385 + 2 / 42); node 2 is in place at 469 + 2 / 42.
    near(facesInPlaceNs(r, m, to, from, &scene), {48, 283 + 1.0 / 42, 469 + 2.0 / 42});
}
