"""Tests that a sweep stops when told (scripts/sweep.py; issue 60, "Stops that
stop"): Ctrl-C (SIGINT) or SIGTERM to a 12-point sweep ends it within 1 s,
exit 128 + the signal (130, 143) and one line; its running rtsim children and their process groups
are gone, their temporary reports removed, no queued point starts after the
stop; the journal holds the points that finished before it, parses, and a
rerun resumes them. A second sweep of the same NAME meanwhile is refused
(the journal's lock). rtsim is a fake here (a shell script that sleeps), so
the test takes seconds.
Run by ctest as: /usr/bin/python3 test_sweep_stops.py <rtsim binary> (unused)."""
import json
import os
import shlex
import signal
import stat
import subprocess
import sys
import tempfile
import time
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
SWEEP = os.path.join(HERE, "..", "..", "scripts", "sweep.py")
if len(sys.argv) > 1:
    sys.argv.pop(1)  # (the real rtsim: not needed)

POINTS = 12
FAST = 2  # points 1 and 2 finish at once, the others sleep until killed
JOBS = 3

# A fake rtsim: logs its start (point and pid), sleeps for points above FAST
# unless the file `fast` exists (in a child of its own, which must die with
# it: the whole process group), then writes the report the driver reads.
FAKE = """#!/bin/sh
dir={dir}
k=; report=; prev=
for a in "$@"; do
  case "$a" in --k=*) k="${{a#--k=}}";; esac
  [ "$prev" = "--report" ] && report="$a"
  prev="$a"
done
echo "$k $$" >> "$dir/starts.log"
if [ ! -e "$dir/fast" ] && [ "$k" -gt {fast} ]; then
  sleep 60 &
  echo "$!" >> "$dir/sleeps.log"
  wait
fi
cat > "$report" <<EOF
{{"render_time_ns": $k, "frames": [{{"render_time_ns": $k}}], "nodes": [{{"node": [0, 0, 0], "busy_ns": 1}}],
 "busiest_links": []}}
EOF
"""


