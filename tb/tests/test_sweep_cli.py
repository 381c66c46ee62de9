"""Tests of sweeps from the command line (scripts/sweep.py NAME --set ...,
scripts/sweep_grid.py) and of their chart (scripts/plot_sweep.py): the grid
is the product of the --set lists, each row's figures are those of rtsim run
directly with the same flags, the comparisons are the ratios they say, a
second run reruns nothing, bad input gets one line and a nonzero exit, the
same grid through a local Dask cluster gives the same rows, and the chart's
knees are in tb/tests/test_plot_sweep.py.
SweepEdges holds the promises of issue 60 for sweeps (with a fake rtsim, a
shell script, where the real one is not needed): a NAME that climbs, an
output that is a folder, a FIFO, a device, the journal or in doc/, an
output flag in --set, the base flags or a preset, flags that contradict
(mesh and mesh-dims, two --frames), an input that would block, a Latin-1
preset, --jobs -1, a bad or silent --dask: one line, exit 2, nothing
written; a damaged journal line reported FILE:LINE and skipped; another
binary's points not resumed; two grids of one NAME never overwriting each
other's CSV; --repeat's median and spread.
Run by ctest as: /usr/bin/python3 test_sweep_cli.py <rtsim binary>."""
import csv
import hashlib
import json
import os
import shlex
import shutil
import signal
import socket
import stat
import subprocess
import sys
import tempfile
import time
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPTS = os.path.join(HERE, "..", "..", "scripts")
sys.path.insert(0, SCRIPTS)
import sweep_driver as sweep  # noqa: E402

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


# A fake rtsim: logs each run (its flags) and writes the report the driver
# reads, its render time a function of its flags (FACTOR times their checksum).
FAKE = """#!/bin/sh
report=; prev=; key=
for a in "$@"; do
  if [ "$prev" = "--report" ]; then report="$a"; else key="$key $a"; fi
  prev="$a"
done
echo "$key" >> {log}
t=$(( {factor} * ($(echo "$key" | cksum | cut -d' ' -f1) % 100000 + 1) ))
printf '{{"render_time_ns": %s, "frames": [{{"render_time_ns": %s}}], "nodes": [{{"node": [0, 0, 0], "busy_ns": 1}}], "busiest_links": []}}' "$t" "$t" > "$report"
"""
SWEEP = os.path.join(SCRIPTS, "sweep.py")


def tree(folder):
    """Every file under `folder` and its SHA-256: what a refused sweep must leave as it was."""
    out = {}
    for d, _, files in os.walk(folder):
        for f in files:
            path = os.path.join(d, f)
            if stat.S_ISREG(os.lstat(path).st_mode):
                with open(path, "rb") as fh:
                    out[os.path.relpath(path, folder)] = hashlib.sha256(fh.read()).hexdigest()
            else:
                out[os.path.relpath(path, folder)] = "special"
    return out


