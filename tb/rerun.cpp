#include "rerun.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "config_echo.h"
#include "config_file.h"
#include "json_input.h"

namespace rt {
namespace {

using json = nlohmann::json;

std::string absolutePath(const std::string& p) { return std::filesystem::absolute(p).lexically_normal().string(); }

}  // namespace

std::string flagsGiven(const CLI::App& app) {
    // In the order CLI11's config_to_str writes them (group by group, the
    // unnamed group first), which reports have always used.
    std::vector<std::string> groups = app.get_groups();
    groups.insert(groups.begin(), "Options");
    std::string out;
    bool unnamedDone = false;
    for (const std::string& group : groups) {
        const bool unnamed = group == "Options" || group.empty();
        if (unnamed && unnamedDone) continue;
        unnamedDone = unnamedDone || unnamed;
        for (const CLI::Option* opt : app.get_options({})) {
            if (!opt->get_configurable() || !(opt->get_group() == group || (unnamed && opt->get_group().empty()))) continue;
            const std::string name = opt->get_single_name();
            std::vector<std::string> values = opt->reduced_results();
            if (values.empty() || isOutputOrInternal(name)) continue;
            if (name == "scene" || name == "boundaries-from") values = {absolutePath(values.front())};  // files: by absolute path
            out += configLine(name, values) + "\n";
        }
    }
    return out;
}

Rerun readRerun(const std::string& path) {
    json report;
    try {
        report = readJsonFile(path, kMaxReportBytes);
    } catch (const JsonInputError& e) {
        throw JsonInputError("--rerun " + std::string(e.what()));
    }
    return rerunOf(std::move(report), path);
}

Rerun rerunOf(json report, const std::string& path) {
    const std::string origin = "--rerun " + path;
    using T = json::value_t;
    if (!report.is_object()) throw JsonInputError(origin + ": not an rtsim report (not a JSON object)");
    if (!hasJsonField(report, "rerun.flags"))
        throw JsonInputError(origin + ": rerun.flags: missing (not an rtsim report, or one from before they were recorded)");
    jsonField(report, "rerun.flags", T::string, origin);
    if (hasJsonField(report, "rerun.version")) jsonField(report, "rerun.version", T::string, origin);
    const json& scene = jsonField(report, "config.scene", T::object, origin);
    if (scene.contains("file")) {
        jsonField(report, "config.scene.file", T::string, origin);
        const std::string sha = jsonField(report, "config.scene.sha256", T::string, origin).get<std::string>();
        if (sha.size() != 64 || sha.find_first_not_of("0123456789abcdef") != std::string::npos)
            throw JsonInputError(origin + ": config.scene.sha256: not a SHA-256 in hex");
    }
    Rerun r;
    r.path = path;
    r.rerun = {{"flags", report["rerun"]["flags"]}, {"version", report["rerun"].value("version", "an unknown build")}};
    r.config = std::move(report["config"]);
    return r;
}

bool isSceneFlag(const std::string& name) {
    for (const char* s : {"scene", "spheres", "radius", "concentration", "seed", "axis"})
        if (name == s) return true;
    return false;
}

void checkRerunSceneFile(const Rerun& r, const SceneOptions& scene) {
    const json& recorded = r.config["scene"];
    const std::string origin = "--rerun " + r.path + ": ";
    if (scene.file.empty()) {
        if (recorded.contains("file")) throw std::invalid_argument(origin + "its flags name no scene file, config.scene names one");
        return;
    }
    if (!recorded.contains("file"))
        throw std::invalid_argument(origin + "its flags name the scene " + scene.file + ", config.scene names none");
    const std::string file = recorded["file"].get<std::string>(), sha = recorded["sha256"].get<std::string>();
    if (absolutePath(scene.file) != file)
        throw std::invalid_argument(origin + "its flags name the scene " + scene.file + ", config.scene " + file);
    std::string now;
    try {
        now = sha256OfFile(scene.file);
    } catch (const std::exception& e) {
        throw std::invalid_argument(origin + "the report's scene " + e.what());
    }
    if (now != sha)
        throw std::invalid_argument(origin + "the scene " + file + " has changed since the report was written (sha256 " +
                                    now.substr(0, 12) + "..., was " + sha.substr(0, 12) + "...)");
}

std::string rerunSceneDifference(const Rerun& r, const json& config) {
    json there = json::object(), here = json::object();
    there["scene"] = r.config["scene"];
    here["scene"] = config["scene"];
    return firstDifference(there, here);
}

}  // namespace rt
