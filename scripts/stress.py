#!/usr/bin/python3
"""Randomized stress: random meshes, link and per-link settings, node
speeds, policies, intervals, gains, quanta, batches and frame-buffer layouts
on small scenes. Every run must exit 0 (the run checks its own
conservation), give the image rtref gives for the same scene and size, and
give the same image and report again when run a second time through
--config files (its flags spread over two files and the command line, with
decoy values that later ones must replace) and a third time with --rerun
of its report from another folder (wall-clock fields and rerun.of aside).
Each report is then turned hostile (a flag naming an output, a field of
the wrong type, nesting too deep): that rerun must exit 2 with one line and
write nothing. A seed fixes the configurations.

  /usr/bin/python3 scripts/stress.py --count 1000 --doc   # the full run; figures to doc/results/stress.md
  /usr/bin/python3 scripts/stress.py --count 50           # the slice ctest runs (StressSlice)
"""
import argparse
import concurrent.futures
import json
import os
import random
import shlex
import shutil
import subprocess
import sys
import tempfile
import threading
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import outputs  # noqa: E402
from project import RESULTS, ROOT, RTREF, RTSIM, publish_table, spd_scene  # noqa: E402

# Set on a stop: the workers start no more runs (outputs.guard kills the running ones).
STOPPING = threading.Event()

POLICIES = ["none", "slide", "work", "quantile", "resplit", "measured", "median", "recommended"]
DIRS = ["+x", "-x", "+y", "-y", "+z", "-z"]


def time_between(rng, lo_ps, hi_ps):
    """A time with a unit, log-uniform between lo and hi picoseconds."""
    ps = int(round(10 ** rng.uniform(len(str(lo_ps)) - 1, len(str(hi_ps)) - 1)))
    ps = max(lo_ps, min(hi_ps, ps))
    return f"{ps}ps"


def configuration(rng):
    """One random configuration: (scene flags shared with rtref, rtsim-only flags)."""
    w, h = rng.randint(8, 40), rng.randint(8, 40)
    if rng.random() < 0.3:
        scene = [spd_scene(rng.choice(["balls-1", "tetra-3", "balls-2"])), "--size", f"{w}x{h}"]
        rtsim_scene = ["--scene"] + scene[:1] + scene[1:]
    else:
        scene = ["--spheres", str(rng.randint(5, 300)), "--radius", f"{rng.uniform(0.01, 0.08):.3f}",
                 "--concentration", f"{rng.choice([0.25, 0.5, 1.0])}", "--seed", str(rng.randint(1, 10 ** 6)),
                 "--axis", rng.choice("xyz"), "--size", f"{w}x{h}"]
        rtsim_scene = scene
    dims = [rng.randint(1, 4) for _ in range(3)]
    a = ["--mesh-dims", "x".join(map(str, dims)),
         "--link-latency", time_between(rng, 1000, 10 ** 7),
         "--link-bandwidth", f"{rng.choice([10, 100, 1000, 10000])}MB/s",
         "--link-depth", str(rng.randint(1, 16)),
         "--link-control-depth", str(rng.choice([0, 0, 1, 2])),
         "--fb-units", str(rng.choice([1, 2, 3, 16])),
         "--fb-batch", str(rng.randint(1, 64)),
         "--ray-batch", str(rng.choice([1, 1, 2, 8])),
         "--balance", rng.choice(POLICIES),
         "--balance-interval", f"{rng.choice([1, 2, 5, 20, 50])}us",
         "--gain", f"{rng.choice([0, 0.1, 0.5, 1.0])}",
         "--quantum", rng.choice(["0", "lookahead", "lookahead", "1us", "20us"])]
    cells = [(x, y, z) for x in range(dims[0]) for y in range(dims[1]) for z in range(dims[2])]
    for _ in range(rng.randint(0, 3)):
        x, y, z = rng.choice(cells)
        a += ["--node-speed", f"{x},{y},{z}={rng.choice([0.25, 0.5, 2.0, 4.0])}"]
    for _ in range(rng.randint(0, 3)):
        x, y, z = rng.choice(cells)
        d = rng.choice(DIRS)
        axis, step = "xyz".index(d[1]), 1 if d[0] == "+" else -1
        if not 0 <= (x, y, z)[axis] + step < dims[axis]:
            continue
        a += ["--link-set", f"{x},{y},{z},{d}:latency={time_between(rng, 1000, 10 ** 7)},depth={rng.randint(1, 4)}"]
    if rng.random() < 0.2:
        a += ["--frames", str(rng.randint(2, 3))]
    return scene, rtsim_scene + a


