#!/usr/bin/python3
"""Draws any sweep's CSV (scripts/sweep.py NAME ..., or an experiment's
doc/results/*.csv): y against x, one line per group, log axes where the
values span a decade or more, and each line's knees marked: where, walked
from a reference point (--reference: by default the point at the largest
x, the fast end of a bandwidth sweep), it first reaches 1.1 x and 2 x the
reference's value, found by linear interpolation between the points around
them (in log x on a log axis). The reference and the knees are printed, so
that "below what link bandwidth does the frame take 10 % longer than with
fast links" is read off as a number. x values with units (100MB/s, 2us) are
read as quantities; known columns are drawn in words and units
(render_time_ns as "render time (us)"). A NaN or infinite value is no
point: it is left out of the line, its best and its knees, and said so.
The chart goes to out/plots/ unless --out names a path (into doc/ only
with --doc). Run with /usr/bin/python3 (Debian's python3-matplotlib)."""
import argparse
import contextlib
import csv
import io
import math
import os
import re
import sys
import warnings

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import outputs  # noqa: E402
from outputs import (ToolError, check_distinct, check_input, check_output, guard, one_line_errors, out_path,  # noqa: E402
                     savefig)
from project import pyplot  # noqa: E402

# Units rtsim's flags take (models/base/units.cpp, parseTime and parseRate): times and rates.
UNITS = {"ps": 1e-12, "ns": 1e-9, "us": 1e-6, "ms": 1e-3, "s": 1.0,
         "B/s": 1.0, "KB/s": 1e3, "MB/s": 1e6, "GB/s": 1e9, "TB/s": 1e12,
         "b/s": 1 / 8, "Kb/s": 1e3 / 8, "Mb/s": 1e6 / 8, "Gb/s": 1e9 / 8, "Tb/s": 1e12 / 8}
KNEES = (1.1, 2.0)  # +10 % and x2 of a line's reference value
DECADE = 10.0       # values spanning this ratio or more get a log axis
FORMATS = ("png", "svg", "pdf")

# Known columns in words and units: column -> (words in a legend, the
# quantity an axis names, the unit shown, the factor from the column's
# value to that unit). An x column's value with a unit (100MB/s) is first
# read in SI (B/s, s). Columns not here are shown as given.
KNOWN = {
    "render_time_ns": ("render time", "render time", "us", 1e-3),
    "time_none_ns": ("without balancing", "render time", "us", 1e-3),
    "time_one_ns": ("on one node", "render time", "us", 1e-3),
    "one_node_ns": ("on one node", "render time", "us", 1e-3),
    "balance_ratio": ("time / time without balancing", "time / time without balancing", "", 1.0),
    "balance_gain": ("balancing gain (time without / with)", "balancing gain", "", 1.0),
    "speedup": ("speed-up (one node's time / the mesh's)", "speed-up", "", 1.0),
    "wall_s": ("wall time", "wall time", "s", 1.0),
    "busiest_node_busy": ("busiest node's busy share", "share of the render time", "", 1.0),
    "busiest_link_utilisation": ("busiest link's utilisation", "utilisation", "", 1.0),
    "link-bandwidth": ("link bandwidth", "link bandwidth", "MB/s", 1e-6),
    "bandwidth": ("link bandwidth", "link bandwidth", "MB/s", 1e-6),
    "link-latency": ("link latency", "link latency", "us", 1e6),
    "latency": ("link latency", "link latency", "us", 1e6),
    "mesh": ("mesh (nodes per side)", "nodes per side", "", 1.0),
    "N": ("nodes per side", "nodes per side", "", 1.0),
}
# What a bare x value of these columns is in (a unit's dimension must match).
SI_UNIT = {"MB/s": "B/s", "us": "s"}


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
    """The SI unit of x values like `sample`: 'B/s' for rates, 's' for times, '' for numbers."""
    unit = (split(sample) or (0, ""))[1]
    return "" if not unit else "B/s" if unit.endswith("/s") else "s"


