#include "output_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <vector>

namespace rt {

namespace fs = std::filesystem;

namespace {

std::string folderOf(const std::string& path) {
    const fs::path parent = fs::path(path).parent_path();
    return parent.empty() ? "." : parent.string();
}

// A new, empty file beside `path` (mkstemp: unique, not shared with another run).
std::string makeTemp(const std::string& path, int& err) {
    std::string name = (fs::path(folderOf(path)) / ("." + fs::path(path).filename().string() + ".tmp-XXXXXX")).string();
    std::vector<char> buf(name.begin(), name.end());
    buf.push_back('\0');
    const int fd = ::mkstemp(buf.data());
    if (fd < 0) {
        err = errno;
        return "";
    }
    ::close(fd);
    return std::string(buf.data());
}

}  // namespace

void checkWritable(const std::string& flag, const std::string& path) {
    auto bad = [&](const std::string& why) { throw OutputError(flag + ": " + path + ": " + why); };
    std::error_code ec;
    if (fs::is_directory(path, ec)) bad("is a folder");
    const std::string folder = folderOf(path);
    if (!fs::is_directory(folder, ec)) bad("no such folder: " + folder);
    int err = 0;
    const std::string t = makeTemp(path, err);
    if (t.empty()) bad(std::string("cannot create a file there (") + std::strerror(err) + ")");
    std::remove(t.c_str());
}

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)) {
    int err = 0;
    temp_ = makeTemp(path_, err);
    if (temp_.empty()) throw std::runtime_error(path_ + ": cannot create a file beside it (" + std::strerror(err) + ")");
}

void AtomicFile::write(const std::string& text) const {
    std::ofstream f(temp_, std::ios::binary);
    f << text;
    f.close();
    if (!f) throw std::runtime_error(path_ + ": cannot write");
}

AtomicFile::~AtomicFile() {
    if (!committed_) std::remove(temp_.c_str());
}

void AtomicFile::commit() {
    // mkstemp makes the file 0600; an output gets what a plain fopen would give.
    const mode_t mask = ::umask(0);
    ::umask(mask);
    ::chmod(temp_.c_str(), 0666 & ~mask);
    if (std::rename(temp_.c_str(), path_.c_str()) != 0)
        throw std::runtime_error(path_ + ": cannot write (" + std::strerror(errno) + ")");
    committed_ = true;
}

}  // namespace rt
