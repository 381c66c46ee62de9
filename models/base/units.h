// Times and rates with units, as the command line and config files give them:
// "20ns", "2.5us", "1ms", "0s"; "1GB/s", "100MB/s", "10Gb/s" (bits), "1e9B/s".
// Decimal prefixes (1 GB/s = 1e9 bytes per second). Times are kept as integer
// picoseconds, the kernel's resolution, so sums of costs are exact.
#pragma once
#include <cstdint>
#include <optional>
#include <string>

namespace rt {

using Picos = uint64_t;

// The picosecond counter (SystemC's and ours) wraps at 2^64 ps, about 213
// days. Any one time given (a cost, a latency, an interval) is at most
// kMaxTimeValue, and a run stops with an error once a process's time passes
// kMaxSimTime, so sums of such values cannot wrap silently.
constexpr Picos kMaxTimeValue = Picos(1000) * 1000000000000;  // 1,000 s
constexpr Picos kMaxSimTime = Picos(1) << 62;                  // about 53 days
// Throws std::runtime_error naming `who` once `t` is past kMaxSimTime.
// (Inline, the throw out of line: every step, message and express hop
// checks; doc/history.md, "Figures behind the code's comments".)
// `who` is a callable giving the name, asked only once the check fails: a
// name was read at every node's step and every message sent, where it was
// a cache line nothing else read (on a large mesh a miss each time: the
// compiler loads an argument before the call, whatever the branch).
[[noreturn]] void throwSimTimePast(const char* who);
template <class Who>
inline void checkSimTime(Picos t, const Who& who) {
    if (__builtin_expect(t > kMaxSimTime, 0)) throwSimTimePast(who());
}
// A time the model computes in floating point (an estimate, a wire time)
// as picoseconds: truncated (as a cast), saturated at kMaxSimTime (converting
// a larger double to an integer unchecked is undefined behaviour, and no
// time the model reaches is beyond it). NaN or negative: 0.
Picos saturatedPicos(double ps);
// a * n (n a count of operations at a cost a): exact, or throws
// std::runtime_error naming `what` if past kMaxSimTime.
Picos timesCount(Picos a, uint64_t n, const std::string& what);

// Parses a non-negative time ("0" may go without a unit); nullopt when
// malformed (no unit, unknown unit, negative, not finite, not a whole
// number of picoseconds) or above kMaxTimeValue.
std::optional<Picos> parseTime(const std::string& text);
// Parses a positive, finite rate in bytes per second.
std::optional<double> parseRate(const std::string& text);

// A time in ns, as the report gives every time.
constexpr double inNs(Picos t) { return double(t) / 1000.0; }
std::string formatTime(Picos t);    // "12.5 us"
std::string formatRate(double bps); // "1 GB/s"
std::string formatNumber(double v);  // "%g": "0.5", "1e+09"

}  // namespace rt
