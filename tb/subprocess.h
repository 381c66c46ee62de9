// What rtsim starts beside itself: its own reference runs (the 1x1x1
// baseline, the balancing comparison, the earlier frames of a sequence;
// SystemC elaborates once per process) and scripts/mesh_map.py; and the
// temporary files it hands them. Started with posix_spawn: no shell, no
// thread (a thread around system() left LeakSanitizer's tracer a stale
// stack to read), so two can run at once by starting both, then waiting.
#pragma once
#include <sys/types.h>

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace rt {

// A new empty file /tmp/PREFIX-XXXXXX holding `text`; throws
// std::runtime_error if it cannot be made.
std::string makeTempFile(const std::string& prefix, const std::string& text = "");

// Starts args[0] (a path) with the rest; stdin from /dev/null, and stdout
// too unless `keepStdout`; stderr is rtsim's. -1 if it could not start.
pid_t spawn(std::vector<std::string> args, bool keepStdout);
// Waits for it: its exit code, or -1 if it did not exit by itself.
int waitExit(pid_t pid);

// rtsim's own command (argv) with `extra` flags after the user's and a
// report to a temporary file: how it exited, and the report it wrote.
class Child {
public:
    Child(int argc, char** argv, const std::vector<std::string>& extra);
    Child(const Child&) = delete;
    Child& operator=(const Child&) = delete;
    ~Child();
    int wait();
    // Its report, if it ended normally and wrote one.
    std::optional<nlohmann::json> report();
    // Its report so far, if the watchdog stopped it (exit 3).
    std::optional<nlohmann::json> stoppedReport();

private:
    pid_t pid_ = -1;
    int exitCode_ = -1;
    std::string report_;
    std::optional<nlohmann::json> result_;
};

}  // namespace rt
