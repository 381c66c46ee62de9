// What a finished frame leaves behind for the next (balance/frame_state.h),
// taken from the machine's results: the report serialises this value, and
// the frames of a sequence hand it on.
#pragma once
#include "balance/frame_state.h"
#include "config/machine_config.h"
#include "machine/machine.h"

namespace rt {

FrameState frameStateOf(const MachineResult& r, const MachineConfig& cfg);

}  // namespace rt
