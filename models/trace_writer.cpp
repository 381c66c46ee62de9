#include "trace_writer.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <stdexcept>

#include "output_file.h"

namespace rt {
namespace {

// VCD identifier codes: printable characters from '!' on.
std::string code(size_t i) {
    std::string s;
    do {
        s.push_back(char('!' + i % 94));
        i /= 94;
    } while (i);
    return s;
}

struct Event {
    Picos t;
    size_t signal;  // order of declaration breaks ties: stable output
    int kind;       // 0 bit, 1 integer, 2 real
    int64_t iv;
    double rv;
};

// Value of a change list at time t (before any change: 0).
int64_t valueAt(const std::vector<Change>& s, Picos t) {
    auto it = std::upper_bound(s.begin(), s.end(), t, [](Picos x, const Change& c) { return x < c.t; });
    return it == s.begin() ? 0 : std::prev(it)->v;
}

// busy / (busy + wait) over [a, b), from the busy and wait change lists.
double loadOver(const NodeTrace& tr, Picos a, Picos b) {
    auto timeHigh = [&](const std::vector<Change>& s) {
        Picos total = 0, t = a;
        int64_t v = valueAt(s, a);
        auto it = std::upper_bound(s.begin(), s.end(), a, [](Picos x, const Change& c) { return x < c.t; });
        for (; it != s.end() && it->t < b; ++it) {
            if (v) total += it->t - t;
            t = it->t;
            v = it->v;
        }
        if (v) total += b - t;
        return total;
    };
    const Picos busy = timeHigh(tr.busy), wait = timeHigh(tr.wait);
    return busy + wait ? double(busy) / double(busy + wait) : 0.0;
}

}  // namespace

Picos loadWindow(Picos renderTime) { return std::max<Picos>(1, renderTime / 200); }

std::string gtkwPathFor(const std::string& vcdPath) {
    const std::string ext = ".vcd";
    if (vcdPath.size() > ext.size() && vcdPath.compare(vcdPath.size() - ext.size(), ext.size(), ext) == 0)
        return vcdPath.substr(0, vcdPath.size() - ext.size()) + ".gtkw";
    return vcdPath + ".gtkw";
}

void writeVcd(const std::string& path, const std::vector<TracedNode>& nodes,
              const std::vector<TracedBoundary>& boundaries, Picos from, Picos to, Picos renderTime,
              const std::string& incomplete) {
    AtomicFile out(path);  // written whole or not at all (output_file.h)
    std::ofstream f(out.temp());
    if (!f) throw std::runtime_error(path + ": cannot open for writing");
    f << "$version rtsim $end\n";
    if (!incomplete.empty()) f << "$comment incomplete: " << incomplete << " $end\n";
    f << "$timescale 1ps $end\n$scope module machine $end\n";
    for (size_t n = 0; n < nodes.size(); ++n) {
        f << "$scope module " << nodes[n].name << " $end\n"
          << "$var wire 1 " << code(4 * n) << " busy $end\n"
          << "$var wire 1 " << code(4 * n + 1) << " wait $end\n"
          << "$var real 64 " << code(4 * n + 2) << " load $end\n"
          << "$var integer 32 " << code(4 * n + 3) << " queue $end\n"
          << "$upscope $end\n";
    }
    const size_t b0 = 4 * nodes.size();  // boundary signals follow the nodes'
    if (!boundaries.empty()) {
        f << "$scope module boundaries $end\n";
        for (size_t i = 0; i < boundaries.size(); ++i)
            f << "$scope module " << boundaries[i].name << " $end\n"
              << "$var real 64 " << code(b0 + 2 * i) << " position $end\n"
              << "$var integer 32 " << code(b0 + 2 * i + 1) << " slides $end\n"
              << "$upscope $end\n";
        f << "$upscope $end\n";
    }
    f << "$upscope $end\n$enddefinitions $end\n";

    std::vector<Event> ev;
    const Picos window = loadWindow(renderTime);
    for (size_t n = 0; n < nodes.size(); ++n) {
        const NodeTrace& tr = *nodes[n].trace;
        const std::vector<Change>* lists[3] = {&tr.busy, &tr.wait, &tr.queue};
        for (int k = 0; k < 3; ++k) {
            const size_t sig = 4 * n + (k < 2 ? k : 3);
            ev.push_back({from, sig, k < 2 ? 0 : 1, valueAt(*lists[k], from), 0});
            for (const Change& c : *lists[k])
                if (c.t > from && c.t <= to) ev.push_back({c.t, sig, k < 2 ? 0 : 1, c.v, 0});
        }
        // Load: one value per window [a, b), shown from the window's start.
        for (Picos a = 0; a < renderTime && a <= to; a += window) {
            const Picos b = std::min(a + window, renderTime);
            if (b <= from) continue;
            ev.push_back({std::max(a, from), 4 * n + 2, 2, 0, loadOver(tr, a, b)});
        }
    }
    for (size_t i = 0; i < boundaries.size(); ++i) {
        const auto& p = boundaries[i].positions;  // p[0] is the start position, each later entry a slide
        size_t k = 0;
        while (k + 1 < p.size() && p[k + 1].first <= from) ++k;
        ev.push_back({from, b0 + 2 * i, 2, 0, p[k].second});
        ev.push_back({from, b0 + 2 * i + 1, 1, int64_t(k), 0});
        for (++k; k < p.size() && p[k].first <= to; ++k) {
            ev.push_back({p[k].first, b0 + 2 * i, 2, 0, p[k].second});
            ev.push_back({p[k].first, b0 + 2 * i + 1, 1, int64_t(k), 0});
        }
    }
    std::stable_sort(ev.begin(), ev.end(), [](const Event& a, const Event& b) {
        return a.t != b.t ? a.t < b.t : a.signal < b.signal;
    });
    Picos cur = ~Picos(0);
    char buf[64];
    for (const Event& e : ev) {
        if (e.t != cur) {
            f << "#" << e.t << "\n";
            cur = e.t;
        }
        if (e.kind == 0) {
            f << (e.iv ? '1' : '0') << code(e.signal) << "\n";
        } else if (e.kind == 1) {
            std::string bits;
            for (uint64_t v = uint64_t(e.iv); v; v >>= 1) bits.insert(bits.begin(), char('0' + (v & 1)));
            f << "b" << (bits.empty() ? "0" : bits) << " " << code(e.signal) << "\n";
        } else {
            std::snprintf(buf, sizeof buf, "r%.6g ", e.rv);
            f << buf << code(e.signal) << "\n";
        }
    }
    f.close();
    if (!f) throw std::runtime_error(path + ": write failed");
    out.commit();
}

void writeGtkw(const std::string& path, const std::string& vcdPath, const std::vector<TracedNode>& nodes,
               const std::vector<TracedBoundary>& boundaries, Picos from, Picos to) {
    AtomicFile out(path);  // written whole or not at all (output_file.h)
    std::ofstream f(out.temp());
    if (!f) throw std::runtime_error(path + ": cannot open for writing");
    // Signal flags (GTKWave's TR_* bits, hex): 28 binary; 24 decimal;
    // 48020 real, analog step; 8024 integer, analog step; 20000 a blank row
    // stretching the analog trace above it; 800200 / 1000200 open / close a group.
    std::string vcdName = vcdPath.substr(vcdPath.find_last_of('/') + 1);
    f << "[*] written by rtsim: gtkwave -a " << path.substr(path.find_last_of('/') + 1) << "\n"
      << "[dumpfile] \"" << vcdName << "\"\n"
      << "[timestart] " << from << "\n[size] 1400 900\n[pos] -1 -1\n"
      // Zoom so that the window fills the wave pane: measured with GTKWave
      // 3.3.118 at this window size, zoom z shows about 3.5 * 2^-z time units.
      << "*" << -std::log2(std::max(1.0, double(to - from) / 3.5)) << " -1\n"
      << "[treeopen] machine.\n[sst_width] 220\n[signals_width] 200\n[sst_expanded] 1\n[sst_vpaned_height] 250\n";
    for (const TracedNode& n : nodes) {
        const std::string p = "machine." + n.name + ".";
        f << "@800200\n-" << n.name << "\n"
          << "@28\n" << p << "busy\n" << p << "wait\n"
          << "@48020\n" << p << "load\n@20000\n-\n"
          << "@8024\n" << p << "queue\n@20000\n-\n"
          << "@1000200\n-" << n.name << "\n";
    }
    if (!boundaries.empty()) {
        f << "@800200\n-boundaries\n";
        for (const TracedBoundary& b : boundaries)
            f << "@48020\nmachine.boundaries." << b.name << ".position\n@20000\n-\n"
              << "@24\nmachine.boundaries." << b.name << ".slides\n";
        f << "@1000200\n-boundaries\n";
    }
    f.close();
    if (!f) throw std::runtime_error(path + ": write failed");
    out.commit();
}

}  // namespace rt
