"""Sweeps of any scene and any flags from the command line (scripts/sweep.py
NAME --set FLAG=V1,V2 ... -- RTSIM_FLAGS): the grid of points (the product
of the --set lists) over the base flags, each point one rtsim run and, where
asked, its comparison runs (the same flags without balancing; on one
computer), run by the sweep driver (sweep.run: parallel or Dask, journal,
resume, provenance), one CSV row per point. doc/exploration.md, "Sweeps of
your own", shows it at work."""
import argparse
import itertools
import os
import sys
import textwrap

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import sweep  # noqa: E402
from project import QUIET, RTSIM  # noqa: E402

SWEEPS = sweep.JOURNALS  # out/sweeps: the CSV beside its journal
# Flags the driver gives every run itself (sweep.FIXED_FLAGS): a user's copy
# of the quiet ones is dropped, an output of their own refused.
DRIVER_OWNS = {"--report": "the driver reads each run's report itself",
               "--image": "sweeps write no images", "--map": "sweeps draw no maps", "--vcd": "sweeps write no VCD"}

# Settings of particular nodes and links: not for the one-node run.
PER_NODE = ("--node-speed", "--node-cost", "--link-set", "--trace-nodes", "--trace-links", "--boundaries-from")

EXAMPLES = """examples:
  /usr/bin/python3 scripts/sweep.py links --set link-bandwidth=100MB/s,200MB/s,1GB/s --gain -- \\
      --scene ../shared/scenes/spd/balls-4.nff --size 256x256 --mesh 6
  /usr/bin/python3 scripts/sweep.py sizes --set mesh=2,4,8 --set cost-sphere=10ns,1us --speedup -- --config configs/paper.conf
  /usr/bin/python3 scripts/plot_sweep.py out/sweeps/links.csv --x link-bandwidth --y render_time_ns,time_none_ns

A value list holding commas itself (--eye=1,2,3) is split at semicolons instead: --set 'eye=-1,0.5,0.5;0.5,-1,0.5'."""


def parse_set(text):
    """'FLAG=V1,V2' -> ('--flag', ['V1', 'V2']); a list with a ';' is split there."""
    flag, eq, values = text.partition("=")
    flag = flag.strip().lstrip("-")
    if not eq or not flag or not values:
        raise ValueError(f"--set {text!r}: expected FLAG=V1,V2,... (for example link-bandwidth=100MB/s,1GB/s)")
    vals = [v.strip() for v in values.split(";" if ";" in values else ",")]
    if any(not v for v in vals):
        raise ValueError(f"--set {text!r}: an empty value in the list")
    if len(set(vals)) != len(vals):
        raise ValueError(f"--set {text!r}: a value given twice")
    return "--" + flag, vals


def flag_names(args):
    """The long flags named in a list of rtsim flags ('--mesh 4' and '--mesh=4' both name --mesh)."""
    return {a.split("=", 1)[0] for a in args if a.startswith("--")}


def without(args, flag):
    """`args` without `flag` and its value, in either spelling ('--flag V', '--flag=V')."""
    out, skip = [], False
    for a in args:
        if skip:
            skip = False
        elif a == flag:
            skip = True
        elif not a.startswith(flag + "="):
            out.append(a)
    return out


def base_flags(args):
    """The user's base flags, checked: the quiet flags the driver adds anyway
    are dropped (not recorded twice); outputs the driver owns are refused."""
    args = [a for a in args if a not in QUIET and a != "--quiet"]
    for flag in flag_names(args) & set(DRIVER_OWNS):
        raise ValueError(f"{flag} in the rtsim flags: {DRIVER_OWNS[flag]}")
    return args


def grid(sets, base):
    """The points: one per combination of the --set values, in the order
    given (the last --set varies fastest), as (params, rtsim flags)."""
    names = [flag.lstrip("-") for flag, _ in sets]
    clash = flag_names(base) & {flag for flag, _ in sets}
    if clash:
        raise ValueError(f"{', '.join(sorted(clash))} is both swept (--set) and in the base flags")
    if len(set(names)) != len(names):
        raise ValueError("a flag swept by two --set")
    for combo in itertools.product(*(vals for _, vals in sets)):
        params = dict(zip(names, combo))
        args = list(base)
        for (flag, _), v in zip(sets, combo):
            args += [f"{flag}={v}"]
        yield params, args


def runs_of(args, frames, gain, speedup):
    """The rtsim runs one point needs, by role: the point itself; without
    balancing (gain); on one computer (speed-up)."""
    main = args + (["--frames", str(frames)] if frames > 1 else [])
    out = {"point": main}
    if gain:
        out["none"] = without(args, "--balance") + ["--balance", "none"]
    if speedup:  # one node with the global settings, as rtsim's own baseline (--as-baseline) runs it
        one = args
        for flag in ("--mesh", "--mesh-dims") + PER_NODE:
            one = without(one, flag)
        out["one"] = one + ["--mesh", "1"]
    return out


