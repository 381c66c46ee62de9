// Reports that reproduce their run. A report records the flags its run was
// given (on the command line or in --config; outputs and internal flags
// left out, the scene file's path made absolute) and the scene file's
// SHA-256; `rtsim --rerun REPORT.json` runs them again, with any flags
// given after it on top (a what-if: `--rerun r.json --link-latency 1us`).
// Every effective setting is also in the report's `config`, and a rerun
// with no flags of its own checks that it arrives at the same `config` (a
// default changed since, or a scene file edited, is an error, not a
// different run under the same name).
//
// A report is data people pass around, so a rerun trusts none of it
// (doc/robustness.md, "Trust"): the fields it reads are type-checked, its
// flags may not name an output or start a program (tb/command_line.h), and
// the scene a rerun loads is the one the report records, by path and
// SHA-256 (checked before the file is parsed) and by every parameter in
// `config.scene`, what-ifs included, unless the command line itself
// names another scene.
#pragma once
#include <set>
#include <string>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "rtsim_cli.h"
#include "scene.h"

namespace rt {

// The flags given to `app` (config_file.h's form), without outputs and
// internal flags.
std::string flagsGiven(const CLI::App& app);

struct Rerun {
    std::string path;            // the report given
    nlohmann::json rerun;        // its `rerun` (flags, version)
    nlohmann::json config;       // its `config`
    bool overrides = false;      // flags other than outputs given with --rerun
};

// Reads REPORT.json (a regular file of at most 1 GB, JSON within limits,
// `rerun.flags` a string, `config.scene` an object). Throws
// std::invalid_argument naming the field (exit 2).
Rerun readRerun(const std::string& path);
// The same checks on a report already read (`path` names it in errors).
Rerun rerunOf(nlohmann::json report, const std::string& path);

// The flags that choose the scene (config.scene's fields).
bool isSceneFlag(const std::string& name);

// Before the scene is read: the file the flags name is the report's, by
// path and SHA-256 (or neither names a file). Throws std::invalid_argument.
void checkRerunSceneFile(const Rerun& r, const SceneOptions& scene);
// After: this run's config.scene is the report's; "" or the difference.
std::string rerunSceneDifference(const Rerun& r, const nlohmann::json& config);

}  // namespace rt
