#include "rerun.h"

#include "subprocess.h"

#include <openssl/evp.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace rt {
namespace {

// Not part of what a run computes: where it writes, and the flags the
// parent process gives its reference runs.
bool isOutput(const std::string& name) {
    for (const char* o : {"image", "report", "vcd", "quiet", "verbose", "map", "config", "rerun", "as-frame", "as-baseline",
                          "as-comparison", "frame-index", "targets-from"})
        if (name == o) return true;
    return false;
}

bool takesNoValue(const std::string& arg) {
    return arg == "-q" || arg == "--quiet" || arg == "--verbose" || (arg.size() >= 2 && arg[0] == '-' && arg[1] == 'v' &&
                                                                     arg.find_first_not_of('v', 1) == std::string::npos);
}

}  // namespace

std::string flagsGiven(const CLI::App& app) {
    std::istringstream all(app.config_to_str(false, false));
    std::string line, out;
    while (std::getline(all, line)) {
        const size_t eq = line.find('=');
        if (eq == std::string::npos) continue;
        const std::string name = line.substr(0, eq);
        if (isOutput(name)) continue;
        if (name == "scene" || name == "boundaries-from") {  // files: by absolute path
            const std::string path = app.get_option("--" + name)->as<std::string>();
            line = name + "=" + nlohmann::json(std::filesystem::absolute(path).lexically_normal().string()).dump();
        }
        out += line + "\n";
    }
    return out;
}

std::string sha256OfFile(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    if (!f) throw std::runtime_error(path + ": cannot read");
    EVP_MD_CTX* ctx = EVP_MD_CTX_new();
    EVP_DigestInit_ex(ctx, EVP_sha256(), nullptr);
    char buf[1 << 16];
    while (f.read(buf, sizeof buf) || f.gcount() > 0) EVP_DigestUpdate(ctx, buf, size_t(f.gcount()));
    unsigned char md[EVP_MAX_MD_SIZE];
    unsigned int n = 0;
    EVP_DigestFinal_ex(ctx, md, &n);
    EVP_MD_CTX_free(ctx);
    std::string hex;
    char h[3];
    for (unsigned int i = 0; i < n; ++i) {
        std::snprintf(h, sizeof h, "%02x", md[i]);
        hex += h;
    }
    return hex;
}

Rerun::Rerun(Rerun&& o) noexcept
    : report(std::move(o.report)), configPath(std::move(o.configPath)), args(std::move(o.args)), overrides(o.overrides) {
    o.configPath.clear();
}

Rerun& Rerun::operator=(Rerun&& o) noexcept {
    if (this != &o) {
        if (!configPath.empty()) std::remove(configPath.c_str());
        report = std::move(o.report);
        configPath = std::move(o.configPath);
        args = std::move(o.args);
        overrides = o.overrides;
        o.configPath.clear();
    }
    return *this;
}

Rerun::~Rerun() {
    if (!configPath.empty()) std::remove(configPath.c_str());
}

std::optional<Rerun> prepareRerun(int argc, char** argv) {
    std::string path;
    std::vector<std::string> rest;
    bool config = false;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--rerun" || a.rfind("--rerun=", 0) == 0) {
            if (a == "--rerun" && i + 1 >= argc) throw std::invalid_argument("--rerun: expected a report (REPORT.json)");
            path = a == "--rerun" ? argv[++i] : a.substr(8);
            continue;
        }
        if (a == "--config" || a.rfind("--config=", 0) == 0) config = true;
        rest.push_back(a);
    }
    if (path.empty()) return std::nullopt;
    if (config) throw std::invalid_argument("--rerun: cannot be combined with --config (give the flags to change instead)");
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) throw std::invalid_argument("--rerun: not a regular file: '" + path + "'");
    if (std::filesystem::file_size(path, ec) > (uintmax_t(1) << 30))
        throw std::invalid_argument("--rerun: '" + path + "' is larger than 1 GB");
    Rerun r;
    try {
        std::ifstream f(path);
        r.report = nlohmann::json::parse(f);
    } catch (const std::exception&) {
        throw std::invalid_argument("--rerun: " + path + ": not a JSON report");
    }
    if (!r.report.is_object() || !r.report.contains("rerun") || !r.report["rerun"].contains("flags") ||
        !r.report["rerun"]["flags"].is_string())
        throw std::invalid_argument("--rerun: " + path + ": no rerun.flags (not an rtsim report, or one from before they were recorded)");
    // The scene file must be the one the report's run read.
    const nlohmann::json& scene = r.report["config"]["scene"];
    if (scene.contains("file")) {
        const std::string file = scene["file"].get<std::string>();
        std::string now;
        try {
            now = sha256OfFile(file);
        } catch (const std::exception& e) {
            throw std::invalid_argument("--rerun: the report's scene " + std::string(e.what()));
        }
        if (now != scene["sha256"].get<std::string>())
            throw std::invalid_argument("--rerun: the scene " + file + " has changed since " + path + " was written (sha256 " +
                                        now.substr(0, 12) + "..., was " + scene["sha256"].get<std::string>().substr(0, 12) + "...)");
    }
    r.configPath = makeTempFile("rtsim-rerun", r.report["rerun"]["flags"].get<std::string>());
    r.args = {"--config", r.configPath};
    for (size_t i = 0; i < rest.size(); ++i) {
        r.args.push_back(rest[i]);
        std::string name = rest[i].rfind("--", 0) == 0 ? rest[i].substr(2) : "";
        name = name.substr(0, name.find('='));
        if (takesNoValue(rest[i])) continue;
        if (isOutput(name)) {
            if (rest[i].find('=') == std::string::npos && i + 1 < rest.size()) r.args.push_back(rest[++i]);  // its value
            continue;
        }
        if (rest[i].rfind("-", 0) == 0) r.overrides = true;
    }
    return r;
}

}  // namespace rt
