#define SC_INCLUDE_DYNAMIC_PROCESSES  // (sc_spawn: only where it is used)
#include "process/spawn.h"

#include <string>

namespace rt {

sc_core::sc_process_handle spawnMethod(std::function<void()> body, sc_core::sc_module& owner, int frame) {
    sc_core::sc_spawn_options options;
    options.spawn_method();
    // A child of its module, not a top-level object: SystemC removes a
    // top-level object from the one list of them all by a linear search,
    // and each frame's processes are removed in turn, a search of a list
    // as long as the mesh for each node (doc/history.md, "Figures behind
    // the code's comments").
    sc_core::sc_simcontext& kernel = *sc_core::sc_get_curr_simcontext();
    kernel.hierarchy_push(&owner);
    struct Pop {
        sc_core::sc_simcontext& k;
        ~Pop() { k.hierarchy_pop(); }
    } pop{kernel};
    return sc_core::sc_spawn(std::move(body), ("frame" + std::to_string(frame)).c_str(), &options);
}

}  // namespace rt
