// A fixture for tests that run one of the programs as a user would: a fresh
// temporary folder per test, the exit code and both output streams.
#pragma once
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

namespace rt::test {

namespace fs = std::filesystem;

struct Outcome {
    int code;
    std::string out, err;
};

// Standard error without AddressSanitizer's warning about exceptions thrown
// on SystemC's hand-switched thread stacks ("==N==WARNING: ASan is ignoring
// requested __asan_handle_no_return", and its two lines of advice), which a
// sanitizer build (scripts/sanitize.sh) prints before rtsim's own error.
inline std::string withoutSanitizerNoise(const std::string& err) {
    std::istringstream in(err);
    std::string line, out;
    while (std::getline(in, line))
        if (line.rfind("==", 0) != 0 && line != "False positive error reports may follow" &&
            line.rfind("For details see https://github.com/google/sanitizers/issues/189", 0) != 0)
            out += line + "\n";
    return out;
}

inline std::string slurp(const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    std::ostringstream s;
    s << f.rdbuf();
    return s.str();
}

class CommandTest : public testing::Test {
protected:
    explicit CommandTest(std::string exe) : exe_(std::move(exe)) {}
    void SetUp() override {
        // A parameterised test's name is "Name/3": flattened, so that TearDown's
        // remove_all takes the whole folder and leaves no empty parent behind.
        std::string name = testing::UnitTest::GetInstance()->current_test_info()->name();
        std::replace(name.begin(), name.end(), '/', '_');
        dir_ = fs::temp_directory_path() / ("rt_test_" + std::to_string(::getpid()) + "_" + name);
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }

    // The program with `args`, in the folder `cwd` if given.
    Outcome run(const std::string& args, const fs::path& cwd = {}) {
        const fs::path out = dir_ / "stdout", err = dir_ / "stderr";
        const std::string cd = cwd.empty() ? "" : "cd '" + cwd.string() + "' && ";
        const std::string cmd = cd + exe_ + " " + args + " >" + out.string() + " 2>" + err.string();
        const int status = std::system(cmd.c_str());
        return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(out), withoutSanitizerNoise(slurp(err))};
    }
    // Bad input: exit code 2 and one line on stderr that mentions `mention`.
    void expectBad(const std::string& args, const std::string& mention) {
        SCOPED_TRACE(args);
        const Outcome o = run(args);
        EXPECT_EQ(o.code, 2);
        EXPECT_EQ(std::count(o.err.begin(), o.err.end(), '\n'), 1) << o.err;
        EXPECT_NE(o.err.find(mention), std::string::npos) << o.err;
    }
    std::string scene(const std::string& n) const { return std::string(RT_SCENE_DIR) + "/" + n + ".nff"; }

    fs::path dir_;

private:
    std::string exe_;
};

}  // namespace rt::test
