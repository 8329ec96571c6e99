"""Batches against ngspice itself: ``lcchain batch`` beside ``xargs -P2 ngspice -b``, a bash loop and spicelib.

Run from the repository root, on a quiet machine:

    .venv/bin/python benchmarks/bench_batch.py [--spicelib PYTHON] > benchmarks/batch.md

``--spicelib PYTHON``: an interpreter with spicelib installed (a benchmark-only dependency, kept out of
lcchain's environment: ``python3 -m venv /tmp/spl && /tmp/spl/bin/pip install spicelib``).

Every contender runs the same distinct netlists, written once by lcchain into a temporary folder; each time is
the wall time of the whole command (interpreter start, imports, store and all), measured from here, in
interleaved rounds (each round runs every contender once, in a rotated order) so that a change in the machine's
load falls on all of them alike; the table gives the median over the rounds.  ``xargs`` and the bash loop run
``ngspice -b`` alone: they are the limit one process per run can reach.  lcchain's foreign netlists run in its
sandbox (bubblewrap), which the bare ngspice contenders do not pay.  The first table measures one run by
itself (``lcchain.spice.ngspice.runner.run``): a new ``ngspice -b`` process against a warm worker, where the
crossover that :data:`lcchain.spice.ngspice.warm.WARM_BELOW_SECONDS` is set from shows.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

import lcchain
from lcchain.runs.simulate import simulation_spec
from lcchain.spice.ngspice.find import find_simulator
from lcchain.spice.ngspice.runner import run
from lcchain.spice.ngspice.warm import WARM_BELOW_SECONDS, close_workers, warm_simulator
from lcchain.studies.plan import _seconds

ROUNDS = int(os.environ.get("LCCHAIN_BENCH_ROUNDS", "5"))
LCCHAIN = [sys.executable, "-m", "lcchain"]
SPICELIB = """
import sys, tempfile
from spicelib import SimRunner
from spicelib.simulators.ngspice_simulator import NGspiceSimulator
with tempfile.TemporaryDirectory() as out:
    runner = SimRunner(simulator=NGspiceSimulator, parallel_sims=2, output_folder=out, verbose=False)
    for path in sys.argv[1:]:
        runner.run(path)
    runner.wait_completion()
    assert runner.okSim == len(sys.argv) - 1, (runner.okSim, runner.failSim)
