// Output files (images, reports, stats, waveforms): the output policy
// (doc/robustness.md, "Outputs").
//  - Before a run, each path is checked: absent, or a regular file (not a
//    folder, a device, a FIFO, a socket or a symbolic link, which a
//    renamed file would replace), in a folder that takes a new file; no two
//    outputs, and no output and input, name the same file; each output's
//    name says its format. A bad path is bad input (exit 2), found before
//    hours of simulation, not after.
//  - Each output is written to a temporary file beside it, named
//    NAME.incomplete-XXXXXX, and renamed over the path only when the run
//    succeeds: a run that fails, or is killed while writing, never leaves a
//    truncated file that looks like a result, and never removes a file it
//    did not create. A temporary left behind (a run killed with SIGKILL)
//    says so in its name.
#pragma once
#include <signal.h>

#include <functional>
#include <ostream>
#include <string>
#include <vector>

#include "scene_error.h"

namespace rt {

// Bad input about an output (exit 2, as a scene error is).
struct OutputError : SceneError {
    using SceneError::SceneError;
};

// Throws OutputError ("FLAG: PATH: why") unless `path` can be an output.
void checkWritable(const std::string& flag, const std::string& path);
// Throws OutputError unless `path` ends in one of `extensions` (".png";
// any case).
// Returns the one it ends in.
const std::string& checkExtension(const std::string& flag, const std::string& path,
                                  const std::vector<std::string>& extensions);

// A file a run names: an output or an input.
struct NamedFile {
    std::string flag, path;
    bool output = true;
};
// Throws OutputError if an output names the same file as another output or
// an input (by path, or by device and inode if both exist: a hard link).
void checkDistinct(const std::vector<NamedFile>& files);

class AtomicFile {
public:
    explicit AtomicFile(std::string path);
    ~AtomicFile();  // removes the temporary file unless committed
    AtomicFile(const AtomicFile&) = delete;
    AtomicFile& operator=(const AtomicFile&) = delete;

    const std::string& path() const { return path_; }
    // Where to write: a fresh file in the same folder as the path.
    const std::string& temp() const { return temp_; }
    // Writes `text` to the temporary file (throws, naming the path, if it
    // cannot); or what `fill` writes to it, without the text in memory.
    void write(const std::string& text) const;
    void write(const std::function<void(std::ostream&)>& fill) const;
    // Renames the temporary file over the path (throws on failure).
    void commit();

private:
    std::string path_, temp_;
    bool committed_ = false;
};

// The temporary files this process holds (AtomicFile's, and others it
// registers), for a signal that ends the process at once: removes them.
// Async-signal-safe (fixed slots, unlink only).
void registerTempFile(const std::string& path);
void forgetTempFile(const std::string& path);
void removeTempFilesNow();

// Holds the signals that stop a run (SIGINT, SIGTERM, SIGALRM) for its
// scope, on this thread: one that comes meanwhile is handled when the
// scope ends. A temporary file is made and registered (or made and removed)
// within one, so that a stop finds it registered or not there at all: a
// SIGTERM to a reference run in its start-up, between the file's making
// and its registering, left NAME.incomplete-XXXXXX behind (once, in a
// fresh clone's tests).
class StopsHeld {
public:
    StopsHeld();
    ~StopsHeld();
    StopsHeld(const StopsHeld&) = delete;
    StopsHeld& operator=(const StopsHeld&) = delete;
    const sigset_t& before() const { return before_; }  // the mask it restores

private:
    sigset_t before_;
};

}  // namespace rt