def alive(pid):
    """Whether a process lives (a zombie, killed and waiting to be reaped, does not)."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rsplit(")", 1)[1].split()[0] != "Z"
    except (FileNotFoundError, ProcessLookupError):
        return False


def group_members(pgid):
    """The living processes of a process group."""
    out = []
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                with open(f"/proc/{entry}/stat") as f:
                    fields = f.read().rsplit(")", 1)[1].split()
            except OSError:
                continue
            if int(fields[2]) == pgid and fields[0] != "Z":
                out.append(int(entry))
    return out


class SweepStops(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.dir = self.tmp.name
        self.binary = os.path.join(self.dir, "rtsim")
        with open(self.binary, "w") as f:
            f.write(FAKE.format(dir=shlex.quote(self.dir), fast=FAST))
        os.chmod(self.binary, os.stat(self.binary).st_mode | stat.S_IEXEC)
        self.temps = os.path.join(self.dir, "tmp")  # the sweep's TMPDIR: its temporary reports
        os.mkdir(self.temps)
        self.journal = os.path.join(self.dir, "j", "stops.jsonl")
        self.csv = os.path.join(self.dir, "stops.csv")
        self.procs = []

    def tearDown(self):
        for p in self.procs:  # a sweep that did not stop (a failed test): end it and its children
            if p.poll() is None:
                os.killpg(p.pid, signal.SIGKILL)
                p.wait()
        for pid, _ in self.starts():
            for member in group_members(pid):
                os.kill(member, signal.SIGKILL)
        self.tmp.cleanup()

    def command(self):
        return ["/usr/bin/python3", SWEEP, "stops", "--rtsim", self.binary, "--journal-dir", os.path.dirname(self.journal),
                "--csv", self.csv, "--jobs", str(JOBS), "--set", "k=" + ",".join(str(k) for k in range(1, POINTS + 1))]

    def start(self):
        env = {**os.environ, "TMPDIR": self.temps}
        p = subprocess.Popen(self.command(), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env,
                             start_new_session=True)
        self.procs.append(p)
        return p

    def starts(self):
        """[(pid, point)] of every fake rtsim started so far."""
        try:
            with open(os.path.join(self.dir, "starts.log")) as f:
                return [(int(pid), int(k)) for k, pid in (line.split() for line in f)]
        except FileNotFoundError:
            return []

    def records(self):
        with open(self.journal) as f:
            return [json.loads(line) for line in f]

    def wait_for(self, what, timeout=20):
        deadline = time.monotonic() + timeout
        while not what():
            self.assertLess(time.monotonic(), deadline, "the sweep never got there")
            time.sleep(0.02)

    def stop_midway(self, signum):
        p = self.start()
        # Running: the fast points journalled, JOBS slow ones started.
        self.wait_for(lambda: os.path.exists(self.journal) and len(self.records()) == FAST
                      and len(self.starts()) == FAST + JOBS and os.path.exists(os.path.join(self.dir, "sleeps.log")))
        # Meanwhile a second sweep of the same NAME is refused: one line, exit 2.
        second = subprocess.run(self.command(), capture_output=True, text=True, timeout=30)
        self.assertEqual(second.returncode, 2, second.stderr)
        self.assertEqual(len(second.stderr.strip().splitlines()), 1, second.stderr)
        self.assertIn("another sweep of that NAME is running", second.stderr)

        t0 = time.monotonic()
        os.kill(p.pid, signum)
        try:
            _, err = p.communicate(timeout=5)
        except subprocess.TimeoutExpired:
            self.fail(f"{signal.Signals(signum).name}: the sweep did not end within 5 s")
        took = time.monotonic() - t0
        # (The stop returns as soon as the children are gone: waiting out a
        # fixed delay once took 0.83 s every time.)
        self.assertLess(took, 0.5, f"{signal.Signals(signum).name}: the sweep took {took:.2f} s to end")
        self.assertEqual(p.returncode, 128 + signum, err)  # (130 for Ctrl-C, 143 for SIGTERM, as rtsim's)
        self.assertEqual(err.strip().splitlines()[-1], f"sweep.py: stopped ({signal.Signals(signum).name})")

        # No child and nothing of its group remains (the fake's own `sleep` neither).
        started = self.starts()
        for pid, k in started:
            self.assertFalse(alive(pid), f"point {k}'s rtsim {pid} still runs")
            self.assertEqual(group_members(pid), [], f"point {k}'s process group still has processes")
        with open(os.path.join(self.dir, "sleeps.log")) as f:
            for pid in f.read().split():
                self.assertFalse(alive(int(pid)), "a grandchild of a point still runs")
        # No queued point started after the stop.
        time.sleep(0.3)
        self.assertEqual(len(self.starts()), FAST + JOBS, "a queued point started after the stop")
        # No temporary report or half-written output left.
        self.assertEqual(os.listdir(self.temps), [])
        self.assertEqual(sorted(os.listdir(os.path.dirname(self.journal))), ["stops.jsonl"])
        self.assertFalse(os.path.exists(self.csv))
        # The journal holds the finished points and parses; a rerun resumes them.
        self.assertEqual(sorted(r["params"]["k"] for r in self.records()), ["1", "2"])
        open(os.path.join(self.dir, "fast"), "w").close()
        p = self.start()
        out, err = p.communicate(timeout=60)
        self.assertEqual(p.returncode, 0, err)
        self.assertIn(f"{POINTS} points", out)
        rerun = [k for _, k in self.starts()[len(started):]]
        self.assertEqual(sorted(rerun), list(range(FAST + 1, POINTS + 1)))  # the finished points were not rerun
        self.assertEqual(len(self.records()), POINTS)

    def test_a_stop_before_any_point_ends_is_one_line(self):
        """No progress line was printed yet: the stop's line is the only
        one on stderr (it began with an empty line)."""
        with open(self.binary, "w") as f:
            f.write(f"#!/bin/sh\necho \"0 $$\" >> {shlex.quote(os.path.join(self.dir, 'starts.log'))}\n"
                    "exec sleep 60\n")
        p = self.start()
        self.wait_for(lambda: len(self.starts()) == JOBS)
        os.kill(p.pid, signal.SIGINT)
        _, err = p.communicate(timeout=5)
        self.assertEqual((p.returncode, err), (130, "sweep.py: stopped (SIGINT)\n"))

    def test_sigkill_leaves_no_child_and_the_next_sweep_cleans_up(self):
        """kill -9 of a sweep: no handler runs, yet its rtsim children die
        with it (setpriv --pdeathsig), and its folder of temporary reports
        (TMPDIR/rtsim-reports-PID) goes when the next sweep starts."""
        with open(self.binary, "w") as f:  # a fake that stays this process while it sleeps (exec)
            f.write(f"#!/bin/sh\necho \"0 $$\" >> {shlex.quote(os.path.join(self.dir, 'starts.log'))}\n"
                    "exec sleep 60\n")
        p = self.start()
        self.wait_for(lambda: len(self.starts()) == JOBS)
        folders = os.listdir(self.temps)
        self.assertEqual(folders, [f"rtsim-reports-{p.pid}"])
        p.kill()
        p.wait()
        deadline = time.monotonic() + 2
        while any(alive(pid) for pid, _ in self.starts()) and time.monotonic() < deadline:
            time.sleep(0.02)
        for pid, _ in self.starts():
            self.assertFalse(alive(pid), "an rtsim of the killed sweep still runs")
        self.assertEqual(os.listdir(self.temps), folders)  # (what a SIGKILL leaves: the folder, until the next sweep)
        with open(self.binary, "w") as f:
            f.write(FAKE.format(dir=shlex.quote(self.dir), fast=POINTS))
        os.remove(self.journal)  # (nothing journalled; the lock died with the sweep)
        again = self.start()
        _, err = again.communicate(timeout=60)
        self.assertEqual(again.returncode, 0, err)
        self.assertEqual(os.listdir(self.temps), [])

    def test_ctrl_c_stops_the_sweep_and_its_children(self):
        self.stop_midway(signal.SIGINT)

    def test_sigterm_stops_the_sweep_and_its_children(self):
        self.stop_midway(signal.SIGTERM)


if __name__ == "__main__":
    unittest.main()
