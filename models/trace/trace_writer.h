// The GTKWave save file for a run's VCD (vcd_stream.h writes the VCD).
#pragma once
#include <string>

#include "trace/vcd_stream.h"

namespace rt {

// A .gtkw save file that groups the signals by their top scope (each node,
// with its links in subgroups; the frame buffer; the boundaries), so
// GTKWave opens straight to them: gtkwave -a FILE.gtkw. [from, to] is the
// traced window, which it opens zoomed to. `path`: the save file's name,
// `vcdPath`: the VCD's (the file it opens). Its text; the caller writes it.
std::string gtkwText(const std::string& path, const std::string& vcdPath, const VcdStream& vcd, Picos from, Picos to);
// FILE.vcd -> FILE.gtkw
std::string gtkwPathFor(const std::string& vcdPath);

}  // namespace rt
