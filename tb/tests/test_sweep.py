"""Tests of the sweep driver (scripts/sweep_driver.py): parallel local runs, CSV in
point order with command and version, resume without rerunning, a failing
point reported, an edited preset rerun, and the same sweep through a local
Dask cluster.
Run by ctest as: /usr/bin/python3 test_sweep.py <rtsim binary>."""
import csv
import json
import os
import shlex
import stat
import subprocess
import sys
import tempfile
import types
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "scripts"))
import sweep_driver as sweep  # noqa: E402

RTSIM = os.path.abspath(sys.argv.pop(1)) if len(sys.argv) > 1 else sweep.RTSIM
SMALL = ["--spheres", "60", "--radius", "0.05", "--size", "24x24", "--seed", "3"]


def points(extra_n=()):
    pts = [{"params": {"N": n, "latency": lat}, "args": SMALL + ["--mesh", n, "--link-latency", lat]}
           for n in (1, 2) for lat in ("100ns", "2us")]
    pts += [{"params": {"N": n, "latency": "100ns"}, "args": SMALL + ["--mesh", n, "--link-latency", "100ns"]}
            for n in extra_n]
    return pts


def read_json(path):
    with open(path) as f:
        return json.load(f)


def extract(r):
    return {"render_time_ns": r["render_time_ns"], "ray_messages": r["totals"]["messages"]["ray"]}


