#include "nff_reader.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cstdio>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include <glm/geometric.hpp>

namespace rt {
namespace {

std::string shortNumber(double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%g", v);
    return b;
}

// A token as an error message quotes it: bytes outside printable ASCII as
// \xNN (a binary file's bytes, a NUL, would garble or cut the line), and
// at most 40 of them (a file with no space is one token).
std::string shown(const std::string& token) {
    std::string out;
    for (size_t i = 0; i < token.size() && i < 40; ++i) {
        const unsigned char c = static_cast<unsigned char>(token[i]);
        if (c >= 0x20 && c < 0x7f) {
            out += char(c);
        } else {
            char b[5];
            std::snprintf(b, sizeof b, "\\x%02x", c);
            out += b;
        }
    }
    if (token.size() > 40) out += "...";
    return out;
}

struct Token {
    std::string text;
    int line;
};

std::vector<Token> tokenize(const std::string& text) {
    std::vector<Token> out;
    int line = 1;
    size_t i = 0;
    while (i < text.size()) {
        const char c = text[i];
        if (c == '\n') {
            ++line;
            ++i;
        } else if (c == '#') {
            while (i < text.size() && text[i] != '\n') ++i;
        } else if (std::isspace(static_cast<unsigned char>(c))) {
            ++i;
        } else {
            size_t j = i;
            while (j < text.size() && !std::isspace(static_cast<unsigned char>(text[j])) && text[j] != '#') ++j;
            out.push_back({text.substr(i, j - i), line});
            i = j;
        }
    }
    return out;
}

class Parser {
public:
    Parser(const std::string& text, std::string name) : toks_(tokenize(text)), name_(std::move(name)) {}

    Scene parse() {
        Scene s;
        s.name = name_;
        while (pos_ < toks_.size()) {
            const Token& kw = toks_[pos_++];
            line_ = kw.line;
            if (!viewKeyword(s.view, kw) && !sceneKeyword(s, kw)) fail("unknown keyword '" + shown(kw.text) + "'");
        }
        checkView(s.view);
        if (s.materials.empty()) s.materials.push_back(Material{});
        return s;
    }

private:
    // The 'v' block: which of from at up angle hither resolution were given.
    std::array<int, 6> viewSeen_{};  // the line each of from, at, up, angle, hither, resolution was on (0: none)
    int viewLine_ = 0;

    bool viewKeyword(View& v, const Token& kw) {
        const std::string& k = kw.text;
        if (k == "v") {
            viewLine_ = kw.line;
        } else if (k == "from") {
            v.from = vec("'from' eye position");
            viewSeen_[0] = kw.line;
        } else if (k == "at") {
            v.at = vec("'at' look-at point");
            viewSeen_[1] = kw.line;
        } else if (k == "up") {
            v.up = vec("'up' vector");
            viewSeen_[2] = kw.line;
        } else if (k == "angle") {
            v.angle = number("'angle' in degrees");
            if (!(v.angle > 0 && v.angle < 180)) fail("'angle' must be in (0, 180) degrees");
            viewSeen_[3] = kw.line;
        } else if (k == "hither") {
            v.hither = number("'hither' distance");
            if (v.hither < 0) fail("'hither' must not be negative");
            viewSeen_[4] = kw.line;
        } else if (k == "resolution") {
            v.width = integer("'resolution' width");
            v.height = integer("'resolution' height");
            if (v.width <= 0 || v.height <= 0) fail("'resolution' must be positive");
            if (v.width > 65536 || v.height > 65536) fail("'resolution' must be at most 65536");
            viewSeen_[5] = kw.line;
        } else {
            return false;
        }
        return true;
    }

    bool sceneKeyword(Scene& s, const Token& kw) {
        const std::string& k = kw.text;
        if (k == "b") {
            s.background = colour("background colour 'b r g b'");
        } else if (k == "l") {
            Light l;
            l.position = vec("light position 'l x y z'");
            if (nextIsNumberOnLine(kw.line)) l.colour = colour("light colour 'l x y z r g b'");
            s.lights.push_back(l);
        } else if (k == "f") {
            s.materials.push_back(material());
        } else if (k == "s") {
            add(s, sphere());
        } else if (k == "p" || k == "pp") {
            add(s, polygon(kw));
        } else if (k == "c") {
            add(s, cone(kw.line));
        } else {
            return false;
        }
        return true;
    }

