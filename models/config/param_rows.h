// Every parameter row with a value of its own (not Special), the parts in
// their places: its flag and its place in the report's config echo. One
// walk over the tables (base/param.h) for whatever needs the rows by flag:
// the parameter tests, and a rerun that names the flag of a setting its
// report lacks (tb/config_echo.h, firstDifference).
#pragma once
#include <string>

#include "channel/link_params.h"
#include "config/machine_config.h"

namespace rt {

// Calls f(row, flag, echo) for each row: `row` a Param<S> of its table,
// `flag` with its "--", `echo` its JSON pointer in the config echo ("" if
// it has none).
template <class F>
void forEachParamRow(F&& f) {
    auto row = [&](const auto& p, const std::string& flag, const std::string& echoAt) {
        f(p, flag, p.echo ? echoAt + p.echo : std::string());
    };
    for (const Param<MachineConfig>& p : machineParams()) {
        if (p.kind == ParamKind::Special) continue;
        if (p.kind != ParamKind::Part) {
            row(p, std::string("--") + p.name, "");
        } else if (p.part == std::string("costs")) {
            for (const auto& c : costParams()) row(c, std::string("--cost-") + c.name, "/costs");
        } else if (p.part == std::string("link")) {
            for (const auto& l : linkParams()) row(l, std::string("--link-") + l.name, "/link");
        } else if (p.part == std::string("fb-port")) {
            for (const auto& l : linkParams())
                if (l.portHelp) row(l, std::string("--fb-") + l.name, "/fb_port");
        } else {
            for (const auto& b : balanceParams())
                if (b.kind != ParamKind::Special) row(b, std::string("--") + b.name, "/balance");
        }
    }
}

}  // namespace rt
