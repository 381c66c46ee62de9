#include "subprocess.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "json_input.h"
#include "output_file.h"
#include "wall_limit.h"
#include "process/watchdog.h"

namespace rt {
namespace {

// The children running: fixed slots a signal handler may read.
constexpr int kChildSlots = 16;
std::atomic<pid_t> children[kChildSlots];

void registerChild(pid_t pid) {
    for (auto& c : children) {
        pid_t none = 0;
        if (c.compare_exchange_strong(none, pid)) return;
    }
}

void forgetChild(pid_t pid) {
    for (auto& c : children) {
        pid_t p = pid;
        if (c.compare_exchange_strong(p, 0)) return;
    }
}

// A child's report: rtsim's own output, still read within limits.
constexpr uintmax_t kMaxChildReportBytes = uintmax_t(1) << 30;

// Removes `folder`'s files PREFIX-PID-... of a PID no longer running
// (kill(PID, 0): ESRCH), left by a process killed with SIGKILL. A file of
// another user's or of a running process stays.
void removeOrphans(const std::string& folder, const std::string& prefix) {
    namespace fs = std::filesystem;
    std::error_code ec;
    for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string name = it->path().filename().string();
        if (name.rfind(prefix + "-", 0) != 0) continue;
        const size_t from = prefix.size() + 1, to = name.find('-', from);
        if (to == std::string::npos || to == from || to - from > 9 ||
            name.find_first_not_of("0123456789", from) != to)
            continue;
        const pid_t pid = pid_t(std::stol(name.substr(from, to - from)));
        if (pid > 0 && ::kill(pid, 0) != 0 && errno == ESRCH) {
            std::error_code gone;
            fs::remove(it->path(), gone);
        }
    }
}

}  // namespace

TempFile::TempFile(const std::string& prefix, const std::string& suffix, const std::string& text) {
    const char* dir = std::getenv("TMPDIR");  // (as mkstemp's callers do; the tests give their own)
    const std::string folder = dir && *dir ? dir : "/tmp";
    removeOrphans(folder, prefix);
    std::string path = folder + "/" + prefix + "-" + std::to_string(::getpid()) + "-XXXXXX" + suffix;
    int fd = -1;
    {
        const StopsHeld held;  // (made and registered: a stop removes it)
        fd = mkstemps(path.data(), int(suffix.size()));
        if (fd >= 0) registerTempFile(path);
    }
    if (fd < 0) throw std::runtime_error("cannot create a temporary file " + path);
    path_ = path;
    const bool ok = text.empty() || ::write(fd, text.data(), text.size()) == ssize_t(text.size());
    ::close(fd);
    if (!ok) {
        std::remove(path_.c_str());
        forgetTempFile(path_);
        throw std::runtime_error("cannot write the temporary file " + path_);
    }
}

TempFile::~TempFile() {
    std::remove(path_.c_str());  // (then forgotten: a stop between finds nothing to remove)
    forgetTempFile(path_);
}

pid_t spawn(std::vector<std::string> args, bool keepStdout, const std::string& stderrPath, bool stopsIfStopped) {
    std::vector<char*> av;
    for (std::string& a : args) av.push_back(a.data());
    av.push_back(nullptr);
    posix_spawn_file_actions_t io;
    posix_spawn_file_actions_init(&io);
    posix_spawn_file_actions_addopen(&io, 0, "/dev/null", O_RDONLY, 0);
    if (!keepStdout) posix_spawn_file_actions_addopen(&io, 1, "/dev/null", O_WRONLY, 0);
    if (!stderrPath.empty()) posix_spawn_file_actions_addopen(&io, 2, stderrPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    posix_spawnattr_t attr;
    posix_spawnattr_init(&attr);
    posix_spawnattr_setpgroup(&attr, 0);  // a group of its own (see the header)
    sigset_t defaults;                    // and rtsim's own signal handling, not ours
    sigemptyset(&defaults);
    for (int s : {SIGINT, SIGTERM, SIGALRM}) sigaddset(&defaults, s);
    posix_spawnattr_setsigdefault(&attr, &defaults);
    // A stop must reach a child however close to its start it comes: held
    // from before the spawn until the child is in its slot, then passed on
    // by the handler; one that came before is passed on here if asked.
    // (Without this, a stop between "reference runs:" and the slot let a
    // 1x1x1 baseline run to its end: 3.9 s under AddressSanitizer in CI.)
    const StopsHeld held;
    posix_spawnattr_setsigmask(&attr, &held.before());  // the child starts with the mask rtsim had
    posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETPGROUP | POSIX_SPAWN_SETSIGDEF | POSIX_SPAWN_SETSIGMASK);
    pid_t pid = -1;
    if (posix_spawn(&pid, av[0], &io, &attr, av.data(), environ) != 0) pid = -1;
    posix_spawnattr_destroy(&attr);
    posix_spawn_file_actions_destroy(&io);
    if (pid > 0) {
        registerChild(pid);
        if (const int sig = stopSignal; sig && stopsIfStopped) ::kill(pid, sig);
    }
    return pid;  // (the stops held come once it returns)
}

int waitExit(pid_t pid) {
    if (pid <= 0) return -1;
    int status = 0;
    while (waitpid(pid, &status, 0) < 0)
        if (errno != EINTR) {
            forgetChild(pid);
            return -1;
        }
    forgetChild(pid);
    if (WIFEXITED(status)) return WEXITSTATUS(status);
    return WIFSIGNALED(status) ? 128 + WTERMSIG(status) : -1;
}

void signalChildrenNow(int sig) {
    for (auto& c : children) {
        const pid_t p = c.load();
        if (p > 0) ::kill(p, sig);
    }
}

Child::Child(const std::vector<std::string>& command, const std::vector<std::string>& extra) {
    try {
        report_.emplace("rtsim-child", ".json");
    } catch (const std::exception&) {
        return;  // (it did not start: no report)
    }
    std::vector<std::string> args{"/proc/self/exe"};  // this very program
    args.insert(args.end(), command.begin() + 1, command.end());
    args.insert(args.end(), extra.begin(), extra.end());
    // The wall-clock limit is the whole run's: a child gets what is left.
    if (const double left = wallLeft(); left > 0) args.insert(args.end(), {"--watchdog-wall", std::to_string(left)});
    args.insert(args.end(), {"--report", report_->path()});
    pid_ = spawn(std::move(args), false, "", true);
}

Child::~Child() { wait(); }

int Child::wait() {
    if (pid_ > 0) {
        exitCode_ = waitExit(pid_);
        pid_ = -1;
        if (exitCode_ == 0 || exitCode_ == 3 || exitCode_ > 128) {
            try {
                result_ = readJsonFile(report_->path(), kMaxChildReportBytes);
            } catch (const std::exception&) {  // (stopped before it wrote one)
            }
        }
    }
    return exitCode_;
}

std::optional<nlohmann::json> Child::report() {
    wait();
    return exitCode_ == 0 ? result_ : std::nullopt;
}

std::optional<nlohmann::json> Child::stoppedReport() {
    wait();
    return exitCode_ == 3 || exitCode_ > 128 ? result_ : std::nullopt;
}

}  // namespace rt
