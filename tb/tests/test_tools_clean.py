"""Every tool leaves the tree as it was (issue 60; the tools' table of
doc/robustness.md): each script in scripts/ and scripts/experiments/ is
run from an empty temporary folder outside the repository, with --help
and, where one finishes in a few seconds, one small real run without
--doc; after each, the repository holds the same files (tracked,
untracked and ignored, each with its size and time of change) but under
out/ and build*/, where the tools may write, and the temporary folder is
still empty. A tool that writes into doc/, the repository's root or the
working folder fails here.

Run by ctest as: /usr/bin/python3 test_tools_clean.py <rtsim> (its rtref
beside it)."""
import glob
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
SCRIPTS = os.path.join(ROOT, "scripts")
RTSIM = os.path.abspath(sys.argv.pop(1)) if len(sys.argv) > 1 else os.path.join(ROOT, "build", "rtsim")
RTREF = os.path.join(os.path.dirname(RTSIM), "rtref")
PY = "/usr/bin/python3"
# Where the tools may write: out/ (their default place) and the builds.
# Python's own bytecode cache (__pycache__, ignored) is not a tool's output.
FREE = ("out", ".git", "__pycache__")
# A tool's sweep, plot and journal files under out/ carry this name, and are removed at the end.
NAME = f"tools-clean-{os.getpid()}"
TINY = ["--spheres", "20", "--size", "16x16", "--mesh", "2"]


def free(rel):
    top = rel.split(os.sep, 1)[0].split("/", 1)[0]
    return top in FREE or top.startswith("build") or "__pycache__" in rel.split("/")


def tree():
    """The repository's files and folders but the free ones: {path: (kind,
    size, time of change)}, and git's own listing of what is changed,
    untracked or ignored."""
    files = {}
    for folder, subs, names in os.walk(ROOT):
        rel_folder = os.path.relpath(folder, ROOT)
        subs[:] = [s for s in subs if not free(os.path.normpath(os.path.join(rel_folder, s)))]
        for name in subs + names:
            path = os.path.join(folder, name)
            st = os.lstat(path)
            files[os.path.relpath(path, ROOT)] = (st.st_mode >> 12, st.st_size, st.st_mtime_ns)
    git = subprocess.run(["git", "-C", ROOT, "status", "--porcelain", "--ignored", "--untracked-files=all"],
                         capture_output=True, text=True)
    status = git.stdout.splitlines() if git.returncode == 0 else []  # (a tree that is no clone: the files alone)
    return files, sorted(line for line in status if not free(line[3:]))


def changes(before, after):
    """What changed between two tree() listings, in words."""
    (fa, sa), (fb, sb) = before, after
    out = [f"new {p}" for p in sorted(fb.keys() - fa.keys())]
    out += [f"removed {p}" for p in sorted(fa.keys() - fb.keys())]
    out += [f"changed {p}" for p in sorted(fa.keys() & fb.keys()) if fa[p] != fb[p]]
    out += [f"git status: {line}" for line in sorted(set(sb) ^ set(sa))]
    return out


