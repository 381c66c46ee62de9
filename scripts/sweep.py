#!/usr/bin/python3
"""Sweeps of any flags of any scene from the command line: the grid and its
rows are scripts/sweep_grid.py, run by the sweep driver every experiment
uses (scripts/sweep_driver.py).

  /usr/bin/python3 scripts/sweep.py --help
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import outputs  # noqa: E402
import sweep_grid  # noqa: E402

if __name__ == "__main__":
    sys.exit(outputs.guard("sweep.py", sweep_grid.main))
