#!/usr/bin/python3
"""The best static one-axis partition, by search: how fast the frame of the
Fig. 4 experiment can be with fixed boundaries along the progress axis (the
same in every column), found by coordinate descent over the planes, each
candidate a full rtsim run without balancing that starts at those planes
(--boundaries-from). It is what a balancer that slides boundaries could at
best settle on, all costs of thin boxes included (rays crossing more boxes,
their messages), unlike the column bound, which spreads the unbalanced run's
work. --per-column then refines the search in the CSV with planes of each
column's own (columns unequally loaded want different planes). Both are
local searches. With --doc, writes doc/results/partition_search.{csv,md} and its table into
doc/balancing.md. Run with /usr/bin/python3."""
import argparse
import concurrent.futures
import json
import os
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))  # scripts/: project, sweep
import outputs  # noqa: E402
import sweep_driver as driver  # noqa: E402
from project import PAPER_SCENE, ROOT, VIEWS, preset_flags, publish_table, start_boundaries, variant  # noqa: E402
from csv_rows import read_csv  # noqa: E402
from sweep_driver import write_csv  # noqa: E402


def args_of(a, n, f, balance=("none",)):
    return (preset_flags(a.preset) + PAPER_SCENE + VIEWS[a.view] +
            ["--mesh", n, "--concentration", f"{f:.6f}", "--balance", *balance] + a.extra.split())


def unbalanced(a, n, f):
    """The frame on the uniform split: (render time in ns, the world's extent along x)."""
    report, _ = driver.run_rtsim(args_of(a, n, f))
    boxes = [node["box"] for node in report["nodes"]]
    return report["render_time_ns"], min(b[0][0] for b in boxes), max(b[1][0] for b in boxes)


def run(a, n, f, planes):
    """Render time (ns) of the frame with every column's inner planes at `planes`."""
    return run_columns(a, n, f, {(i, j): planes for i in range(n) for j in range(n)})[0]


def run_columns(a, n, f, cols):
    """(Render time in ns, report) of the frame with column (i, j)'s inner
    planes at cols[(i, j)]."""
    rep = start_boundaries(n, cols)
    fd, path = tempfile.mkstemp(suffix=".json")
    with os.fdopen(fd, "w") as fh:
        json.dump(rep, fh)
    try:
        report, _ = driver.run_rtsim(args_of(a, n, f) + ["--boundaries-from", path])
        return report["render_time_ns"], report
    finally:
        os.remove(path)


def planes_of(report, n):
    """Each column's inner planes along x where the report's last frame held them."""
    cols = {}
    for b in report["boundaries"]:
        cols.setdefault(tuple(b["column"]), {})[b["index"]] = b["history"][-1][1]
    return {c: [v[k] for k in range(1, n)] for c, v in cols.items()}


def refine_columns(a, n, f, lo, hi, pool, cols, best, report):
    """Descent with planes of each column's own, from `cols`: the frame is
    its busiest nodes', so each step tries thinning each of the
    `--busiest` busiest boxes by `step` from below or from above (a plane of its
    column moved towards it), keeps the best move if it shortens the frame
    and halves the step when none does. A local search for the splits that
    one set of planes cannot reach (columns unequally loaded). `best` and
    `report` are the frame at `cols`. Returns (best time, planes per
    column, runs, the best frame's report)."""
    min_gap = 0.05 * (hi - lo) / n
    runs, step = 0, f / n / 4
    while step >= a.min_step / 2 and runs < a.max_runs:
        moves = []
        for node in sorted(report["nodes"], key=lambda x: -x["busy_ns"])[:a.busiest]:
            k, col = node["node"][0], (node["node"][1], node["node"][2])
            for plane, d in ((k - 1, step), (k, -step)):  # its lower face up, its upper face down
                if 0 <= plane < n - 1:
                    p = list(cols[col])
                    p[plane] = round(p[plane] + d, 6)
                    edges = [lo] + p + [hi]
                    if all(edges[i + 1] - edges[i] >= min_gap for i in range(n)):
                        moves.append({**cols, col: p})
        found = list(pool.map(lambda c: run_columns(a, n, f, c), moves))
        runs += len(moves)
        i = min(range(len(found)), key=lambda x: found[x][0]) if found else None
        if i is not None and found[i][0] < best:
            best, report, cols = found[i][0], found[i][1], moves[i]
        else:
            step /= 2
    return best, cols, runs, report


