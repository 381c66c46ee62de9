// What the report and config fuzz targets share: merged flags parsed as
// rtsim parses them (tb/rtsim.cpp, readCommandLine), and the rule for what
// a reader may throw. A reader of untrusted input may refuse it only with
// one of rtsim's one-line errors (std::invalid_argument: ConfigError,
// JsonInputError, OptionError; CLI11's ParseError); anything else (a
// library's exception naming no field, a crash, undefined behaviour) is a
// finding, and escapes to libFuzzer.
#pragma once
#include <string>
#include <vector>

#include "command_line.h"
#include "rtsim_cli.h"

namespace rt::fuzz {

// Merges `sources` and parses the result with every check rtsim makes
// before reading the scene.
inline void parseFlags(const std::vector<ConfigSource>& sources) {
    try {
        const CommandLine cl = mergeFlags(sources, {}, "rtsim");
        RtsimOptions o;
        CLI::App app{"fuzz", "rtsim"};
        o.addTo(app);
        std::vector<std::string> reversed(cl.args.rbegin(), cl.args.rend() - 1);
        app.parse(reversed);
        o.finish();
    } catch (const std::invalid_argument&) {
    } catch (const CLI::ParseError&) {
    }
}

}  // namespace rt::fuzz
