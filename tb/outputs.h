// What a run writes: the image, the report, the mesh picture (--map), and
// the VCD that the machine streams as it runs (models/vcd_stream.h). Each
// output path is checked before the run (a path that cannot be written is
// bad input, exit 2); the image and the report are written whole or not at
// all, to a temporary file renamed over the path (sw/output_file.h).
#pragma once
#include <string>

#include <nlohmann/json.hpp>

#include "image.h"
#include "rtsim_cli.h"

namespace rt {

// Throws OutputError for the first output path that cannot be written.
void checkOutputs(const RtsimOptions& o);
// The report (nothing if `path` is empty).
void writeReport(const std::string& path, const nlohmann::json& report);
// The image and the report, each renamed over its path once both are
// written; then the mesh picture, drawn from the report.
void writeOutputs(const RtsimOptions& o, const Image& image, const nlohmann::json& report);
// A failed run leaves no waveform that looks like a result.
void removeFailedTrace(const std::string& vcd);

}  // namespace rt
