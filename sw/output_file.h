// Output files (images, reports, stats, waveforms) written whole or not at
// all. Before a run, each path is checked: it must not be a folder, and its
// folder must exist and take a new file (a bad path is bad input: exit 2,
// before hours of simulation, not after). At the end, each file is written
// to a temporary file beside it and renamed over the path, so a failure
// half way, or a run killed while writing, never leaves a truncated file
// that looks like a result.
#pragma once
#include <string>

#include "scene_error.h"

namespace rt {

// Bad input about an output (exit 2, as a scene error is).
struct OutputError : SceneError {
    using SceneError::SceneError;
};

// Throws OutputError ("FLAG: PATH: why") unless `path` can be written.
void checkWritable(const std::string& flag, const std::string& path);

class AtomicFile {
public:
    explicit AtomicFile(std::string path);
    ~AtomicFile();  // removes the temporary file unless committed
    AtomicFile(const AtomicFile&) = delete;
    AtomicFile& operator=(const AtomicFile&) = delete;

    // Where to write: a fresh file in the same folder as the path.
    const std::string& temp() const { return temp_; }
    // Writes `text` to the temporary file (throws, naming the path, if it
    // cannot).
    void write(const std::string& text) const;
    // Renames the temporary file over the path (throws on failure).
    void commit();

private:
    std::string path_, temp_;
    bool committed_ = false;
};

}  // namespace rt
