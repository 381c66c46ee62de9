"""What a sweep's point is: its identity (a hash of its flags, the binary's
and the presets' contents, so that a journalled point is known again), the
flags of the presets and reports it names, and its command line as run.
Used by the sweep driver (scripts/sweep_driver.py) and the grid
(scripts/sweep_grid.py).

Standard library only."""
import hashlib
import json
import os
import re
import shlex
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import outputs  # noqa: E402
import project  # noqa: E402
from outputs import ToolError  # noqa: E402
from project import ROOT, RTSIM  # noqa: E402

# Flags every point gets (project.run_rtsim): no reference runs, quiet, no image.
FIXED_FLAGS = project.QUIET + ["--image", ""]

# rtsim's flags that write a file (rtsim --help, "Outputs"): the driver gives
# every run its own report and no image; the others would write into the
# working folder, once per point. Refused in --set, the base flags and presets.
DRIVER_OWNS = {"--report": "the driver reads each run's report itself",
               "--image": "sweeps write no images", "--map": "sweeps draw no maps", "--vcd": "sweeps write no VCD"}
# rtsim's flags that read a file: checked (a regular file) before any run;
# a FIFO or /dev/zero would block every point.
INPUTS = ("--config", "--scene", "--rerun", "--boundaries-from")
# Flags that set the mesh's shape, one setting: rtsim refuses both on one
# command line, and the command line's replaces a preset's.
MESH = ("--mesh", "--mesh-dims")
# rtsim's flags that may be given more than once (rtsim --help: "repeatable", "repeat for more");
# of every other flag the last one given wins.
REPEATABLE = ("--config", "--node-speed", "--node-cost", "--link-set", "--trace-nodes", "--trace-links", "--light")
# Flags after which rtsim prints and stops, writing no report.
NO_RUN = ("--help", "-h", "--version")


def flag_names(args):
    """The long flags named in a list of rtsim flags ('--mesh 4' and '--mesh=4' both name --mesh)."""
    return {a.split("=", 1)[0] for a in args if a.startswith("--")}


def flag_values(args):
    """[(flag, value)] of a list of rtsim flags: '--flag=V' and '--flag V'
    give V, a flag alone (followed by another flag, or last) None."""
    out, i = [], 0
    while i < len(args):
        a = args[i]
        if a.startswith("--"):
            if "=" in a:
                out.append(tuple(a.split("=", 1)))
            elif i + 1 < len(args) and not args[i + 1].startswith("--"):
                out.append((a, args[i + 1]))
                i += 1
            else:
                out.append((a, None))
        i += 1
    return out


def check_point(args):
    """A point's flags as an experiment made them (its own and the user's
    --extra or --flags), checked before any run; ToolError, one line, for
    a flag that writes a file (the driver owns the outputs), that stops
    rtsim before it runs, a flag other than a repeatable one given twice
    with two values (rtsim runs the last, where the point's row says the
    first), both --mesh and --mesh-dims, or an input that is not a file."""
    args = [str(a) for a in args]
    for a in args:
        if a in NO_RUN or a.split("=", 1)[0] in NO_RUN:
            raise ToolError(f"{a} in a point's rtsim flags: rtsim would print and stop, with no report to read")
    seen = {}
    for flag, value in flag_values(args):
        if flag in DRIVER_OWNS:
            raise ToolError(f"{flag} in a point's rtsim flags writes a file: {DRIVER_OWNS[flag]}")
        if flag in INPUTS and value is not None:
            outputs.check_input(value, flag)
        if flag in seen and flag not in REPEATABLE and seen[flag] != value:
            raise ToolError(f"{flag} given twice in a point's rtsim flags ({seen[flag]}, then {value}): rtsim "
                            "would run the last and the row name the first; give it once (an experiment's own "
                            "flag is not for its --extra or --flags)")
        seen.setdefault(flag, value)
    if all(m in seen for m in MESH):
        raise ToolError(f"--mesh {seen['--mesh']} and --mesh-dims {seen['--mesh-dims']} in a point's rtsim flags: "
                        "both set the mesh's shape, which rtsim refuses; give one")


_binary_ids = {}