def search(a, n, f, lo, hi, pool, reach):
    """Descent from planes spread evenly over the first `reach` of the
    crowded layer: move one plane by +-step, or scale all of them by
    1 +- step / f, while that helps; halve the step when nothing does.
    Returns (best time, planes, runs)."""
    min_gap = 0.05 * (hi - lo) / n  # the default minimum thickness
    planes = [reach * f * k / n for k in range(1, n)]
    best = run(a, n, f, planes)
    runs, step = 1, f / n / 2
    while step >= a.min_step:
        moves = []
        for k in range(n - 1):
            for d in (-step, step):
                p = list(planes)
                p[k] = p[k] + d
                moves.append(p)
        for d in (-step, step):
            moves.append([x * (1 + d / f) for x in planes])
        cands = []
        for p in moves:
            p = [round(x, 6) for x in p]
            edges = [lo] + p + [hi]
            if all(edges[i + 1] - edges[i] >= min_gap for i in range(n)):
                cands.append(p)
        times = list(pool.map(lambda p: run(a, n, f, p), cands))
        runs += len(cands)
        t, p = min(zip(times, cands), key=lambda x: x[0]) if cands else (best, planes)
        if t < best:
            best, planes = t, p
        else:
            step /= 2
    return best, planes, runs


def one_set(a, n, pool):
    """The search with one set of planes for all columns, from two starts
    (the planes spread over the whole crowded layer, and over its first
    three quarters, where the rays that hit stop), the better kept."""
    f = 1 / n
    none, lo, hi = unbalanced(a, n, f)
    found = [search(a, n, f, lo, hi, pool, reach) for reach in (1.0, 0.75)]
    t, planes = min((x[0], x[1]) for x in found)
    runs = sum(x[2] for x in found)
    print(f"N = {n}: {t / 1e3:.1f} us, ratio {t / none:.3f}, planes {planes} ({runs} runs)", file=sys.stderr)
    return {"preset": a.preset, "view": a.view, "N": n, "f": round(f, 6), "time_none_ns": none,
            "best_ns": t, "ratio": t / none, "planes": " ".join(f"{p:.4f}" for p in planes),
            "runs": runs, "version": driver.version()}


