// JSON that rtsim reads back: a report given to --rerun or
// --boundaries-from (passed around between people: untrusted input), and
// the reports of its own child runs. Read with limits, so that no file can
// crash the reader or the code after it (a report nested 300,000 brackets
// deep once overflowed the stack in a recursive comparison), and each field
// taken by its path with its type checked, so that a wrong one is one line
// naming it (exit 2), not a library's message naming nothing.
#pragma once
#include <cstdint>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

namespace rt {

// Bad JSON input: "WHERE: why" (exit 2).
struct JsonInputError : std::invalid_argument {
    using std::invalid_argument::invalid_argument;
};

// Nesting deeper than any report has (a report is about 6 levels deep).
constexpr int kMaxJsonDepth = 64;
// A report given to --rerun or --boundaries-from: with the per-interval
// history bounded, a few MB; one of a long --frames sequence at N = 16
// some hundreds.
constexpr uintmax_t kMaxReportBytes = uintmax_t(1) << 30;

// `path`: a regular file of at most `maxBytes`, JSON nested at most
// kMaxJsonDepth deep. Throws JsonInputError "PATH: why".
nlohmann::json readJsonFile(const std::string& path, uintmax_t maxBytes);
// The same for text in memory; errors name `origin`.
nlohmann::json parseJsonText(const std::string& text, const std::string& origin);

// The field at `path` ("config.scene.sha256") of `j`, which must be of
// type `type` (nlohmann's value_t; number_float also takes integers).
// Throws JsonInputError "ORIGIN: PATH: missing" or "...: expected a
// string, got a number".
const nlohmann::json& jsonField(const nlohmann::json& j, const std::string& path, nlohmann::json::value_t type,
                                const std::string& origin);
// Whether `j` has a field at `path` (of any type).
bool hasJsonField(const nlohmann::json& j, const std::string& path);

}  // namespace rt
