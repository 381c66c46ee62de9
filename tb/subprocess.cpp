#include "subprocess.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <fstream>
#include <stdexcept>

namespace rt {

std::string makeTempFile(const std::string& prefix, const std::string& text) {
    std::string path = "/tmp/" + prefix + "-XXXXXX";
    const int fd = mkstemp(path.data());
    if (fd < 0) throw std::runtime_error("cannot create a temporary file in /tmp");
    close(fd);
    if (!text.empty()) std::ofstream(path) << text;
    return path;
}

pid_t spawn(std::vector<std::string> args, bool keepStdout) {
    std::vector<char*> av;
    for (std::string& a : args) av.push_back(a.data());
    av.push_back(nullptr);
    posix_spawn_file_actions_t io;
    posix_spawn_file_actions_init(&io);
    posix_spawn_file_actions_addopen(&io, 0, "/dev/null", O_RDONLY, 0);
    if (!keepStdout) posix_spawn_file_actions_addopen(&io, 1, "/dev/null", O_WRONLY, 0);
    pid_t pid = -1;
    if (posix_spawn(&pid, av[0], &io, nullptr, av.data(), environ) != 0) pid = -1;
    posix_spawn_file_actions_destroy(&io);
    return pid;
}

int waitExit(pid_t pid) {
    if (pid <= 0) return -1;
    int status = 0;
    while (waitpid(pid, &status, 0) < 0)
        if (errno != EINTR) return -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

Child::Child(int argc, char** argv, const std::vector<std::string>& extra) {
    try {
        report_ = makeTempFile("rtsim-child");
    } catch (const std::exception&) {
        return;  // (it did not start: no report)
    }
    std::vector<std::string> args{"/proc/self/exe"};  // this very program
    args.insert(args.end(), argv + 1, argv + argc);
    args.insert(args.end(), extra.begin(), extra.end());
    args.insert(args.end(), {"--report", report_});
    pid_ = spawn(std::move(args), false);
}

Child::~Child() {
    wait();
    if (!report_.empty()) std::remove(report_.c_str());
}

int Child::wait() {
    if (pid_ > 0) {
        exitCode_ = waitExit(pid_);
        pid_ = -1;
        if (exitCode_ == 0 || exitCode_ == 3) {
            std::ifstream f(report_);
            try {
                result_ = nlohmann::json::parse(f);
            } catch (const std::exception&) {
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
    return exitCode_ == 3 ? result_ : std::nullopt;
}

}  // namespace rt
