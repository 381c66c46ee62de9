#!/usr/bin/python3
"""Waveforms without a GUI: reads an rtsim VCD (--vcd) and prints, per
traced node, its busy share over time windows, and per traced link, its
wire's busy share over the same windows and the time the wire was busy
with messages waiting for it (`backlog` above 0 while `wire` is), the
links ranked by that time, the top ones first. The windows cut the traced
span (the VCD's first to last time) in --windows equal parts. A bottleneck
shows as a link whose wire is busy and backlogged through the windows in
which the nodes downstream of it wait (doc/machine.md, "Finding a
bottleneck"). Times are read in the VCD's $timescale and printed in real
units. Standard library only (Debian has no VCD reader for Python): it
reads the declarations and value changes of IEEE 1364 VCD (scopes, scalar
and vector wires, integers, reals; $comment, $date and $version blocks,
one line or several), and answers anything else with one line naming the
file and line. Run with /usr/bin/python3."""
import argparse
import contextlib
import io
import itertools
import os
import re
import sys
from collections import defaultdict

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import outputs  # noqa: E402
from outputs import ToolError, check_input, guard, one_line_errors  # noqa: E402

WANTED = {"busy", "wait", "wire", "backlog"}
SECONDS = {"s": 1.0, "ms": 1e-3, "us": 1e-6, "ns": 1e-9, "ps": 1e-12, "fs": 1e-15}
TIMESCALE_RE = re.compile(r"(1|10|100)\s*(s|ms|us|ns|ps|fs)")
# Declaration blocks whose text is free (and may span lines): skipped.
FREE_TEXT = {"$comment", "$date", "$version"}
# Commands of the value-change section that only bracket value changes.
BRACKETS = {"$dumpvars", "$dumpall", "$dumpon", "$dumpoff", "$end"}
SCALAR = set("01xzXZ")


def lines(path, ends=None):
    """(line number, words) of the file's lines; a line that is not
    ASCII/UTF-8 text is refused with its line. `ends`, a list, gets whether
    the last line ended with a newline (rtsim ends every line: a file that
    does not was cut short)."""
    with open(path, "rb") as f:
        for n, raw in enumerate(f, 1):
            if ends is not None:
                ends[:] = [raw.endswith(b"\n")]
            try:
                yield n, raw.decode("utf-8").split()
            except UnicodeDecodeError:
                raise ToolError(f"{path}:{n}: bytes that are not text (a VCD is ASCII)")