"""


def write_netlists(folder: Path, N: int, count: int) -> list[str]:
    """``count`` distinct netlists of the optimal two-mass chain (steps 0.05 x (1 + i/1000))."""
    folder.mkdir()
    chain = lcchain.chain_for_case("two-mass", N)
    paths = []
    for i in range(count):
        spec, _, _ = simulation_spec(chain, dt=0.05 * (1 + i / 1000))
        path = folder / f"n{i:03d}.cir"
        path.write_text(spec.netlist)
        paths.append(str(path))
    return paths


def per_run_table() -> list[str]:
    batch = find_simulator("batch")
    hot = warm_simulator(batch)
    lines = ["| N | predicted (s) | `ngspice -b` process (ms) | warm worker (ms) | process / warm |",
             "|---:|---:|---:|---:|---:|"]
    for N in (10, 30, 100, 150, 200, 300, 1000):
        spec, _, _ = simulation_spec(lcchain.chain_for_case("two-mass", N), dt=0.05)
        repeat = 21 if N <= 100 else 7 if N <= 300 else 3
        times: dict[str, list[float]] = {"batch": [], "warm": []}
        run(spec.netlist, spec.vectors, spec.tstop, simulator=hot, trusted=True, foreign=False)  # worker started
        for _ in range(repeat):
            for name, simulator in (("batch", batch), ("warm", hot)):
                start = time.perf_counter()
                run(spec.netlist, spec.vectors, spec.tstop, simulator=simulator, trusted=True, foreign=False)
                times[name].append(time.perf_counter() - start)
        b, w = (statistics.median(times[k]) for k in ("batch", "warm"))
        lines.append(f"| {N} | {_seconds(spec):.3f} | {1e3 * b:.1f} | {1e3 * w:.1f} | {b / w:.2f} |")
    close_workers()
    return lines


def timed(command: list[str], cwd: Path) -> tuple[float, dict[str, float]]:
    start = time.perf_counter()
    done = subprocess.run(command, cwd=cwd, capture_output=True)
    wall = time.perf_counter() - start
    if done.returncode != 0:
        raise SystemExit(f"{command[:4]} failed: {done.stderr.decode()[-2000:]}")
    extra = {}
    if b'"wall_s"' in done.stdout:
        extra["in_batch"] = float(json.loads(done.stdout)["wall_s"])
    return wall, extra


def contenders(paths: list[str], work: Path, spicelib: str | None) -> dict[str, Callable[[int], list[str]]]:
    ngspice = shutil.which("ngspice") or "ngspice"
    found: dict[str, Callable[[int], list[str]]] = {
        "`xargs -P2 ngspice -b`": lambda r: ["bash", "-c", f'printf "%s\\n" "$@" | xargs -P2 -I{{}} {ngspice} -b '
                                             '-r {}.raw {} >/dev/null 2>&1', "_", *paths],
        "bash loop of `ngspice -b`": lambda r: ["bash", "-c", f'for f in "$@"; do {ngspice} -b -r "$f.raw" "$f" '
                                                '>/dev/null 2>&1 || exit 1; done', "_", *paths],
        "`lcchain batch --workers 2`": lambda r: [*LCCHAIN, "batch", *paths, "--workers", "2", "--json",
                                                  "--store", str(work / f"w{r}.sqlite")],
        "`lcchain batch --workers 2 --transport process`": lambda r: [
            *LCCHAIN, "batch", *paths, "--workers", "2", "--json", "--transport", "process",
            "--store", str(work / f"p{r}.sqlite")],
        "`lcchain batch --executor serial`": lambda r: [*LCCHAIN, "batch", *paths, "--executor", "serial",
                                                        "--json", "--store", str(work / f"s{r}.sqlite")],
        "`lcchain batch --executor serial --transport process`": lambda r: [
            *LCCHAIN, "batch", *paths, "--executor", "serial", "--json", "--transport", "process",
            "--store", str(work / f"sp{r}.sqlite")],
    }
    if spicelib:
        found["spicelib 1.6.4 `SimRunner(parallel_sims=2)`"] = lambda r: [spicelib, "-c", SPICELIB, *paths]
    return found


def race(paths: list[str], work: Path, spicelib: str | None) -> list[str]:
    runners = contenders(paths, work, spicelib)
    names = list(runners)
    walls: dict[str, list[float]] = {name: [] for name in names}
    inside: dict[str, list[float]] = {name: [] for name in names}
    for r in range(ROUNDS):
        order = names[r % len(names):] + names[:r % len(names)]
        for name in order:
            wall, extra = timed(runners[name](r), work)
            walls[name].append(wall)
            if "in_batch" in extra:
                inside[name].append(extra["in_batch"])
    limit = statistics.median(walls[names[0]])
    serial_limit = statistics.median(walls[names[1]])
    lines = ["| command | runs/s | wall (s) | vs `xargs -P2` | vs the bash loop | runs only (s) |",
             "|---|---:|---:|---:|---:|---:|"]
    for name in names:
        wall = statistics.median(walls[name])
        runs_only = f"{statistics.median(inside[name]):.2f}" if inside[name] else ""
        lines.append(f"| {name} | {len(paths) / wall:.1f} | {wall:.2f} | {wall / limit:.2f} | "
                     f"{wall / serial_limit:.2f} | {runs_only} |")
    return lines


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--spicelib", metavar="PYTHON", help="an interpreter with spicelib installed")
    args = parser.parse_args()
    batch = find_simulator("batch")
    out = ["# Batches against ngspice itself", "",
           f"Command: `.venv/bin/python benchmarks/bench_batch.py{' --spicelib PYTHON' if args.spicelib else ''} "
           "> benchmarks/batch.md`  ",
           f"Machine: {platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}, "
           f"ngspice {batch.version}, lcchain {lcchain.__version__}. Chains: optimal two-mass, kick, one transit.",
           "", "## One run by itself", "",
           "Wall time of `lcchain.spice.ngspice.runner.run` on lcchain's own netlist (no sandbox), median: a new "
           "`ngspice -b` process each time, or the same warm worker (`lcchain.spice.ngspice.warm`). "
           "\"predicted\" is the "
           f"study planner's price of the run; studies send runs predicted under {WARM_BELOW_SECONDS} s to warm "
           "workers (`--transport auto`).", ""]
    out += per_run_table()
    with tempfile.TemporaryDirectory(prefix="lcchain-bench-batch-") as folder:
        work = Path(folder)
        for N, count in ((100, 40), (10, 400)):
            paths = write_netlists(work / f"N{N}", N, count)
            out += ["", f"## {count} distinct N = {N} netlists", "",
                    f"Wall time of each whole command (start-up included), median of {ROUNDS} interleaved rounds. "
                    "\"runs only\": lcchain's own `wall_s`, from the first run's start to the last one stored.", ""]
            stores = work / f"stores{N}"
            stores.mkdir()
            out += race(paths, stores, args.spicelib)
    print("\n".join(out))


if __name__ == "__main__":
    main()
