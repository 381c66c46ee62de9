// A method process for the next frame of a sequence (machine.h,
// MachineSession). The modules are elaborated once; each frame's processes
// are new, since a frame's end kills the last frame's (Machine::
// endProcesses), and a killed process cannot run again. The new one runs
// at once when the simulation goes on, as a static SC_METHOD without
// dont_initialize runs at the start.
#pragma once
#include <functional>
#include <string>

#include <systemc>

namespace rt {

// A SystemC dynamic method process running `body` at each activation,
// named `name` (a top-level object, so unique: the module's name with the
// frame's number).
sc_core::sc_process_handle spawnMethod(std::function<void()> body, const std::string& name);

}  // namespace rt