class Reader:
    """The signals named busy, wait, wire and backlog of a VCD, with their
    changes in time order, in ticks of `seconds_per_tick` (None: the file
    gave no $timescale)."""

    def __init__(self, path):
        self.path = path
        self.declared = set()            # every identifier code declared
        self.names = defaultdict(list)   # identifier code -> the wanted signals' paths
        self.changes = defaultdict(list)  # signal path -> [(tick, value)]
        self.seconds_per_tick = None
        self.first = self.last = None    # the first and last time stamps
        self.incomplete = None           # rtsim's "$comment incomplete: WHY $end": the run stopped early
        self.ended = [True]              # the last line ended with a newline (lines())
        self.source = lines(path, self.ended)
        self.stream = self.tokens()
        self.n = 0
        self.rest = (0, [], 0)  # the line the header ended on: its number, its words, the first not read

    def tokens(self):
        """(line number, word) of the words left in the file."""
        for n, words in self.source:
            for i, w in enumerate(words):
                self.rest = (n, words, i + 1)
                yield n, w

    def fail(self, what):
        raise ToolError(f"{self.path}:{self.n}: {what}")

    def next_token(self, inside):
        for self.n, tok in self.stream:
            return tok
        raise ToolError(f"{self.path}:{self.n}: the file ends inside {inside}")

    def until_end(self, command):
        """The words of a declaration up to its $end."""
        words = []
        while True:
            tok = self.next_token(command)
            if tok == "$end":
                return words
            words.append(tok)

    def read(self):
        self.header()
        self.body()
        return self

    def header(self):
        scope = []
        for self.n, tok in self.stream:
            if tok in FREE_TEXT:
                self.until_end(tok)
            elif tok == "$timescale":
                self.timescale(" ".join(self.until_end(tok)))
            elif tok == "$scope":
                words = self.until_end(tok)
                if len(words) != 2:
                    self.fail(f"$scope {' '.join(words)[:40]}: expected a kind and a name")
                scope.append(words[1])
            elif tok == "$upscope":
                self.until_end(tok)
                if not scope:
                    self.fail("$upscope without a $scope to close")
                scope.pop()
            elif tok == "$var":
                self.var(self.until_end(tok), scope)
            elif tok == "$enddefinitions":
                self.until_end(tok)
                if scope:  # (its signals' names would be wrong, or missing from the summary)
                    self.fail(f"$enddefinitions with $scope {scope[-1][:40]} not closed by its $upscope")
                return
            else:
                self.fail(f"'{tok[:40]}' in the declarations (expected $scope, $var, $upscope, ... $enddefinitions)")
        raise ToolError(f"{self.path}: no $enddefinitions (not a VCD, or cut short in its header)")

    def timescale(self, text):
        m = TIMESCALE_RE.fullmatch(text.strip())
        if not m:
            self.fail(f"$timescale '{text[:40]}': expected 1, 10 or 100 and s, ms, us, ns, ps or fs")
        self.seconds_per_tick = int(m.group(1)) * SECONDS[m.group(2)]

    def var(self, words, scope):
        # $var TYPE SIZE CODE REFERENCE [RANGE] $end
        if len(words) < 4:
            self.fail(f"$var {' '.join(words)[:40]}: expected a type, a size, a code and a name")
        code, ref = words[2], words[3]
        self.declared.add(code)
        if ref in WANTED:
            # rtsim's machine/node_X_Y_Z[/LINK]/SIGNAL: the top scope left out.
            self.names[code].append("/".join(scope[1:] + [ref]))

    def body(self):
        # Line by line, the common changes inline and in local names: a VCD
        # has nearly all its lines here. A vector's or a real's code is on
        # its value's line.
        sinks = {code: [self.changes[name] for name in names] for code, names in self.names.items()}
        declared = self.declared
        free = None  # the $comment (or $date, $version) whose $end is still to come
        comment = []  # its words
        # The words after $enddefinitions $end on its line first (a VCD
        # may be all on one line), then the lines after it.
        n, words, i = self.rest
        for self.n, words in itertools.chain([(n, words[i:])], self.source):
            i = 0
            while i < len(words):
                tok = words[i]
                i += 1
                if free:
                    if tok != "$end":
                        comment.append(tok)
                        continue
                    if free == "$comment" and comment[:1] == ["incomplete:"]:
                        self.incomplete = " ".join(comment[1:])
                    free, comment = None, []
                    continue
                c = tok[0]
                if c == "#":
                    self.time(tok)
                    continue
                if c in SCALAR:
                    code, value = tok[1:], 1 if c == "1" else 0
                elif c in "bBrR":
                    if i == len(words):
                        self.fail(f"'{tok[:40]}': a value without its identifier code on its line")
                    code, value = words[i], self.vector(tok) if c in "bB" else self.real(tok)
                    i += 1
                elif tok in FREE_TEXT:
                    free = tok
                    continue
                elif tok in BRACKETS:
                    continue
                else:
                    self.fail(f"'{tok[:40]}': not a value change or a time")
                to = sinks.get(code)
                if to is None and code not in declared:
                    self.fail(f"a change of '{code[:20]}', which no $var declares")
                if self.last is None:
                    self.fail("a value change before the first time (#T)")
                for changes in to or ():
                    changes.append((self.last, value))
        if free:
            self.fail(f"the file ends inside {free}")

    def vector(self, tok):
        bits = tok[1:]
        if bits and not bits.strip("01"):
            return int(bits, 2)
        if bits and not bits.strip("01xzXZ"):
            return 0  # x or z in it: not busy
        self.fail(f"'{tok[:40]}': not a binary value")

    def real(self, tok):
        try:
            return float(tok[1:])
        except ValueError:
            self.fail(f"'{tok[:40]}': not a real value")

    def time(self, tok):
        # ASCII digits only ('#²' is isdigit() and not int()), and a time a
        # 64-bit counter holds: a longer one overflowed the windows' width.
        digits = tok[1:]
        if not (digits.isascii() and digits.isdigit()) or len(digits) > 19 or int(digits) >= 2 ** 63:
            self.fail(f"'{tok[:40]}': not a time (# and a whole number below 2^63)")
        t = int(digits)
        if self.last is not None and t < self.last:
            self.fail(f"time #{t} after #{self.last}: times go forward")
        if self.first is None:
            self.first = t
        self.last = t


