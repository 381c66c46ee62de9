// rtsim's messages through SystemC's reporting (sc_report), with an ID per
// kind, so a user or a testbench can filter or promote them as with any
// SystemC model (sc_report_handler::set_actions("rtsim/scene", ...)):
//
//   rtsim/config     a flag, a --config or --rerun file        (exit 2)
//   rtsim/scene      the scene file                             (exit 2)
//   rtsim/output     an output that cannot be written           (exit 2)
//   rtsim/run        a run that failed: a conservation law broken, a
//                    SystemC error, a child run                 (exit 1)
//   rtsim/watchdog   a run stopped by the watchdog              (exit 3)
//   rtsim/signal     a run stopped by Ctrl-C or SIGTERM         (exit 128 + N)
//   rtsim/reference  the baseline or comparison run failed (a warning)
//   rtsim/info       what rtsim does, with --verbose
//
// Each is one line on stderr, "rtsim: error: ..." (or "warning: "; a stop
// by signal is plain); with --verbose the ID follows in brackets.
#pragma once
#include <string>

namespace rt::msg {

constexpr const char* kConfig = "rtsim/config";
constexpr const char* kScene = "rtsim/scene";
constexpr const char* kOutput = "rtsim/output";
constexpr const char* kRun = "rtsim/run";
constexpr const char* kWatchdog = "rtsim/watchdog";
constexpr const char* kSignal = "rtsim/signal";
constexpr const char* kReference = "rtsim/reference";
constexpr const char* kInfo = "rtsim/info";

// Who speaks on stderr: "rtsim", or a reference run's name when this
// process is one (a child of another rtsim, sharing its stderr), so that
// its stop or error does not read as the parent's. Set once, before the
// stop handlers (which read it).
const char* program();
void setProgram(const char* name);

// Installs the handler that prints rtsim's messages as one line each and
// sets which are shown: `verbose` 0 (errors, warnings), 1 (and what rtsim
// does: rtsim/info), 2 (and SystemC's own informational messages).
void install(int verbose);
void error(const char* id, const std::string& text);
void warning(const char* id, const std::string& text);
void note(const char* id, const std::string& text);  // always shown, no "error:" (a stop by signal)
void info(const std::string& text);                  // with --verbose

}  // namespace rt::msg
