#include "option_parsers.h"

#include <algorithm>
#include <cstdlib>
#include <sstream>

namespace rt {
namespace {

// A whole integer of at least `least`, or nothing.
bool readInt(const std::string& text, int& out, int least) {
    std::istringstream in(text);
    return (in >> out) && in.eof() && out >= least;
}

// Cost names used by --node-cost (config/machine_config.h, costParams).
Picos* costField(Costs& c, const std::string& name) {
    for (const Param<Costs>& p : costParams())
        if (name == p.name) return &fieldOf<Picos>(p, c);
    return nullptr;
}

// One "key=value" of --link-set into `p` (channel/link_params.h, linkParams).
void setLinkField(LinkParams& p, const std::string& key, const std::string& val) {
    const std::string flag = "--link-set";
    std::string keys;
    for (const Param<LinkParams>& l : linkParams()) {
        keys += std::string(keys.empty() ? "" : ", ") + linkSetKey(l.name);
        if (key != linkSetKey(l.name)) continue;
        if (l.kind == ParamKind::Time) {
            fieldOf<Picos>(l, p) = parseTimeOf(flag, val);
        } else if (l.kind == ParamKind::Rate) {
            fieldOf<double>(l, p) = parseRateOf(flag, val);
        } else if (!readInt(val, fieldOf<int>(l, p), int(l.lo))) {
            throw OptionError(flag, key + (l.lo >= 1 ? " must be a positive integer" : " must be a non-negative integer") +
                                        ", got '" + val + "'");
        }
        return;
    }
    throw OptionError(flag, "unknown setting '" + key + "' (" + keys + ")");
}

}  // namespace

std::string linkSetKey(const std::string& name) {
    std::string k = name;
    std::replace(k.begin(), k.end(), '-', '_');
    return k;
}

Cell parseCell(const std::string& flag, const std::string& text) {
    Cell c{};
    char comma1 = 0, comma2 = 0;
    std::istringstream in(text);
    if (!(in >> c[0] >> comma1 >> c[1] >> comma2 >> c[2]) || comma1 != ',' || comma2 != ',' || !in.eof())
        throw OptionError(flag, "expected node coordinates x,y,z, got '" + text + "'");
    return c;
}

int parseBusiest(const std::string& text) {
    if (text == "busiest") return 4;
    int k = 0;
    if (text.rfind("busiest:", 0) != 0 || !readInt(text.substr(8), k, 1) || k > 64)
        throw OptionError("--trace-nodes", "expected x,y,z, busiest or busiest:K with K in 1..64, got '" + text + "'");
    return k;
}

double parseErrorShare(const std::string& text) {
    std::string t = text;
    const bool percent = !t.empty() && t.back() == '%';
    if (percent) t.pop_back();
    char* end = nullptr;
    const double v = std::strtod(t.c_str(), &end);
    const double e = percent ? v / 100 : v;
    if (t.empty() || end != t.c_str() + t.size() || t.find_first_of("xX") != std::string::npos || !(e > 0 && e < 1))
        throw OptionError("--max-error", "expected a share above 0 and below 1 (0.02) or a percentage (2%), got '" + text + "'");
    return e;
}

Picos parseTimeOf(const std::string& flag, const std::string& text) {
    const auto t = parseTime(text);
    if (!t)
        throw OptionError(flag, "expected a non-negative time with a unit (ps ns us ms s), at most 1000 s, got '" + text + "'");
    return *t;
}

double parseRateOf(const std::string& flag, const std::string& text) {
    const auto r = parseRate(text);
    if (!r) throw OptionError(flag, "expected a positive rate with a unit (B/s KB/s MB/s GB/s, b/s .. Gb/s), got '" + text + "'");
    return *r;
}

std::array<int, 3> parseMeshDims(const std::string& text) {
    int x, y, z;
    char a = 0, b = 0;
    std::istringstream in(text);
    const int most = kMaxNodesPerAxis;
    if (!(in >> x >> a >> y >> b >> z) || a != 'x' || b != 'x' || !in.eof() || x < 1 || y < 1 || z < 1 || x > most ||
        y > most || z > most)
        throw OptionError("--mesh-dims", "expected XxYxZ with each in 1.." + std::to_string(most) + ", got '" + text + "'");
    if (long(x) * y * z > kMaxNodes)
        throw OptionError("--mesh-dims", "at most " + std::to_string(kMaxNodes) + " nodes (32x32x32, or 64x64x8), not " +
                                             std::to_string(long(x) * y * z) + " ('" + text + "')");
    return {x, y, z};
}

std::pair<Cell, double> parseNodeSpeed(const std::string& spec) {
    const size_t eq = spec.find('=');
    if (eq == std::string::npos) throw OptionError("--node-speed", "expected x,y,z=SPEED, got '" + spec + "'");
    double speed;
    std::istringstream in(spec.substr(eq + 1));
    if (!(in >> speed) || !in.eof() || !(speed > 0))
        throw OptionError("--node-speed", "speed must be a positive number in '" + spec + "'");
    return {parseCell("--node-speed", spec.substr(0, eq)), speed};
}

void applyNodeCost(const std::string& spec, const Costs& base, std::map<Cell, Costs>& costs) {
    const size_t colon = spec.find(':'), eq = spec.find('=');
    if (colon == std::string::npos || eq == std::string::npos || eq < colon)
        throw OptionError("--node-cost", "expected x,y,z:NAME=TIME, got '" + spec + "'");
    const Cell c = parseCell("--node-cost", spec.substr(0, colon));
    auto it = costs.find(c);
    Costs& k = it == costs.end() ? (costs[c] = base) : it->second;
    Picos* f = costField(k, spec.substr(colon + 1, eq - colon - 1));
    if (!f) throw OptionError("--node-cost", "unknown cost name in '" + spec + "'");
    *f = parseTimeOf("--node-cost", spec.substr(eq + 1));
}

std::pair<std::pair<Cell, int>, LinkParams> parseLinkSet(const std::string& spec, const LinkParams& base) {
    const std::string flag = "--link-set";
    const size_t colon = spec.find(':');
    if (colon == std::string::npos) throw OptionError(flag, "expected x,y,z,DIR:settings, got '" + spec + "'");
    const std::string where = spec.substr(0, colon);
    const size_t lastComma = where.find_last_of(',');
    if (lastComma == std::string::npos) throw OptionError(flag, "expected x,y,z,DIR, got '" + where + "'");
    const Cell c = parseCell(flag, where.substr(0, lastComma));
    const std::string dirText = where.substr(lastComma + 1);
    const std::optional<int> dir = dirNamed(dirText);
    if (!dir) throw OptionError(flag, "direction must be one of +x -x +y -y +z -z, got '" + dirText + "'");
    LinkParams p = base;
    if (spec.size() == colon + 1)  // (accepted, it changed nothing: a setting lost in a script?)
        throw OptionError(flag, "no setting after the ':' in '" + spec + "' (latency=T, bandwidth=R, depth=N, ...)");
    std::istringstream items(spec.substr(colon + 1));
    std::string item;
    while (std::getline(items, item, ',')) {
        const size_t eq = item.find('=');
        setLinkField(p, item.substr(0, eq), eq == std::string::npos ? "" : item.substr(eq + 1));
    }
    return {{c, *dir}, p};
}

std::pair<Cell, int> parseTraceLink(const std::string& spec) {
    const size_t commas = size_t(std::count(spec.begin(), spec.end(), ','));
    if (commas == 2) return {parseCell("--trace-links", spec), -1};
    const size_t last = spec.find_last_of(',');
    const std::string dirText = last == std::string::npos ? spec : spec.substr(last + 1);
    const std::optional<int> dir = dirText == "fb" ? std::optional<int>(kDirs) : dirNamed(dirText);
    if (commas != 3 || !dir)
        throw OptionError("--trace-links", "expected x,y,z or x,y,z,DIR with DIR one of +x -x +y -y +z -z fb, got '" + spec + "'");
    return {parseCell("--trace-links", spec.substr(0, last)), *dir};
}

std::pair<Picos, Picos> parseTraceWindow(const std::string& text) {
    const size_t comma = text.find(',');
    if (comma == std::string::npos) throw OptionError("--trace-window", "expected FROM,TO, got '" + text + "'");
    return {parseTimeOf("--trace-window", text.substr(0, comma)), parseTimeOf("--trace-window", text.substr(comma + 1))};
}

}  // namespace rt