def extract(report):
    """What a row keeps of a run: its render time (the last frame's), every
    frame's, and the busiest node and link."""
    t = report["render_time_ns"]
    node = max(report["nodes"], key=lambda n: n["busy_ns"])
    link = report["busiest_links"][0] if report.get("busiest_links") else None
    return {"render_time_ns": t,
            "frames_ns": " ".join(f"{f['render_time_ns']:.0f}" for f in report.get("frames", [])) or f"{t:.0f}",
            "busiest_node": "node_" + "_".join(str(c) for c in node["node"]),
            "busiest_node_busy": node["busy_ns"] / t if t > 0 else 0.0,
            "busiest_link": link["name"] if link else "",
            "busiest_link_utilisation": link["utilisation"] if link else 0.0}


def rows_of(points, results, gain, speedup):
    """One row per point: the swept values, the point's figures, and its
    comparisons (time_none_ns and balance_ratio = time / time without
    balancing; time_one_ns and speedup = one computer's time / the point's)."""
    by_args = {tuple(r["args"]): r for r in results}
    rows = []
    for params, runs in points:
        p = by_args[tuple(runs["point"])]
        row = dict(params)
        row.update({k: p[k] for k in ("render_time_ns", "frames_ns", "busiest_node", "busiest_node_busy",
                                      "busiest_link", "busiest_link_utilisation")})
        if gain:
            none = by_args[tuple(runs["none"])]["render_time_ns"]
            row.update({"time_none_ns": none, "balance_ratio": p["render_time_ns"] / none})
        if speedup:
            one = by_args[tuple(runs["one"])]["render_time_ns"]
            row.update({"time_one_ns": one, "speedup": one / p["render_time_ns"]})
        row.update({"wall_s": p["wall_s"], "version": p["version"], "command": p["command"]})
        rows.append(row)
    return rows


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    ours, rtsim_flags = (argv[:argv.index("--")], argv[argv.index("--") + 1:]) if "--" in argv else (argv, [])
    ap = argparse.ArgumentParser(
        prog="sweep.py", formatter_class=argparse.RawDescriptionHelpFormatter, epilog=EXAMPLES,
        usage="/usr/bin/python3 scripts/sweep.py NAME --set FLAG=V1,V2,... [--set ...] [options] -- RTSIM_FLAGS...",
        description=textwrap.fill("Runs rtsim over the grid of the --set lists (their product), each point with the rtsim "
                    "flags after --, and writes out/sweeps/NAME.csv: a row per point with the swept values, its "
                    "render time (simulated ns; the last frame's with --frames), each frame's, the busiest node "
                    "(its busy share of the render time) and link (its utilisation), and the comparisons asked "
                    "for. Finished points are journalled (out/sweeps/NAME.jsonl): an interrupted or extended "
                    "sweep reruns nothing; each row records the exact command and the tree's version.", 79))
    ap.add_argument("name", help="the sweep's name: out/sweeps/NAME.csv and its journal out/sweeps/NAME.jsonl")
    ap.add_argument("--set", dest="sets", action="append", default=[], metavar="FLAG=V1,V2,...",
                    help="an rtsim flag (without its dashes) and the values it takes; repeat for a grid")
    ap.add_argument("--frames", type=int, default=1, help="frames per point (rtsim --frames); the row's time is the last's")
    ap.add_argument("--gain", action="store_true",
                    help="also run each point without balancing: time_none_ns, balance_ratio = time / that")
    ap.add_argument("--speedup", action="store_true",
                    help="also run each point on one computer (--mesh 1): time_one_ns, speedup = that / time")
    ap.add_argument("--csv", help="where to write the CSV (default out/sweeps/NAME.csv)")
    ap.add_argument("--rtsim", default=RTSIM, help="the rtsim binary (default: build/rtsim, scripts/build.sh)")
    sweep.add_arguments(ap)
    a = ap.parse_args(ours)
    try:
        if not a.sets:
            raise ValueError("nothing to sweep: give at least one --set FLAG=V1,V2,...")
        if a.frames < 1:
            raise ValueError(f"--frames {a.frames}: at least 1")
        if not os.path.isfile(a.rtsim):
            raise ValueError(f"{a.rtsim}: no rtsim binary there (build it with scripts/build.sh)")
        base = base_flags(rtsim_flags)
        points = [(params, runs_of(args, a.frames, a.gain, a.speedup)) for params, args in grid([parse_set(s) for s in a.sets], base)]
    except ValueError as e:
        ap.error(str(e))
    unique = {}
    for params, runs in points:
        for role, args in runs.items():
            unique.setdefault(tuple(args), {"params": {**params, "run": role}, "args": args})
    try:
        results = sweep.run(a.name, list(unique.values()), extract, None, a, binary=a.rtsim)
    except RuntimeError as e:
        print(f"sweep.py: {e}", file=sys.stderr)
        return 1
    for r, p in zip(results, unique.values()):
        r["args"] = p["args"]
    rows = rows_of(points, results, a.gain, a.speedup)
    csv_path = a.csv or os.path.join(SWEEPS, a.name + ".csv")
    sweep.write_csv(csv_path, rows)
    print(f"{len(rows)} points ({len(unique)} runs) -> {os.path.relpath(csv_path)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
