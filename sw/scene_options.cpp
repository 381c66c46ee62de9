#include "scene_options.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <sstream>

#include "nff_reader.h"
#include "scene_error.h"
#include "utf8.h"

namespace rt {

void parseSize(const std::string& text, int& width, int& height) {
    const size_t x = text.find('x');
    auto num = [&](const char* b, const char* e, int& v) {
        auto r = std::from_chars(b, e, v);
        return r.ec == std::errc() && r.ptr == e && b != e && v > 0 && v <= 65536;
    };
    if (x == std::string::npos || !num(text.data(), text.data() + x, width) ||
        !num(text.data() + x + 1, text.data() + text.size(), height))
        throw CLI::ValidationError("--size", "expected WxH with W and H in 1..65536, got '" + text + "'");
}

CLI::Validator finiteNumber() {
    return CLI::Validator(
        [](std::string& s) {
            double v;
            std::istringstream in(s);
            if (!(in >> v) || !in.eof() || !std::isfinite(v)) return "expected a finite number, got '" + s + "'";
            if (std::abs(v) > kMaxSceneMagnitude) return "expected a number of magnitude at most 1e9, got '" + s + "'";
            return std::string();
        },
        "", "");
}

void checkTriples(const std::vector<std::string>& args, const std::vector<std::string>& flags) {
    const auto pieces = [](const std::string& t) { return size_t(std::count(t.begin(), t.end(), ',')) + 1; };
    for (size_t i = 1; i < args.size(); ++i)
        for (const std::string& flag : flags) {
            size_t n = 0;
            if (args[i].rfind(flag + "=", 0) == 0) {
                n = pieces(args[i].substr(flag.size() + 1));
            } else if (args[i] == flag) {  // its values follow, as many tokens as CLI11 takes for three
                for (size_t j = i + 1; j < args.size() && n < 3 && args[j].rfind("--", 0) != 0; ++j) n += pieces(args[j]);
            } else {
                continue;
            }
            if (n != 3) throw CLI::ValidationError(flag, "expected three numbers x y z (or x,y,z), got " + std::to_string(n));
        }
}

void checkNoEmptyValues(const std::vector<std::string>& args) {
    for (const std::string& a : args) {
        if (a.size() > 3 && a.rfind("--", 0) == 0 && a.back() == '=' && a.find('=') == a.size() - 1) {
            const std::string flag = a.substr(0, a.size() - 1);
            throw CLI::ValidationError(flag, "nothing after '=' in '" + a + "': write " + flag + " VALUE (an empty value: " + flag + " '')");
        }
    }
}

void decimalNumbersOnly(CLI::App& app) {
    const CLI::Validator decimal(
        [](std::string& s) {
            const size_t digits = s.find_first_not_of("+-") == 1 ? 1 : 0;  // (one sign at most)
            const bool ok = s.size() > digits && s.find_first_not_of("0123456789", digits) == std::string::npos &&
                            (s[digits] != '0' || s.size() == digits + 1);
            if (ok) return std::string();
            return "expected a decimal integer, got '" + s + "'" +
                   (s.size() > digits + 1 && s[digits] == '0' ? " (a leading 0 reads as C's octal or hexadecimal: write it in decimal)" : "");
        },
        "", "");
    const CLI::Validator noHex(
        [](std::string& s) {
            return s.find_first_of("xX") == std::string::npos ? std::string()
                                                               : "expected a decimal number, got '" + s + "'";
        },
        "", "");
    for (CLI::Option* o : app.get_options()) {
        const std::string type = o->get_type_name();  // ("INT", or "INT:" and its validators' descriptions)
        const std::string base = type.substr(0, type.find(':'));
        // transform, not check: these run before the option's own range
        // check, which would read "08" as a number and call it out of range.
        if (base == "INT" || base == "UINT") o->transform(decimal);
        if (base == "FLOAT") o->transform(noHex);  // (read as strtod does: 0x10 was 16)
    }
}

namespace {
// A number in the open-closed interval (lo, hi], said the way a user reads it.
CLI::Validator openClosed(double lo, double hi) {
    return CLI::Validator(
        [lo, hi](std::string& s) {
            double v;
            std::istringstream in(s);
            if (!(in >> v) || !in.eof() || !(v > lo && v <= hi)) {
                std::ostringstream m;
                m << "expected a number in (" << lo << ", " << hi << "], got '" << s << "'";
                return m.str();
            }
            return std::string();
        },
        "", "");
}
}  // namespace

void SceneOptions::addTo(CLI::App& app, bool positional) {
    auto* f = positional ? app.add_option("scene", file, "NFF scene file (default: the built-in procedural scene)")
                         : app.add_option("--scene", file, "NFF scene file (default: the built-in procedural scene)");
    f->check(CLI::ExistingFile);
    app.add_option("--size", size, "image size WxH (default: the scene's resolution)")
        ->check([](const std::string& s) {
            int w, h;
            try {
                parseSize(s, w, h);
            } catch (const CLI::ValidationError&) {
                return std::string("expected WxH with W and H in 1..65536");
            }
            return std::string();
        });
    const std::string g = "Procedural scene";
    ProceduralParams& p = procedural;
    app.add_option("--spheres", p.spheres, "procedural: number of spheres M")->group(g)->check(CLI::Range(1, 10000000));
    app.add_option("--radius", p.radius, "procedural: sphere radius r (unit cube)")->group(g)->check(openClosed(0, 0.49));
    app.add_option("--concentration", p.concentration, "procedural: fraction f of the progress axis the spheres crowd into, in (0, 1]")
        ->capture_default_str()
        ->group(g)
        ->check(openClosed(0, 1));
    app.add_option("--axis", axis, "progress axis: the procedural scene's and the balancing's")->group(g)->check(CLI::IsMember({"x", "y", "z"}));
    // (CLI11 took -1 into the unsigned seed as 2^64 - 1, and 2^64 and beyond as that too.)
    app.add_option("--seed", p.seed, "procedural: random seed for sphere placement")->group(g)->check(CLI::Validator(
        [](std::string& v) {
            if (v.rfind('-', 0) == 0) return std::string("expected a whole number, 0 or more");
            uint64_t n;
            const auto r = std::from_chars(v.data(), v.data() + v.size(), n);
            return r.ec == std::errc::result_out_of_range ? "above " + std::to_string(UINT64_MAX) + ", got '" + v + "'" : std::string();
        },
        ""));
    app.add_option("--eye", eye, "procedural: camera position x y z (or x,y,z)")
        ->group(g)
        ->expected(3)
        ->delimiter(',')
        ->check(finiteNumber());
    app.add_option("--look-at", lookAt, "procedural: point at the image centre x y z (or x,y,z)")
        ->group(g)
        ->expected(3)
        ->delimiter(',')
        ->check(finiteNumber());
    app.add_option("--light", lights, "procedural: a white point light x y z (repeat for more; replaces the defaults)")
        ->group(g)
        ->expected(3)
        ->delimiter(',')
        ->check(finiteNumber())
        ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
    app.add_option("--fov", p.angle, "procedural: field of view in degrees")->group(g)->check(openClosed(0, 179.9));
}

Scene SceneOptions::load() const {
    if (!file.empty()) {
        if (const std::string shown = notUtf8(file); !shown.empty())
            throw SceneError(shown + ": the scene file's name is not valid UTF-8 (its bad bytes shown as U+FFFD): the "
                                     "outputs' JSON keeps it and could not hold it; rename the file");
        return readNff(file);
    }
    ProceduralParams p = procedural;
    p.axis = axis == "x" ? 0 : axis == "y" ? 1 : 2;
    auto vec3 = [](const std::vector<double>& v, const char* flag, Vec3& out) {
        if (v.empty()) return;
        if (v.size() != 3) throw SceneError(std::string(flag) + ": expected three numbers x y z");
        out = Vec3(v[0], v[1], v[2]);
    };
    vec3(eye, "--eye", p.eye);
    vec3(lookAt, "--look-at", p.lookAt);
    if (lights.size() % 3 != 0) throw SceneError("--light: expected three numbers x y z per light");
    if (!lights.empty()) {
        p.lights.clear();
        for (size_t i = 0; i + 2 < lights.size(); i += 3) p.lights.push_back(Vec3(lights[i], lights[i + 1], lights[i + 2]));
    }
    return makeProceduralScene(p);
}

void SceneOptions::imageSize(const Scene& scene, int& width, int& height) const {
    width = scene.view.width;
    height = scene.view.height;
    if (!size.empty()) parseSize(size, width, height);
}

std::string SceneOptions::sizeNamed(int width, int height) const {
    const std::string wxh = std::to_string(width) + "x" + std::to_string(height);
    return size.empty() ? "the scene's resolution " + wxh + " (--size sets another)" : "--size " + wxh;
}

}  // namespace rt
