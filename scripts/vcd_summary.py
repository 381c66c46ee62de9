#!/usr/bin/python3
"""Waveforms without a GUI: reads an rtsim VCD (--vcd) and prints, per
traced node, its busy share over time windows, and per traced link, its
wire's busy share over the same windows and the time the wire was busy
with messages waiting for it (`backlog` above 0 while `wire` is), the
links ranked by that time, the top ones first. The windows cut the traced
span (the VCD's first to last time) in --windows equal parts. A bottleneck
shows as a link whose wire is busy and backlogged through the windows in
which the nodes downstream of it wait (doc/machine.md, "Finding a
bottleneck"). Standard library only (Debian has no VCD reader for Python;
the format read is the subset rtsim writes: scopes, 1-bit wires, integers,
reals). Run with /usr/bin/python3."""
import argparse
import sys
from collections import defaultdict


class VcdError(Exception):
    pass


def read(path):
    """{signal path: [(time, value)]} for the signals named busy, wait,
    wire and backlog, and the last time in the file."""
    ids, scope, changes, t, last = {}, [], defaultdict(list), 0, 0
    wanted = {"busy", "wait", "wire", "backlog"}
    with open(path, errors="replace") as f:
        header = True
        for n, line in enumerate(f, 1):
            tok = line.split()
            if not tok:
                continue
            if header:
                if tok[0] == "$scope" and len(tok) >= 3:
                    scope.append(tok[2])
                elif tok[0] == "$upscope":
                    scope.pop()
                elif tok[0] == "$var" and len(tok) >= 5 and tok[4] in wanted:
                    ids.setdefault(tok[3], []).append("/".join(scope[1:] + [tok[4]]))
                elif tok[0] == "$enddefinitions":
                    header = False
                continue
            c = tok[0][0]
            try:
                if c == "#":
                    t = int(tok[0][1:])
                    last = max(last, t)
                elif c in "01xz":
                    for name in ids.get(tok[0][1:], ()):
                        changes[name].append((t, 1 if c == "1" else 0))
                elif c in "bB":
                    for name in ids.get(tok[1], ()):
                        changes[name].append((t, int(tok[0][1:], 2) if set(tok[0][1:]) <= {"0", "1"} else 0))
            except (ValueError, IndexError):
                raise VcdError(f"{path}:{n}: not a value change: {line.strip()[:60]}")
    if header:
        raise VcdError(f"{path}: no $enddefinitions (not a VCD, or cut short in its header)")
    return changes, last


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


def summarise(changes, end, k):
    """Per node its busy intervals; per link its wire-busy and saturated
    intervals; the windows' start and width."""
    starts = [ch[0][0] for ch in changes.values() if ch]
    start = min(starts) if starts else 0
    width = max(1, (end - start)) / k
    nodes, links = {}, {}
    for name, ch in changes.items():
        owner, sig = name.rsplit("/", 1)
        on = [(a, b) for a, b, v in spans(ch, end) if v > 0]
        if sig == "busy" and "/" not in owner:
            nodes[owner] = on
        elif sig in ("wire", "backlog") and "/" in owner:
            links.setdefault(owner, {})[sig] = on
    return start, width, nodes, links


def link_name(owner):
    """node_1_0_2/py -> node_1_0_2_py, as the report names it."""
    return owner.replace("/", "_")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("vcd", help="a VCD written by rtsim --vcd")
    ap.add_argument("--windows", type=int, default=10, help="time windows across the traced span (default 10)")
    ap.add_argument("--top", type=int, default=5, help="links listed (default 5; 0: all)")
    a = ap.parse_args()
    if not 1 <= a.windows <= 1000:
        ap.error(f"--windows {a.windows}: 1 to 1000")
    try:
        changes, end = read(a.vcd)
    except OSError as e:
        sys.exit(f"vcd_summary: {a.vcd}: {e.strerror}")
    except VcdError as e:
        sys.exit(f"vcd_summary: {e}")
    if not changes:
        sys.exit(f"vcd_summary: {a.vcd}: no busy, wait, wire or backlog signal in it")
    start, width, nodes, links = summarise(changes, end, a.windows)
    span = end - start
    print(f"{a.vcd}: {span / 1e6:.6g} us traced ({start / 1e6:.6g} to {end / 1e6:.6g} us), {a.windows} windows of "
          f"{width / 1e6:.4g} us; shares of each window")
    if nodes:
        print("\nnodes: busy share per window | over the span")
        for name in sorted(nodes):
            w = per_window(nodes[name], start, width, a.windows)
            total = sum(b - a_ for a_, b in nodes[name])
            print(f"  {name:16} " + " ".join(f"{x / width:4.2f}" for x in w) + f" | {total / span:.2f}")
    ranked = []
    for owner, sig in links.items():
        wire, backlog = sig.get("wire", []), sig.get("backlog", [])
        sat = overlap(wire, backlog)
        ranked.append((sum(b - a_ for a_, b in sat), owner, wire, sat))
    ranked.sort(key=lambda x: (-x[0], x[1]))
    if ranked:
        shown = ranked if a.top == 0 else ranked[:a.top]
        print(f"\nlinks, by time busy with a backlog: wire busy share per window | busy | backlogged "
              f"({len(shown)} of {len(ranked)})")
        for sat_t, owner, wire, sat in shown:
            w = per_window(wire, start, width, a.windows)
            busy = sum(b - a_ for a_, b in wire)
            print(f"  {link_name(owner):18} " + " ".join(f"{x / width:4.2f}" for x in w) +
                  f" | {busy / span:.2f} | {sat_t / span:.2f}")


if __name__ == "__main__":
    main()
