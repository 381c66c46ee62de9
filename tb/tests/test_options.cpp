// The values of rtsim's flags that have a syntax of their own
// (tb/option_parsers.h), parsed without CLI11: what each accepts, and for
// what it refuses, the flag it names.
#include <gtest/gtest.h>

#include "option_parsers.h"

using namespace rt;

namespace {

// The flag an OptionError names, or "" if `f` throws none.
template <class F>
std::string refusedBy(F f) {
    try {
        f();
    } catch (const OptionError& e) {
        return e.flag;
    }
    return "";
}

}  // namespace

TEST(Options, NodesTimesRatesAndTheMeshShape) {
    EXPECT_EQ(parseCell("--x", "1,2,3"), (Cell{1, 2, 3}));
    for (const char* bad : {"1,2", "1,2,3,", "1;2;3", "a,b,c", ""}) EXPECT_EQ(refusedBy([&] { parseCell("--x", bad); }), "--x") << bad;
    EXPECT_EQ(parseTimeOf("--t", "2.5us"), 2500000u);
    EXPECT_EQ(refusedBy([] { parseTimeOf("--t", "5"); }), "--t");
    EXPECT_EQ(refusedBy([] { parseTimeOf("--t", "2000s"); }), "--t");
    EXPECT_EQ(parseRateOf("--r", "10Gb/s"), 1.25e9);
    EXPECT_EQ(refusedBy([] { parseRateOf("--r", "0B/s"); }), "--r");
    // As --help shows the defaults and the summary prints them (formatTime, formatRate): with a space.
    EXPECT_EQ(parseTimeOf("--t", "10 ns"), 10000u);
    EXPECT_EQ(parseTimeOf("--t", formatTime(123500)), 123500u);
    EXPECT_EQ(parseRateOf("--r", "1 GB/s"), 1e9);
    EXPECT_EQ(refusedBy([] { parseTimeOf("--t", "10 "); }), "--t");
    EXPECT_EQ(refusedBy([] { parseTimeOf("--t", "10 n s"); }), "--t");
    EXPECT_EQ(parseMeshDims("2x3x16"), (std::array<int, 3>{2, 3, 16}));
    EXPECT_EQ(parseMeshDims("32x32x32"), (std::array<int, 3>{32, 32, 32}));
    EXPECT_EQ(parseMeshDims("64x64x8"), (std::array<int, 3>{64, 64, 8}));  // 32,768 nodes: the most
    for (const char* bad : {"2x3", "65x1x1", "64x64x9", "33x32x32", "0x1x1", "2*3*4", "2x3x4x"})
        EXPECT_EQ(refusedBy([&] { parseMeshDims(bad); }), "--mesh-dims") << bad;
}

TEST(Options, PerNodeSpeedsAndCosts) {
    EXPECT_EQ(parseNodeSpeed("1,0,2=2.5"), (std::pair<Cell, double>{{1, 0, 2}, 2.5}));
    for (const char* bad : {"1,0,2", "1,0,2=0", "1,0,2=-1", "1,0,2=x", "1,0=2"})
        EXPECT_EQ(refusedBy([&] { parseNodeSpeed(bad); }), "--node-speed") << bad;
    Costs base;
    std::map<Cell, Costs> costs;
    applyNodeCost("1,1,1:sphere=1ns", base, costs);
    applyNodeCost("1,1,1:recv=3ns", base, costs);  // the same node's set, one more cost
    ASSERT_EQ(costs.size(), 1u);
    EXPECT_EQ(costs.at({1, 1, 1}).test[0], 1000u);
    EXPECT_EQ(costs.at({1, 1, 1}).recv, 3000u);
    EXPECT_EQ(costs.at({1, 1, 1}).send, base.send);  // the rest as the machine's
    for (const char* bad : {"1,1,1=sphere:1ns", "1,1,1:foo=1ns", "1,1,1:sphere=1", "1,1:sphere=1ns"})
        EXPECT_EQ(refusedBy([&] { applyNodeCost(bad, base, costs); }), "--node-cost") << bad;
}

TEST(Options, PerLinkSettings) {
    LinkParams base;
    const auto [where, p] = parseLinkSet("0,1,2,-y:latency=1us,depth=4,out_depth=0,bandwidth=2GB/s,control_depth=3", base);
    EXPECT_EQ(where, (std::pair<Cell, int>{{0, 1, 2}, NegY}));
    EXPECT_EQ(p.latency, 1000000u);
    EXPECT_EQ(p.depth, 4);
    EXPECT_EQ(p.bandwidth, 2e9);
    EXPECT_EQ(p.controlDepth, 3);
    EXPECT_EQ(p.outDepth, 0);
    EXPECT_EQ(parseLinkSet("0,0,0,+z:depth=2", base).second.latency, base.latency);  // the rest as the machine's
    EXPECT_EQ(parseLinkSet("0,0,0,+z:control_depth=0,out_depth=5", base).second.outDepth, 5);  // 0: no lane
    for (const char* bad : {"0,0,0,+z", "0,0,+z:depth=2", "0,0,0,+w:depth=2", "0,0,0,+z:depth=0", "0,0,0,+z:control_depth=-1",
                            "0,0,0,+z:out_depth=x", "0,0,0,+z:colour=red", "0,0,0,+z:latency=1",
                            "0,0,0,+z:"})  // (no setting: it was accepted, and changed nothing)
        EXPECT_EQ(refusedBy([&] { parseLinkSet(bad, base); }), "--link-set") << bad;
}

TEST(Options, TracedLinksAndTheWindow) {
    EXPECT_EQ(parseTraceLink("1,2,3"), (std::pair<Cell, int>{{1, 2, 3}, -1}));
    EXPECT_EQ(parseTraceLink("1,2,3,+x"), (std::pair<Cell, int>{{1, 2, 3}, PosX}));
    EXPECT_EQ(parseTraceLink("1,2,3,fb"), (std::pair<Cell, int>{{1, 2, 3}, kDirs}));
    for (const char* bad : {"1,2", "fb", "1,2,3,up", "1,2,3,4,+x"})
        EXPECT_EQ(refusedBy([&] { parseTraceLink(bad); }), "--trace-links") << bad;
    EXPECT_EQ(parseTraceWindow("0,50us"), (std::pair<Picos, Picos>{0, 50000000}));
    EXPECT_EQ(refusedBy([] { parseTraceWindow("50us"); }), "--trace-window");
    EXPECT_EQ(refusedBy([] { parseTraceWindow("1us,x"); }), "--trace-window");
}
