// The machine's parameters, declared once (base/param.h): every row of the
// tables makes its flag, its --help line, its config-file line, its range
// check and its place in the report's config, with nothing else written
// for it. Each row is tried as a user would: a value through a config
// file, read back from the echo; a value out of its range on the command
// line, refused naming the flag.
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "analysis/report.h"
#include "cli_test.h"
#include "config/param_rows.h"
#include "command_line.h"
#include "config_file.h"
#include "rtsim_cli.h"

using namespace rt;
using nlohmann::json;

namespace {

// A row of any table, with its flag and its place in the echo.
struct Row {
    std::string flag, echo;
    ParamKind kind;
    double lo, hi;
    bool openBelow;
    std::string on, off;
    std::string help;
};

// Every row with a value of its own (not Special), the parts in their places.
std::vector<Row> allRows() {
    std::vector<Row> rows;
    forEachParamRow([&](const auto& p, const std::string& flag, const std::string& echo) {
        const char* help = p.portHelp && flag.rfind("--fb-", 0) == 0 ? p.portHelp : p.help;
        rows.push_back({flag, echo, p.kind, p.lo, p.hi, p.openBelow, p.on ? p.on : "", p.off ? p.off : "", help});
    });
    return rows;
}

// The options a config file's text gives (tb/command_line.h), then the command line `rest`.
RtsimOptions parsed(const std::string& file, const std::vector<std::string>& rest = {}) {
    return rt::test::parsed(mergeFlags({{parseConfig(file, "p.conf"), false}}, rest, "rtsim"));
}

std::string number(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
}

// A value of `r` other than `was` (its default's echo): its text, and its echo.
std::pair<std::string, json> otherValue(const Row& r, const json& was) {
    switch (r.kind) {
        case ParamKind::Time: return {"123ns", 123.0};
        case ParamKind::Rate: return {"7MB/s", 7e6};
        case ParamKind::Choice: return was == r.on ? std::make_pair(r.off, json(r.off)) : std::make_pair(r.on, json(r.on));
        default: break;
    }
    const double top = std::isinf(r.hi) ? r.lo + 10 : r.hi;
    for (const double v : {r.lo + 1, top, (r.lo + top) / 2, r.lo}) {
        if (v < r.lo || v > top || (r.openBelow && v == r.lo)) continue;
        const json echo = r.kind == ParamKind::Count ? json(int(v)) : json(v);
        if (echo != was) return {number(v), echo};
    }
    ADD_FAILURE() << r.flag << ": no value other than its default";
    return {"", json()};
}

// A value of `r` out of its range.
std::string outOfRange(const Row& r) {
    switch (r.kind) {
        case ParamKind::Time: return "-1ns";
        case ParamKind::Rate: return "0B/s";
        case ParamKind::Choice: return "neither";
        default: break;
    }
    if (r.openBelow) return number(r.lo);
    return std::isinf(r.hi) ? number(r.lo - 1) : number(r.hi * 2 + 1);
}

}  // namespace

TEST(Parameters, EachRowMakesItsFlagItsCheckAndItsEcho) {
    const std::vector<Row> rows = allRows();
    ASSERT_GE(rows.size(), 35u);
    RtsimOptions o;
    CLI::App app;
    o.addTo(app);
    const std::string help = app.help();
    for (const Row& r : rows) {
        SCOPED_TRACE(r.flag);
        // (A balancing policy, so that every balancing setting has a meaning:
        // --faces ideal-layer needs slide, --start-mix a policy that starts at the objects,
        // --sample-end and --sample-links sample, --polish-tries planes held between frames; --fidelity express boxes that stay put, as median's.)
        const bool sample = r.flag == "--start-mix" || r.flag == "--sample-end" || r.flag == "--sample-links" || r.flag == "--polish-tries";
        const char* policy = sample ? "sample" : r.flag == "--fidelity" ? "median" : "slide";
        const std::string context = std::string("balance = \"") + policy + "\"\n";
        const json defaults = machineConfigJson(parsed(context).machine, 8, 8);
        EXPECT_NE(help.find(r.flag), std::string::npos);
        EXPECT_NE(help.find(r.help.substr(0, 30)), std::string::npos);
        if (!r.echo.empty()) {
            const json was = defaults.at(json::json_pointer(r.echo));
            const auto [text, echo] = otherValue(r, was);
            const json now = machineConfigJson(parsed(context + r.flag.substr(2) + " = \"" + text + "\"\n").machine, 8, 8);
            EXPECT_EQ(now.at(json::json_pointer(r.echo)), echo) << text;
        }
        // Out of its range, and (a number) not a finite one or not a number.
        std::vector<std::string> bad{outOfRange(r)};
        if (r.kind == ParamKind::Real) bad.insert(bad.end(), {"nan", "inf", "1e400", "abc"});
        if (r.kind == ParamKind::Count) bad.insert(bad.end(), {"1.5", "abc", "99999999999"});
        for (const std::string& value : bad) {
            std::string error;
            try {
                parsed(context, {r.flag, value});
            } catch (const CLI::ParseError& e) {
                error = e.what();
            }
            EXPECT_NE(error.find(r.flag), std::string::npos) << value << ": " << error;
        }
    }
}

