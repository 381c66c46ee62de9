#include "outputs.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "base/progress.h"
#include "subprocess.h"
#include "trace/trace_writer.h"

namespace rt {
namespace {

const std::string kMapScript = std::string(RT_SCRIPTS_DIR) + "/mesh_map.py";
const std::vector<std::string> kMapFormats = {".png", ".svg", ".pdf"};

// --map's format, from its name (checked before the run): png, svg or pdf.
std::string mapFormat(const std::string& path) { return checkExtension("--map", path, kMapFormats).substr(1); }

// nlohmann's serializer, writing through a buffer: streamed to an
// ostream it wrote a character or a token at a time, each a call through
// the stream's sentry (at 32x32x32, a 70 MB report). The same bytes.
class BufferedJsonOut final : public nlohmann::detail::output_adapter_protocol<char> {
public:
    explicit BufferedJsonOut(std::ostream& o) : o_(o) { buf_.reserve(kChunk); }
    ~BufferedJsonOut() override { flush(); }
    void write_character(char c) override {
        buf_.push_back(c);
        if (buf_.size() >= kChunk) flush();
    }
    void write_characters(const char* s, std::size_t n) override {
        buf_.append(s, n);
        if (buf_.size() >= kChunk) flush();
    }

private:
    void flush() {
        o_.write(buf_.data(), std::streamsize(buf_.size()));
        buf_.clear();
    }
    static constexpr std::size_t kChunk = 1 << 16;
    std::ostream& o_;
    std::string buf_;
};

// `entries` as nlohmann's serializer writes an array at indentation `at`
// (pretty printed: `step` more for each entry), made one at a time.
void writeEntries(BufferedJsonOut& out, nlohmann::detail::serializer<nlohmann::json>& s, const ReportEntries& entries,
                  bool pretty, unsigned step, unsigned at) {
    const std::string inner(pretty ? at + step : 0, ' ');
    out.write_characters(pretty ? "[\n" : "[", pretty ? 2 : 1);
    for (size_t i = 0; i < entries.size(); ++i) {
        out.write_characters(inner.data(), inner.size());
        s.dump(entries[i], pretty, false, step, at + step);
        if (i + 1 < entries.size()) out.write_characters(pretty ? ",\n" : ",", pretty ? 2 : 1);
    }
    if (pretty) {
        out.write_character('\n');
        out.write_characters(std::string(at, ' ').data(), at);
    }
    out.write_character(']');
}

// As `o << std::setw(indent) << j` writes it (indent < 0: on one line),
// with the entries `report` makes (if given) in their top-level arrays.
void writeJson(std::ostream& o, const nlohmann::json& j, const Report* report, int indent) {
    const bool pretty = indent >= 0, made = report && !report->made.empty() && j.is_object() && !j.empty();
    const unsigned step = unsigned(std::max(indent, 0));
    {
        auto out = std::make_shared<BufferedJsonOut>(o);
        nlohmann::detail::serializer<nlohmann::json> s(out, ' ');
        if (!made) {
            s.dump(j, pretty, false, step);
        } else {  // the top-level object as the serializer writes one
            const std::string inner(pretty ? step : 0, ' ');
            out->write_characters(pretty ? "{\n" : "{", pretty ? 2 : 1);
            for (auto it = j.begin(); it != j.end(); ++it) {
                if (it != j.begin()) out->write_characters(pretty ? ",\n" : ",", pretty ? 2 : 1);
                out->write_characters(inner.data(), inner.size());
                s.dump(nlohmann::json(it.key()), false, false, 0);
                out->write_characters(pretty ? ": " : ":", pretty ? 2 : 1);
                if (const ReportEntries* entries = report->madeAt(it.key())) writeEntries(*out, s, *entries, pretty, step, step);
                else s.dump(it.value(), pretty, false, step, step);
            }
            if (pretty) out->write_character('\n');
            out->write_character('}');
        }
    }  // (the buffer flushed)
    o << '\n';
}

}  // namespace

void writeReport(std::ostream& o, const Report& report, int indent) { writeJson(o, report.json, &report, indent); }

namespace {

// --map draws with Debian's Python and matplotlib: there before the run,
// not found missing after it.
void checkMapPython() {
    const int code = waitExit(spawn({"/usr/bin/python3", "-c", "import matplotlib"}, false, "/dev/null"));
    if (code != 0)
        throw OutputError("--map: needs /usr/bin/python3 with python3-matplotlib (scripts/setup.sh installs them)");
}

}  // namespace

void checkOutputs(const RtsimOptions& o, std::vector<NamedFile> files) {
    for (NamedFile& f : files) f.output = false;
    auto output = [&](const std::string& flag, const std::string& path, const std::vector<std::string>& formats) {
        if (path.empty()) return;
        checkWritable(flag, path);
        checkExtension(flag, path, formats);
        files.push_back({flag, path, true});
    };
    output("--image", o.image, {".png"});
    output("--report", o.report, {".json"});
    output("--map", o.map, kMapFormats);
    if (!o.vcd.empty()) {
        output("--vcd", o.vcd, {".vcd"});
        checkWritable("--vcd", gtkwPathFor(o.vcd));
        files.push_back({"--vcd's .gtkw", gtkwPathFor(o.vcd), true});
    }
    checkDistinct(files);
    if (!o.map.empty()) checkMapPython();
}

AtomicFile& RunOutputs::open(std::optional<AtomicFile>& f, const std::string& path) {
    if (!f) f.emplace(path);
    return *f;
}

std::string RunOutputs::vcdStream() { return o_.vcd.empty() ? "" : open(vcd_, o_.vcd).temp(); }

void RunOutputs::image(const Image& image) {
    if (!o_.image.empty()) writePng(image, open(image_, o_.image).temp());
}

void RunOutputs::report(const Report& report) { writeReportFile(report.json, &report); }

void RunOutputs::report(const nlohmann::json& report) { writeReportFile(report, nullptr); }

void RunOutputs::writeReportFile(const nlohmann::json& j, const Report* made) {
    // Streamed: the text of a 32x32x32 mesh's report was over 300 MB. A
    // summary (--report-detail) is for programs: without indentation, which
    // was half of its size.
    const bool indent = !o_.report.empty() && o_.fullReport();
    if (!o_.report.empty())
        open(report_, o_.report).write([&](std::ostream& f) { writeJson(f, j, made, indent ? 2 : -1); });
}

void RunOutputs::gtkw(const std::string& text) {
    if (!o_.vcd.empty() && !text.empty()) open(gtkw_, gtkwPathFor(o_.vcd)).write(text);
}

bool RunOutputs::map(const Report& report) {
    if (o_.map.empty()) return true;
    // The report's temporary, or one of its own in /tmp.
    std::optional<TempFile> own;
    if (!report_) {
        std::ostringstream text;
        writeReport(text, report, -1);
        own.emplace("rtsim-map", ".json", text.str());
    }
    const std::string from = report_ ? report_->temp() : own->path();
    const TempFile log("rtsim-map", ".log");
    // --doc: the user named this path himself (rtsim --map doc/MAP.png, as
    // scripts/mesh_map_example.sh --doc does), and checkOutputs held it to
    // rtsim's own rules; the script is given the temporary beside it.
    const int code = waitExit(spawn({"/usr/bin/python3", kMapScript, from, "-o", open(map_, o_.map).temp(), "--format",
                                     mapFormat(o_.map), "--doc"},
                                    true, log.path()));
    if (code != 0 && stopSignal) {  // (the script got the signal too: the frame's outputs are whole)
        map_.reset();
        return false;
    }
    if (code != 0) {
        std::ifstream f(log.path());
        std::string line, last;
        while (std::getline(f, line))
            if (!line.empty()) last = line;
        throw std::runtime_error("--map: scripts/mesh_map.py failed: " + (last.empty() ? "exit " + std::to_string(code) : last));
    }
    return true;
}

void RunOutputs::commit() {
    // The VCD before its .gtkw, the report last: a report on disk means the
    // outputs beside it are this run's.
    for (std::optional<AtomicFile>* f : {&vcd_, &gtkw_, &image_, &map_, &report_})
        if (*f) (*f)->commit();
}

}  // namespace rt