# Valid values that a later file or the command line must replace.
DECOYS = {"--link-depth": "3", "--fb-units": "2", "--balance": "none", "--quantum": "0", "--mesh-dims": "1x1x1",
          "--gain": "0.5", "--fb-batch": "7", "--node-speed": "0,0,0=3"}
REPEATABLE = {"--node-speed", "--link-set"}
# Flags a report may never carry (tb/command_line.h), and the hostile
# changes a received report may carry instead.
FORBIDDEN = ["image", "report", "vcd", "map", "quiet", "as-baseline", "as-comparison"]


def flag_groups(args):
    """args as [(flag, [values])], in order; a repeatable flag's values together."""
    groups = []
    for i in range(0, len(args), 2):
        flag, value = args[i], args[i + 1]
        if flag in REPEATABLE and any(g[0] == flag for g in groups):
            next(g for g in groups if g[0] == flag)[1].append(value)
        else:
            groups.append((flag, [value]))
    return groups


def config_value(rng, v):
    """v as a config file may write it: bare when it can be, else quoted."""
    plain = v and v.strip() == v and not any(c in v for c in "#\"'[],")
    return v if plain and rng.random() < 0.5 else json.dumps(v)


def config_line(rng, flag, values):
    name = flag[2:]
    if flag in REPEATABLE and (len(values) > 1 or rng.random() < 0.5):
        text = f"{name} = [{', '.join(json.dumps(v) for v in values)}]"
    else:
        text = f"{name} = {config_value(rng, values[0])}"
    return text + ("  # a comment" if rng.random() < 0.2 else "")


def through_configs(rng, args, d):
    """The same run's arguments given through two --config files and the
    command line, with decoys that the later values must replace."""
    files, rest = {"a": ["# stress: the first file"], "b": [""]}, []
    for flag, values in flag_groups(args):
        where = rng.choice(["a", "b", "cli"])
        if where != "a" and flag in DECOYS and rng.random() < 0.5:
            files["a"].append(config_line(rng, flag, [DECOYS[flag]]))
        if where == "cli":
            for v in values:
                rest += [flag, v]
        else:
            files[where].append(config_line(rng, flag, values))
    paths = []
    for name, lines in files.items():
        paths += ["--config", os.path.join(d, name + ".conf")]
        with open(paths[-1], "w") as f:
            f.write("\n".join(lines) + "\n")
    return paths + rest


def hostile(rng, report, d):
    """A received report turned hostile in one of the ways a rerun must refuse."""
    r = json.loads(json.dumps(report))
    kind = rng.randrange(4)
    if kind == 0:
        name = rng.choice(FORBIDDEN)
        value = json.dumps(os.path.join(d, "victim.png")) if name not in ("quiet", "as-baseline", "as-comparison") else "true"
        r["rerun"]["flags"] += f"{name}={value}\n"
    elif kind == 1:
        r["rerun"]["flags"] = rng.choice([5, None, ["mesh=2"]])
    elif kind == 2:
        r["config"]["scene"] = rng.choice(["x", 3, []])
    else:
        r["config"]["deep"] = json.loads("[" * 100 + "]" * 100)
    return r


def without_wall(report):
    """The report without what depends on the wall clock."""
    if isinstance(report, dict):
        return {k: without_wall(v) for k, v in report.items() if "wall" not in k}
    if isinstance(report, list):
        return [without_wall(v) for v in report]
    return report


