#include "output_file.h"

#include <fcntl.h>
#include <pthread.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
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

// A new, empty file beside `path` (mkstemp: unique, not shared with another
// run), named to say what it is if a killed run leaves it.
std::string makeTemp(const std::string& path, int& err) {
    std::string name = (fs::path(folderOf(path)) / (fs::path(path).filename().string() + ".incomplete-XXXXXX")).string();
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

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return s;
}

// The registry of temporary files: fixed slots a signal handler may read.
constexpr int kSlots = 64;
constexpr size_t kPathBytes = 4096;
struct Slot {
    std::atomic<int> state{0};  // 0 free, 1 being filled, 2 holds a path
    char path[kPathBytes];
};
Slot slots[kSlots];

}  // namespace

void registerTempFile(const std::string& path) {
    if (path.size() >= kPathBytes) return;  // (not removed by a signal; still by its owner)
    for (Slot& s : slots) {
        int expected = 0;
        if (!s.state.compare_exchange_strong(expected, 1)) continue;
        std::memcpy(s.path, path.c_str(), path.size() + 1);
        s.state.store(2);
        return;
    }
}

void forgetTempFile(const std::string& path) {
    for (Slot& s : slots)
        if (s.state.load() == 2 && path == s.path) {
            s.state.store(0);
            return;
        }
}

void removeTempFilesNow() {
    for (Slot& s : slots)
        if (s.state.load() == 2) ::unlink(s.path);
}

void checkWritable(const std::string& flag, const std::string& path) {
    auto bad = [&](const std::string& why) { throw OutputError(flag + ": " + path + ": " + why); };
    if (path.empty()) bad("an empty name");
    struct stat st {};
    if (::lstat(path.c_str(), &st) == 0) {
        if (S_ISLNK(st.st_mode)) bad("is a symbolic link (name the file it points to: an output is renamed over its path)");
        if (S_ISDIR(st.st_mode)) bad("is a folder");
        if (!S_ISREG(st.st_mode)) bad("is not a regular file (a device, FIFO or socket); an output is a file of its own");
    } else if (errno != ENOENT) {
        bad(std::strerror(errno));
    }
    const std::string folder = folderOf(path);
    std::error_code ec;
    if (!fs::is_directory(folder, ec)) bad("no such folder: " + folder);
    int err = 0;
    std::string t;
    {
        const StopsHeld held;  // (made and removed: never left by a stop)
        t = makeTemp(path, err);
        if (!t.empty()) std::remove(t.c_str());
    }
    if (t.empty()) bad(std::string("cannot create a file there (") + std::strerror(err) + ")");
}

const std::string& checkExtension(const std::string& flag, const std::string& path,
                                  const std::vector<std::string>& extensions) {
    const std::string p = lower(path);
    std::string list;
    for (const std::string& e : extensions) {
        if (p.size() > e.size() && p.compare(p.size() - e.size(), e.size(), e) == 0) return e;
        list += (list.empty() ? "" : ", ") + e;
    }
    throw OutputError(flag + ": " + path + ": the name must end in " + list + " (the format written)");
}

void checkDistinct(const std::vector<NamedFile>& files) {
    auto same = [](const std::string& a, const std::string& b) {
        // (Absolute first: a name of a file not there yet, "c1.png", stays
        // relative in weakly_canonical, where "./c1.png" becomes absolute.)
        std::error_code ec1, ec2, ec3, ec4;
        const fs::path fa = fs::absolute(a, ec3), fb = fs::absolute(b, ec4);
        if (!ec3 && !ec4 && fs::weakly_canonical(fa, ec1) == fs::weakly_canonical(fb, ec2) && !ec1 && !ec2) return true;
        struct stat sa {}, sb {};
        return ::stat(a.c_str(), &sa) == 0 && ::stat(b.c_str(), &sb) == 0 && sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
    };
    for (size_t j = 0; j < files.size(); ++j)
        for (size_t i = 0; i < j; ++i) {
            const NamedFile &a = files[i], &b = files[j];
            if (!a.output && !b.output) continue;
            if (!same(a.path, b.path)) continue;
            const NamedFile& out = b.output ? b : a;
            const NamedFile& other = b.output ? a : b;
            throw OutputError(out.flag + ": " + out.path + ": the same file as " + (other.output ? "" : "the input ") +
                              other.flag + (other.path == out.path ? "" : " " + other.path));
        }
}

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)) {
    int err = 0;
    {
        const StopsHeld held;  // (made and registered: a stop removes it)
        temp_ = makeTemp(path_, err);
        if (!temp_.empty()) registerTempFile(temp_);
    }
    if (temp_.empty()) throw std::runtime_error(path_ + ": cannot create a file beside it (" + std::strerror(err) + ")");
}

StopsHeld::StopsHeld() {
    sigset_t stops;
    sigemptyset(&stops);
    for (int s : {SIGINT, SIGTERM, SIGALRM}) sigaddset(&stops, s);
    pthread_sigmask(SIG_BLOCK, &stops, &before_);
}

StopsHeld::~StopsHeld() { pthread_sigmask(SIG_SETMASK, &before_, nullptr); }

void AtomicFile::write(const std::string& text) const {
    write([&](std::ostream& o) { o << text; });
}

void AtomicFile::write(const std::function<void(std::ostream&)>& fill) const {
    std::ofstream f(temp_, std::ios::binary);
    fill(f);
    f.close();
    if (!f) throw std::runtime_error(path_ + ": cannot write");
}

AtomicFile::~AtomicFile() {
    if (committed_) return;
    std::remove(temp_.c_str());  // (then forgotten: a stop between finds nothing to remove)
    forgetTempFile(temp_);
}

void AtomicFile::commit() {
    // mkstemp makes the file 0600; an output gets what a plain fopen would give.
    const mode_t mask = ::umask(0);
    ::umask(mask);
    ::chmod(temp_.c_str(), 0666 & ~mask);
    if (std::rename(temp_.c_str(), path_.c_str()) != 0)
        throw std::runtime_error(path_ + ": cannot write (" + std::strerror(errno) + ")");
    forgetTempFile(temp_);
    committed_ = true;
}

}  // namespace rt
