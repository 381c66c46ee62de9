#!/usr/bin/python3
"""Where the paper's rule used to fail, now: the cases of issue 11 (1,000
spheres, 4x4x4, 256x256, rtsim's default costs; view along the progress
axis unless said), each rendered without balancing, with `slide` for one
frame and for --frames frames, and with `resplit` over --frames frames;
the ratios to the unbalanced frame and the 95th percentile age of the
loads the first frame's decisions used. Also `resplit`'s sequence of
--sequence frames along and across the axis, and what `slide`'s slides
cost at Fig. 4's best and worst points (rays forwarded and passed on
untraced). With --doc, writes doc/results/failure_cases.{csv,md}, resplit_sequences.md,
slide_costs.md and the tables into doc/balancing.md (slide costs: doc/fig4.md).
Run with /usr/bin/python3."""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))  # scripts/: project, sweep
import outputs  # noqa: E402
import sweep_driver as driver  # noqa: E402
from project import PAPER_SCENE, ROOT, VIEWS, publish_table  # noqa: E402
from sweep_driver import write_csv  # noqa: E402

# Fig. 4 points (modern) where `slide`'s first frame gains most and where it
# loses most, for what its slides cost: rays forwarded, and of them rays
# passed on untraced (a face moved, or the neighbouring column's faces are
# elsewhere). A point that is one of the CASES below (rtsim's defaults are
# N = 4, f = 1/4) names that case and uses its runs.


def case(view, *more):
    """A run's flags: the paper's scene seen from `view`, at rtsim's default
    concentration (f = 1/4) unless `more` gives one, on its default 4x4x4
    mesh unless `more` gives one (each flag once: the row names what runs)."""
    more = list(more)
    return PAPER_SCENE + VIEWS[view] + ([] if "--concentration" in more else ["--concentration", "0.25"]) + more


COSTS = {
    "along, N = 4, f = 1/4": "defaults (100 ns, 1 GB/s), f = 1/4",
    "across, N = 4, f = 1/4": "view across the axis",
    "along, N = 8, f = 7/8": case("along", "--mesh", "8", "--concentration", "0.875"),
    "across, N = 7, f = 1": case("across", "--mesh", "7", "--concentration", "1"),
    "across, N = 8, f = 1": case("across", "--mesh", "8", "--concentration", "1"),
}

