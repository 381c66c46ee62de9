#include "config_echo.h"

#include <openssl/evp.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <stdexcept>

#include "analysis/report.h"
#include "config/param_rows.h"
#include "fidelity_choice.h"

namespace rt {

std::string sha256OfFile(const std::string& path) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) throw std::runtime_error(path + ": not a regular file");  // (/dev/zero never ends)
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

namespace {

nlohmann::json vec(const Vec3& v) { return nlohmann::json{v.x, v.y, v.z}; }
std::string absolutePath(const std::string& p) { return std::filesystem::absolute(p).lexically_normal().string(); }

}  // namespace

nlohmann::json sceneEcho(const RtsimOptions& o, const Scene& scene) {
    nlohmann::json s;
    s["objects"] = scene.objects.size();
    if (!o.scene.file.empty()) {
        s["file"] = absolutePath(o.scene.file);
        s["sha256"] = sha256OfFile(o.scene.file);
    } else {
        const ProceduralParams& p = o.scene.procedural;
        s["procedural"] = {{"spheres", p.spheres}, {"radius", p.radius}, {"concentration", p.concentration},
                           {"seed", p.seed}};
    }
    s["axis"] = o.scene.axis;
    return s;
}

nlohmann::json configEcho(const RtsimOptions& o, const Scene& scene) {
    nlohmann::json c = machineConfigJson(o.machine, o.machine.width, o.machine.height);
    c["fidelity"]["rung"] = rungOf(o.machine);  // (with --quantum too: fidelity_choice.h)
    if (o.maxError > 0) c["fidelity"]["max_error"] = o.maxError;
    c["scene"] = sceneEcho(o, scene);
    c["camera"] = {{"eye", vec(scene.view.from)}, {"look_at", vec(scene.view.at)}, {"up", vec(scene.view.up)},
                   {"fov_deg", scene.view.angle}};
    for (const Light& l : scene.lights) c["lights"].push_back({{"position", vec(l.position)}, {"colour", vec(l.colour)}});
    c["frames"] = {{"count", o.frames}, {"index", o.frameIndex}, {"eye_step", o.eyeStep}};
    if (!o.boundariesFrom.empty()) c["frames"]["boundaries_from"] = absolutePath(o.boundariesFrom);
    return c;
}

namespace {

// The path of the first setting where two configs differ, if any ("": the
// whole of them).
std::optional<std::string> firstDifferingPath(const nlohmann::json& there, const nlohmann::json& here) {
    for (const nlohmann::json& op : nlohmann::json::diff(there, here)) return op["path"].get<std::string>();
    return std::nullopt;
}

}  // namespace

std::string firstDifference(const nlohmann::json& there, const nlohmann::json& here) {
    const std::optional<std::string> differs = firstDifferingPath(there, here);
    if (!differs) return "";
    const std::string where = differs->empty() ? "/" : *differs;
    const nlohmann::json::json_pointer path(*differs);
    const std::string a = there.contains(path) ? there[path].dump() + " there" : "not in the report";
    const std::string b = here.contains(path) ? here[path].dump() + " here" : "not a setting of this run";
    return where + ": " + a + ", " + b;
}

std::string newerSettingHint(const nlohmann::json& there, const nlohmann::json& here, const std::string& report) {
    const std::optional<std::string> differs = firstDifferingPath(there, here);
    if (!differs || differs->empty()) return "";
    const std::string& where = *differs;
    const nlohmann::json::json_pointer path(where);
    if (!here.contains(path)) return "";
    // Not in the report: a setting newer than its build, this build's value
    // named. In it with another value: a default changed, the report's named.
    const bool newer = !there.contains(path);
    const nlohmann::json& value = newer ? here[path] : there[path];
    if (!newer && value.is_structured()) return "";
    std::string flag;
    forEachParamRow([&](const auto& p, const std::string& name, const std::string& echo) {
        if (!flag.empty() || echo != where) return;
        flag = name + " " + (value.is_string() ? value.get<std::string>() : value.dump());
        if (p.kind == ParamKind::Time && value.is_number()) flag += "ns";  // (echoed in ns)
        if (p.kind == ParamKind::Rate && value.is_number()) flag += "B/s";
    });
    if (flag.empty()) return "";
    const std::string whatIf = " (--rerun " + report + " " + flag + "), which makes the rerun a what-if, not checked against the report";
    if (newer) return "; a setting newer than the report's build: to rerun it as this build does, give it after the report" + whatIf;
    return "; the report's build ran it otherwise (a default changed since, or the report was edited): to rerun it as "
           "it ran, give the report's value after it" + whatIf;
}

}  // namespace rt
