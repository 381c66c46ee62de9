"""Reading a CSV's rows, each column's values checked where the caller
names its type: a CSV edited by hand, cut short or of another script
(--plot-only reads one) is one line naming the file and line, not a
traceback.

Standard library only."""
import csv
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from outputs import ToolError  # noqa: E402


def read_csv(path, types=None):
    """A CSV's rows as dicts (its header the keys). With `types` ({column:
    int, float or str}), each of those columns must be in the header and
    hold such a value on every row, converted; and there must be a row:
    otherwise ToolError naming the file and line (a CSV edited by hand, cut
    short or of another script, read by --plot-only), not a traceback."""
    try:
        with open(path, newline="", encoding="utf-8") as f:
            reader = csv.DictReader(f)
            rows = list(reader)
            header = reader.fieldnames or []
    except (UnicodeDecodeError, csv.Error) as e:
        raise ToolError(f"{path}: not a CSV ({e})")
    if types is None:
        return rows
    missing = [c for c in types if c not in header]
    if missing:
        raise ToolError(f"{path}: no column {missing[0]!r} (not this script's CSV?)")
    if not rows:
        raise ToolError(f"{path}: no rows")
    for i, r in enumerate(rows, 2):  # (line 1: the header)
        for column, kind in types.items():
            if r[column] is None:
                raise ToolError(f"{path}:{i}: the row ends before column {column} (cut short?)")
            try:
                r[column] = kind(r[column])
            except (TypeError, ValueError):
                what = "a whole number" if kind is int else "a number"
                raise ToolError(f"{path}:{i}: column {column}: {r[column]!r} is not {what}") from None
    return rows
