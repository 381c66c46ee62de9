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
// `owner`'s frame `frame`: a child of the module, named by the frame's
// number ("rtsim.node_1_0_2.frame3").
sc_core::sc_process_handle spawnMethod(std::function<void()> body, sc_core::sc_module& owner, int frame);

}  // namespace rt
