#include "trace/vcd_stream.h"

#include <cerrno>
#include <cstring>

#include <algorithm>
#include <cstdio>
#include <map>
#include <stdexcept>

namespace rt {
namespace {

// VCD identifier codes: printable characters from '!' on.
std::string code(size_t i) {
    std::string s;
    do {
        s.push_back(char('!' + i % 94));
        i /= 94;
    } while (i);
    return s;
}

constexpr Picos kFirstWindow = 1000;  // 1 ns
constexpr size_t kWriteBytes = 1 << 20;

// A scope tree in the order scopes were first declared.
struct Scope {
    std::vector<std::pair<std::string, Scope>> children;
    std::vector<size_t> signals;
    Scope& child(const std::string& name) {
        for (auto& [n, s] : children)
            if (n == name) return s;
        children.emplace_back(name, Scope());
        return children.back().second;
    }
};

}  // namespace

Picos VcdStream::loadWindowAfter(Picos end) {
    if (end < 256 * kFirstWindow) return end + kFirstWindow;
    Picos w = kFirstWindow;
    while (end / (128 * kFirstWindow) >= 2 * (w / kFirstWindow)) w *= 2;  // w = W0 * 2^floor(log2(end / 128 W0))
    return end + w;
}

int VcdStream::declare(const std::string& scope, const std::string& name, Kind kind) {
    if (out_.is_open()) throw std::logic_error("VCD: signal declared after the header");
    signals_.push_back({scope, name, kind});
    return int(signals_.size() - 1);
}

void VcdStream::declareLoad(const std::string& scope, int busy, int wait) {
    const int s = declare(scope, "load", Kind::Real);
    signals_[size_t(busy)].load = signals_[size_t(wait)].load = int(loads_.size());
    loads_.push_back({s, busy, wait});
}

void VcdStream::open(const std::string& path, Picos from, Picos to, const std::string& name) {
    name_ = name.empty() ? path : name;
    out_.open(path, std::ios::binary | std::ios::trunc);
    if (!out_) throw std::runtime_error(name_ + ": cannot open for writing");
    from_ = from;
    to_ = to;
    windowEnd_ = loadWindowAfter(0);
    Scope root;
    codes_.clear();
    for (size_t i = 0; i < signals_.size(); ++i) codes_.push_back(code(i));
    for (size_t i = 0; i < signals_.size(); ++i) {
        Scope* s = &root;
        const std::string& path = signals_[i].scope;
        for (size_t a = 0; a <= path.size();) {
            const size_t dot = std::min(path.find('.', a), path.size());
            if (dot > a) s = &s->child(path.substr(a, dot - a));
            a = dot + 1;
        }
        s->signals.push_back(i);
    }
    buf_ = "$version rtsim $end\n$timescale 1ps $end\n$scope module machine $end\n";
    auto write = [&](const Scope& s, auto&& self) -> void {
        for (size_t i : s.signals) {
            const Signal& g = signals_[i];
            buf_ += g.kind == Kind::Bit ? "$var wire 1 " : g.kind == Kind::Integer ? "$var integer 32 " : "$var real 64 ";
            buf_ += code(i) + " " + g.name + " $end\n";
        }
        for (const auto& [name, c] : s.children) {
            buf_ += "$scope module " + name + " $end\n";
            self(c, self);
            buf_ += "$upscope $end\n";
        }
    };
    write(root, write);
    buf_ += "$upscope $end\n$enddefinitions $end\n";
    writeOut(true);
}

void VcdStream::add(Picos t, int signal, Op op, int64_t iv, double rv) {
    pending_.push_back({t, seq_++, signal, op, iv, rv});
    if (pending_.size() >= flushAt_ && horizon_) {
        flush(horizon_());
        flushAt_ = std::max(kMaxWaiting, 2 * pending_.size());  // (if little could go, not again at once)
    }
}

void VcdStream::accumulate(Load& l, Picos t) {
    if (t <= l.since) return;
    if (signals_[size_t(l.busy)].iv) l.busyTime += t - l.since;
    if (signals_[size_t(l.wait)].iv) l.waitTime += t - l.since;
    l.since = t;
}

void VcdStream::apply(const Change& c) {
    Signal& s = signals_[size_t(c.signal)];
    if (s.load >= 0) accumulate(loads_[size_t(s.load)], c.t);
    if (c.op == Op::Set) s.iv = c.iv;
    else if (c.op == Op::Step) s.iv += c.iv;
    else s.rv = c.rv;
}

void VcdStream::stamp(Picos t) {
    if (!started_) {  // the values at `from`, once
        started_ = true;
        buf_ += "#" + std::to_string(from_) + "\n";
        stamped_ = from_;
        for (Signal& s : signals_) {
            s.shown = false;
            show(s, from_);
        }
    }
    if (t != stamped_) {
        buf_ += "#" + std::to_string(t) + "\n";
        stamped_ = t;
    }
}

void VcdStream::show(Signal& s, Picos t) {
    (void)t;
    const std::string& c = codes_[size_t(&s - signals_.data())];
    if (s.kind == Kind::Real) {
        if (s.shown && s.rv == s.shownR) return;
        char b[40];
        const int n = std::snprintf(b, sizeof b, "r%.6g ", s.rv);
        buf_.append(b, size_t(n));
        s.shownR = s.rv;
    } else {
        if (s.shown && s.iv == s.shownI) return;
        if (s.kind == Kind::Bit) {
            buf_ += s.iv ? '1' : '0';
        } else {
            char b[40];
            char* p = b + sizeof b;
            *--p = ' ';
            uint32_t v = uint32_t(s.iv);
            do {
                *--p = char('0' + (v & 1));
                v >>= 1;
            } while (v);
            *--p = 'b';
            buf_.append(p, size_t(b + sizeof b - p));
        }
        s.shownI = s.iv;
    }
    buf_ += c;
    buf_ += '\n';
    s.shown = true;
}

void VcdStream::closeWindowsBefore(Picos t) {
    while (windowEnd_ <= t) {
        const Picos e = windowEnd_;
        const bool inside = e >= from_ && e <= to_;
        if (inside) stamp(e);
        for (Load& l : loads_) {
            accumulate(l, e);
            Signal& s = signals_[size_t(l.signal)];
            s.rv = l.busyTime + l.waitTime ? double(l.busyTime) / double(l.busyTime + l.waitTime) : 0.0;
            if (inside) show(s, e);
            l.busyTime = l.waitTime = 0;
        }
        windowEnd_ = loadWindowAfter(e);
    }
}

void VcdStream::flush(Picos horizon) {
    if (!out_.is_open()) return;
    std::sort(pending_.begin(), pending_.end(),
              [](const Change& a, const Change& b) { return a.t != b.t ? a.t < b.t : a.seq < b.seq; });
    size_t n = 0;
    std::vector<int> changed;
    auto finish = [&](Picos t) {  // the values at time t, once all its changes are applied
        if (changed.empty()) return;
        if (t >= from_ && t <= to_) {
            if (!started_ && t == from_) stamp(t);  // (the values at `from` include its changes)
            stamp(t);
            std::sort(changed.begin(), changed.end());
            changed.erase(std::unique(changed.begin(), changed.end()), changed.end());
            for (int i : changed) show(signals_[size_t(i)], t);
        }
        changed.clear();
    };
    while (n < pending_.size() && pending_[n].t < horizon) {
        const Picos t = pending_[n].t;
        closeWindowsBefore(t);
        // (A window ending at t was shown before t's changes: they do not
        // count in it.)
        if (t > from_ && !started_ && from_ <= to_) stamp(from_);  // nothing changed at `from` itself
        for (; n < pending_.size() && pending_[n].t == t; ++n) {
            apply(pending_[n]);
            changed.push_back(pending_[n].signal);
        }
        finish(t);
        if (buf_.size() > kWriteBytes) writeOut(false);
    }
    pending_.erase(pending_.begin(), pending_.begin() + long(n));
    if (horizon > 0 && horizon != ~Picos(0)) closeWindowsBefore(horizon - 1);
    writeOut(true);
}

void VcdStream::close(Picos end, const std::string& comment) {
    if (!out_.is_open()) return;
    to_ = std::min(to_, end);  // (a process may have recorded past the frame's end)
    flush(~Picos(0));
    closeWindowsBefore(end);
    // The last, partial window: up to the end.
    const Picos last = std::min(end, to_);
    if (last >= from_) {
        stamp(last);
        for (Load& l : loads_) {
            accumulate(l, end);
            Signal& s = signals_[size_t(l.signal)];
            if (l.busyTime + l.waitTime) s.rv = double(l.busyTime) / double(l.busyTime + l.waitTime);
            show(s, last);
        }
    }
    if (!comment.empty()) buf_ += "$comment " + comment + " $end\n";
    writeOut(true);
    out_.close();
    if (!out_) throw std::runtime_error(name_ + ": cannot write the VCD (" + std::strerror(errno) + ")");
}

void VcdStream::writeOut(bool force) {
    if (buf_.empty() || (!force && buf_.size() < kWriteBytes)) return;
    out_.write(buf_.data(), std::streamsize(buf_.size()));
    out_.flush();  // whole lines on disk: a run killed now leaves a valid VCD up to here
    // (A full disk: an error now, not a VCD that ends early and a run that says it succeeded.)
    if (!out_) throw std::runtime_error(name_ + ": cannot write the VCD (" + std::strerror(errno) + ")");
    buf_.clear();
}

}  // namespace rt
