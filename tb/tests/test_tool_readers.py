"""The tools' readers never trace back (issue 60, "Readers that never trace
back"): the VCD reader of scripts/vcd_summary.py, the CSV reader of
scripts/plot_sweep.py, the report reader of scripts/mesh_map.py and the
sweep driver's journal (scripts/sweep_driver.py), fed
damaged copies of the small real files in tb/tests/corpus/ (bytes flipped
or inserted, the file cut, lines deleted, duplicated, swapped or run
together; a CSV
field or a report's field given another value), answer
each with a result or one line and exit 2: never a traceback, never an
"internal error", never more than one line. Hypothesis (Debian's
python3-hypothesis) draws the damage, derandomized (the same cases every
run) and with no example database (nothing written). The corpus's
hand-made cases go through each tool's command line too.
Run by ctest as: /usr/bin/python3 test_tool_readers.py <rtsim binary>."""
import atexit
import contextlib
import csv
import io
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import unittest

# Hypothesis keeps caches in .hypothesis/ under the working folder: here,
# in a temporary of the test's own (removed at exit), not in the tree.
STORE = tempfile.mkdtemp(prefix="tool-readers-hypothesis-")
atexit.register(shutil.rmtree, STORE, True)
os.environ["HYPOTHESIS_STORAGE_DIRECTORY"] = STORE
from hypothesis import HealthCheck, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
SCRIPTS = os.path.join(ROOT, "scripts")
CORPUS = os.path.join(HERE, "corpus")
sys.argv[1:] = []  # the rtsim binary: not needed, the corpus is made
sys.path.insert(0, SCRIPTS)
import mesh_map  # noqa: E402
import outputs  # noqa: E402
import plot_sweep  # noqa: E402
import sweep_driver as sweep  # noqa: E402
import vcd_summary  # noqa: E402

# The same cases every run, nothing written beside the tests, no time limit
# per case (a loaded machine is slow, not wrong).
FUZZ = settings(derandomize=True, database=None, deadline=None, max_examples=300,
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])


# Bytes that mean something to one of the readers: a flip to one of these
# reaches past the first check more often than a random byte.
SYNTAX = list(b"0123456789.-+eE,\"\n #$bBrxz!()[]{}:naif")
# What a report's field may become.
VALUES = st.one_of(st.none(), st.booleans(), st.integers(-2, 2 ** 40), st.floats(), st.text(max_size=6),
                   st.lists(st.integers(-1, 3), max_size=4), st.just({}), st.just("DELETE"))


def corpus(name):
    with open(os.path.join(CORPUS, name), "rb") as f:
        return f.read()


def damage(data, draw):
    """`data` with one to three kinds of damage drawn by hypothesis."""
    for _ in range(draw(st.integers(1, 3))):
        kind = draw(st.sampled_from(["flip", "insert", "cut", "delete", "duplicate", "swap", "join"]))
        lines = data.split(b"\n")
        if kind == "flip" and data:
            i = draw(st.integers(0, len(data) - 1))
            data = data[:i] + bytes([draw(st.one_of(st.sampled_from(SYNTAX), st.integers(0, 255)))]) + data[i + 1:]
        elif kind == "insert":
            i = draw(st.integers(0, len(data)))
            data = data[:i] + draw(st.binary(min_size=1, max_size=8)) + data[i:]
        elif kind == "cut":
            data = data[:draw(st.integers(0, len(data)))]
        elif kind == "join" and len(lines) > 1:  # lines i..j run together (a VCD may be all on one line)
            i = draw(st.integers(0, len(lines) - 2))
            j = draw(st.integers(i + 1, len(lines) - 1))
            data = b"\n".join(lines[:i] + [b" ".join(lines[i:j + 1])] + lines[j + 1:])
        elif kind in ("delete", "duplicate", "swap") and len(lines) > 1:
            i, j = draw(st.integers(0, len(lines) - 1)), draw(st.integers(0, len(lines) - 1))
            if kind == "delete":
                del lines[i]
            elif kind == "duplicate":
                lines.insert(i, lines[i])
            else:
                lines[i], lines[j] = lines[j], lines[i]
            data = b"\n".join(lines)
    return data


def paths_in(tree, at=()):
    """Every path to a value in a JSON tree (the first 3 items of a list)."""
    yield at
    items = tree.items() if isinstance(tree, dict) else enumerate(tree[:3]) if isinstance(tree, list) else ()
    for k, v in items:
        yield from paths_in(v, at + (k,))