CASES = {
    "defaults (100 ns, 1 GB/s), f = 1/4": case("along"),
    "links at 3 us": case("along", "--link-latency", "3us"),
    "links at 300 MB/s": case("along", "--link-bandwidth", "300MB/s"),
    "spheres everywhere (f = 1)": case("along", "--concentration", "1"),
    "view across the axis": case("across"),
}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--frames", type=int, default=6)
    ap.add_argument("--sequence", type=int, default=10, help="frames of the resplit sequences")
    driver.add_output_arguments(ap, os.path.join(ROOT, "doc", "balancing.md"), plot_only=False)  # (it cannot redraw from a CSV)
    driver.add_arguments(ap)
    a = driver.parse_outputs(ap)
    runs = [("none", []), ("slide", []), (f"slide@{a.frames}", ["--frames", a.frames]),
            (f"resplit@{a.frames}", ["--frames", a.frames]), (f"measured@{a.frames}", ["--frames", a.frames])]
    points = [{"params": {"case": case, "run": name},
               "args": flags + ["--balance", name.partition("@")[0]] + extra}
              for case, flags in CASES.items() for name, extra in runs]
    sequences = {"along": "defaults (100 ns, 1 GB/s), f = 1/4", "across": "view across the axis"}  # view: its case
    points += [{"params": {"case": f"sequence {view}", "run": "resplit"},
                "args": CASES[case] + ["--balance", "resplit", "--frames", a.sequence]}
               for view, case in sequences.items()]
    points += [{"params": {"case": f"cost {point}", "run": policy}, "args": flags + ["--balance", policy]}
               for point, flags in COSTS.items() if not isinstance(flags, str) for policy in ("none", "slide")]
    got = driver.run("failure_cases", points, extract, None, a)
    by = {(r["case"], r["run"]): r for r in got}
    rows, lines = [], [f"<!-- written by scripts/experiments/failure_cases.py --frames {a.frames}; do not edit -->",
                       "| case | none | slide | slide / none | slide, frame " f"{a.frames} | resplit, frame {a.frames}"
                       f" | measured (the default), frame {a.frames} | load age p95 (intervals) |",
                       "|---|---:|---:|---:|---:|---:|---:|---:|"]
    for case in CASES:
        none = by[(case, "none")]["render_time_ns"]
        r = {name: by[(case, name)] for name, _ in runs}
        rows.append({"case": case, "none_ns": none, **{f"{n}_ns": r[n]["render_time_ns"] for n, _ in runs[1:]},
                     "age_p95": r["slide"]["age_p95"], "version": r["slide"]["version"]})
        ratio = {n: r[n]["render_time_ns"] / none for n, _ in runs[1:]}
        age = r["slide"]["age_p95"]
        lines.append(f"| {case} | {none / 1e3:,.1f} us | {r['slide']['render_time_ns'] / 1e3:,.1f} us | "
                     f"{ratio['slide']:.3f} | {ratio[f'slide@{a.frames}']:.3f} | {ratio[f'resplit@{a.frames}']:.3f} | "
                     f"{ratio[f'measured@{a.frames}']:.3f} | "
                     f"{'-' if age == '' else f'{age:.2f}'} |")
    write_csv(os.path.join(a.out, "failure_cases.csv"), rows)
    publish_table(lines, os.path.join(a.out, "failure_cases.md"), a.doc or None, "failure cases")
    seq = [f"<!-- written by scripts/experiments/failure_cases.py --sequence {a.sequence}; do not edit -->",
           "| view | none | " + " | ".join(f"frame {k + 1}" for k in range(a.sequence)) + " | last / none |",
           "|---|---:|" + "---:|" * (a.sequence + 1)]
    for view in sequences:
        none = by[(sequences[view], "none")]["render_time_ns"]
        r = by[(f"sequence {view}", "resplit")]
        times = [float(t) for t in r["frames_ns"].split()]
        seq.append(f"| {view} | {none / 1e3:,.1f} | " + " | ".join(f"{t / 1e3:,.1f}" for t in times) +
                   f" | {times[-1] / none:.3f} |")
    publish_table(seq, os.path.join(a.out, "resplit_sequences.md"), a.doc or None, "resplit sequences")
    cost = ["<!-- written by scripts/experiments/failure_cases.py; do not edit -->",
            "| Fig. 4 point | slide / none | busy, slide / none | rays forwarded, none | slide | "
            "passed untraced, none | slide | of them between columns | slides |",
            "|---|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for point in COSTS:
        case = COSTS[point] if isinstance(COSTS[point], str) else f"cost {point}"
        n, sl = by[(case, "none")], by[(case, "slide")]
        cost.append(f"| {point} | {sl['render_time_ns'] / n['render_time_ns']:.3f} | {sl['busy_ns'] / n['busy_ns']:.3f} | "
                    f"{n['forwarded']:,} | {sl['forwarded']:,} | {n['passed']:,} | {sl['passed']:,} | {sl['passed_between']:,} | "
                    f"{sl['slides']:,} |")
    publish_table(cost, os.path.join(a.out, "slide_costs.md"), a.doc or None, "slide costs")


def extract(r):
    ages = r["balance"].get("load_age_intervals") or {}
    t = r["totals"]
    return {"render_time_ns": r["render_time_ns"], "age_p95": ages.get("p95", ""), "busy_ns": t["busy_ns"],
            "forwarded": t["rays_forwarded"], "passed": t["rays_passed"],
            "passed_between": t["rays_passed_between_columns"], "slides": r["balance"].get("slides", 0),
            "frames_ns": " ".join(f"{f['render_time_ns']:.0f}" for f in r.get("frames", []))}


if __name__ == "__main__":
    sys.exit(outputs.guard("failure_cases.py", main))