def child(cmd, timeout=None, cwd=None):
    """Runs cmd like subprocess.run(capture_output=True, text=True), as a
    child a stop ends (outputs.run_child); after a stop, runs nothing."""
    if STOPPING.is_set():
        return subprocess.CompletedProcess(cmd, -1, "", "stopped")
    return outputs.run_child(cmd, timeout=timeout, cwd=cwd)


def check(index, scene, args, rtsim, rtref, tmp):
    """'' if the configuration passes, else what failed."""
    try:
        return run_and_compare(index, scene, args, rtsim, rtref, tmp)
    except OSError as e:  # a program that cannot be run (replaced by a build meanwhile, say)
        return f"could not run: {e}"


def rtsim_run(rtsim, args, d, name, cwd=None):
    """rtsim with `args`, its image and report as d/name.png and .json:
    (exit code, stderr, image bytes, report) (the last two None if it failed)."""
    image, report = os.path.join(d, name + ".png"), os.path.join(d, name + ".json")
    p = child([rtsim] + args + ["-q", "--no-baseline", "--image", image, "--report", report], timeout=120, cwd=cwd)
    if p.returncode != 0:
        return p.returncode, p.stderr.strip(), None, None
    with open(image, "rb") as f, open(report) as g:
        return 0, "", f.read(), json.load(g)


def run_and_compare(index, scene, args, rtsim, rtref, tmp):
    d = os.path.join(tmp, str(index))
    os.makedirs(os.path.join(d, "elsewhere"))
    rng = random.Random(index)
    ref = child([rtref] + scene + ["-o", os.path.join(d, "ref.png")])
    if ref.returncode != 0:
        return f"rtref failed: {ref.stderr.strip()}"
    runs = {}
    try:
        for name, given, cwd in (("direct", args, None), ("configs", through_configs(rng, args, d), None),
                                 ("rerun", ["--rerun", os.path.join(d, "direct.json")], os.path.join(d, "elsewhere"))):
            code, err, image, report = rtsim_run(rtsim, given, d, name, cwd)
            if code != 0:
                return f"{name}: exit {code}: {err}"
            report["rerun"].pop("of", None)
            runs[name] = (image, without_wall(report))
    except subprocess.TimeoutExpired:
        return "timed out after 120 s"
    with open(os.path.join(d, "ref.png"), "rb") as f:
        if runs["direct"][0] != f.read():
            return "image differs from rtref's"
    for name in ("configs", "rerun"):
        if runs[name][0] != runs["direct"][0]:
            return f"{name}: image differs"
        if runs[name][1] != runs["direct"][1]:
            return f"{name}: report differs"
    # The report, received hostile: refused in one line, nothing written.
    with open(os.path.join(d, "direct.json")) as f, open(os.path.join(d, "hostile.json"), "w") as g:
        json.dump(hostile(rng, json.load(f), d), g)
    with open(os.path.join(d, "victim.png"), "w") as f:
        f.write("precious")
    before = sorted(os.listdir(d))
    p = child([rtsim, "--rerun", os.path.join(d, "hostile.json"), "-q", "--image", ""], timeout=120,
              cwd=os.path.join(d, "elsewhere"))
    if p.returncode != 2 or p.stderr.count("\n") != 1:
        return f"hostile report: exit {p.returncode}, {p.stderr.strip()!r}"
    with open(os.path.join(d, "victim.png")) as f:
        if f.read() != "precious" or sorted(os.listdir(d)) != before or os.listdir(os.path.join(d, "elsewhere")):
            return "hostile report: a file was written"
    return ""