class ToolsLeaveNoTrace(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.work = tempfile.mkdtemp(prefix="tools-clean-")
        cls.cwd = os.path.join(cls.work, "cwd")      # where every tool runs: must stay empty
        cls.files = os.path.join(cls.work, "files")  # inputs made for them, and the outputs flags name
        os.makedirs(cls.cwd)
        os.makedirs(cls.files)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.work, ignore_errors=True)
        for folder in ("sweeps", "plots"):
            for path in glob.glob(os.path.join(ROOT, "out", folder, NAME + "*")):
                os.remove(path)

    def run_tool(self, cmd, codes=(0,), timeout=120):
        """Runs a tool from the empty folder; asserts its exit code is one
        of `codes`, that the repository holds what it held and that the
        folder is still empty. Returns the finished process."""
        before = tree()
        p = subprocess.run(cmd, cwd=self.cwd, capture_output=True, text=True, timeout=timeout,
                           stdin=subprocess.DEVNULL)
        shown = " ".join(os.path.relpath(c, ROOT) if c.startswith(ROOT) else c for c in cmd)
        self.assertIn(p.returncode, codes, f"{shown}: exit {p.returncode}: {p.stderr.strip()[-600:]}")
        self.assertEqual(changes(before, tree()), [], f"{shown} changed the repository outside out/ and build*/")
        self.assertEqual(sorted(os.listdir(self.cwd)), [], f"{shown} wrote into its working folder")
        return p

    def file(self, name):
        return os.path.join(self.files, name)

    def test_every_script_answers_help_and_writes_nothing(self):
        scripts = sorted(glob.glob(os.path.join(SCRIPTS, "*.py")) + glob.glob(os.path.join(SCRIPTS, "experiments", "*.py")))
        self.assertGreater(len(scripts), 25)
        for path in scripts:
            with open(path) as f:
                if "__main__" not in f.read():  # a module (project.py, outputs.py)
                    continue
            with self.subTest(script=os.path.relpath(path, SCRIPTS)):
                self.assertIn("usage", self.run_tool([PY, path, "--help"]).stdout.lower())
        # The shell scripts that take --help answer it before they install, build or run anything
        # (run.sh and setup.sh take no --help: their arguments go to rtsim or name a package set).
        for name in ("build.sh", "build_fast.sh", "fuzz.sh", "gtkwave_screenshot.sh", "mesh_map_example.sh",
                     "render_gallery.sh", "sanitize.sh", "test.sh"):
            with self.subTest(script=name):
                self.assertTrue(self.run_tool(["bash", os.path.join(SCRIPTS, name), "--help"]).stdout)

    def test_a_sweep_its_chart_and_the_readers(self):
        """sweep.py (2 points of a tiny scene, by default under out/sweeps/),
        plot_sweep.py on its CSV (by default under out/plots/), vcd_summary.py
        on a tiny VCD and mesh_map.py on a tiny report."""
        self.run_tool([PY, os.path.join(SCRIPTS, "sweep.py"), NAME, "--set", "link-bandwidth=100MB/s,1GB/s", "--rtsim",
                       RTSIM, "--jobs", "2", "--"] + TINY)
        # Outputs a point would write into the working folder are refused before any run.
        for flags in (["--set", "vcd=a.vcd,b.vcd", "--"] + TINY, ["--set", "mesh=1,2", "--", "--map", "m.png"] + TINY[:4]):
            self.run_tool([PY, os.path.join(SCRIPTS, "sweep.py"), NAME + "-refused", "--rtsim", RTSIM] + flags, codes=(2,))
        csv_path = os.path.join(ROOT, "out", "sweeps", NAME + ".csv")
        self.assertTrue(os.path.exists(csv_path))
        self.run_tool([PY, os.path.join(SCRIPTS, "plot_sweep.py"), csv_path, "--x", "link-bandwidth"])
        # A published CSV's chart goes under out/plots/ too, not beside the CSV in doc/
        # (what the test makes there, it removes).
        plots = os.path.join(ROOT, "out", "plots")
        there = set(os.listdir(plots)) if os.path.isdir(plots) else set()
        self.run_tool([PY, os.path.join(SCRIPTS, "plot_sweep.py"), os.path.join(ROOT, "doc", "results", "fb_scaling.csv"),
                       "--x", "N", "--group", "units"])
        for name in set(os.listdir(plots)) - there:
            os.remove(os.path.join(plots, name))
        self.run_tool([RTSIM] + TINY + ["--no-baseline", "-q", "--image", "", "--vcd", self.file("tiny.vcd"),
                                        "--report", self.file("tiny.json")])
        self.run_tool([PY, os.path.join(SCRIPTS, "vcd_summary.py"), self.file("tiny.vcd")])
        self.run_tool([PY, os.path.join(SCRIPTS, "mesh_map.py"), self.file("tiny.json"), "-o", self.file("map.png")])
        self.assertTrue(os.path.exists(self.file("map.png")))

    def test_the_experiments(self):
        """One experiment run for real, on its smallest grid; the others
        redraw their published results (--plot-only, or partition_search.py
        --merge) into a folder of the test's: their charts and tables land
        there, not in doc/."""
        out, journals = self.file("results"), self.file("journals")
        self.run_tool([PY, os.path.join(SCRIPTS, "experiments", "fb_scaling.py"), "--n", "2", "--units", "1",
                       "--out", out, "--journal-dir", journals])
        self.assertTrue(os.path.exists(os.path.join(out, "fb_scaling.md")))
        for name, csv_name in (("presets", "presets"), ("link_sweep", "link_sweep"), ("fig4", "fig4"),
                               ("stability_map", "stability"), ("links_at_scale", "links_at_scale"),
                               ("spd_never_hurts", "spd_never_hurts"), ("speed_accuracy", "speed_accuracy")):
            published = os.path.join(ROOT, "doc", "results", csv_name + ".csv")
            if not os.path.exists(published):
                continue
            shutil.copy(published, out)
            with self.subTest(experiment=name):
                self.run_tool([PY, os.path.join(SCRIPTS, "experiments", name + ".py"), "--plot-only", "--out", out])
        # partition_search.py searches nothing with --merge: the table of the published rows
        self.run_tool([PY, os.path.join(SCRIPTS, "experiments", "partition_search.py"), "--merge",
                       os.path.join(ROOT, "doc", "results", "partition_search.csv"), "--out", out])
        self.assertTrue(os.path.exists(os.path.join(out, "partition_search.md")))

    def test_the_other_tools(self):
        """The benchmarks, checkers and recorders that finish in a few
        seconds, on tiny inputs; those that build first (bench_rtsim.py,
        bench_scaling.py, the shell scripts but render_gallery.sh) only up to
        refusing a bad flag, before any work."""
        s = lambda name: os.path.join(SCRIPTS, name)
        self.run_tool([PY, s("bench_rtref.py"), "--rtref", RTREF, "--size", "16x16", "--runs", "1", "--cpu", "-1"])
        self.run_tool([PY, s("bench_rtsim.py"), "--growth", "x"], codes=(2,))
        self.run_tool([PY, s("bench_scaling.py"), "--n", "x"], codes=(2,))
        self.run_tool([PY, s("bench_edges.py"), "--runs", "0"], codes=(2,))
        self.run_tool([PY, s("bench_frames.py"), "--runs", "0"], codes=(2,))
        self.run_tool([PY, s("stress.py"), "--count", "2", "--jobs", "1", "--rtsim", RTSIM, "--rtref", RTREF])
        self.run_tool([PY, s("same_outputs.py"), "--record", self.file("same"), "--only", "out-depth-lockstep",
                       "--build", os.path.dirname(RTSIM)])
        self.run_tool([PY, s("usage_doc.py"), "--check", "--build", os.path.dirname(RTSIM)], codes=(0, 1))
        self.run_tool([PY, s("check_sizes.py")], codes=(0, 1))
        self.run_tool([PY, s("check_docs.py")], codes=(0, 1))
        # (2 while a mutant is planted: mutate.py runs this suite with one in
        # the code, and every mutant then counted this test as catching it;
        # whether the mutants fit the code is MutantsApply's to say.)
        self.run_tool([PY, s("mutate.py"), "--check"], codes=(0, 2))
        with open(self.file("fuzz.log"), "w") as f:
            f.write("stat::number_of_executed_units: 10\n")
        os.makedirs(self.file("fuzz"))
        self.run_tool([PY, s("fuzz_report.py"), self.file("fuzz.log"), "0", "1", self.file("fuzz")])
        self.assertTrue(os.path.exists(self.file("fuzz/fuzz.md")))
        self.run_tool(["bash", s("fuzz.sh"), "x"], codes=(2,))
        if os.path.exists(os.path.join(ROOT, "build", "rtref")):  # (its rtref is build/'s)
            self.run_tool(["bash", s("render_gallery.sh")])


if __name__ == "__main__":
    unittest.main()