def spans_decades(values):
    vals = [v for v in values if v is not None]
    return bool(vals) and min(vals) > 0 and max(vals) / min(vals) >= DECADE


class Table:
    """A CSV read and checked: its columns and its rows, each row a dict
    with the line it starts on."""

    def __init__(self, path):
        self.path = path
        self.columns, self.rows, self.lines = [], [], []
        self.read()

    def fail(self, line, what):
        raise ToolError(f"{self.path}:{line}: {what}")

    def text(self):
        with open(self.path, "rb") as f:
            data = f.read()
        try:
            return data.decode("utf-8")
        except UnicodeDecodeError as e:
            self.fail(data[:e.start].count(b"\n") + 1, "bytes that are not UTF-8 text")

    def read(self):
        reader = csv.reader(io.StringIO(self.text(), newline=""))
        try:
            for fields in reader:
                if not fields:  # a blank line
                    continue
                if not self.columns:
                    self.header(reader.line_num, fields)
                elif len(fields) != len(self.columns):
                    self.fail(reader.line_num, f"{len(fields)} fields, the header has {len(self.columns)} "
                                               f"(a row cut short or run together?)")
                else:
                    self.rows.append(dict(zip(self.columns, fields)))
                    self.lines.append(reader.line_num)
        except csv.Error as e:
            self.fail(reader.line_num + 1, f"not CSV: {e}")
        if not self.columns:
            raise ToolError(f"{self.path}: empty (no header)")
        if not self.rows:
            raise ToolError(f"{self.path}: no rows")

    def header(self, line, fields):
        for i, name in enumerate(fields):
            if not name.strip():
                self.fail(line, f"column {i + 1} has no name")
            if name in fields[:i]:
                self.fail(line, f"column '{name}' twice")
        self.columns = fields

    def has(self, col, flag):
        if col not in self.columns:
            raise ToolError(f"{self.path}: {flag}: no column '{col}' (there are: {', '.join(self.columns)})")

    def keep(self, col, value):
        """Only the rows with `col` = `value`; none left is bad input."""
        kept = [(r, n) for r, n in zip(self.rows, self.lines) if r[col] == value]
        if not kept:
            seen = sorted({r[col] for r in self.rows})
            raise ToolError(f"{self.path}: --where {col}={value}: no row has it ({col} is one of: "
                            f"{', '.join(seen[:10])}{', ...' if len(seen) > 10 else ''})")
        self.rows, self.lines = [r for r, _ in kept], [n for _, n in kept]


def number(table, row, line, col):
    """A y value: a float (NaN and inf included: the caller leaves them
    out), None for an empty field; anything else is named."""
    text = row[col].strip()
    if text == "":
        return None
    try:
        return float(text)
    except ValueError:
        table.fail(line, f"column '{col}': '{row[col][:40]}' is not a number")


class Line:
    """One line of the chart: its points (x in SI, y as in the CSV, the x
    as written, the CSV line) in x order, and the points left out."""

    def __init__(self, label, col):
        self.label, self.col, self.points, self.left_out = label, col, [], []

    @property
    def xs(self):
        return [p[0] for p in self.points]

    @property
    def ys(self):
        return [p[1] for p in self.points]


def lines_of(table, x, ys, group):
    """{label: Line}; x as quantities; NaN, inf and empty y left out, said."""
    out, first = {}, None  # (first: the first row's x, whose kind of quantity every x must share)
    for row, line in zip(table.rows, table.lines):
        xq = quantity(row[x])
        if xq is None or not math.isfinite(xq):
            table.fail(line, f"column '{x}' (--x): '{row[x][:40]}' is not a number or quantity")
        first = first or (row[x], line)
        if base_unit(row[x]) != base_unit(first[0]):
            kinds = {"B/s": "a rate", "s": "a time", "": "a bare number"}
            table.fail(line, f"column '{x}' (--x): '{row[x][:40]}' is {kinds[base_unit(row[x])]}, where line {first[1]}'s "
                             f"'{first[0][:40]}' is {kinds[base_unit(first[0])]}: one axis, one kind of quantity")
        for col in ys:
            label = " ".join(s for s in ((f"{group}={row[group]}" if group else ""),
                                         (words(col) if len(ys) > 1 else "")) if s) or words(col)
            ln = out.setdefault(label, Line(label, col))
            y = number(table, row, line, col)
            if y is None or not math.isfinite(y):
                ln.left_out.append(f"{x}={row[x]} (line {line}: {col} {'empty' if y is None else row[col].strip()})")
            else:
                ln.points.append((xq, y, row[x], line))
    for ln in out.values():
        ln.points.sort(key=lambda p: (p[0], p[3]))
    return out


