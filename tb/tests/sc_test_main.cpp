// main() for the SystemC test executables: SystemC warnings and errors
// become exceptions, so a test that provokes one fails; the copyright banner
// is off. Each test runs in its own process, because SystemC elaborates
// only once per process: ctest runs each alone (gtest_discover_tests), and
// the executable run by hand on more than one test (`build/test_balance`,
// or a filter with a wildcard) runs each of them as a child of its own
// (runEachAlone), where they failed at 0 ms with "set time resolution
// failed: already specified" after the first.
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <systemc>

extern char** environ;

namespace {

constexpr const char* kAlone = "RT_SC_TEST_ALONE";  // set in the children: run in this process
const std::string kFilter = "--gtest_filter=";

// Whether the arguments name at most one test (the last filter, as gtest
// reads them, with no wildcard, no list and no negation) or only ask for
// the list or the help: then this process runs it.
bool inThisProcess(int argc, char** argv) {
    if (std::getenv(kAlone)) return true;
    std::string filter = "*";
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a.rfind("--gtest_list_tests", 0) == 0 || a == "--help" || a == "-h" || a == "-?" || a == "--gtest_help") return true;
        if (a.rfind(kFilter, 0) == 0) filter = a.substr(kFilter.size());
    }
    return filter.find_first_of("*?:-") == std::string::npos;
}

// What a child cannot do alone: repeat (each child would elaborate again)
// or write gtest's XML or JSON (each child would overwrite the last's).
const char* refusedFlag(const std::string& a) {
    for (const char* f : {"--gtest_repeat", "--gtest_output"})
        if (a.rfind(f, 0) == 0) return f;
    return nullptr;
}

// Runs `args` (args[0] the program) with this process's environment plus
// kAlone; its stdout into `out` if given, else this process's. Its exit status.
int run(const std::vector<std::string>& args, std::string* out) {
    std::vector<char*> argv;
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    setenv(kAlone, "1", 1);
    int fds[2] = {-1, -1};
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    if (out) {
        if (pipe(fds) != 0) return -1;
        posix_spawn_file_actions_adddup2(&actions, fds[1], STDOUT_FILENO);
        posix_spawn_file_actions_addclose(&actions, fds[0]);
    }
    std::cout.flush();
    pid_t pid = 0;
    const int spawned = posix_spawn(&pid, "/proc/self/exe", &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    if (out) {
        close(fds[1]);
        char buf[4096];
        for (ssize_t n; spawned == 0 && (n = read(fds[0], buf, sizeof buf)) > 0;) out->append(buf, size_t(n));
        close(fds[0]);
    }
    if (spawned != 0) return -1;
    int status = 0;
    pid_t got;
    while ((got = waitpid(pid, &status, 0)) < 0 && errno == EINTR) {
    }
    if (got != pid) return -1;  // (SIGCHLD ignored: the child was reaped unseen)
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

// The tests the arguments select ("Suite.Name", parameterised ones with
// their prefix and index), from the program's own --gtest_list_tests.
std::vector<std::string> selectedTests(const std::vector<std::string>& args, bool& listed) {
    std::vector<std::string> list = args;
    list.push_back("--gtest_list_tests");
    std::string text;
    listed = run(list, &text) == 0;
    if (!listed) return {};
    std::vector<std::string> names;
    std::string suite;
    size_t at = 0;
    while (at < text.size()) {
        const size_t end = std::min(text.find('\n', at), text.size());
        std::string line = text.substr(at, end - at);
        at = end + 1;
        line = line.substr(0, line.find("  #"));  // (a parameterised test's "  # GetParam() = ...")
        if (line.empty()) continue;
        if (line[0] != ' ') {
            suite = line;  // "Suite." (ends in the dot)
        } else {
            names.push_back(suite + line.substr(line.find_first_not_of(' ')));
        }
    }
    return names;
}

// Each selected test in a child of its own, its output as it comes; a
// summary at the end, as gtest's own. Exit 1 if any failed.
int runEachAlone(int argc, char** argv) {
    signal(SIGCHLD, SIG_DFL);  // (ignored, the children would be reaped before their status is read)
    std::vector<std::string> args(argv, argv + argc);
    for (const std::string& a : args)
        if (const char* f = refusedFlag(a)) {
            std::cerr << args[0] << ": " << f << " with more than one test: give one test (--gtest_filter=Suite.Name), "
                      << "or run them through ctest (--repeat, --output-junit)\n";
            return 2;
        }
    bool listed = false;
    const std::vector<std::string> tests = selectedTests(args, listed);
    if (!listed) {
        std::cerr << args[0] << ": listing the tests failed\n";
        return 1;
    }
    std::vector<std::string> kept;  // the arguments other than the filter
    bool disabledToo = false;
    for (const std::string& a : args) {
        if (a.rfind(kFilter, 0) != 0) kept.push_back(a);
        disabledToo |= a.rfind("--gtest_also_run_disabled_tests", 0) == 0;
    }
    std::vector<std::string> failed;
    size_t ran = 0;
    for (const std::string& t : tests) {
        if (!disabledToo && (t.find("DISABLED_") == 0 || t.find(".DISABLED_") != std::string::npos)) continue;
        std::vector<std::string> one = kept;
        one.push_back(kFilter + t);
        ++ran;
        if (run(one, nullptr) != 0) failed.push_back(t);
    }
    std::cout << "\n" << ran << " tests, each in a process of its own (SystemC elaborates once per process): "
              << ran - failed.size() << " passed, " << failed.size() << " failed\n";
    for (const std::string& t : failed) std::cout << "  FAILED " << t << "\n";
    return failed.empty() ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
    if (!inThisProcess(argc, argv)) return runEachAlone(argc, argv);
    setenv("SYSTEMC_DISABLE_COPYRIGHT_MESSAGE", "1", 0);
    using namespace sc_core;
    sc_report_handler::set_actions(SC_WARNING, SC_THROW);
    sc_report_handler::set_actions(SC_ERROR, SC_THROW);
    sc_report_handler::set_actions("/OSCI/SystemC", SC_INFO, SC_DO_NOTHING);
    testing::InitGoogleTest(&argc, argv);
    return RUN_ALL_TESTS();
}

// libsystemc's own main() refers to sc_main; ours above is the one that runs.
int sc_main(int, char**) { return 1; }
