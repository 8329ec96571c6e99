"""Behaviour's fingerprint, to compare before and after a refactoring (issue 34's "Done when").

Prints, one line each, what must not change when the code is reshaped:

- every reference netlist (``lcchain reference-netlists``), hashed byte for byte;
- every example scene's plan: each row's key (its netlist and run options hashed) and label;
- a small transient sweep and a small AC sweep run in real ngspice: every row's key and stored digest.

Usage (the two outputs must be equal)::

    git stash; .venv/bin/python benchmarks/fingerprint.py > before.txt; git stash pop
    .venv/bin/python benchmarks/fingerprint.py > after.txt; diff before.txt after.txt

It reaches the plans through the command line where one exists and through ``lcchain.studies.plan`` where none
does (:func:`_scene_plan`, the one call to update when the planner's signature changes).
"""

from __future__ import annotations

import hashlib
import json
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parent.parent
LCCHAIN = [sys.executable, "-m", "lcchain"]


def _run(*args: str) -> str:
    done = subprocess.run([*LCCHAIN, *args], capture_output=True, text=True, check=False)
    if done.returncode != 0:
        raise SystemExit(f"lcchain {' '.join(args)} failed ({done.returncode}):\n{done.stderr}")
    return done.stdout


def reference_netlists(tmp: Path) -> list[str]:
    out = tmp / "netlists"
    _run("reference-netlists", "--out", str(out))
    return [f"netlist {path.name} {hashlib.sha256(path.read_bytes()).hexdigest()}"
            for path in sorted(out.glob("*.cir"))]


def _scene_plan(path: Path) -> Any:
    """The scene's plan with nothing varied (update this call, and only it, when the planner's signature changes)."""
    from lcchain.studies import plan

    return plan.scene_sweep_plan(path, [])


def scene_plans() -> list[str]:
    from lcchain.spice.engines import find_engine

    version = find_engine("ngspice").version
    lines = []
    for path in sorted((ROOT / "examples" / "scenes").glob("*.toml")):
        made = _scene_plan(path)
        rows = made.rows(version)
        for key, params, label in rows:
            lines.append(f"scene {path.name} {key} {label} {json.dumps(params, sort_keys=True)}")
    return lines


def sweeps(tmp: Path) -> list[str]:
    lines = []
    for name, extra in (("transient", ["--dt", "0.05,0.03"]), ("ac", ["--analysis", "ac"])):
        store = tmp / f"{name}.sqlite"
        _run("sweep", "--case", "one-mass,two-mass", "--N", "20,40", *extra, "--store", str(store))
        rows = json.loads(_run("results", str(store), "--json"))
        runs = rows["runs"] if isinstance(rows, dict) else rows
        for run in runs:
            lines.append(f"sweep {name} {run['key']} {run['digest']} {run['status']}")
    return lines


def main() -> None:
    with tempfile.TemporaryDirectory() as folder:
        tmp = Path(folder)
        lines = reference_netlists(tmp) + scene_plans() + sweeps(tmp)
    print("\n".join(lines))
    print(f"# {len(lines)} lines", file=sys.stderr)


if __name__ == "__main__":
    main()
