// Reports that reproduce their run. A report records the flags its run was
// given (on the command line or in --config; outputs and internal flags
// left out, the scene file's path made absolute) and the scene file's
// SHA-256; `rtsim --rerun REPORT.json` runs them again, with any flags
// given after it on top (a what-if: `--rerun r.json --link-latency 1us`).
// Every effective setting is also in the report's `config`, and a rerun
// with no flags of its own checks that it arrives at the same `config` (a
// default changed since, or a scene file edited, is an error, not a
// different run under the same name).
#pragma once
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

namespace rt {

// The flags given to `app` as a config file CLI11 reads back (--config),
// without outputs (--image --report --vcd -q --map) and internal flags.
std::string flagsGiven(const CLI::App& app);

// SHA-256 of a file's bytes, in hex; throws std::runtime_error if unreadable.
std::string sha256OfFile(const std::string& path);

struct Rerun {
    nlohmann::json report;          // the report being rerun
    std::string configPath;         // its flags, written to a temporary config file (removed by the destructor)
    std::vector<std::string> args;  // the command line to parse: --config configPath, then the flags given after --rerun
    bool overrides = false;         // flags other than outputs given with --rerun
    Rerun() = default;
    Rerun(Rerun&& o) noexcept;  // (the file has one owner)
    Rerun(const Rerun&) = delete;
    Rerun& operator=(const Rerun&) = delete;
    Rerun& operator=(Rerun&& o) noexcept;
    ~Rerun();
};

// If the command line has --rerun FILE: FILE read (a regular file of at
// most 1 GB, a report of rtsim with `rerun.flags`) and the arguments to
// parse instead; nothing otherwise. Throws std::invalid_argument with a
// one-line message naming what is wrong (exit 2).
std::optional<Rerun> prepareRerun(int argc, char** argv);

}  // namespace rt
