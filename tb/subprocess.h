// What rtsim starts beside itself: its own reference runs (the 1x1x1
// baseline and the balancing comparison, two at once) and
// scripts/mesh_map.py; and the
// temporary files it hands them. Started with posix_spawn: no shell, no
// thread (a thread around system() left LeakSanitizer's tracer a stale
// stack to read), so two can run at once by starting both, then waiting.
//
// Each child runs in a process group of its own, so that Ctrl-C at the
// terminal reaches rtsim alone, which passes the stop on to each child
// once (tb/stops.h); a child rtsim ends if its parent dies.
#pragma once
#include <csignal>
#include <sys/types.h>

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace rt {

// A new file $TMPDIR/PREFIX-PID-XXXXXXSUFFIX (/tmp without TMPDIR) holding
// `text`, removed with this object (and by a signal that ends rtsim at
// once). A SIGKILL leaves it (and a child's report being written beside
// it), so each new one first removes those of PREFIX whose PID is no
// longer running. Throws std::runtime_error if it cannot be made or
// written.
class TempFile {
public:
    TempFile(const std::string& prefix, const std::string& suffix, const std::string& text = "");
    ~TempFile();
    TempFile(const TempFile&) = delete;
    TempFile& operator=(const TempFile&) = delete;
    const std::string& path() const { return path_; }

private:
    std::string path_;
};

// Starts args[0] (a path) with the rest; stdin from /dev/null, stdout too
// unless `keepStdout`, stderr to `stderrPath` if given (else rtsim's). -1 if
// it could not start. A stop (SIGINT, SIGTERM) that comes while it runs is
// passed on to it; one rtsim already had is passed on at its start if
// `stopsIfStopped` (a reference run; not the map a stopped run still draws).
pid_t spawn(std::vector<std::string> args, bool keepStdout, const std::string& stderrPath = "", bool stopsIfStopped = false);
// Waits for it: its exit code, 128 + N if signal N ended it, -1 if unknown.
int waitExit(pid_t pid);

// Sends `sig` to every child still running (async-signal-safe).
void signalChildrenNow(int sig);

// rtsim's own command (`command`, argv[0] first: the flags of the files
// and the command line, tb/command_line.h) with `extra` flags after them and a
// report to a temporary file: how it exited, and the report it wrote. Started
// after a stop, it is stopped at once.
class Child {
public:
    Child(const std::vector<std::string>& command, const std::vector<std::string>& extra);
    Child(const Child&) = delete;
    Child& operator=(const Child&) = delete;
    ~Child();
    int wait();
    // Its report, if it ended normally and wrote one.
    std::optional<nlohmann::json> report();
    // Its report so far, if the watchdog or a signal stopped it (exit 3,
    // 128 + N).
    std::optional<nlohmann::json> stoppedReport();
    // 0 done, 3 or 128 + N stopped, anything else failed.
    int exitCode() { return wait(); }
    // Stopped as rtsim stops a run, with its report so far: by the watchdog
    // (3), Ctrl-C or SIGTERM (130, 143).
    bool stopped() {
        const int code = wait();
        return code == 3 || code == 128 + SIGINT || code == 128 + SIGTERM;
    }

private:
    pid_t pid_ = -1;
    int exitCode_ = -1;
    std::optional<TempFile> report_;
    std::optional<nlohmann::json> result_;
};

}  // namespace rt