class SweepEdges(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.dir = os.path.realpath(self.tmp.name)
        self.log = os.path.join(self.dir, "calls.log")
        self.fake = self.make_fake("rtsim", 1)
        self.work = os.path.join(self.dir, "work")  # the working folder, and the journal's below it
        self.journals = os.path.join(self.work, "a", "b")
        os.makedirs(self.journals)

    def tearDown(self):
        self.tmp.cleanup()

    def make_fake(self, name, factor):
        path = os.path.join(self.dir, name)
        with open(path, "w") as f:
            f.write(FAKE.format(log=shlex.quote(self.log), factor=factor))
        os.chmod(path, 0o755)
        return path

    def calls(self):
        if not os.path.exists(self.log):
            return 0
        with open(self.log) as f:
            return len(f.read().splitlines())

    def sweep(self, name, *args, binary=None, csv_path=None, timeout=60):
        cmd = ["/usr/bin/python3", SWEEP, name, "--rtsim", binary or self.fake, "--journal-dir", self.journals]
        cmd += ["--csv", csv_path] if csv_path else []
        return subprocess.run(cmd + list(args), capture_output=True, text=True, timeout=timeout, cwd=self.work)

    def refused(self, p, says):
        self.assertEqual(p.returncode, 2, p.stderr)
        lines = p.stderr.strip().splitlines()
        self.assertEqual(len(lines), 1, p.stderr)
        self.assertTrue(lines[0].startswith("sweep.py: "), p.stderr)
        self.assertIn(says, lines[0])

    def rows(self, path):
        with open(path, newline="") as f:
            return list(csv.DictReader(f))

    def test_names_that_climb_are_refused_and_nothing_is_written(self):
        results = os.path.join(sweep.ROOT, "doc", "results")
        before_doc = tree(results)
        before = tree(self.dir)
        for name in ("../../doc/results/fb_scaling", "../../x", "../x", "/abs", "", ".hidden", "a/b"):
            with self.subTest(name=name):
                # Without --csv the CSV would be out/sweeps/NAME.csv; the journal is in the journal folder.
                self.refused(self.sweep(name, "--set", "a=1,2"), "a name, not a path")
                self.refused(self.sweep(name, "--set", "a=1,2", csv_path=os.path.join(self.dir, "x.csv")),
                             "a name, not a path")
        # A byte that is not UTF-8 is quoted as the byte it was (it read '\\udcff').
        self.refused(self.sweep(os.fsdecode(b"a\xff"), "--set", "a=1,2"), "NAME 'a\\xff': a name, not a path")
        self.assertEqual(tree(self.dir), before)
        self.assertEqual(tree(results), before_doc)
        self.assertFalse(os.path.exists(os.path.join(sweep.ROOT, "x.csv")))
        self.assertEqual(self.calls(), 0)

    def test_bad_outputs_inputs_and_flags_get_one_line_before_any_run(self):
        fifo = os.path.join(self.work, "fifo")
        os.mkfifo(fifo)
        presets = {"vcd.conf": b"# writes a VCD\nvcd = cfg.vcd\n", "dims.conf": b"mesh-dims = 2x2x2\n",
                   "frames.conf": b"frames = 3\n", "latin1.conf": b"# caf\xe9\nlink-latency = 1us # d\xe9j\xe0\n",
                   "nodes.conf": b"node-speed = 1,1,1=2\n", "map.conf": b"map\n",
                   "report.json": json.dumps({"rerun": {"flags": 'spheres=30\nmesh-dims="2x2x1"\n'}}).encode(),
                   "deep.json": b"[" * 100000 + b"]" * 100000}
        for name, text in presets.items():
            with open(os.path.join(self.work, name), "wb") as f:
                f.write(text)
        journal = os.path.join(self.journals, "s.jsonl")
        cases = [
            (["--set", "vcd=a.vcd,b.vcd"], "--set vcd: --vcd writes a file"),
            (["--set", "map=a.png,b.png"], "--set map: --map writes a file"),
            (["--set", "a=1,2", "--", "--map", "m.png"], "--map in the rtsim flags"),
            (["--set", "a=1,2", "--", "--config", "vcd.conf"], "vcd.conf:2: --vcd writes a file"),
            (["--set", "a=1,2", "--", "--config=map.conf"], "map.conf:1: --map writes a file"),
            (["--set", "config=dims.conf,vcd.conf"], "vcd.conf:2: --vcd writes a file"),
            (["--set", "mesh=1,2", "--", "--mesh-dims", "2x2x2"], "--mesh-dims in the rtsim flags too"),
            (["--set", "mesh-dims=1x1x2,2x2x2", "--", "--mesh", "2"], "give the mesh's shape once"),
            (["--set", "frames=1,2", "--frames", "2"], "--set frames: --frames, with the driver's --frames 2"),
            (["--set", "a=1,2", "--frames", "2", "--", "--frames", "3"], "the rtsim flags: --frames, with the driver's"),
            (["--set", "a=1,2", "--frames", "2", "--", "--config", "frames.conf"], "frames.conf:1: --frames"),
            (["--set", "a=1,2", "--speedup", "--", "--config", "nodes.conf"], "nodes.conf:1: node-speed sets particular"),
            (["--set", "config=dims.conf,frames.conf", "--", "--mesh-dims", "2x2x2"],
             "dims.conf:1: mesh-dims in a swept preset"),
            (["--set", "a=1,2", "--", "--rerun", "dims.conf"], "--rerun dims.conf: not an rtsim report"),
            (["--set", "a=1,2", "--", "--rerun", "deep.json"], "--rerun deep.json: not an rtsim report"),  # (RecursionError)
            # A product built in memory before any run (10^9 points filled it): refused.
            (["--set", "seed=" + ",".join(map(str, range(1, 401))), "--set", "spheres=" + ",".join(map(str, range(1, 401)))],
             "make 160,000 points (400 x 400); a sweep runs at most 100,000"),
            (["--set", "a=1,2", "--", "--config", "latin1.conf"], "latin1.conf:2: not UTF-8"),
            (["--set", "a=1,2", "--", "--config", fifo], "a FIFO, not a file"),
            (["--set", "a=1,2", "--", "--config", "/dev/zero"], "--config /dev/zero: a device"),
            (["--set", "a=1,2", "--", "--scene", "/dev/zero"], "--scene /dev/zero: a device"),
            (["--set", "scene=/dev/zero,x.nff"], "--scene /dev/zero: a device"),
            (["--set", "a=1,2", "--csv", fifo], "--csv " + fifo + ": a FIFO"),
            (["--set", "a=1,2", "--csv", "/dev/null"], "a device"),
            (["--set", "a=1,2", "--csv", self.dir], "a folder"),
            (["--set", "a=1,2", "--csv", os.path.join(self.dir, "no", "x.csv")], "no folder"),
            (["--set", "a=1,2", "--csv", journal], "the same file"),
            (["--set", "config=dims.conf,frames.conf", "--csv", "dims.conf"], "the same file"),
            (["--set", "a=1,2", "--csv", os.path.join(sweep.ROOT, "doc", "x.csv")], "in doc/"),
            (["--set", "a=1,2", "--journal-dir", "/dev/null"], "--journal-dir /dev/null: not a folder"),
            (["--set", "a=1,2", "--journal-dir", ""], "--journal-dir '': an empty folder name"),
            (["--set", "a=1,2", "--jobs", "-1"], "--jobs: '-1'"),
            (["--set", "a=1,2", "--dask", "tcp://127.0.0.1:1", "--dask-timeout", "nan"], "--dask-timeout: 'nan'"),
            (["--set", "a=1,2", "--repeat", "0"], "--repeat 0: at least 1"),
            (["--set", "a=1,2", "--repeat", "1000000000"], "--repeat 1000000000: at least 1 and at most 1000"),
            (["--set", "a=1,2", "--csv", os.path.join(self.dir, "j"), "--journal-dir", os.path.join(self.dir, "j")],
             "the same path (the journal's folder)"),
            (["--set", "a=1,2", "--dask", "nohost:8786"], "tcp://HOST:PORT"),
            (["--set", "a=1,2", "--dask", "tcp://nohost"], "tcp://HOST:PORT"),
        ]
        before = tree(self.dir)
        for args, says in cases:
            with self.subTest(args=args):
                self.refused(self.sweep("s", *args, timeout=20), says)
        self.assertEqual(tree(self.dir), before)  # nothing written: no journal, no CSV
        self.assertEqual(self.calls(), 0)

    def test_a_silent_dask_scheduler_is_one_line_within_its_timeout(self):
        with socket.socket() as s:  # a port nobody listens on
            s.bind(("127.0.0.1", 0))
            port = s.getsockname()[1]
        before = tree(self.dir)
        t0 = time.monotonic()
        p = self.sweep("s", "--set", "a=1,2", "--dask", f"tcp://127.0.0.1:{port}", "--dask-timeout", "1")
        self.assertLess(time.monotonic() - t0, 15)
        self.refused(p, "no scheduler answered within 1 s")
        self.assertEqual(tree(self.dir), before)  # no journal started
        self.assertEqual(self.calls(), 0)

    def test_damaged_journal_lines_are_named_and_skipped(self):
        out = os.path.join(self.dir, "s.csv")
        p = self.sweep("s", "--set", "a=1,2,3,4,5", csv_path=out)
        self.assertEqual(p.returncode, 0, p.stderr)
        first = self.rows(out)
        path = os.path.join(self.journals, "s.jsonl")
        with open(path, "rb") as f:
            lines = f.read().splitlines()
        # Points 1, 2 and 5 lose their records: undecodable, foreign and
        # malformed lines come first, the last record is cut short (a kill).
        damaged = [b"\xff\xfe not text", b"123", b'{"x": 1}', lines[2], lines[3], b'{"id": 5, "params": {}}',
                   b"[" * 100000 + b"]" * 100000, lines[4][:len(lines[4]) // 2]]
        with open(path, "wb") as f:
            f.write(b"\n".join(damaged))
        p = self.sweep("s", "--set", "a=1,2,3,4,5", csv_path=out)
        self.assertEqual(p.returncode, 0, p.stderr)
        warned = [ln for ln in p.stderr.splitlines() if ln.startswith(path + ":")]
        self.assertEqual([ln.split(":")[1] for ln in warned], ["1", "2", "3", "6", "7", "8"], p.stderr)
        self.assertTrue(all(ln.endswith("skipped (any point it held runs again)") for ln in warned), warned)
        self.assertEqual(self.calls(), 5 + 3)  # the three points whose records were lost
        strip = [{k: v for k, v in r.items() if k != "wall_s"} for r in first]
        self.assertEqual([{k: v for k, v in r.items() if k != "wall_s"} for r in self.rows(out)], strip)
        # The records appended after the cut line are whole: a third run reruns nothing.
        p = self.sweep("s", "--set", "a=1,2,3,4,5", csv_path=out)
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertEqual(self.calls(), 8)

    def test_a_report_without_what_the_sweep_reads_fails_its_point_in_words(self):
        # --rtsim another program (or an older rtsim) whose report lacks `nodes`:
        # the point fails naming what is missing, exit 1; not "internal error: KeyError".
        other = os.path.join(self.dir, "other")
        with open(self.fake) as f:
            fake = f.read()
        text = fake.replace('"nodes": [{"node": [0, 0, 0], "busy_ns": 1}], ', "")
        self.assertNotEqual(text, fake)
        with open(other, "w") as g:
            g.write(text)
        os.chmod(other, 0o755)
        p = self.sweep("lacks", "--set", "mesh=1,2", "--", "--spheres", "5", binary=other)
        self.assertEqual(p.returncode, 1, p.stderr)
        self.assertIn("2 point(s) failed", p.stderr)
        self.assertIn("its report lacks what the sweep reads (KeyError: 'nodes'): not this rtsim's report?", p.stderr)
        self.assertNotIn("internal error", p.stderr)

    def test_another_binarys_points_are_not_resumed(self):
        out = os.path.join(self.dir, "s.csv")
        self.assertEqual(self.sweep("s", "--set", "a=1,2", csv_path=out).returncode, 0)
        ones = [float(r["render_time_ns"]) for r in self.rows(out)]
        other = self.make_fake("rtsim-other", 3)
        p = self.sweep("s", "--set", "a=1,2", csv_path=out, binary=other)
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertEqual(self.calls(), 4)
        self.assertEqual([float(r["render_time_ns"]) for r in self.rows(out)], [3 * t for t in ones])
        self.assertEqual(self.sweep("s", "--set", "a=1,2", csv_path=out).returncode, 0)
        self.assertEqual(self.calls(), 4)  # the first binary's points: resumed

    def test_two_sweeps_of_one_name_never_overwrite_each_others_csv(self):
        out = os.path.join(self.dir, "s.csv")
        self.assertEqual(self.sweep("s", "--set", "a=1,2", csv_path=out).returncode, 0)
        with open(out, "rb") as f:
            kept = f.read()
        for args in (["--set", "b=1,2"], ["--set", "a=1,2", "--gain"], ["--set", "a=1,2", "--", "--mesh", "2"]):
            with self.subTest(args=args):
                self.refused(self.sweep("s", *args, csv_path=out), "holds the rows of another sweep")
                with open(out, "rb") as f:
                    self.assertEqual(f.read(), kept)
        # The same sweep extended: its CSV grows.
        self.assertEqual(self.sweep("s", "--set", "a=1,2,3", csv_path=out).returncode, 0)
        self.assertEqual([r["a"] for r in self.rows(out)], ["1", "2", "3"])
        # Another grid under the same NAME, its CSV elsewhere: the journal keeps both.
        self.assertEqual(self.sweep("s", "--set", "b=1,2", csv_path=os.path.join(self.dir, "t.csv")).returncode, 0)

    def test_a_csv_written_by_another_sweep_meanwhile_is_left_as_it_is(self):
        """Two sweeps writing one CSV at once (other NAMEs, or one NAME and
        two --journal-dir): the later refuses to replace the other's rows;
        its points are journalled, a rerun with another --csv writes them
        without running anything."""
        out = os.path.join(self.dir, "shared.csv")
        meddler = os.path.join(self.dir, "rtsim-meddler")  # the other sweep, writing the CSV while this one runs
        with open(meddler, "w") as f:
            f.write(FAKE.format(log=shlex.quote(self.log), factor=1) + f"printf 'theirs\\n' > {shlex.quote(out)}\n")
        os.chmod(meddler, 0o755)
        p = self.sweep("s", "--set", "a=1,2", binary=meddler, csv_path=out)
        self.assertEqual(p.returncode, 2, p.stderr)  # (after the progress lines, one line)
        self.assertTrue(p.stderr.strip().splitlines()[-1].startswith("sweep.py: --csv "), p.stderr)
        self.assertIn("written by another process while this sweep ran", p.stderr.strip().splitlines()[-1])
        with open(out) as f:
            self.assertEqual(f.read(), "theirs\n")
        self.assertEqual(self.calls(), 2)
        p = self.sweep("s", "--set", "a=1,2", binary=meddler, csv_path=os.path.join(self.dir, "mine.csv"))
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertIn("2 points (0 runs, 2 resumed)", p.stdout)
        self.assertEqual(self.calls(), 2)
        self.assertEqual([r["a"] for r in self.rows(os.path.join(self.dir, "mine.csv"))], ["1", "2"])

    def test_journal_records_with_bad_metrics_run_again(self):
        out = os.path.join(self.dir, "s.csv")
        self.assertEqual(self.sweep("s", "--set", "a=1,2,3", csv_path=out).returncode, 0)
        first = [r["render_time_ns"] for r in self.rows(out)]
        path = os.path.join(self.journals, "s.jsonl")
        with open(path) as f:
            recs = [json.loads(line) for line in f]
        recs[0]["metrics"] = {}
        recs[1]["metrics"]["render_time_ns"] = "abc"
        with open(path, "w") as f:
            f.write("".join(json.dumps(r) + "\n" for r in recs))
        p = self.sweep("s", "--set", "a=1,2,3", csv_path=out)
        self.assertEqual(p.returncode, 0, p.stderr)
        warned = [ln for ln in p.stderr.splitlines() if ln.startswith(path + ":")]
        self.assertEqual([ln.split(":")[1] for ln in warned], ["1", "2"], p.stderr)
        self.assertIn("'abc', not a number", warned[1])
        self.assertEqual(self.calls(), 3 + 2)
        self.assertEqual([r["render_time_ns"] for r in self.rows(out)], first)

    def test_refusals_before_any_run_leave_no_journal(self):
        notes = os.path.join(self.dir, "notes.csv")
        with open(notes, "w") as f:
            f.write("x\n")
        self.refused(self.sweep("zz", "--set", "a=1,2", csv_path=notes), "a file this sweep did not write")
        self.refused(self.sweep("p", "--set", "a=1,2", csv_path="/proc/t.csv"), "takes no new file")
        self.assertEqual(os.listdir(self.journals), [])
        self.assertEqual(self.calls(), 0)
        # The default CSV is named plainly, not as a path climbing from the working folder.
        p = self.sweep("zz", "--set", "a=1", "--journal-dir", os.path.join(self.dir, "no", "such"))
        self.refused(p, "--journal-dir")
        self.assertFalse(os.path.exists(os.path.join(self.dir, "no")))

    def test_working_folder_and_rtsim_names(self):
        # A bare name is the binary in the working folder, run by its absolute path.
        shutil.copy(self.fake, os.path.join(self.work, "myrtsim"))
        out = os.path.join(self.dir, "r.csv")
        p = subprocess.run(["/usr/bin/python3", SWEEP, "r", "--rtsim", "myrtsim", "--journal-dir", self.journals,
                            "--csv", out, "--set", "a=1,2"], capture_output=True, text=True, timeout=60, cwd=self.work)
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertEqual(self.calls(), 2)
        # A working folder deleted under the sweep: one line.
        gone = os.path.join(self.dir, "gone")
        os.mkdir(gone)
        p = subprocess.run(f"cd {shlex.quote(gone)} && rmdir {shlex.quote(gone)} && /usr/bin/python3 {shlex.quote(SWEEP)} "
                           f"g --rtsim {shlex.quote(self.fake)} --set a=1,2", shell=True, capture_output=True, text=True,
                           timeout=60)
        self.refused(p, "the working folder is gone")
        self.assertEqual(self.calls(), 2)

    def test_a_stop_ends_the_runs_on_dask_workers_too(self):
        """Ctrl-C to a sweep on a Dask cluster: one line, exit 130, and the
        rtsim runs already on the workers end too (cancelling their futures
        alone leaves them running to their end)."""
        import distributed
        starts = os.path.join(self.dir, "starts.log")
        slow = os.path.join(self.dir, "rtsim-slow")
        with open(slow, "w") as f:
            f.write(f"#!/bin/sh\necho $$ >> {shlex.quote(starts)}\nsleep 30\n")
        os.chmod(slow, 0o755)
        pids = lambda: open(starts).read().split() if os.path.exists(starts) else []
        alive = lambda pid: os.path.exists(f"/proc/{pid}") and open(f"/proc/{pid}/stat").read().rsplit(")", 1)[1].split()[0] != "Z"
        with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None,
                                      host="127.0.0.1", scheduler_port=0, silence_logs=40) as cluster:
            p = subprocess.Popen(["/usr/bin/python3", SWEEP, "d", "--rtsim", slow, "--journal-dir", self.journals,
                                  "--csv", os.path.join(self.dir, "d.csv"), "--dask", cluster.scheduler_address,
                                  "--set", "a=1,2,3,4,5,6"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
            deadline = time.monotonic() + 30
            while len(pids()) < 2 and time.monotonic() < deadline and p.poll() is None:
                time.sleep(0.02)
            self.assertEqual(len(pids()), 2, p.stderr.read() if p.poll() is not None else "no run started")
            t0 = time.monotonic()
            p.send_signal(signal.SIGINT)
            _, err = p.communicate(timeout=10)
            # (the runs sleep 30 s: 5 s tells a stop from their end even on a
            # loaded machine, where 1 s failed under the suite's other tests)
            self.assertLess(time.monotonic() - t0, 5.0)
            self.assertEqual(p.returncode, 130, err)
            self.assertEqual(err.strip().splitlines(), ["sweep.py: stopped (SIGINT)"])
            while any(alive(pid) for pid in pids()) and time.monotonic() < t0 + 5:
                time.sleep(0.02)
            self.assertFalse([pid for pid in pids() if alive(pid)], "a worker's rtsim still runs after the stop")

    def test_repeat_keeps_the_median_and_the_spread(self):
        out = os.path.join(self.dir, "s.csv")
        p = self.sweep("s", "--set", "a=1,2", "--repeat", "3", csv_path=out)
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertEqual(self.calls(), 6)
        for r in self.rows(out):
            self.assertLessEqual(float(r["wall_s_min"]), float(r["wall_s"]))
            self.assertLessEqual(float(r["wall_s"]), float(r["wall_s_max"]))
        # A binary whose render time changes from run to run: the point fails (exit 1).
        jitter = os.path.join(self.dir, "rtsim-jitter")
        with open(jitter, "w") as f:
            f.write(FAKE.format(log=shlex.quote(self.log), factor="$$"))
        os.chmod(jitter, 0o755)
        p = self.sweep("j", "--set", "a=1", "--repeat", "2", binary=jitter, csv_path=os.path.join(self.dir, "j.csv"))
        self.assertEqual(p.returncode, 1, p.stderr)
        self.assertIn("different render times", p.stderr)

    # A small scene, with a preset that sets the mesh's shape (2x2x2), for
    # the sweeps below run with the real rtsim.
    SMALL = ["--spheres", "60", "--radius", "0.05", "--size", "24x24", "--seed", "3"]

    def sweep_with_shape_preset(self, *args):
        """The rows of sweep `s` of SMALL with a preset of mesh-dims 2x2x2
        (args: the driver's, before the rtsim flags)."""
        preset = os.path.join(self.work, "dims.conf")
        with open(preset, "w") as f:
            f.write("mesh-dims = 2x2x2\n")
        out = os.path.join(self.dir, "s.csv")
        p = self.sweep("s", *args, "--", *self.SMALL, "--config", preset, binary=RTSIM, csv_path=out)
        self.assertEqual(p.returncode, 0, p.stderr)
        return self.rows(out)

    def direct_time(self, *flags):
        """The render time of SMALL run directly with `flags`, no preset."""
        rep = os.path.join(self.dir, "direct.json")
        subprocess.run([RTSIM, *self.SMALL, *flags, "--no-baseline", "-q", "--image", "", "--report", rep], check=True)
        with open(rep) as f:
            return json.load(f)["render_time_ns"]

    def test_speedup_runs_one_node_whatever_a_preset_says(self):
        for r in self.sweep_with_shape_preset("--set", "link-latency=100ns,1us", "--speedup"):
            self.assertEqual(float(r["time_one_ns"]), self.direct_time("--mesh", "1", "--link-latency", r["link-latency"]))
            self.assertGreater(float(r["speedup"]), 1.5)

    def test_a_swept_mesh_replaces_a_presets_mesh_shape(self):
        # rtsim's command line replaces a preset's mesh shape (either
        # spelling): each point runs its own --mesh, not the preset's 2x2x2.
        times = set()
        for r in self.sweep_with_shape_preset("--set", "mesh=1,3"):
            self.assertEqual(float(r["render_time_ns"]), self.direct_time("--mesh", r["mesh"]), r["mesh"])
            times.add(r["render_time_ns"])
        self.assertEqual(len(times), 2)  # (two meshes, two times: not the preset's mesh twice)

    def test_experiment_flags_get_one_line(self):
        script = os.path.join(SCRIPTS, "experiments", "speed_accuracy.py")
        for args, says in ((["--n", "4,64"], "--n 4,64: each N in 1..32"),
                           (["--scenes", "balls-9"], "--scenes: 'balls-9' is not one of"),
                           (["--out", "/dev/null"], "--out /dev/null: not a folder"),
                           (["--out", ""], "--out '': an empty folder name"),  # (not the default folder)
                           (["--journal-dir", ""], "--journal-dir '': an empty folder name"),
                           (["--out", os.path.join(sweep.ROOT, "doc", "results")], "in doc/, which changes only with --doc"),
                           (["--jobs", "-1"], "--jobs: '-1'")):
            with self.subTest(args=args):
                p = subprocess.run(["/usr/bin/python3", script] + args, capture_output=True, text=True, timeout=60,
                                   cwd=self.work)
                self.assertEqual(p.returncode, 2, p.stderr)
                lines = p.stderr.strip().splitlines()
                self.assertEqual(len(lines), 1, p.stderr)
                self.assertTrue(lines[0].startswith("speed_accuracy.py: error: "), p.stderr)
                self.assertIn(says, lines[0])


if __name__ == "__main__":
    unittest.main()