    void checkView(const View& v) {
        static const char* names[6] = {"from", "at", "up", "angle", "hither", "resolution"};
        line_ = toks_.empty() ? 1 : toks_.back().line;
        if (!viewLine_) fail("no viewpoint: the 'v' block is missing");
        for (int i = 0; i < 6; ++i)
            if (!viewSeen_[i]) fail(std::string("viewpoint block lacks '") + names[i] + "'");
        // (Each named at the line that made it so: the later of 'from' and 'at', and 'up'.)
        const ViewFault f = viewFault(v.from, v.at, v.up);
        line_ = f == ViewFault::EyeAtTarget ? std::max(viewSeen_[0], viewSeen_[1]) : viewSeen_[2];
        if (f == ViewFault::EyeAtTarget) fail("'from' and 'at' are the same point");
        if (f == ViewFault::ZeroUp) fail("'up' vector has zero length");
        if (f == ViewFault::UpAlongView) fail("'up' is parallel to the viewing direction");
    }

    // A colour: three numbers, none below 0 (a negative one took light away:
    // 'f -1 -1 -1' rendered black, its highlights gone).
    Vec3 colour(const std::string& what) {
        const Vec3 c = vec(what);
        if (c.x < 0 || c.y < 0 || c.z < 0) fail(what + " must not be below 0");
        return c;
    }

    Material material() {
        Material m;
        m.colour = colour("material colour 'f r g b'");
        m.kd = number("Kd of 'f'");
        m.ks = number("Ks of 'f'");
        m.shine = number("Shine of 'f'");
        // (Negative, Kd and Ks take light away, and Shine raises a cosine
        // below one to a negative power: inf, NaN against a light's zero channel.)
        if (m.kd < 0) fail("diffuse Kd of 'f' must be at least 0");
        if (m.ks < 0) fail("specular Ks of 'f' must be at least 0");
        if (m.shine < 0) fail("Phong exponent Shine of 'f' must be at least 0");
        m.t = number("T of 'f'");
        const double ior = number("index of refraction of 'f'");
        if (m.t < 0 || m.t > 1) fail("transmittance T of 'f' must be in [0, 1]");
        if (m.t > 0) {
            if (!(ior > 0)) fail("index of refraction of 'f' must be positive when T > 0");
            m.ior = ior;
        }
        return m;
    }

    Sphere sphere() {
        Sphere sp;
        sp.centre = vec("sphere centre 's x y z r'");
        const double r = number("sphere radius");
        if (r == 0) fail("sphere radius must not be zero");
        // Below 1e-12 of its centre's distance from the origin a sphere has
        // no extent in doubles there: the world box's planes collapse.
        const double far = std::max({std::abs(sp.centre.x), std::abs(sp.centre.y), std::abs(sp.centre.z)});
        if (std::abs(r) < 1e-12 * far)
            fail("sphere radius " + shortNumber(std::abs(r)) + " is too small for a centre that far from the origin (" +
                 shortNumber(far) + "): at least 1e-12 of it, or the sphere has no extent in doubles");
        sp.radius = std::abs(r);
        sp.insideVisible = r < 0;
        return sp;
    }

    Polygon polygon(const Token& kw) {
        const std::string& k = kw.text;
        const bool normals = k == "pp";
        const int count = integer("vertex count of '" + k + "'");
        if (count < 3) fail("polygon needs at least 3 vertices, got " + std::to_string(count));
        Polygon poly;
        for (int i = 0; i < count; ++i) {
            poly.vertices.push_back(vec("vertex " + std::to_string(i + 1) + " of '" + k + "'"));
            if (normals) {
                const Vec3 vn = vec("normal " + std::to_string(i + 1) + " of 'pp'");
                if (glm::length(vn) == 0) fail("zero-length vertex normal in 'pp'");
            }
        }
        line_ = kw.line;
        if (!poly.finish()) fail("polygon vertices are collinear (no plane)");
        return poly;
    }

