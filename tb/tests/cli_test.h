// rtsim's command line parsed in the test's process, as rtsim parses it:
// the flags of config files merged before the command line's
// (tb/command_line.h), then checked (RtsimOptions::finish).
#pragma once
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "command_line.h"
#include "rtsim_cli.h"

namespace rt::test {

inline RtsimOptions parsed(const CommandLine& cl) {
    RtsimOptions o;
    CLI::App app;
    o.addTo(app);
    std::vector<std::string> reversed(cl.args.rbegin(), cl.args.rend() - 1);
    app.parse(reversed);
    o.finish();
    return o;
}

}  // namespace rt::test
