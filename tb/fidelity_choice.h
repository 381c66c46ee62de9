// --max-error E: rtsim picks the fidelity rung (doc/fidelity.md) for this
// scene, mesh and machine: the fastest whose render time is within E of
// the exact model's, judged on calibration frames it runs itself: the same
// machine and camera tracing every k-th pixel of every k-th row, run exact
// and then at each rung it tries in turn, the coarsest first, until one is
// within (today express, as the quantum rungs' calibration errors did not
// foretell the frame's). They run in the machine that then renders the
// frame (a MachineSession built with the express routes), so a calibration
// adds frames, not machines. The choice rests on simulated figures only,
// so the same inputs choose the same rung; the calibration's wall time is
// reported beside it.
#pragma once
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "machine/machine.h"
#include "rtsim_cli.h"
#include "scene.h"

namespace rt {

// A rung: what it sets in the machine.
struct FidelityRung {
    std::string name;
    bool express = false;
    bool through = false;  // (--fidelity through: express too)
    Picos quantum = 0;  // 0: each process's lookahead (exact); else a fixed quantum
};

// The rungs from the exact model down, each coarser than the one before.
const std::vector<FidelityRung>& fidelityRungs();

// The choice: what the report records as `fidelity` (the rung, the error
// asked for, the calibration: its size, each rung's error, events and wall
// time; and why), and the machine that ran the calibration frames, ready
// to render the frame asked for (null: no calibration ran).
struct FidelityChoice {
    nlohmann::json json;
    std::unique_ptr<MachineSession> session;
};

// Chooses the rung for `o` (maxError set) and sets it in o.machine.
FidelityChoice chooseFidelity(const Scene& scene, RtsimOptions& o);

// The rung `m` runs (config.fidelity.rung of a run without --max-error).
std::string rungOf(const MachineConfig& m);

}  // namespace rt
