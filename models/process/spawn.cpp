#define SC_INCLUDE_DYNAMIC_PROCESSES  // (sc_spawn: only where it is used)
#include "process/spawn.h"

namespace rt {

sc_core::sc_process_handle spawnMethod(std::function<void()> body, const std::string& name) {
    sc_core::sc_spawn_options options;
    options.spawn_method();
    return sc_core::sc_spawn(std::move(body), name.c_str(), &options);
}

}  // namespace rt
