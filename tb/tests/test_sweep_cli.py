"""Tests of sweeps from the command line (scripts/sweep.py NAME --set ...,
scripts/sweep_grid.py) and of their chart (scripts/plot_sweep.py): the grid
is the product of the --set lists, each row's figures are those of rtsim run
directly with the same flags, the comparisons are the ratios they say, a
second run reruns nothing, bad input gets one line and a nonzero exit, the
same grid through a local Dask cluster gives the same rows, and the chart's
knees are in tb/tests/test_plot_sweep.py.
Run by ctest as: /usr/bin/python3 test_sweep_cli.py <rtsim binary>."""
import csv
import json
import os
import shlex
import stat
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPTS = os.path.join(HERE, "..", "..", "scripts")
sys.path.insert(0, SCRIPTS)
import sweep  # noqa: E402

RTSIM = os.path.abspath(sys.argv.pop(1)) if len(sys.argv) > 1 else sweep.RTSIM
SMALL = ["--spheres", "60", "--radius", "0.05", "--size", "24x24", "--seed", "3", "--balance", "measured"]


class SweepCommand(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.dir = self.tmp.name
        self.log = os.path.join(self.dir, "calls.log")
        self.binary = os.path.join(self.dir, "rtsim")  # logs each run, to count them
        with open(self.binary, "w") as f:
            f.write(f"#!/bin/sh\necho run >> {shlex.quote(self.log)}\nexec {shlex.quote(RTSIM)} \"$@\"\n")
        os.chmod(self.binary, os.stat(self.binary).st_mode | stat.S_IEXEC)

    def tearDown(self):
        self.tmp.cleanup()

    def sweep(self, *args, check=True):
        cmd = ["/usr/bin/python3", os.path.join(SCRIPTS, "sweep.py"), args[0], "--rtsim", self.binary,
               "--journal-dir", self.dir, "--csv", os.path.join(self.dir, args[0] + ".csv"), "--jobs", "2"] + list(args[1:])
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
        if check:
            self.assertEqual(p.returncode, 0, p.stderr)
        return p

    def rows(self, name):
        with open(os.path.join(self.dir, name + ".csv")) as f:
            return list(csv.DictReader(f))

    def calls(self):
        with open(self.log) as f:
            return len(f.read().split())

    def direct(self, args):
        """The render time of rtsim run directly with `args`, outside the driver."""
        rep = os.path.join(self.dir, "direct.json")
        subprocess.run([RTSIM, *args, "--no-baseline", "-q", "--image", "", "--report", rep], check=True)
        with open(rep) as f:
            return json.load(f)["render_time_ns"]

    def test_grid_rows_are_direct_runs_and_their_ratios(self):
        self.sweep("g", "--set", "mesh=1,2", "--set", "link-latency=100ns,2us", "--gain", "--speedup", "--frames", "2",
                   "--", *SMALL, "-q", "--no-baseline")
        rows = self.rows("g")
        self.assertEqual([(r["mesh"], r["link-latency"]) for r in rows],
                         [("1", "100ns"), ("1", "2us"), ("2", "100ns"), ("2", "2us")])
        for r in rows:
            flags = SMALL + ["--mesh", r["mesh"], "--link-latency", r["link-latency"]]
            t = self.direct(flags + ["--frames", "2"])
            none = self.direct([a if a != "measured" else "none" for a in flags])
            one = self.direct(SMALL + ["--mesh", "1", "--link-latency", r["link-latency"]])
            self.assertEqual(float(r["render_time_ns"]), t)
            self.assertEqual(float(r["frames_ns"].split()[-1]), t)
            self.assertEqual(len(r["frames_ns"].split()), 2)
            self.assertEqual(float(r["time_none_ns"]), none)
            self.assertAlmostEqual(float(r["balance_ratio"]), t / none, places=12)
            self.assertAlmostEqual(float(r["speedup"]), one / t, places=12)
            self.assertTrue(r["busiest_node"].startswith("node_"))
            # The quiet flags the driver adds are recorded once, not twice.
            self.assertEqual(shlex.split(r["command"]).count("--no-baseline"), 1)
        # More latency on two nodes costs time: the figures are real.
        self.assertGreater(float(rows[3]["render_time_ns"]), float(rows[2]["render_time_ns"]))
        # The point, its unbalanced run and its one-node run, less the runs two points share.
        ran = self.calls()
        self.sweep("g", "--set", "mesh=1,2", "--set", "link-latency=100ns,2us", "--gain", "--speedup", "--frames", "2",
                   "--", *SMALL)
        self.assertEqual(self.calls(), ran)  # everything resumed from the journal

    def test_the_one_node_run_drops_settings_of_particular_nodes(self):
        # A node 1,1,1 of a 2x2x2 mesh has no place on one node: the one-node
        # run is the flags without it, as rtsim's own baseline is.
        self.sweep("one", "--set", "mesh=2", "--speedup", "--", *SMALL, "--node-speed", "1,1,1=2")
        row = self.rows("one")[0]
        self.assertEqual(float(row["time_one_ns"]), self.direct(SMALL + ["--mesh", "1"]))

    def test_bad_input_gets_one_line_and_a_nonzero_exit(self):
        for args, says in ((["--set", "mesh"], "expected FLAG=V1,V2"),
                           (["--set", "mesh=1,1"], "a value given twice"),
                           (["--set", "mesh=1,2", "--", "--mesh", "2"], "both swept"),
                           (["--set", "mesh=1,2", "--", "--report", "x.json"], "--report in the rtsim flags"),
                           ([], "nothing to sweep")):
            with self.subTest(args=args):
                p = self.sweep("bad", *args, check=False)
                self.assertEqual(p.returncode, 2)
                last = p.stderr.strip().splitlines()[-1]
                self.assertTrue(last.startswith("sweep.py: error: "), p.stderr)
                self.assertIn(says, last)
        p = self.sweep("bad", "--set", "link-latency=1us,fast", "--", *SMALL, check=False)
        self.assertEqual(p.returncode, 1)
        self.assertIn("1 point(s) failed", p.stderr)
        self.assertIn("--link-latency=fast", p.stderr)

    def test_same_rows_through_a_local_dask_cluster(self):
        import distributed
        args = ["--set", "mesh=1,2", "--set", "link-bandwidth=100MB/s,1GB/s", "--gain", "--", *SMALL]
        self.sweep("local", *args)
        with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None,
                                      host="127.0.0.1", scheduler_port=0, silence_logs=40) as cluster:
            self.sweep("remote", "--dask", cluster.scheduler_address, *args)
        strip = ("wall_s",)
        local, remote = ([{k: v for k, v in r.items() if k not in strip} for r in self.rows(n)] for n in ("local", "remote"))
        self.assertEqual(remote, local)


if __name__ == "__main__":
    unittest.main()
