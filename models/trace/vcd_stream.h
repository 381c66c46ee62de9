// The VCD, written while the run goes: a run that crashes, is stopped by the
// watchdog or interrupted (Ctrl-C) leaves a valid waveform up to then.
//
// Processes record value changes at their own (local) times, which may be
// ahead of the kernel's, and a link records a message's changes (backlog,
// on the wire, buffered) only once it is consumed. So changes arrive out of
// time order; they wait here until a horizon is passed: a time before
// which every change is known (the kernel's time, and the sending time of
// the oldest message still on a traced link; Machine::traceHorizon). Then
// those before it are written in time order, and only values that changed.
// Memory is bounded by the changes between horizons: the machine flushes
// every watchdog period and whenever a million changes are waiting.
//
// The output does not depend on when flushes happen (a time is written
// whole in one flush: every change before the horizon is known), so it is
// the same in every exact mode and byte for byte from run to run. We write
// the VCD ourselves rather than with sc_trace: SystemC's writer stamps the
// wall-clock date into the file, knows no time window, and would need a
// signal and a delta cycle per change.
//
// Per node, a `load` signal: busy / (busy + wait) over windows that widen
// as the frame goes on (1 ns for the first 256 ns, then 128 windows per
// doubling of the time: about 1/128 to 1/256 of the time so far; so a
// frame of any length has a few hundred to a few thousand values), shown
// at each window's end.
#pragma once
#include <cstdint>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "base/units.h"

namespace rt {

class VcdStream {
public:
    enum class Kind { Bit, Integer, Real };
    // Scopes are '.'-separated under "machine" ("node_0_0_0.px").
    int declare(const std::string& scope, const std::string& name, Kind kind);
    // A `load` signal of the node whose busy and wait bits these are.
    void declareLoad(const std::string& scope, int busy, int wait);

    // Writes the header; changes before `from` set the values shown at
    // `from`, changes after `to` are not written. `name`: the VCD's name in
    // messages (a write that fails throws std::runtime_error naming it).
    void open(const std::string& path, Picos from, Picos to, const std::string& name = "");
    bool isOpen() const { return out_.is_open(); }

    // A change at `t`: a new value, or (counters) a step up or down.
    void set(Picos t, int signal, int64_t v) { add(t, signal, Op::Set, v, 0); }
    void setReal(Picos t, int signal, double v) { add(t, signal, Op::SetReal, 0, v); }
    void step(Picos t, int signal, int64_t dv) { add(t, signal, Op::Step, dv, 0); }

    size_t waiting() const { return pending_.size(); }
    // Where a flush may go (see above); called when too many changes wait.
    void setHorizon(std::function<Picos()> h) { horizon_ = std::move(h); }
    static constexpr size_t kMaxWaiting = 1 << 20;
    // Writes every change before `horizon`.
    void flush(Picos horizon);
    // Writes the rest, the last load windows up to `end`, a final time
    // stamp, and `comment` if any ("incomplete: ..."), and closes the file.
    void close(Picos end, const std::string& comment);
    // The window after the one ending at `end` (see above).
    static Picos loadWindowAfter(Picos end);

    // The signals, in declaration order (for the .gtkw).
    size_t signalCount() const { return signals_.size(); }
    const std::string& scopeOf(size_t i) const { return signals_[i].scope; }
    const std::string& nameOf(size_t i) const { return signals_[i].name; }
    Kind kindOf(size_t i) const { return signals_[i].kind; }

private:
    enum class Op : uint8_t { Set, SetReal, Step };
    struct Change {
        Picos t;
        uint64_t seq;  // order of recording: the last change at one time stands
        int signal;
        Op op;
        int64_t iv;
        double rv;
    };
    struct Signal {
        std::string scope, name;
        Kind kind;
        int64_t iv = 0, shownI = 0;
        double rv = 0, shownR = 0;
        bool shown = false;
        int load = -1;  // a busy or wait bit: its node's load accumulator
    };
    struct Load {
        int signal, busy, wait;
        Picos busyTime = 0, waitTime = 0, since = 0;  // in the current window
    };
    void add(Picos t, int signal, Op op, int64_t iv, double rv);
    void apply(const Change& c);
    void closeWindowsBefore(Picos t);  // load windows ending at or before t
    void accumulate(Load& l, Picos t);
    void stamp(Picos t);               // "#t", once per time
    void show(Signal& s, Picos t);     // its value, if it changed
    void writeOut(bool force);

    std::vector<Signal> signals_;
    std::vector<std::string> codes_;  // each signal's VCD identifier
    std::vector<Load> loads_;
    std::vector<Change> pending_;
    std::function<Picos()> horizon_;
    size_t flushAt_ = kMaxWaiting;
    uint64_t seq_ = 0;
    std::ofstream out_;
    std::string name_;
    std::string buf_;  // written in whole lines
    Picos from_ = 0, to_ = ~Picos(0);
    Picos windowEnd_ = 0;  // the end of the current load window
    Picos stamped_ = ~Picos(0);
    bool started_ = false;  // the values at `from` are written
};

}  // namespace rt