    Cone cone(int line) {
        Cone c;
        c.base = vec("cone base centre 'c bx by bz br ax ay az ar'");
        const double rb = number("cone base radius");
        c.apex = vec("cone apex centre");
        const double ra = number("cone apex radius");
        if ((rb > 0 && ra < 0) || (rb < 0 && ra > 0)) fail("cone radii must not have opposite signs");
        c.baseRadius = std::abs(rb);
        c.apexRadius = std::abs(ra);
        c.insideVisible = rb < 0 || ra < 0;
        line_ = line;
        if (!c.finish()) fail("degenerate cone: base and apex coincide or both radii are zero");
        return c;
    }

    template <class G>
    void add(Scene& s, G geometry) {
        if (s.materials.empty()) s.materials.push_back(Material{});  // objects before any 'f': white, diffuse
        Shape sh;
        sh.geometry = std::move(geometry);
        sh.material = uint32_t(s.materials.size() - 1);
        sh.id = uint32_t(s.objects.size());
        sh.twoSided = s.materials[sh.material].t > 0;
        s.objects.push_back(std::move(sh));
    }

    [[noreturn]] void fail(const std::string& what) const {
        throw SceneError(name_ + ":" + std::to_string(line_) + ": " + what);
    }

    const Token& next(const std::string& what) {
        if (pos_ >= toks_.size()) fail("expected " + what + ", got end of file");
        const Token& t = toks_[pos_++];
        line_ = t.line;
        return t;
    }

    static bool parseDouble(const std::string& s, double& v) {
        const char* begin = s.data();
        const char* end = begin + s.size();
        if (begin != end && *begin == '+') ++begin;  // from_chars takes no leading '+'
        auto res = std::from_chars(begin, end, v);
        return res.ec == std::errc() && res.ptr == end;
    }

    double number(const std::string& what) {
        const Token& t = next(what);
        double v;
        if (!parseDouble(t.text, v)) fail("expected a number for " + what + ", got '" + shown(t.text) + "'");
        if (!std::isfinite(v)) fail("expected a finite number for " + what + ", got '" + shown(t.text) + "'");
        if (std::abs(v) > kMaxSceneMagnitude)  // (scene_error.h)
            fail("expected a number of magnitude at most 1e9 for " + what + ", got '" + shown(t.text) + "'");
        return v;
    }

    int integer(const std::string& what) {
        const Token& t = next(what);
        int v;
        const char* end = t.text.data() + t.text.size();
        auto res = std::from_chars(t.text.data(), end, v);
        if (res.ec != std::errc() || res.ptr != end) fail("expected an integer for " + what + ", got '" + shown(t.text) + "'");
        return v;
    }

    Vec3 vec(const std::string& what) {
        Vec3 v;
        for (int i = 0; i < 3; ++i) v[i] = number(what);
        return v;
    }

    bool nextIsNumberOnLine(int line) const {
        if (pos_ >= toks_.size() || toks_[pos_].line != line) return false;
        double v;
        return parseDouble(toks_[pos_].text, v);
    }

    std::vector<Token> toks_;
    std::string name_;
    size_t pos_ = 0;
    int line_ = 1;
};

}  // namespace

Scene parseNff(const std::string& text, const std::string& name) { return Parser(text, name).parse(); }

Scene readNff(const std::string& path) {
    std::error_code ec;
    const std::filesystem::file_status st = std::filesystem::status(path, ec);
    if (!std::filesystem::exists(st)) throw SceneError(path + ": no such scene file");
    if (std::filesystem::is_directory(st)) throw SceneError(path + ": a folder, not a scene file");
    if (!std::filesystem::is_regular_file(st))  // (a FIFO or a device would block or never end)
        throw SceneError(path + ": not a regular file (a FIFO, device or socket): a scene is a file");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw SceneError(path + ": cannot open scene file");
    std::ostringstream ss;
    ss << in.rdbuf();
    return parseNff(ss.str(), path);
}

}  // namespace rt
