#include "base/units.h"

#include <algorithm>

#include <stdexcept>

#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace rt {
namespace {

// Splits "12.5us" (or "12.5 us", as formatTime writes it and --help shows
// the defaults) into 12.5 and "us"; false if the number part is malformed.
bool splitNumber(const std::string& text, double& value, std::string& unit) {
    if (text.empty()) return false;
    const char* begin = text.c_str();
    char* end = nullptr;
    value = std::strtod(begin, &end);
    if (end == begin || !std::isfinite(value)) return false;
    if (std::find_if(begin, static_cast<const char*>(end), [](char c) { return c == 'x' || c == 'X'; }) != end)
        return false;  // (strtod reads C's hexadecimal: 0x10ns was 16 ns)
    while (*end == ' ') ++end;
    unit.assign(end);
    return true;
}

}  // namespace

void throwSimTimePast(const char* who) {
    throw std::runtime_error(std::string(who) + ": simulated time past " + formatTime(kMaxSimTime) +
                             " (the picosecond counter would wrap); are the costs, latencies or bandwidths meant to be this large?");
}

Picos saturatedPicos(double ps) {
    if (!(ps > 0)) return 0;
    if (ps >= double(kMaxSimTime)) return kMaxSimTime;
    return Picos(ps);
}

Picos timesCount(Picos a, uint64_t n, const std::string& what) {
    Picos p = 0;
    if (__builtin_mul_overflow(a, n, &p) || p > kMaxSimTime)
        throw std::runtime_error(what + ": " + std::to_string(n) + " x " + formatTime(a) + " is past " + formatTime(kMaxSimTime) +
                                 " (the picosecond counter would wrap)");
    return p;
}

std::optional<Picos> parseTime(const std::string& text) {
    if (text == "0") return Picos(0);  // zero needs no unit
    double v;
    std::string unit;
    if (!splitNumber(text, v, unit) || v < 0) return std::nullopt;
    double scale;
    if (unit == "ps") scale = 1;
    else if (unit == "ns") scale = 1e3;
    else if (unit == "us") scale = 1e6;
    else if (unit == "ms") scale = 1e9;
    else if (unit == "s") scale = 1e12;
    else return std::nullopt;
    const double ps = v * scale;
    if (!(ps <= double(kMaxTimeValue)) || std::abs(ps - std::round(ps)) > 1e-6 * std::max(1.0, ps)) return std::nullopt;
    return Picos(std::llround(ps));
}

std::optional<double> parseRate(const std::string& text) {
    double v;
    std::string unit;
    if (!splitNumber(text, v, unit) || !(v > 0)) return std::nullopt;
    static const struct { const char* name; double scale; } units[] = {
        {"B/s", 1},         {"KB/s", 1e3},      {"MB/s", 1e6},      {"GB/s", 1e9},      {"TB/s", 1e12},
        {"b/s", 1 / 8.0},   {"Kb/s", 1e3 / 8},  {"Mb/s", 1e6 / 8},  {"Gb/s", 1e9 / 8}, {"Tb/s", 1e12 / 8},
    };
    for (const auto& u : units)
        if (unit == u.name) return v * u.scale;
    return std::nullopt;
}

std::string formatTime(Picos t) {
    char buf[64];
    const double v = double(t);
    if (t < 1000) std::snprintf(buf, sizeof buf, "%llu ps", (unsigned long long)t);
    else if (t < 1000000) std::snprintf(buf, sizeof buf, "%.4g ns", v / 1e3);
    else if (t < 1000000000ULL) std::snprintf(buf, sizeof buf, "%.4g us", v / 1e6);
    else if (t < 1000000000000ULL) std::snprintf(buf, sizeof buf, "%.4g ms", v / 1e9);
    else std::snprintf(buf, sizeof buf, "%.4g s", v / 1e12);
    return buf;
}

std::string formatRate(double bps) {
    char buf[64];
    if (bps >= 1e9) std::snprintf(buf, sizeof buf, "%.4g GB/s", bps / 1e9);
    else if (bps >= 1e6) std::snprintf(buf, sizeof buf, "%.4g MB/s", bps / 1e6);
    else if (bps >= 1e3) std::snprintf(buf, sizeof buf, "%.4g KB/s", bps / 1e3);
    else std::snprintf(buf, sizeof buf, "%.4g B/s", bps);
    return buf;
}

std::string formatNumber(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
}

}  // namespace rt