def words(col):
    return KNOWN[col][0] if col in KNOWN else col


# A column not in KNOWN whose name ends in a unit: its values in that unit,
# shown in the unit that suits a frame's times.
SUFFIXES = {"_ns": ("us", 1e-3), "_us": ("us", 1.0), "_ms": ("ms", 1.0), "_s": ("s", 1.0)}


def known(col):
    """(words, quantity, unit shown, factor) of a column: KNOWN's, or its
    name's unit suffix (x_ns: us), or None."""
    if col in KNOWN:
        return KNOWN[col]
    for suffix, (unit, factor) in SUFFIXES.items():
        if col.endswith(suffix) and len(col) > len(suffix):
            return col, col[:-len(suffix)].replace("_", " "), unit, factor
    return None


def knee(xs, ys, level, logx, start=None):
    """The x at which a line, walked from point `start` (default: its best)
    outward, first reaches `level`: on the side of smaller x first (slower
    links, fewer nodes), else the other; None where it never does."""
    ref = min(range(len(ys)), key=lambda i: ys[i]) if start is None else start
    if not ys[ref] < level:
        return None
    for step in (-1, 1):
        i = ref
        while 0 <= i + step < len(ys):
            j = i + step
            if ys[j] >= level:  # ys[i] < level <= ys[j]
                t = (level - ys[i]) / (ys[j] - ys[i])
                a, b = (math.log(xs[i]), math.log(xs[j])) if logx else (xs[i], xs[j])
                return math.exp(a + t * (b - a)) if logx else a + t * (b - a)
            i = j
    return None


def reference_of(line, reference):
    """(index of the reference point, why it is the reference) or (None, why none)."""
    xs, ys = line.xs, line.ys
    if reference == "max-x":
        return len(xs) - 1, "the largest x"
    if reference == "min-x":
        return 0, "the smallest x"
    if reference == "best":
        i = min(range(len(ys)), key=lambda k: (ys[k], k))
        return i, "the best (lowest) value"
    want = quantity(reference)
    at = [i for i, x in enumerate(xs) if math.isclose(x, want, rel_tol=1e-9)]
    return (at[0], f"x = {reference}") if at else (None, f"no point at x = {reference}")


def parse_args(argv):
    ap = one_line_errors(argparse.ArgumentParser(description=__doc__.split("\n\n")[0]))
    ap.add_argument("csv", help="a sweep's CSV (out/sweeps/NAME.csv)")
    ap.add_argument("--x", required=True, help="the column along x (a swept flag, say link-bandwidth)")
    ap.add_argument("--y", default="render_time_ns", help="the column(s) along y, comma-separated (default render_time_ns)")
    ap.add_argument("--group", help="one line per value of this column")
    ap.add_argument("--where", action="append", default=[], metavar="COL=V", help="keep only rows with COL = V")
    ap.add_argument("--reference", default="max-x", metavar="max-x|min-x|best|X",
                    help="the point each line's knees are measured from: the largest x (default: the fast end of "
                         "a bandwidth sweep), the smallest x (of a latency sweep), the line's best (lowest) value, "
                         "or the point at x = X (say 16GB/s)")
    ap.add_argument("--out", help="the chart, .png, .svg or .pdf (default: out/plots/CSVNAME-X-Y.png)")
    ap.add_argument("--doc", action="store_true", help="allow --out under doc/")
    ap.add_argument("--title")
    a = ap.parse_args(argv)
    if a.group is not None and a.group == a.x:
        raise ToolError(f"--group {a.group}: the x column itself, a line per x value (its knees would be its own point)")
    if a.reference not in ("max-x", "min-x", "best") and quantity(a.reference) is None:
        raise ToolError(f"--reference {a.reference}: max-x, min-x, best or an x value (say 16GB/s)")
    for w in a.where:
        if "=" not in w:
            raise ToolError(f"--where {w}: expected COL=V")
    return a


