"""A study's pool against ngspice alone (issue 35, item 2): the speed-up 2 workers give a 12-run sweep.

Run from the repository root:

    .venv/bin/python benchmarks/bench_pool.py [--rounds 2] > benchmarks/pool.md
    .venv/bin/python benchmarks/bench_pool.py --plan-only [--rounds 2]   # the plan alone: driver or pool

The sweep of ``benchmarks/pool.md``: the optimal two-mass chain, N = 300, 310, ..., 410, dt = 0.02 (runs of
1 to 2 s).  Four commands, each a whole process timed from here, in interleaved rounds (each round runs all four,
in a rotated order, so that a change in the machine's load falls on all alike): ``xargs -P1`` and ``-P2`` of
``ngspice -b`` on lcchain's 12 netlists (written once), and the installed ``lcchain sweep`` with the serial
executor and with the process executor on 2 workers, each into a new store.  Medians over the rounds, with the
load average (1 min) before and after.  The two sweeps' stores are compared at the end: the same keys, digests
and metrics (the pool must not change a result).
"""

from __future__ import annotations

import argparse
import os
import shutil
import sqlite3
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

NS = list(range(300, 411, 10))
DT = "0.02"
LCCHAIN = str(Path(sys.executable).with_name("lcchain"))
#: Every process may write and read its bytecode, as an installed lcchain does.
ENV = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}


def load() -> float:
    return os.getloadavg()[0]


def timed(command: list[str], cwd: Path) -> float:
    start = time.perf_counter()
    done = subprocess.run(command, cwd=cwd, capture_output=True, text=True, env=ENV)
    if done.returncode != 0:
        raise SystemExit(f"{command[:3]} failed: {done.stderr[-2000:]}")
    return time.perf_counter() - start


def rows(store: Path) -> list[tuple[str, str, str]]:
    with sqlite3.connect(store) as db:
        return sorted(db.execute("SELECT key, digest, metrics FROM records").fetchall())


def plan_table(rounds: int) -> list[str]:
    """The sweep's plan alone, in this process: designed in the driver, or on a pool started for it (its start
    included), interleaved; wall and CPU time (the driver's, and the workers'), the plans' fingerprints compared."""
    import resource

    from lcchain.studies.plan import SweepAxes, sweep_plan
    from lcchain.studies.pools import started_pool

    def cpu(who: int) -> float:
        used = resource.getrusage(who)
        return used.ru_utime + used.ru_stime

    axes = {"cases": ["two-mass"], "Ns": NS, "dts": [float(DT)]}
    rows = []
    same = True
    before = load()
    for _ in range(rounds):
        driver, start = cpu(resource.RUSAGE_SELF), time.perf_counter()
        alone = sweep_plan(SweepAxes(**axes))
        rows.append(("in the driver", time.perf_counter() - start, cpu(resource.RUSAGE_SELF) - driver, 0.0))
        driver, workers, start = cpu(resource.RUSAGE_SELF), cpu(resource.RUSAGE_CHILDREN), time.perf_counter()
        with started_pool(2) as pool:
            shared = sweep_plan(SweepAxes(**axes), pool=pool)
            wall = time.perf_counter() - start
        rows.append(("on 2 workers started for it (their start included)", wall,
                     cpu(resource.RUSAGE_SELF) - driver, cpu(resource.RUSAGE_CHILDREN) - workers))
        same = same and alone.fingerprint("39") == shared.fingerprint("39")
    lines = [f"The plan alone: `sweep_plan` of the 12 points in one process, {rounds} interleaved rounds, load "
             f"average {before:.2f} to {load():.2f}; the same plan both ways (fingerprints equal): {same}.", "",
             "| designed | wall (s) | driver's CPU (s) | workers' CPU (s) |", "|---|---:|---:|---:|"]
    lines += [f"| {where} | {wall:.2f} | {mine:.2f} | {theirs:.2f} |" for where, wall, mine, theirs in rows]
    return lines


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--rounds", type=int, default=2)
    parser.add_argument("--plan-only", action="store_true", help="only the plan, in the driver or on the pool")
    args = parser.parse_args()
    if args.plan_only:
        print("\n".join(plan_table(args.rounds)))
        return
    env = ENV
    ngspice = shutil.which("ngspice") or "ngspice"
    sweep = [LCCHAIN, "sweep", "--case", "two-mass", "--N", ",".join(map(str, NS)), "--dt", DT]
    with tempfile.TemporaryDirectory(prefix="lcchain-bench-pool-") as folder:
        work = Path(folder)
        for N in NS:
            subprocess.run([LCCHAIN, "netlist", "--case", "two-mass", "--N", str(N), "--dt", DT, "-o",
                            f"n{N}.cir"], cwd=work, check=True, env=env, capture_output=True)
        xargs = 'ls n*.cir | xargs -P{} -n1 sh -c \'{} -b -r "${{0%.cir}}.raw" "$0" > "${{0%.cir}}.log" 2>&1\''
        commands = {
            "xargs -P1": lambda r: ["bash", "-c", xargs.format(1, ngspice)],
            "xargs -P2": lambda r: ["bash", "-c", xargs.format(2, ngspice)],
            "serial": lambda r: [*sweep, "--executor", "serial", "--store", f"s{r}.sqlite"],
            "process": lambda r: [*sweep, "--executor", "process", "--workers", "2", "--store", f"p{r}.sqlite"],
        }
        names = list(commands)
        times: dict[str, list[float]] = {name: [] for name in names}
        before = load()
        subprocess.run([*sweep, "--executor", "serial", "--N", "300", "--store", "warm.sqlite"], cwd=work,
                       env=env, capture_output=True)  # bytecode written, caches warm
        for r in range(args.rounds):
            for name in names[r % len(names):] + names[:r % len(names)]:
                times[name].append(timed(commands[name](r), work))
        after = load()
        same = all(rows(work / f"s{r}.sqlite") == rows(work / f"p{r}.sqlite") for r in range(args.rounds))
    med = {name: statistics.median(t) for name, t in times.items()}
    show = {name: ", ".join(f"{t:.2f}" for t in ts) for name, ts in times.items()}
    print("# Pool speed-up on 2 cores: a 12-run sweep (issue 35, item 2)\n")
    print("Command: `.venv/bin/python benchmarks/bench_pool.py "
          f"--rounds {args.rounds} > benchmarks/pool.md`  ")
    print(f"Machine: {os.cpu_count()} cores, shared; load average (1 min) {before:.2f} at the start, "
          f"{after:.2f} at the end. Sweep: two-mass, N = {NS[0]} to {NS[-1]} by 10, dt = {DT}; "
          f"{args.rounds} interleaved rounds, medians (each round's times in brackets).\n")
    print("| what | one at a time | two at a time | speed-up |")
    print("|---|---:|---:|---:|")
    print(f"| `ngspice -b` alone on the 12 netlists (xargs -P1 / -P2) | {med['xargs -P1']:.2f} s "
          f"({show['xargs -P1']}) | {med['xargs -P2']:.2f} s ({show['xargs -P2']}) | "
          f"{med['xargs -P1'] / med['xargs -P2']:.2f} |")
    print(f"| `lcchain sweep` (serial / process, 2 workers) | {med['serial']:.2f} s ({show['serial']}) | "
          f"{med['process']:.2f} s ({show['process']}) | {med['serial'] / med['process']:.2f} |")
    print(f"\nThe serial and pool stores hold the same keys, digests and metrics: {same}.")


if __name__ == "__main__":
    main()
