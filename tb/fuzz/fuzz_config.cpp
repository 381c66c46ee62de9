// libFuzzer target for the config reader (scripts/fuzz.sh --target config):
// any bytes given to `rtsim --config` must be read, each value checked
// alone, or refused with one line naming the file and line
// (tb/fuzz/parse_flags.h); what it accepts is parsed as rtsim parses it.
#include <cstddef>
#include <cstdint>
#include <string>

#include "config_file.h"
#include "parse_flags.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    std::vector<rt::ConfigLine> lines;
    try {
        lines = rt::parseConfig(std::string(reinterpret_cast<const char*>(data), size), "fuzz.conf");
    } catch (const rt::ConfigError&) {
        return 0;
    }
    rt::fuzz::parseFlags({{lines, false}});
    return 0;
}
