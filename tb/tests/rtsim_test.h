// The fixture of rtsim's end-to-end tests (test_rtsim*.cpp): rtsim run as
// a user runs it, each run its own process, and what its report says.
#pragma once
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "command_test.h"

namespace rt::test {

// Removes wall-clock fields (their names contain "wall") everywhere.
inline void dropWall(nlohmann::json& j) {
    if (j.is_object()) {
        for (auto it = j.begin(); it != j.end();) {
            if (it.key().find("wall") != std::string::npos) it = j.erase(it);
            else dropWall(*it++);
        }
    } else if (j.is_array()) {
        for (auto& e : j) dropWall(e);
    }
}

// Six frames of resplit past the links' knee (--link-bandwidth `bandwidth`),
// and the same frame unbalanced: each frame's render time and slides.
struct ResplitAgainstNone {
    std::vector<double> ns;
    std::vector<int> slides;
    double last, none;
};

class Rtsim : public CommandTest {
protected:
    Rtsim() : CommandTest(RTSIM_EXE) {}
    nlohmann::json report(const std::string& args, const std::string& name = "r.json") {
        const Outcome o = run(args + " -q --no-baseline --image '' --report " + (dir_ / name).string());
        EXPECT_EQ(o.code, 0) << o.err;
        return nlohmann::json::parse(slurp(dir_ / name));
    }
    // With the 1x1x1 baseline and the comparison run, and the image into `image`: nothing on stderr.
    nlohmann::json reportWithImage(const std::string& args, const std::string& image) {
        const Outcome o = run(args + " --image " + (dir_ / image).string() + " --report " + (dir_ / "r.json").string());
        EXPECT_EQ(o.code, 0) << o.err;
        EXPECT_EQ(o.err, "");
        return nlohmann::json::parse(slurp(dir_ / "r.json"));
    }
    // A procedural scene and mesh (`scene`: by default 300 spheres spread evenly, 3x3x3).
    ResplitAgainstNone resplitAgainstNone(const std::string& bandwidth,
                                          const std::string& scene = " --spheres 300 --radius 0.03 --concentration 1 --mesh 3") {
        const std::string k = scene + " --size 48x48 --balance-interval 5us"
                              " --link-bandwidth " + bandwidth;
        const nlohmann::json f = report(k + " --balance resplit --frames 6", "f.json");
        ResplitAgainstNone r{{}, {}, f["render_time_ns"].get<double>(),
                             report(k + " --balance none", "n.json")["render_time_ns"].get<double>()};
        for (const nlohmann::json& frame : f["frames"]) {
            r.ns.push_back(frame["render_time_ns"].get<double>());
            r.slides.push_back(frame["slides"].get<int>());
        }
        EXPECT_EQ(r.ns.size(), 6u);
        r.ns.resize(6, -1);  // (a short sequence fails the checks, not the test binary)
        r.slides.resize(6, -1);
        return r;
    }
};

inline constexpr const char* kSmall = " --spheres 200 --radius 0.04 --size 32x32";

}  // namespace rt::test