def publish(a, configs, failures, summary):
    """The figures and the configurations per policy, to doc/results/stress.md and doc/robustness.md."""
    policies = {}
    for _, args in configs:
        p = args[args.index("--balance") + 1]
        policies[p] = policies.get(p, 0) + 1
    lines = ["<!-- written by scripts/stress.py --doc; do not edit -->",
             f"`scripts/stress.py --count {a.count} --seed {a.seed}`: {summary} on {a.jobs} workers.",
             "Each configuration: rtref once and rtsim three times, with its flags on the command line, "
             "spread over two --config files (with decoys a later value replaces) and the command line, and "
             "rerun from its report in another folder: exit 0, the image rtref gives, and the same image and "
             "report each time (wall-clock fields and rerun.of aside); then the report made hostile (a flag "
             "naming an output, a field of the wrong type, nesting 100 deep): exit 2, one line, nothing written.",
             "",
             "| policy | configurations |", "|---|---:|"]
    lines += [f"| {p} | {n} |" for p, n in sorted(policies.items())]
    if failures:
        lines += ["", "Failures:", ""] + [f"- {i}: {why} (`rtsim {shlex.join(args)}`)" for i, why, args in failures]
    publish_table(lines, os.path.join(RESULTS, "stress.md"), os.path.join(ROOT, "doc", "robustness.md"), "stress")


def run_all(a, configs, tmp):
    """Every configuration on a.jobs workers, in `tmp`: the failures, as
    (index, why, its rtsim flags)."""
    failures = []
    with concurrent.futures.ThreadPoolExecutor(a.jobs) as pool:
        try:
            futures = {pool.submit(check, i, s, args, a.rtsim, a.rtref, tmp): (i, args)
                       for i, (s, args) in enumerate(configs)}
            for done, fut in enumerate(concurrent.futures.as_completed(futures), 1):
                i, args = futures[fut]
                why = fut.result()
                if why:
                    failures.append((i, why, args))
                    print(f"stress: configuration {i} failed: {why}\n  rtsim {shlex.join(args)}", file=sys.stderr)
                if sys.stderr.isatty():
                    print(f"\rstress: {done}/{a.count}", end="", file=sys.stderr)
        except BaseException:
            # A stop: no configuration more, and the pool's exit waits only
            # for the runs in flight, which the stop has killed.
            STOPPING.set()
            pool.shutdown(wait=False, cancel_futures=True)
            outputs.clean_up()
            raise
    return failures


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--count", type=int, default=1000)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    ap.add_argument("--rtsim", default=RTSIM)
    ap.add_argument("--rtref", default=RTREF)
    ap.add_argument("--doc", action="store_true", help="write the figures to doc/results/stress.md")
    a = ap.parse_args()
    if a.count < 1 or a.jobs < 1:
        raise outputs.ToolError(f"--count {a.count}, --jobs {a.jobs}: at least 1 each")
    # Each run works in a folder of its own: the binaries by absolute path.
    a.rtsim = os.path.abspath(outputs.check_input(a.rtsim, "--rtsim"))
    a.rtref = os.path.abspath(outputs.check_input(a.rtref, "--rtref"))
    if a.doc:  # (checked before the runs, not after them)
        for page in (os.path.join(RESULTS, "stress.md"), os.path.join(ROOT, "doc", "robustness.md")):
            outputs.check_output(page, "--doc", doc=True)
    rng = random.Random(a.seed)
    configs = [configuration(rng) for _ in range(a.count)]
    t0 = time.time()
    # The temporary folder's removal may not fail a stop: under ctest -j2 a
    # stop once ended in "stress.py: 0: Directory not empty" and exit 1 (a
    # configuration's folder gained a file while it was being removed). It
    # is removed once more after the stop's kills: a stop exits 130 and
    # leaves nothing.
    holder = tempfile.TemporaryDirectory(ignore_cleanup_errors=True)
    try:
        failures = run_all(a, configs, holder.name)
    finally:
        holder.cleanup()
        if os.path.exists(holder.name):
            time.sleep(0.1)
            shutil.rmtree(holder.name, ignore_errors=True)
    wall = time.time() - t0
    summary = (f"{a.count} configurations (seed {a.seed}), {a.count - len(failures)} passed, "
               f"{len(failures)} failed, {wall:.0f} s")
    print(f"stress: {summary}")
    if a.doc:
        publish(a, configs, failures, summary)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(outputs.guard("stress.py", main))