def read_by_the_picture(path):
    """Whether mesh_map reads the field at `path` of a report (the others
    may be anything)."""
    if not path:
        return True
    wanted = {"config": ("mesh", "balance"), "nodes": ("node", "load", "busy_ns"),
              "links": ("from", "to", "utilisation", "saturated_ns"), "boundaries": ("column", "history"),
              "busiest_links": ("name", "utilisation", "saturated_ns"), "render_time_ns": ()}
    if path[0] not in wanted:
        return False
    inner = path[2] if path[0] in ("nodes", "links", "boundaries", "busiest_links") and len(path) > 2 else \
        path[1] if path[0] == "config" and len(path) > 1 else None
    return inner is None or inner in wanted[path[0]]


def with_field_changed(tree, path, value):
    """A copy of the JSON tree with the value at `path` replaced (or deleted)."""
    tree = json.loads(json.dumps(tree))
    if not path:
        return value
    parent = tree
    for k in path[:-1]:
        parent = parent[k]
    if value == "DELETE":
        del parent[path[-1]]
    else:
        parent[path[-1]] = value
    return tree


def in_process(tool, run):
    """run() under outputs.guard, as the tool's command line runs it: (exit
    code, stdout, stderr)."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = outputs.guard(tool, lambda: run() or 0)
    return code, out.getvalue(), err.getvalue()


def read_vcd(path):
    return vcd_summary.main([path, "--windows", "4", "--top", "0"])


def read_csv(path):
    """plot_sweep's reading and knees (the printout), without drawing."""
    a = plot_sweep.parse_args([path, "--x", "link-bandwidth", "--group", "N", "--y", "render_time_ns,wall_s"])
    ys, lines = plot_sweep.analyse(a)
    logx = plot_sweep.spans_decades(x for ln in lines.values() for x in ln.xs)
    for ln in lines.values():
        plot_sweep.report_line(a, ys, ln, logx)


def read_report(path):
    """mesh_map's reading, and its figure for a report it takes."""
    r = mesh_map.read_report(path)
    mesh_map.plt.close(mesh_map.figure(r))


