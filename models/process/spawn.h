// A method process for the next frame of a sequence (machine.h,
// MachineSession). The modules are elaborated once; each frame's processes
// are new, since a frame's end kills the last frame's (Machine::
// endProcesses), and a killed process cannot run again. The new one runs
// at once when the simulation goes on, as a static SC_METHOD without
// dont_initialize runs at the start.
#pragma once
#include <functional>

#include <systemc>

namespace rt {

// A SystemC dynamic method process running `body` at each activation, for
// `owner`'s frame `frame`: a top-level object, so named uniquely by the
// owner's name and the frame's number ("node_1_0_2_frame3").
sc_core::sc_process_handle spawnMethod(std::function<void()> body, const sc_core::sc_object& owner, int frame);

}  // namespace rt
