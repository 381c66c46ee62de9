// What rtsim parses: the flags of its --config files, in the order given,
// or of a report's rerun.flags (--rerun), then the flags on the command line;
// for each flag the last value wins. Each file's or report's value is checked
// alone as it is read, so a bad one is exit 2 naming FILE:LINE; the merged
// list is what CLI11 parses (and what the child runs get: they read no file
// again).
//
// A report is untrusted input (doc/robustness.md, "Trust"): its flags may
// not name outputs, a config file or an internal flag (those come only from
// the command line), and the scene it names is checked against the report's
// own record of it (tb/rerun.h).
#pragma once
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "config_file.h"
#include "output_file.h"
#include "rerun.h"
#include "rtsim_cli.h"

namespace rt {

struct CommandLine {
    std::vector<std::string> args;             // argv[0], the files' flags as --name=value, then the command line's
    std::map<std::string, std::string> where;  // a flag's name -> "FILE:LINE" of the value it has, if from a file
    std::set<std::string> given;               // the flags the command line itself sets
    std::optional<Rerun> rerun;                // --rerun REPORT.json
    std::vector<std::string> configs;          // --config files, in order
    // Whether the command line names the scene itself (a what-if of
    // another scene: --rerun's scene checks do not apply).
    bool givesScene() const;
    // Every file the run reads (no output may name one): the --config
    // files, the --rerun report, and `o`'s scene and reports.
    std::vector<NamedFile> inputs(const RtsimOptions& o) const;
    // "FILE:LINE: " for a message that starts with a flag whose value came
    // from a file; empty otherwise.
    std::string originOf(const std::string& message) const;
};

// Reads --config files and --rerun's report. Throws std::invalid_argument
// (ConfigError, JsonInputError) with a one-line message: exit 2.
CommandLine assembleCommandLine(int argc, char** argv);

// The lines of a config file, or of a report's rerun.flags.
struct ConfigSource {
    std::vector<ConfigLine> lines;
    bool fromReport = false;  // no outputs, no internal flags
};
// The merge itself: each line checked alone, the last value of each flag,
// then `rest` (the command line after argv[0]). Throws as above.
CommandLine mergeFlags(const std::vector<ConfigSource>& sources, const std::vector<std::string>& rest, const std::string& argv0);

}  // namespace rt
