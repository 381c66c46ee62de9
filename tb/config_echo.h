// The report's `config`: every setting as the run used it, the machine's
// (models/analysis/report.h) and the run's own (the scene file and its SHA-256, or
// the procedural parameters; the camera and lights as this frame sees them;
// the frame sequence). A rerun without flags of its own must arrive at the
// report's (tb/rerun.h).
#pragma once
#include <string>

#include <nlohmann/json.hpp>

#include "rtsim_cli.h"
#include "scene.h"

namespace rt {

// SHA-256 of a file's bytes, in hex; throws std::runtime_error if unreadable.
std::string sha256OfFile(const std::string& path);


// Throws (std::runtime_error from sha256OfFile) if the scene file cannot be read.
nlohmann::json configEcho(const RtsimOptions& o, const Scene& scene);
// Its `scene`: the file and its SHA-256, or the procedural parameters; the
// objects and the axis (also what --boundaries-from's run must have had).
nlohmann::json sceneEcho(const RtsimOptions& o, const Scene& scene);

// The first setting where two configs differ, as "PATH: A there, B here"
// ("not in the report" where `there` lacks it, "not a setting of this run"
// where `here` does); empty if none does.
std::string firstDifference(const nlohmann::json& there, const nlohmann::json& here);
// Where the first difference is a setting a flag sets: how to rerun it
// anyway ("; ..."), else empty. A setting `there` (an older build's
// report) lacks came after the report's build: with this build's value.
// One it holds otherwise (a default changed, or an edited report): with
// the report's. A flag after --rerun makes the run a what-if, which is
// not checked against the report.
std::string newerSettingHint(const nlohmann::json& there, const nlohmann::json& here, const std::string& report);

}  // namespace rt