def per_column(a, n, pool, csv_path):
    """The CSV's one-set row for N, with the per-column refinement added:
    from the best of its planes, those the default policy holds in its
    sixth frame (rtsim --balance measured --frames 6) and the planes of
    an earlier refinement in the CSV."""
    old = [r for r in (read_csv(csv_path) if os.path.exists(csv_path) else []) if int(r["N"]) == n]
    if not old:
        raise SystemExit(f"partition_search.py: --per-column: no one-set search for N = {n} in {csv_path}; run it first")
    row = dict(old[0])
    f = 1 / n
    none, lo, hi = unbalanced(a, n, f)
    aligned = [float(x) for x in row["planes"].split()]
    report, _ = driver.run_rtsim(args_of(a, n, f, ("measured", "--frames", "6")))
    keys = [(i, j) for i in range(n) for j in range(n)]  # the columns, in columns_planes' order
    starts = {"one set": {c: aligned for c in keys}, "measured@6": planes_of(report, n)}
    if row.get("columns_planes"):  # a search before this one: the best known split is never lost
        starts["the last search"] = dict(zip(keys, ([float(x) for x in c.split()] for c in row["columns_planes"].split(";"))))
    frames = {}  # (time, report)
    for k, c in starts.items():
        try:
            frames[k] = run_columns(a, n, f, c)
        except RuntimeError as e:  # (an earlier search's planes, written to 4 decimals, may make a box too thin)
            print(f"N = {n}: start {k!r} left out: {e}", file=sys.stderr)
    start = min(frames, key=lambda k: frames[k][0])
    t, cols, runs, best_report = refine_columns(a, n, f, lo, hi, pool, starts[start], *frames[start])
    runs += 1 + len(starts)  # the sixth frame's run and the starts
    print(f"N = {n}: per column {t / 1e3:.1f} us, ratio {t / none:.3f} from {start} (one set "
          f"{frames['one set'][0] / none:.3f}, measured@6's planes {frames['measured@6'][0] / none:.3f}; {runs} runs)",
          file=sys.stderr)
    row.update({"columns_ns": t, "columns_ratio": t / none, "columns_start": start, "columns_runs": runs,
                # its busiest node's busy time, as a fraction of none's time (the rest of its frame is waiting)
                "columns_max_busy": max(x["busy_ns"] for x in best_report["nodes"]) / none,
                "columns_planes": ";".join(" ".join(f"{p:.6f}" for p in cols[c]) for c in sorted(cols))})
    return row


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--n", default="4,5")
    ap.add_argument("--view", default="along", choices=sorted(VIEWS))
    ap.add_argument("--preset", default="modern")
    ap.add_argument("--extra", default="", help="more rtsim flags for every run")
    ap.add_argument("--tag", default="", help="name of the --extra variant: its files are partition_search-PRESET-TAG.*")
    ap.add_argument("--min-step", type=float, default=0.004, help="stop when the step is below this (world units)")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    ap.add_argument("--per-column", action="store_true",
                    help="refine the one-set search already in the CSV with planes of each column's own, from the "
                         "better of its planes and those the default policy holds in its sixth frame")
    ap.add_argument("--busiest", type=int, default=6, help="boxes the --per-column refinement tries to thin at each step")
    ap.add_argument("--max-runs", type=int, default=800, help="runs per N of the --per-column refinement at most")
    ap.add_argument("--merge", metavar="CSV", action="append", default=[],
                    help="search nothing: add the rows of these CSVs (other runs' N) to --out's and write the table")
    driver.add_output_arguments(ap, os.path.join(ROOT, "doc", "balancing.md"), plot_only=False)  # (it cannot redraw from a CSV)
    a = driver.parse_outputs(ap)
    stem = "partition_search" + variant(a.preset, a.tag) + ("" if a.view == "along" else f"-{a.view}")
    csv_path = os.path.join(a.out, stem + ".csv")
    outputs.check_input(preset_flags(outputs.check_name(a.preset, "--preset"))[1], "--preset")
    if a.tag:
        outputs.check_name(a.tag, "--tag")
    ns = outputs.numbers(a.n, "--n", least=2, most=32)  # (nodes per axis: a column has a plane; rtsim --mesh: at most 32)
    rows = []
    for path in a.merge:
        rows += read_csv(outputs.check_input(path, "--merge"))
    if a.jobs < 1:
        raise outputs.ToolError(f"--jobs {a.jobs}: at least 1")
    with concurrent.futures.ThreadPoolExecutor(a.jobs) as pool:
        try:
            for n in ([] if a.merge else ns):
                rows.append(per_column(a, n, pool, csv_path) if a.per_column else one_set(a, n, pool))
        except BaseException:
            # A stop (outputs.guard): the queued runs never start, and the
            # pool's exit waits only for those in flight, their rtsim killed.
            pool.shutdown(wait=False, cancel_futures=True)
            outputs.clean_up()
            raise
    # Rows of other N already there are kept: searches of different N add up.
    if os.path.exists(csv_path):
        ns = {int(r["N"]) for r in rows}
        rows += [r for r in read_csv(csv_path) if int(r["N"]) not in ns and r["view"] == a.view]
    rows.sort(key=lambda r: int(r["N"]))
    keys = list(dict.fromkeys(k for r in rows for k in r))  # the per-column fields where refined
    rows = [{k: r.get(k, "") for k in keys} for r in rows]
    write_csv(csv_path, rows)
    return table(a, rows, os.path.join(a.out, stem + ".md"))


def table(a, rows, md_path):
    """The searches' table, to md_path and (--doc) its section of the page; 1 where no page shows it."""
    lines = [f"<!-- written by scripts/experiments/partition_search.py --preset {a.preset} --view {a.view}"
             f"{' --tag ' + a.tag + ' --extra=' + repr(a.extra) if a.tag else ''}; do not edit -->",
             "| view | N | f | none | best static partition, one set of planes | ratio | its planes along x | runs | "
             "planes of each column's own, refined from | ratio | runs |",
             "|---|---:|---:|---:|---:|---:|---|---:|---|---:|---:|"]
    for r in rows:
        own = (f"{r['columns_start']} | {float(r['columns_ratio']):.3f} | {r['columns_runs']}"
               if r.get("columns_ratio") else "- | - | -")
        lines.append(f"| {r['view']} | {r['N']} | 1/{r['N']} | {float(r['time_none_ns']) / 1e3:,.1f} us | "
                     f"{float(r['best_ns']) / 1e3:,.1f} us | {float(r['ratio']):.3f} | {r['planes']} | {r['runs']} | "
                     f"{own} |")
    section = f"partition search {a.preset}" + (f" {a.tag}" if a.tag else "") + ("" if a.view == "along" else f" {a.view}")
    # (--doc for a view or variant no page shows: only the modern machine along the axis is in balancing.md)
    return 0 if publish_table(lines, md_path, a.doc or None, section) else 1


if __name__ == "__main__":
    sys.exit(outputs.guard("partition_search.py", main))
