// libFuzzer target for the report reader (scripts/fuzz.sh --target report):
// any bytes given to `rtsim --rerun` must be read as a report, or refused
// with one line naming what is wrong (tb/fuzz/parse_flags.h); a report it
// accepts has its flags read and parsed, and its `config` compared with
// itself and with an empty one, as a rerun does.
#include <cstddef>
#include <cstdint>
#include <string>

#include "config_echo.h"
#include "json_input.h"
#include "parse_flags.h"
#include "rerun.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    rt::Rerun r;
    std::vector<rt::ConfigLine> lines;
    try {
        r = rt::rerunOf(rt::parseJsonText(std::string(reinterpret_cast<const char*>(data), size), "fuzz.json"), "fuzz.json");
        lines = rt::parseConfig(r.rerun["flags"].get<std::string>(), "fuzz.json: rerun.flags");
    } catch (const std::invalid_argument&) {
        return 0;  // refused, saying why
    }
    rt::firstDifference(r.config, r.config);
    rt::firstDifference(r.config, nlohmann::json::object());
    rt::rerunSceneDifference(r, nlohmann::json{{"scene", nlohmann::json::object()}});
    rt::fuzz::parseFlags({{lines, true}});
    return 0;
}