class Sweep(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.dir = self.tmp.name
        # A wrapper that logs every invocation, to count the runs.
        self.log = os.path.join(self.dir, "calls.log")
        self.binary = os.path.join(self.dir, "rtsim")
        with open(self.binary, "w") as f:
            f.write(f"#!/bin/sh\necho run >> {shlex.quote(self.log)}\nexec {shlex.quote(RTSIM)} \"$@\"\n")
        os.chmod(self.binary, os.stat(self.binary).st_mode | stat.S_IEXEC)

    def tearDown(self):
        self.tmp.cleanup()

    def opts(self, **kw):
        return types.SimpleNamespace(**{"jobs": 2, "dask": None, "fresh": False, "journal_dir": self.dir, **kw})

    def calls(self):
        if not os.path.exists(self.log):
            return 0
        with open(self.log) as f:
            return len(f.read().split())

    def direct(self, args):
        """Render time from running rtsim directly, outside the driver."""
        rep = os.path.join(self.dir, "direct.json")
        subprocess.run([RTSIM] + [str(a) for a in args] + ["--no-baseline", "-q", "--image", "", "--report", rep],
                       check=True)
        return read_json(rep)["render_time_ns"]

    def test_a_refused_sweep_leaves_no_journal_it_made(self):
        """A sweep refused after its journal was opened (two points with one
        set of flags), before any point finished: the empty journal it made
        goes; a journal that was there stays."""
        pts = points()
        pts.append(dict(pts[0]))
        with self.assertRaises(sweep.ToolError):
            sweep.run("dup", pts, extract, None, self.opts(), binary=self.binary)
        self.assertFalse(os.path.exists(os.path.join(self.dir, "dup.jsonl")))
        open(os.path.join(self.dir, "dup.jsonl"), "w").close()
        with self.assertRaises(sweep.ToolError):
            sweep.run("dup", pts, extract, None, self.opts(), binary=self.binary)
        self.assertTrue(os.path.exists(os.path.join(self.dir, "dup.jsonl")))
        self.assertEqual(self.calls(), 0)

    def test_csv_in_point_order_with_command_and_version(self):
        out = os.path.join(self.dir, "s.csv")
        pts = points()
        rows = sweep.run("t", pts, extract, out, self.opts(), binary=self.binary)
        self.assertEqual(self.calls(), 4)
        with open(out) as f:
            got = list(csv.DictReader(f))
        self.assertEqual([(int(r["N"]), r["latency"]) for r in got], [(p["params"]["N"], p["params"]["latency"])
                                                                       for p in pts])
        for r, p in zip(got, pts):
            self.assertEqual(float(r["render_time_ns"]), self.direct(p["args"]))
            self.assertEqual(r["version"], sweep.version())
            self.assertNotEqual(r["version"], "unknown")
            # The recorded command is the one that ran: rerun it.
            cmd = shlex.split(r["command"])
            rep = os.path.join(self.dir, "again.json")
            cmd = [os.path.join(sweep.ROOT, cmd[0]) if not os.path.isabs(cmd[0]) else cmd[0]] + \
                [rep if a == "REPORT.json" else a for a in cmd[1:]]
            subprocess.run(cmd, check=True)
            self.assertEqual(read_json(rep)["render_time_ns"], float(r["render_time_ns"]))
        self.assertEqual(len(rows), 4)
        # More latency on a 2-node machine must cost time: the metrics are real.
        self.assertGreater(rows[3]["render_time_ns"], rows[2]["render_time_ns"])

    def test_resume_runs_only_new_points(self):
        sweep.run("t", points(), extract, None, self.opts(), binary=self.binary)
        self.assertEqual(self.calls(), 4)
        rows = sweep.run("t", points(extra_n=(3,)), extract, None, self.opts(), binary=self.binary)
        self.assertEqual(self.calls(), 5)
        self.assertEqual(len(rows), 5)
        sweep.run("t", points(), extract, None, self.opts(fresh=True), binary=self.binary)
        self.assertEqual(self.calls(), 9)

    def test_edited_preset_reruns_its_points(self):
        preset = os.path.join(self.dir, "links.conf")

        def write(text):
            with open(preset, "w") as f:
                f.write(text)

        def sweep_with_preset():
            pts = [{"params": {"N": n}, "args": SMALL + ["--mesh", n, "--config", preset]} for n in (1, 2)]
            return sweep.run("t", pts, extract, None, self.opts(), binary=self.binary)

        write("# the links\nlink-latency = 100ns\n")
        fast = sweep_with_preset()
        self.assertEqual(self.calls(), 2)
        write("# the links, commented differently\n\nlink-latency   =  100ns  # same value\n")
        sweep_with_preset()
        self.assertEqual(self.calls(), 2)  # the same settings: resumed
        write("link-latency = 5us\n")
        slow = sweep_with_preset()
        self.assertEqual(self.calls(), 4)  # a setting changed: both points run again
        self.assertGreater(slow[1]["render_time_ns"], fast[1]["render_time_ns"])

    def test_interrupted_journal_line_is_rerun(self):
        sweep.run("t", points(), extract, None, self.opts(), binary=self.binary)
        path = os.path.join(self.dir, "t.jsonl")
        with open(path) as f:
            lines = f.read().splitlines()
        with open(path, "w") as f:  # the last record cut short, as by a kill
            f.write("\n".join(lines[:-1]) + "\n" + lines[-1][: len(lines[-1]) // 2])
        sweep.run("t", points(), extract, None, self.opts(), binary=self.binary)
        self.assertEqual(self.calls(), 5)

    def test_failing_point_is_named(self):
        pts = points() + [{"params": {"N": 2, "latency": "fast"}, "args": SMALL + ["--link-latency", "fast"]}]
        with self.assertRaises(sweep.ToolError) as e:
            sweep.run("t", pts, extract, None, self.opts(), binary=self.binary)
        self.assertIn("1 point(s) failed", str(e.exception))
        self.assertIn("--link-latency", str(e.exception))
        # The good points are journalled: a fixed sweep reruns none of them.
        sweep.run("t", points(), extract, None, self.opts(), binary=self.binary)
        self.assertEqual(self.calls(), 5)

    def test_same_rows_through_a_local_dask_cluster(self):
        import distributed
        local = sweep.run("t", points(), extract, None, self.opts(), binary=self.binary)
        with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None,
                                      scheduler_port=0, silence_logs=40) as cluster:
            opts = self.opts(dask=cluster.scheduler_address, journal_dir=os.path.join(self.dir, "dask"))
            remote = sweep.run("t", points(), extract, None, opts, binary=self.binary)
        self.assertEqual(self.calls(), 8)  # the cluster ran every point again
        strip = [{k: v for k, v in r.items() if k != "wall_s"} for r in local]
        self.assertEqual([{k: v for k, v in r.items() if k != "wall_s"} for r in remote], strip)


if __name__ == "__main__":
    unittest.main()
