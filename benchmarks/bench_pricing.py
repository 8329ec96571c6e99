"""Is every request priced honestly? Each command's own estimate beside its measured wall time.

Run from the repository root:

    .venv/bin/python benchmarks/bench_pricing.py > benchmarks/pricing.md

The estimate is the one lcchain itself holds each command to: the smallest
``--max-time`` it accepts, found by bisection (a refused command exits 2 at
once, before any work; one still running after 3 s was accepted and is
stopped). Then the command runs with the default limits and its wall time is
measured (the whole command, interpreter start included). Target (issue 19):
nothing runs beyond 2x its estimate.
"""

from __future__ import annotations

import math
import os
import platform
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SCENE = """[chain]
case = "two-mass"
N = 50
[excitation]
kind = "pulse"
shape = "gaussian"
width = 0.2
[effects.losses]
Q = 100
[effects.tolerance]
L = 0.05
C = 0.05
samples = 40
seed = 7
[analysis]
dt = 0.05
"""
COMMANDS = [
    ["design", "--case", "two-mass", "--N", "3000"],
    ["design", "--case", "perfect", "--N", "2000"],
    ["table", "--case", "two-mass", "--N", ",".join(str(n) for n in range(10, 110, 10))],
    ["table", "--case", "one-mass", "--N", ",".join(str(n) for n in range(3, 43))],
    ["simulate", "--case", "two-mass", "--N", "100", "--dt", "0.05"],
    ["simulate", "--case", "perfect", "--N", "200", "--dt", "0.02"],
    ["simulate", "--case", "two-mass", "--N", "300", "--dt", "0.02", "--transits", "2"],
    ["run", "samples.toml"],
    ["run", str(ROOT / "examples" / "scenes" / "cradle.toml")],
    ["sweep", "--case", "two-mass,one-mass", "--N", "20,50,100", "--dt", "0.05,0.02", "--store", "s.sqlite",
     "--workers", "2"],
    ["sweep", "samples.toml", "--vary", "chain.N=20,40", "--store", "m.sqlite", "--workers", "2"],
    ["batch", *[str(p) for p in sorted((ROOT / "netlists").glob("*N20.cir"))], "--store", "b.sqlite",
     "--executor", "serial"],
    ["bench", "accuracy", "--quick", "--out", "bq"],
]


def _accepted(command: list[str], seconds: float, folder: str) -> bool:
    """Whether lcchain accepts the command under --max-time SECONDS (it refuses at once, before any work)."""
    with subprocess.Popen([*command, "--max-time", repr(seconds)], cwd=folder, stdout=subprocess.DEVNULL,
                          stderr=subprocess.PIPE, text=True, start_new_session=True) as proc:
        try:
            _, err = proc.communicate(timeout=3.0)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.communicate()
            return True
    for leftover in Path(folder).glob("*.sqlite*"):
        leftover.unlink()
    return not (proc.returncode == 2 and "--max-time" in err)


def _price(command: list[str], folder: str) -> float:
    """The smallest --max-time the command is accepted under, within 3 %."""
    lo, hi = 0.01, 1e5
    while hi / lo > 1.03:
        mid = math.sqrt(lo * hi)
        lo, hi = (lo, mid) if _accepted(command, mid, folder) else (mid, hi)
    return hi


def main() -> None:
    lcchain = [sys.executable, "-m", "lcchain"]
    print("# Requests priced against what they cost\n")
    print("Command: `.venv/bin/python benchmarks/bench_pricing.py > benchmarks/pricing.md`  ")
    print(f"Machine: {platform.machine()}, 2 cores, Python {platform.python_version()}. Estimate: the smallest "
          "`--max-time` lcchain accepts the command under (bisection); measured: the command's wall time, "
          "interpreter start included.\n")
    print("| command | estimate s | measured s | measured / estimate |")
    print("|---|---:|---:|---:|")
    worst = 0.0
    with tempfile.TemporaryDirectory() as folder:
        (Path(folder) / "samples.toml").write_text(SCENE)
        for argv in COMMANDS:
            estimate = _price([*lcchain, *argv], folder)
            with tempfile.TemporaryDirectory() as fresh:  # nothing the bisection's runs left can be resumed
                (Path(fresh) / "samples.toml").write_text(SCENE)
                start = time.perf_counter()
                done = subprocess.run([*lcchain, *argv], cwd=fresh, capture_output=True, text=True)
                measured = time.perf_counter() - start
            if done.returncode != 0:
                raise RuntimeError(f"{argv}: exit {done.returncode}: {done.stderr[-500:]}")
            worst = max(worst, measured / estimate)
            shown = " ".join(a if len(a) < 40 else a[:37] + "..." for a in argv).replace(str(ROOT) + "/", "")
            print(f"| `lcchain {shown}` | {estimate:.3g} | {measured:.3g} | {measured / estimate:.2f} |")
    print(f"\nWorst ratio: {worst:.2f} (target: at most 2).")


if __name__ == "__main__":
    main()
