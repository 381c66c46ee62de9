// The text of a --config file, and of a report's recorded flags (tb/rerun.h):
// one `name = value` per line, the flags' names without `--`.
//
//   # a comment (also `;`)            a line of its own
//   mesh = 4                          a bare value: the rest of the line
//   link-latency = 100ns   # why      (an inline comment follows a space)
//   scene = "/data/my scene.nff"      a quoted string, JSON's escapes
//   image = 'C:\raw'                  a literal string, no escapes
//   light = [1, 2, 3, 4, 5, 6]        a list: a repeatable flag's values
//   no-baseline                       a flag alone: true
//
// Our own reader, not CLI11's: CLI11 2.1 cuts a value at a `#` even inside
// quotes, splits a bare value at its spaces, joins a name's values across
// adjacent lines but not others, and says no line in its errors. Here every
// error names FILE:LINE, and the caller applies one rule: the last value of
// a name wins (tb/command_line.h).
#pragma once
#include <stdexcept>
#include <string>
#include <vector>

namespace rt {

// Bad input in a config text: "ORIGIN:LINE: why" (exit 2).
struct ConfigError : std::invalid_argument {
    using std::invalid_argument::invalid_argument;
};

struct ConfigLine {
    std::string name;                 // without "--"
    std::vector<std::string> values;  // one, or a list's
    bool list = false;                // written as [ ... ]
    bool alone = false;               // the name alone, no '= value' (a flag: true)
    std::string where;                // "ORIGIN:LINE"
};

// Largest config file read (a preset is a few dozen lines).
constexpr size_t kMaxConfigBytes = 1 << 20;

// Throws ConfigError naming ORIGIN:LINE for a line it cannot read.
std::vector<ConfigLine> parseConfig(const std::string& text, const std::string& origin);
// A regular file of at most kMaxConfigBytes, read and parsed (ConfigError
// "--config PATH: why" if it is not one).
std::vector<ConfigLine> readConfigFile(const std::string& path);

// A value as parseConfig reads it back: bare if a number, true or false, a
// single character in '', otherwise a JSON string (the form CLI11 writes).
std::string configValue(const std::string& value);
// `name=value` or `name=[a, b]` (the form CLI11 writes, which reports keep).
std::string configLine(const std::string& name, const std::vector<std::string>& values);

// Flags no report may carry: outputs, what runs a program, internal flags.
bool isOutputOrInternal(const std::string& name);

}  // namespace rt