def read(path):
    """The VCD's wanted signals and span: (Reader, ToolError on bad input)."""
    return Reader(path).read()


def spans(ch, end):
    """[(from, to, value)] of a signal's changes up to `end`."""
    out = []
    for (t0, v), (t1, _) in zip(ch, ch[1:] + [(end, None)]):
        if t1 > t0:
            out.append((t0, t1, v))
    return out


def per_window(intervals, start, width, k):
    """The time covered by `intervals` [(from, to)] in each of k windows."""
    w = [0.0] * k
    for a, b in intervals:
        i = max(0, int((a - start) // width))
        while i < k and start + i * width < b:
            lo, hi = max(a, start + i * width), min(b, start + (i + 1) * width)
            if hi > lo:
                w[i] += hi - lo
            i += 1
    return w


def overlap(a, b):
    """Intervals where both lists of [(from, to)] (each in time order, not overlapping) hold."""
    out, i, j = [], 0, 0
    while i < len(a) and j < len(b):
        lo, hi = max(a[i][0], b[j][0]), min(a[i][1], b[j][1])
        if hi > lo:
            out.append((lo, hi))
        if a[i][1] < b[j][1]:
            i += 1
        else:
            j += 1
    return out


def summarise(changes, start, end, k):
    """Per node its busy intervals; per link its wire-busy and saturated
    intervals; the windows' width (the span is not empty)."""
    width = (end - start) / k
    nodes, links = {}, {}
    for name, ch in changes.items():
        if "/" not in name:
            continue  # a signal outside any node's scope: not rtsim's layout
        owner, sig = name.rsplit("/", 1)
        on = [(a, b) for a, b, v in spans(ch, end) if v > 0]
        if sig == "busy" and "/" not in owner:
            nodes[owner] = on
        elif sig in ("wire", "backlog") and "/" in owner:
            links.setdefault(owner, {})[sig] = on
    return width, nodes, links


def link_name(owner):
    """node_1_0_2/py -> node_1_0_2_py, as the report names it."""
    return owner.replace("/", "_")


def time_text(ticks, seconds_per_tick):
    """A time in ticks, in the unit that suits it ('1.5 us'); in ticks if
    the VCD gave no $timescale."""
    if seconds_per_tick is None:
        return f"{ticks:.6g} ticks"
    if ticks == 0:
        return "0"
    s = ticks * seconds_per_tick
    for unit in ("s", "ms", "us", "ns", "ps"):
        # (10 ps ticks: 100 of them are 1 ns, not 999.999... ps)
        if abs(s) >= SECONDS[unit] * (1 - 1e-9) or unit == "ps":
            return f"{s / SECONDS[unit]:.6g} {unit}"


def parse_args(argv):
    ap = one_line_errors(argparse.ArgumentParser(description=__doc__.split("\n\n")[0]))
    ap.add_argument("vcd", help="a VCD written by rtsim --vcd")
    ap.add_argument("--windows", type=int, default=10, help="time windows across the traced span (default 10)")
    ap.add_argument("--top", type=int, default=5, help="links listed (default 5; 0: all)")
    a = ap.parse_args(argv)
    if not 1 <= a.windows <= 1000:
        raise ToolError(f"--windows {a.windows}: 1 to 1000")
    if a.top < 0:
        raise ToolError(f"--top {a.top}: 0 (all) or more")
    return a


def print_nodes(nodes, start, width, span, k):
    print("\nnodes: busy share per window | over the span")
    for name in sorted(nodes):
        w = per_window(nodes[name], start, width, k)
        total = sum(b - a for a, b in nodes[name])
        print(f"  {name:16} " + " ".join(f"{x / width:4.2f}" for x in w) + f" | {total / span:.2f}")


def print_links(links, start, width, span, k, top):
    ranked = []
    for owner, sig in links.items():
        wire, backlog = sig.get("wire", []), sig.get("backlog", [])
        sat = overlap(wire, backlog)
        ranked.append((sum(b - a for a, b in sat), owner, wire, sat))
    ranked.sort(key=lambda x: (-x[0], x[1]))
    shown = ranked if top == 0 else ranked[:top]
    print(f"\nlinks, by time busy with a backlog: wire busy share per window | busy | backlogged "
          f"({len(shown)} of {len(ranked)})")
    for sat_t, owner, wire, sat in shown:
        w = per_window(wire, start, width, k)
        busy = sum(b - a for a, b in wire)
        print(f"  {link_name(owner):18} " + " ".join(f"{x / width:4.2f}" for x in w) +
              f" | {busy / span:.2f} | {sat_t / span:.2f}")



def main(argv=None):
    a = parse_args(argv)
    if sys.stdout is None or outputs.stdout_closed:  # >&-: Python gives no stdout at all
        raise ToolError("stdout is closed: nowhere to print the summary")
    # Printed whole at the end, so that stdout's failure is met in one place.
    text = io.StringIO()
    with contextlib.redirect_stdout(text):
        summarise_file(a)
    outputs.deliver(text.getvalue(), "the summary is not written")
    return 0


def summarise_file(a):
    vcd = read(check_input(a.vcd, "VCD"))
    if not vcd.names:
        raise ToolError(f"{a.vcd}: no busy, wait, wire or backlog signal changes in it (not an rtsim VCD?)")
    if vcd.first is None:
        # rtsim writes its declarations alone for a --trace-window after the run's end.
        print(f"{a.vcd}: no time and no value change after the declarations: nothing was traced "
              f"(a --trace-window after the run's end?)")
        return
    tick = vcd.seconds_per_tick
    start, end = vcd.first, vcd.last
    if end == start:
        # rtsim writes one for --trace-window T,T: a state, no span to share out.
        print(f"{a.vcd}: the traced span is empty (from {time_text(start, tick)} to {time_text(end, tick)}): "
              f"no shares to give")
        return
    width, nodes, links = summarise(vcd.changes, start, end, a.windows)
    span = end - start
    scale = "" if tick is not None else " (no $timescale: times in the VCD's ticks)"
    print(f"{a.vcd}: {time_text(span, tick)} traced ({time_text(start, tick)} to {time_text(end, tick)}), "
          f"{a.windows} windows of {time_text(width, tick)}; shares of each window{scale}")
    if vcd.incomplete is not None:
        print(f"incomplete: the run that wrote it stopped early ({vcd.incomplete}): the shares are of what it traced")
    if not vcd.ended[0]:
        print("incomplete: its last line has no newline (the file was cut short?): the last time may be partial")
    if nodes:
        print_nodes(nodes, start, width, span, a.windows)
    if links:
        print_links(links, start, width, span, a.windows, a.top)
    if not nodes and not links:
        print("\nno node's busy or link's wire in rtsim's layout (machine/node_X_Y_Z[/LINK]/SIGNAL)")


if __name__ == "__main__":
    sys.exit(guard("vcd_summary", main))