class ToolReaders(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.mkdtemp(prefix="tool-readers-")
        cls.cwd = os.getcwd()
        os.chdir(cls.dir)  # whatever a library might write, it writes here

    @classmethod
    def tearDownClass(cls):
        os.chdir(cls.cwd)
        shutil.rmtree(cls.dir)

    def holds(self, tool, run, data, name):
        """The promise for one damaged file: a result, or one line and exit 2."""
        path = os.path.join(self.dir, name)
        with open(path, "wb") as f:
            f.write(data)
        code, _, err = in_process(tool, lambda: run(path))
        self.assertIn(code, (0, 2), err)
        self.assertNotIn("Traceback", err)
        self.assertNotIn("internal error", err)
        if code == 0:
            self.assertEqual(err, "")
        else:
            self.assertEqual(err.count("\n"), 1, err)
            self.assertTrue(err[:-1].isprintable(), err)
            self.assertTrue(err.startswith(f"{tool}: "), err)

    @FUZZ
    @given(st.data())
    def test_damaged_vcds(self, data):
        source = data.draw(st.sampled_from(["tiny.vcd", "other_tool.vcd", "zero_window.vcd"]))
        self.holds("vcd_summary", read_vcd, damage(corpus(source), data.draw), "d.vcd")

    @FUZZ
    @given(st.data())
    def test_damaged_csvs(self, data):
        self.holds("plot_sweep", read_csv, damage(corpus("sweep.csv"), data.draw), "d.csv")

    @settings(FUZZ, max_examples=60)
    @given(st.data())
    def test_damaged_reports(self, data):
        self.holds("mesh_map", read_report, damage(corpus("tiny.json"), data.draw), "d.json")

    @settings(FUZZ, max_examples=120)
    @given(st.data())
    def test_reports_with_a_field_changed(self, data):
        report = json.loads(corpus("tiny.json"))
        path = data.draw(st.sampled_from([p for p in paths_in(report) if read_by_the_picture(p)]))
        changed = with_field_changed(report, path, data.draw(VALUES))
        self.holds("mesh_map", read_report, json.dumps(changed).encode(), "f.json")

    @FUZZ
    @given(st.data())
    def test_csvs_with_a_field_changed(self, data):
        rows = list(csv.reader(io.StringIO(corpus("sweep.csv").decode())))
        i, j = data.draw(st.integers(0, len(rows) - 1)), data.draw(st.integers(0, len(rows[0]) - 1))
        rows[i][j] = data.draw(st.one_of(st.text(max_size=8), st.sampled_from(["nan", "inf", "-inf", "", "1e999",
                                                                               "0", "-1", "1GB/s", "0B/s"])))
        text = io.StringIO()
        csv.writer(text, lineterminator="\n").writerows(rows)
        self.holds("plot_sweep", read_csv, text.getvalue().encode("utf-8", "surrogatepass"), "f.csv")

    @FUZZ
    @given(st.data())
    def test_damaged_journals(self, data):
        # A damaged journal line is named (FILE:LINE) and skipped, its point
        # run again; the records kept are whole records; nothing raises.
        path = os.path.join(self.dir, "d.jsonl")
        with open(path, "wb") as f:
            f.write(damage(corpus("journal.jsonl"), data.draw))
        err = io.StringIO()
        with contextlib.redirect_stderr(err):
            journal = sweep.Journal(path)
            journal.close()
        for line in err.getvalue().splitlines():
            self.assertRegex(line, r"^" + re.escape(path) + r":\d+: .*; skipped \((its point|any point it held) runs again\)$")
        for rec in journal.done.values():
            for field, kind in sweep.RECORD_FIELDS.items():
                self.assertIsInstance(rec[field], kind)
        self.assertLessEqual(len(journal.done), 4)

    def test_the_corpus_through_each_command_line(self):
        # (file, tool and its flags, exit code, what stdout or stderr says)
        cases = [
            ("tiny.vcd", ["vcd_summary.py"], 0, "5.04 us traced"),
            ("zero_window.vcd", ["vcd_summary.py"], 0, "the traced span is empty (from 1 us to 1 us)"),
            ("header_only.vcd", ["vcd_summary.py"], 0, "no time and no value change after the declarations"),
            ("one_line.vcd", ["vcd_summary.py"], 0, "5.04 us traced"),
            ("other_tool.vcd", ["vcd_summary.py"], 0, "100 ns traced"),
            ("extra_upscope.vcd", ["vcd_summary.py"], 2, "extra_upscope.vcd:110: $upscope without a $scope"),
            # (read as closed, its signals' names were wrong and its nodes missing from the summary)
            ("missing_upscope.vcd", ["vcd_summary.py"], 2,
             "missing_upscope.vcd:109: $enddefinitions with $scope machine not closed by its $upscope"),
            ("stopped.vcd", ["vcd_summary.py"], 0,
             "incomplete: the run that wrote it stopped early (interrupted by signal 2 at 5.04 us)"),
            ("cut.vcd", ["vcd_summary.py"], 0, "incomplete: its last line has no newline"),
            ("nan_inf.csv", ["plot_sweep.py", "--x", "bw", "--y", "t", "--out", "c.png"], 0,
             "left out (not a finite number): bw=2GB/s (line 2: t nan); bw=8GB/s (line 5: t inf)"),
            ("cut_row.csv", ["plot_sweep.py", "--x", "bw", "--y", "t", "--out", "c.png"], 2,
             "cut_row.csv:4: 1 fields, the header has 2"),
            ("mixed_x.csv", ["plot_sweep.py", "--x", "bw", "--y", "t", "--out", "c.png"], 2,
             "mixed_x.csv:4: column 'bw' (--x): '2us' is a time, where line 2's '1GB/s' is a rate"),
            ("sweep.csv", ["plot_sweep.py", "--x", "N", "--group", "N", "--out", "c.png"], 2,
             "--group N: the x column itself"),
            ("cut.json", ["mesh_map.py", "-o", "m.png"], 2, "cut.json:160: not JSON"),
            ("tiny.json", ["mesh_map.py", "-o", "m.png"], 0, ""),
        ]
        for name, (script, *flags), code, said in cases:
            with self.subTest(file=name):
                p = subprocess.run(["/usr/bin/python3", os.path.join(SCRIPTS, script), os.path.join(CORPUS, name),
                                    *flags], capture_output=True, text=True, timeout=120, cwd=self.dir)
                self.assertEqual(p.returncode, code, p.stderr)
                self.assertIn(said, p.stdout if code == 0 else p.stderr)
                self.assertEqual(p.stderr.count("\n"), 0 if code == 0 else 1, p.stderr)


if __name__ == "__main__":
    unittest.main()
