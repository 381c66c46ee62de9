// The clock a frame reads. A --frames sequence runs in one elaboration
// (machine/machine.h, MachineSession): frame k + 1 starts on the kernel's clock
// where frame k ended. Every time the model computes (a node's local time,
// a message's arrival, a report's figure, a waveform's change) counts from
// its own frame's start, so a frame's outcome does not depend on when it
// began; the model reads the kernel's time only through here.
#pragma once
#include <systemc>

#include "base/units.h"

namespace rt {

// The kernel's time at the running frame's start: 0 for a machine's first
// frame (one machine runs at a time: MachineSession sets it).
inline Picos frameOrigin = 0;

// The kernel's time in the running frame.
inline Picos frameClock() { return Picos(sc_core::sc_time_stamp().value()) - frameOrigin; }

}  // namespace rt
