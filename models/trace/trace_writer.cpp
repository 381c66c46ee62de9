#include "trace/trace_writer.h"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <vector>


namespace rt {

std::string gtkwPathFor(const std::string& vcdPath) {
    const std::string ext = ".vcd";
    if (vcdPath.size() > ext.size() && vcdPath.compare(vcdPath.size() - ext.size(), ext.size(), ext) == 0)
        return vcdPath.substr(0, vcdPath.size() - ext.size()) + ".gtkw";
    return vcdPath + ".gtkw";
}

std::string gtkwText(const std::string& path, const std::string& vcdPath, const VcdStream& vcd, Picos from, Picos to) {
    std::ostringstream f;
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
    // Scopes in declaration order: a group per top scope, a subgroup per
    // scope below it (a node's links; a unit; a boundary).
    std::vector<std::string> open;  // the groups open, outermost first
    auto closeTo = [&](size_t depth) {
        while (open.size() > depth) {
            f << "@1000200\n-" << open.back() << "\n";
            open.pop_back();
        }
    };
    for (size_t i = 0; i < vcd.signalCount(); ++i) {
        const std::string& scope = vcd.scopeOf(i);
        std::vector<std::string> parts;
        for (size_t a = 0; a <= scope.size();) {
            const size_t dot = std::min(scope.find('.', a), scope.size());
            parts.push_back(scope.substr(a, dot - a));
            a = dot + 1;
        }
        size_t same = 0;
        while (same < open.size() && same < parts.size() && open[same] == parts[same]) ++same;
        closeTo(same);
        for (size_t k = same; k < parts.size(); ++k) {
            f << "@800200\n-" << parts[k] << "\n";
            open.push_back(parts[k]);
        }
        const std::string name = "machine." + scope + "." + vcd.nameOf(i);
        switch (vcd.kindOf(i)) {
            case VcdStream::Kind::Bit: f << "@28\n" << name << "\n"; break;
            case VcdStream::Kind::Integer: f << "@8024\n" << name << "\n@20000\n-\n"; break;
            case VcdStream::Kind::Real: f << "@48020\n" << name << "\n@20000\n-\n"; break;
        }
    }
    closeTo(0);
    return f.str();
}

}  // namespace rt
