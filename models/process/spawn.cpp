#define SC_INCLUDE_DYNAMIC_PROCESSES  // (sc_spawn: only where it is used)
#include "process/spawn.h"

#include <string>

namespace rt {

sc_core::sc_process_handle spawnMethod(std::function<void()> body, const sc_core::sc_object& owner, int frame) {
    sc_core::sc_spawn_options options;
    options.spawn_method();
    const std::string name = std::string(owner.basename()) + "_frame" + std::to_string(frame);
    return sc_core::sc_spawn(std::move(body), name.c_str(), &options);
}

}  // namespace rt
