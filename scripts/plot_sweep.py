#!/usr/bin/python3
"""Draws any sweep's CSV (scripts/sweep.py NAME ..., or an experiment's
doc/results/*.csv): y against x, one line per group, log axes where the
values span a decade or more, and each line's knees marked: where it first
reaches 1.1 x and 2 x its best (lowest) value, found by linear interpolation
between the points around them (in log x on a log axis). The knees are also
printed, so that "below what link bandwidth does the frame take 10 % longer"
is read off as a number. x values with units (100MB/s, 2us) are read as
quantities. Run with /usr/bin/python3 (Debian's python3-matplotlib)."""
import argparse
import math
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from project import pyplot  # noqa: E402
from sweep import read_csv  # noqa: E402

# Units rtsim's flags take (tb/option_parsers.cpp): times and rates.
UNITS = {"ps": 1e-12, "ns": 1e-9, "us": 1e-6, "ms": 1e-3, "s": 1.0,
         "B/s": 1.0, "KB/s": 1e3, "MB/s": 1e6, "GB/s": 1e9, "TB/s": 1e12,
         "b/s": 1 / 8, "Kb/s": 1e3 / 8, "Mb/s": 1e6 / 8, "Gb/s": 1e9 / 8}
KNEES = (1.1, 2.0)  # +10 % and x2 of a line's best value
DECADE = 10.0       # values spanning this ratio or more get a log axis


def split(text):
    """'100MB/s' -> (100.0, 'MB/s'), '4' -> (4.0, ''); None if not a number with a unit rtsim takes."""
    m = re.fullmatch(r"\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*([A-Za-z/]*)\s*", str(text))
    if not m or (m.group(2) and m.group(2) not in UNITS):
        return None
    return float(m.group(1)), m.group(2)


def quantity(text):
    """'100MB/s' -> 1e8 (B/s), '2us' -> 2e-6 (s), '4' -> 4.0; None if not a number."""
    q = split(text)
    return q[0] * UNITS.get(q[1], 1.0) if q else None


def in_units_of(value, sample):
    """`value` (SI base units) written in the unit of the x value `sample` ('100MB/s' -> '971.3MB/s')."""
    unit = (split(sample) or (0, ""))[1]
    return f"{value / UNITS[unit]:.4g}{unit}" if unit else f"{value:.4g}"


def base_unit(sample):
    """The axis label's unit for x values like `sample`: ' (B/s)' for rates, ' (s)' for times."""
    unit = (split(sample) or (0, ""))[1]
    return "" if not unit else " (B/s)" if unit.endswith("/s") else " (s)"


def spans_decades(values):
    vals = [v for v in values if v is not None]
    return bool(vals) and min(vals) > 0 and max(vals) / min(vals) >= DECADE


def knee(xs, ys, level, logx):
    """The x at which a line, walked from its best point outward, first
    reaches `level`: on the side of smaller x first (slower links, fewer
    nodes), else the other; None where it never does."""
    best = min(range(len(ys)), key=lambda i: ys[i])
    if not ys[best] < level:
        return None
    for step in (-1, 1):
        i = best
        while 0 <= i + step < len(ys):
            j = i + step
            if ys[j] >= level:  # ys[i] < level <= ys[j]
                t = (level - ys[i]) / (ys[j] - ys[i])
                a, b = (math.log(xs[i]), math.log(xs[j])) if logx else (xs[i], xs[j])
                return math.exp(a + t * (b - a)) if logx else a + t * (b - a)
            i = j
    return None


def lines_of(rows, x, ys, group):
    """{label: (xs, ys)} sorted by x; x as quantities where every value is one."""
    out = {}
    for col in ys:
        for r in rows:
            if r.get(col, "") == "":
                continue
            label = " ".join(s for s in ((f"{group}={r[group]}" if group else ""), (col if len(ys) > 1 else "")) if s)
            out.setdefault(label or col, []).append((quantity(r[x]), r[x], float(r[col])))
    for label, pts in out.items():
        if any(p[0] is None for p in pts):
            raise ValueError(f"--x {x}: '{next(p[1] for p in pts if p[0] is None)}' is not a number or quantity")
        pts.sort()
        out[label] = ([p[0] for p in pts], [p[2] for p in pts], [p[1] for p in pts])
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("csv", help="a sweep's CSV (out/sweeps/NAME.csv)")
    ap.add_argument("--x", required=True, help="the column along x (a swept flag, say link-bandwidth)")
    ap.add_argument("--y", default="render_time_ns", help="the column(s) along y, comma-separated (default render_time_ns)")
    ap.add_argument("--group", help="one line per value of this column")
    ap.add_argument("--where", action="append", default=[], metavar="COL=V", help="keep only rows with COL = V")
    ap.add_argument("--out", help="the PNG (default: the CSV's name with the columns, .png)")
    ap.add_argument("--title")
    a = ap.parse_args()
    rows = read_csv(a.csv)
    if not rows:
        ap.error(f"{a.csv}: no rows")
    ys = a.y.split(",")
    for col in [a.x] + ys + ([a.group] if a.group else []) + [w.partition("=")[0] for w in a.where]:
        if col not in rows[0]:
            ap.error(f"{a.csv}: no column '{col}' (there are: {', '.join(rows[0])})")
    for w in a.where:
        col, _, val = w.partition("=")
        rows = [r for r in rows if r[col] == val]
    try:
        lines = lines_of(rows, a.x, ys, a.group)
    except ValueError as e:
        ap.error(str(e))
    logx = spans_decades(x for xs, _, _ in lines.values() for x in xs)
    logy = spans_decades(y for _, yv, _ in lines.values() for y in yv)
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for label, (xs, yv, shown) in lines.items():
        (line,) = ax.plot(xs, yv, "o-", label=label, markersize=4)
        for level, mark in zip(KNEES, ("v", "X")):
            k = knee(xs, yv, level * min(yv), logx)
            if k is not None:
                ax.plot([k], [level * min(yv)], mark, color=line.get_color(), markersize=9)
            where = in_units_of(k, shown[0]) if k is not None else "not reached"
            print(f"{label}: best {min(yv):.6g} at {a.x}={shown[yv.index(min(yv))]}; "
                  f"x{level:g} of it at {a.x} = {where}")
    ax.set_xscale("log" if logx else "linear")
    ax.set_yscale("log" if logy else "linear")
    ax.set_xlabel(a.x + base_unit(rows[0][a.x]))
    ax.set_ylabel(", ".join(ys))
    ax.plot([], [], "kv", label="1.1 x the line's best")
    ax.plot([], [], "kX", label="2 x the line's best")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3, which="both")
    ax.set_title(a.title or os.path.basename(a.csv), fontsize=10)
    out = a.out or os.path.splitext(a.csv)[0] + f"-{a.x}-{'-'.join(ys)}.png"
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    print(f"chart -> {out}")


if __name__ == "__main__":
    main()
