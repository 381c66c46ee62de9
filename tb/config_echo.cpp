#include "config_echo.h"

#include <openssl/evp.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "analysis/report.h"
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

std::string firstDifference(const nlohmann::json& there, const nlohmann::json& here) {
    for (const nlohmann::json& op : nlohmann::json::diff(there, here)) {
        const std::string where = op["path"].get<std::string>();
        const nlohmann::json::json_pointer path(where);
        const nlohmann::json a = there.contains(path) ? there[path] : nlohmann::json();
        const nlohmann::json b = here.contains(path) ? here[path] : nlohmann::json();
        return where + ": " + a.dump() + " there, " + b.dump() + " here";
    }
    return "";
}

}  // namespace rt
