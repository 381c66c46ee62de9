#include "outputs.h"

#include <cstdio>
#include <optional>
#include <stdexcept>

#include "output_file.h"
#include "subprocess.h"
#include "trace_writer.h"

namespace rt {
namespace {

// --map: scripts/mesh_map.py draws the run's report (written to a
// temporary file if the run writes none).
void drawMap(const std::string& reportText, const std::string& reportPath, const std::string& out) {
    const std::string path = reportPath.empty() ? makeTempFile("rtsim-map", reportText) : reportPath;
    const int code = waitExit(spawn({"/usr/bin/python3", std::string(RT_SCRIPTS_DIR) + "/mesh_map.py", path, "-o", out}, true));
    if (reportPath.empty()) std::remove(path.c_str());
    if (code != 0)
        throw std::runtime_error("--map: scripts/mesh_map.py failed (it needs /usr/bin/python3 and python3-matplotlib: "
                                 "scripts/setup.sh)");
}

}  // namespace

void checkOutputs(const RtsimOptions& o) {
    if (!o.image.empty()) checkWritable("--image", o.image);
    if (!o.report.empty()) checkWritable("--report", o.report);
    if (!o.map.empty()) checkWritable("--map", o.map);
    if (!o.vcd.empty()) {
        checkWritable("--vcd", o.vcd);
        checkWritable("--vcd", gtkwPathFor(o.vcd));
    }
}

void writeReport(const std::string& path, const nlohmann::json& report) {
    if (path.empty()) return;
    AtomicFile f(path);
    f.write(report.dump(2) + "\n");
    f.commit();
}

void writeOutputs(const RtsimOptions& o, const Image& image, const nlohmann::json& report) {
    std::optional<AtomicFile> imageFile, reportFile;
    if (!o.image.empty()) {
        imageFile.emplace(o.image);
        writePng(image, imageFile->temp());
    }
    if (!o.report.empty()) {
        reportFile.emplace(o.report);
        reportFile->write(report.dump(2) + "\n");
    }
    if (imageFile) imageFile->commit();
    if (reportFile) reportFile->commit();
    if (!o.map.empty()) drawMap(o.report.empty() ? report.dump() : std::string(), o.report, o.map);
}

void removeFailedTrace(const std::string& vcd) {
    if (vcd.empty()) return;
    std::remove(vcd.c_str());
    std::remove(gtkwPathFor(vcd).c_str());
}

}  // namespace rt