def chart_path(a, ys):
    """The chart's path, checked before any drawing."""
    if a.out:
        path = check_output(a.out, "--out", doc=a.doc)
    else:
        stem = os.path.splitext(os.path.basename(a.csv))[0]
        name = re.sub(r"[^A-Za-z0-9_.-]", "_", f"{stem}-{a.x}-{'-'.join(ys)}")[:96].lstrip(".") + ".png"
        path = check_output(out_path("plots", name), "chart")
    check_distinct([("CSV", a.csv), ("--out", path)])
    fmt = os.path.splitext(path)[1].lstrip(".").lower()
    if fmt not in FORMATS:
        raise ToolError(f"--out {a.out}: the name must end in .png, .svg or .pdf")
    return path


def x_axis(col, sample):
    """(factor from x in SI to the axis's unit, the axis's label): a known
    column's words and unit when its values are of that unit's kind
    (link-bandwidth in MB/s), else the column as given, in SI."""
    unit = base_unit(sample)
    if col in KNOWN and SI_UNIT.get(KNOWN[col][2], "") == unit:
        _, name, shown, factor = KNOWN[col]
        return factor, f"{name} ({shown})" if shown else name
    return 1.0, f"{col} ({unit})" if unit else col


def y_axis(cols):
    """(factor from y to the axis's unit, the unit, the axis's label): the
    columns' quantity and unit if they are known and share them, else
    their names, as given."""
    found = {known(c)[1:] for c in cols if known(c)}
    if len(found) == 1 and all(known(c) for c in cols):
        name, unit, factor = found.pop()
        return factor, unit, f"{name} ({unit})" if unit else name
    return 1.0, "", ", ".join(words(c) for c in cols)


def shown_y(value, col):
    """A y value of column `col` in its unit (render_time_ns: '20693.8 us')."""
    factor, unit, _ = y_axis([col])
    return f"{value * factor:.6g}{' ' + unit if unit else ''}"


def report_line(a, ys, ln, logx):
    """Prints a line's reference, best and knees; returns [(x, y, marker)] to draw."""
    marks = []
    if ln.left_out:
        print(f"{ln.label}: left out (not a finite number): {'; '.join(ln.left_out)}")
    if not ln.points:
        print(f"{ln.label}: no point left to draw")
        return marks
    xs, yv, shown = ln.xs, ln.ys, [p[2] for p in ln.points]
    shared = sorted({p[0] for p, q in zip(ln.points, ln.points[1:]) if p[0] == q[0]})
    if shared:
        # Rows that differ in a column not drawn: one line through them
        # zigzags, and its best and knees mix them.
        first = [p for p in ln.points if p[0] == shared[0]]
        print(f"{ln.label}: more than one row at {len(shared)} values of {a.x} (at {first[0][2]}: lines "
              f"{', '.join(str(p[3]) for p in first)}): --group or --where picks one line per value of the others")
    best = min(range(len(yv)), key=lambda k: (yv[k], k))
    ref, why = reference_of(ln, a.reference)
    if ref is None:
        print(f"{ln.label}: best {shown_y(yv[best], ln.col)} at {a.x}={shown[best]}; {why}: no knees")
        return marks
    print(f"{ln.label}: reference {shown_y(yv[ref], ln.col)} at {a.x}={shown[ref]} ({why}); "
          f"best {shown_y(yv[best], ln.col)} at {a.x}={shown[best]}")
    marks.append((xs[ref], yv[ref], "o"))
    if not yv[ref] > 0:
        print(f"{ln.label}: the reference is not above 0: no knees")
        return marks
    for level, mark in zip(KNEES, ("v", "X")):
        k = knee(xs, yv, level * yv[ref], logx, ref)
        if k is not None:
            marks.append((k, level * yv[ref], mark))
        where = in_units_of(k, shown[0]) if k is not None else "not reached"
        print(f"{ln.label}: x{level:g} of it at {a.x} = {where}")
    return marks