// A configuration built in code is held to the same ranges: validate()
// names the flag of a value out of its row's range.
TEST(Parameters, ValidateChecksEachRowsRange) {
    MachineConfig m;
    m.fbBatch = 0;
    EXPECT_THROW(m.validate(), std::invalid_argument);
    m = MachineConfig{};
    m.balance.deadband = 1.5;
    try {
        m.validate();
        ADD_FAILURE() << "accepted";
    } catch (const std::invalid_argument& e) {
        EXPECT_EQ(std::string(e.what()).rfind("--deadband: ", 0), 0u) << e.what();
    }
    m = MachineConfig{};
    m.fbPort.bandwidth = 0;
    EXPECT_THROW(m.validate(), std::invalid_argument);
    m = MachineConfig{};
    m.speed = 0;
    EXPECT_THROW(m.validate(), std::invalid_argument);
    EXPECT_NO_THROW(MachineConfig{}.validate());
}

// --polish-tries auto is kSamplePolishTries under sample, named or chosen
// by --balance recommended, else 0: not under measured, where the
// recommended policy is measured (columns of more than 8 boxes), nor
// resplit. It is the default; the last value given counts.
TEST(Parameters, PolishTriesAutoIsEightUnderSampleOnly) {
    const auto tries = [](const std::string& file, const std::vector<std::string>& rest = {}) {
        const RtsimOptions o = parsed(file, rest);
        return std::make_pair(o.machine.balance.policy, o.machine.balance.polishTries);
    };
    const std::string autoTries = "polish-tries = \"auto\"\n";
    EXPECT_EQ(tries("balance = \"recommended\"\n" + autoTries), std::make_pair(std::string("sample"), kSamplePolishTries));
    EXPECT_EQ(tries("balance = \"sample\"\n" + autoTries), std::make_pair(std::string("sample"), kSamplePolishTries));
    EXPECT_EQ(tries("balance = \"resplit\"\n" + autoTries), std::make_pair(std::string("resplit"), 0));
    EXPECT_EQ(tries("balance = \"recommended\"\nmesh-dims = \"16x1x1\"\n" + autoTries), std::make_pair(std::string("measured"), 0));
    EXPECT_EQ(tries("balance = \"sample\"\n"), std::make_pair(std::string("sample"), kSamplePolishTries));  // (the default)
    EXPECT_EQ(tries("balance = \"measured\"\n"), std::make_pair(std::string("measured"), 0));
    EXPECT_EQ(tries("balance = \"sample\"\npolish-tries = \"0\"\n"), std::make_pair(std::string("sample"), 0));
    EXPECT_EQ(tries("balance = \"recommended\"\n" + autoTries, {"--polish-tries", "3"}), std::make_pair(std::string("sample"), 3));
    EXPECT_EQ(tries("balance = \"recommended\"\npolish-tries = \"3\"\n", {"--polish-tries", "auto"}),
              std::make_pair(std::string("sample"), kSamplePolishTries));
    // Built in code, auto passes validate() unresolved (and polishes nothing); another negative does not.
    MachineConfig m;
    m.balance.polishTries = kPolishTriesAuto;
    EXPECT_NO_THROW(m.validate());
    m.balance.polishTries = -2;
    EXPECT_THROW(m.validate(), std::invalid_argument);
}