def binary_id(binary):
    """The identity of an rtsim binary: the SHA-256 of its bytes (cached by
    path, size and time of change), so that points run by another binary,
    or by this one rebuilt, are not resumed as this one's."""
    try:
        st = os.stat(binary)
    except OSError as e:
        raise ToolError(f"--rtsim {binary}: {e.strerror}")
    key = (os.path.realpath(binary), st.st_size, st.st_mtime_ns)
    if key not in _binary_ids:
        h = hashlib.sha256()
        with open(binary, "rb") as f:
            for block in iter(lambda: f.read(1 << 20), b""):
                h.update(block)
        _binary_ids[key] = h.hexdigest()[:16]
    return _binary_ids[key]


def point_id(args, binary=None, repeats=1):
    """A stable name for a point: a hash of its flags, of the settings in
    the preset files they name (--config), of the rtsim binary that runs it
    (binary_id) and, when a point runs more than once, of its repeats; so
    that a point whose preset was edited, or run by another binary, runs
    again rather than being resumed from the journal."""
    key = "\0".join(str(a) for a in args)
    settings = preset_settings(args)
    if settings is not None:
        key += "\0--config settings\0" + settings
    if binary is not None:
        key += "\0binary\0" + binary_id(binary)
    if repeats > 1:
        key += f"\0repeats\0{repeats}"
    return hashlib.sha1(key.encode()).hexdigest()[:12]


def config_paths(args):
    """The preset files (--config FILE, --config=FILE) a list of flags names, in order."""
    args = [str(a) for a in args]
    paths = []
    for i, a in enumerate(args):
        if a == "--config" and i + 1 < len(args):
            paths.append(args[i + 1])
        elif a.startswith("--config="):
            paths.append(a.split("=", 1)[1])
    return paths


def config_lines(path):
    """The settings of a preset file as rtsim reads it (tb/config_file.h):
    [(line number, name, value)] for its `name = value` lines (comments and
    blanks aside; the value unquoted, its inline comment dropped; a flag
    alone has the value 'true'). ToolError 'PATH:LINE: why' for a line that
    is not text; a line rtsim cannot read is left for rtsim to name."""
    outputs.check_input(path, "--config")
    with open(path, "rb") as f:
        return parse_config(f.read((1 << 20) + 1), path)


def rerun_lines(path):
    """The settings a report's rerun.flags give a run (rtsim --rerun
    REPORT), as config_lines gives a preset's; ToolError if it is not a
    report."""
    outputs.check_input(path, "--rerun")
    try:
        with open(path, "rb") as f:
            flags = json.loads(f.read().decode("utf-8"))["rerun"]["flags"]
        if not isinstance(flags, str):
            raise TypeError
    except (UnicodeDecodeError, json.JSONDecodeError, KeyError, TypeError, RecursionError):
        raise ToolError(f"--rerun {path}: not an rtsim report (no rerun.flags)") from None
    return parse_config(flags.encode(), f"{path}: rerun.flags")


def parse_config(data, origin):
    """config_lines of the bytes of a config text; `origin` names it in errors."""
    out = []
    if data.startswith(b"\xef\xbb\xbf"):  # (a UTF-8 byte-order mark, as rtsim's reader skips it)
        data = data[3:]
    for n, raw in enumerate(data.split(b"\n"), 1):
        if b"\0" in raw:
            raise ToolError(f"{origin}:{n}: a NUL byte (not a text file)")
        line = raw.strip()
        if not line or line[:1] in (b"#", b";"):
            continue
        try:
            text = line.decode("utf-8")
        except UnicodeDecodeError:
            raise ToolError(f"{origin}:{n}: not UTF-8 text (rtsim's presets are UTF-8)") from None
        m = re.match(r"([A-Za-z0-9][A-Za-z0-9_-]*)\s*(?:=\s*(.*))?$", text)
        if not m:
            continue
        value = "true" if m.group(2) is None else re.split(r"\s#", m.group(2), 1)[0].strip()
        if len(value) >= 2 and value[0] == value[-1] and value[0] in "\"'":
            value = value[1:-1]
        out.append((n, m.group(1), value))
    return out


def preset_settings(args):
    """The settings of the preset files the flags name (their lines without
    comments and blanks, as rtsim reads them), or None if they name none.
    ToolError for a preset that is not a readable text file."""
    paths = config_paths(args)
    if not paths:
        return None
    return "\n".join(f"{name} = {value}" for path in paths for _, name, value in config_lines(path))


def command(args, binary=RTSIM):
    """The command line of a point as run, relative to the repository."""
    rel = os.path.relpath(binary, ROOT)
    return shlex.join([rel] + [str(a) for a in args] + FIXED_FLAGS + ["--report", "REPORT.json"])
