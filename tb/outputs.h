// What a run writes: the image, the report, the VCD and its .gtkw, the mesh
// picture (--map), under the output policy of sw/output_file.h. Every
// output is checked before the run (exit 2: a path that cannot be an
// output, a name whose format is not the one written, two outputs naming
// one file, an output naming an input, --map without its Python). During
// the run each goes to a temporary file beside it (the VCD is streamed
// into its own); commit() renames them all at the end. A run that fails
// (exit 1) commits nothing, and leaves nothing: the temporaries go with
// this object; a run stopped by the watchdog or a signal commits the
// report and the VCD so far (marked incomplete inside).
#pragma once
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "analysis/report.h"
#include "image.h"
#include "output_file.h"
#include "rtsim_cli.h"

namespace rt {

// Throws OutputError for the first output that cannot be written, or that
// names the same file as another output or as one of `inputs`.
void checkOutputs(const RtsimOptions& o, std::vector<NamedFile> inputs);

// `report` as `o << std::setw(indent) << whole` writes its whole tree
// (indent < 0: on one line), its links' entries made one at a time.
void writeReport(std::ostream& o, const Report& report, int indent);

class RunOutputs {
public:
    explicit RunOutputs(const RtsimOptions& o) : o_(o) {}
    // Where the machine streams the VCD: a temporary beside --vcd (empty
    // without --vcd).
    std::string vcdStream();
    void image(const Image& image);
    void report(const Report& report);
    void report(const nlohmann::json& report);  // (a sequence stopped before its last frame)
    void gtkw(const std::string& text);
    // scripts/mesh_map.py draws the report (call after report()).
    // False if a stop (Ctrl-C, SIGTERM) ended the drawing: no map, the rest
    // kept (the frame is done); a map that fails otherwise throws.
    bool map(const Report& report);
    // Renames every temporary written over its path.
    void commit();

private:
    AtomicFile& open(std::optional<AtomicFile>& f, const std::string& path);
    // `j`, with the entries `made` makes where given (writeReport).
    void writeReportFile(const nlohmann::json& j, const Report* made);
    const RtsimOptions& o_;
    std::optional<AtomicFile> image_, report_, vcd_, gtkw_, map_;
};

}  // namespace rt