def draw(a, ys, lines, path):
    sample = next(p[2] for ln in lines.values() for p in ln.points)
    xf, xlabel = x_axis(a.x, sample)
    yf, _, ylabel = y_axis(ys)
    logx = spans_decades(x for ln in lines.values() for x in ln.xs)
    logy = spans_decades(y for ln in lines.values() for y in ln.ys)
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for ln in lines.values():
        marks = report_line(a, ys, ln, logx)
        if not ln.points:
            continue
        (drawn,) = ax.plot([x * xf for x in ln.xs], [y * yf for y in ln.ys], "o-", label=literal(ln.label), markersize=4)
        for x, y, mark in marks:
            face = "none" if mark == "o" else drawn.get_color()
            ax.plot([x * xf], [y * yf], mark, color=drawn.get_color(), mfc=face, markersize=9 if mark != "o" else 11)
    ax.set_xscale("log" if logx else "linear")
    ax.set_yscale("log" if logy else "linear")
    ax.set_xlabel(literal(xlabel))
    ax.set_ylabel(literal(ylabel))
    why = {"max-x": "the largest x", "min-x": "the smallest x", "best": "the line's best"}.get(a.reference,
                                                                                            f"x = {a.reference}")
    ax.plot([], [], "ko", mfc="none", markersize=9, label=f"reference: {why}")
    ax.plot([], [], "kv", label="1.1 x the reference")
    ax.plot([], [], "kX", label="2 x the reference")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3, which="both")
    ax.set_title(literal(a.title or os.path.basename(a.csv)), fontsize=10)
    fig.tight_layout()
    savefig(fig, path, dpi=110)


def analyse(a):
    """The CSV read and checked, and its lines: (y columns, {label: Line})."""
    table = Table(check_input(a.csv, "CSV"))
    ys = a.y.split(",")
    table.has(a.x, "--x")
    for col in ys:
        table.has(col, "--y")
    if a.group:
        table.has(a.group, "--group")
    for w in a.where:
        col, _, val = w.partition("=")
        table.has(col, "--where")
        table.keep(col, val)
    lines = lines_of(table, a.x, ys, a.group)
    if not any(ln.points for ln in lines.values()):
        raise ToolError(f"{a.csv}: no finite value of {', '.join(ys)} to draw")
    return ys, lines


def literal(text):
    """`text` drawn as written: a '$' escaped, so that matplotlib reads no
    mathtext in a title, a column's name or a group's value (an unclosed
    \\frac was a ValueError)."""
    return text.replace("$", r"\$")


def main(argv=None):
    a = parse_args(argv)
    path = chart_path(a, a.y.split(","))  # checked before any work
    # Printed whole at the end, so that stdout's failure is met in one place;
    # a glyph the font lacks (a title in Japanese) is drawn as a box, not
    # warned about in lines on stderr.
    text = io.StringIO()
    with contextlib.redirect_stdout(text), warnings.catch_warnings():
        warnings.filterwarnings("ignore", message="Glyph .* missing from")
        # Nor matplotlib's lines on values near 1e308 or a legend too big to lay out: the chart is drawn.
        warnings.filterwarnings("ignore", message="overflow encountered", category=RuntimeWarning)
        warnings.filterwarnings("ignore", message="Tight layout not applied")
        ys, lines = analyse(a)
        draw(a, ys, lines, path)
        print(f"chart -> {path}")
    outputs.deliver(text.getvalue(), "the chart is written, its printout is not")
    return 0


if __name__ == "__main__":
    sys.exit(guard("plot_sweep", main))
