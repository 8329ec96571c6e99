"""Accuracy for less (issue 14): ``--accuracy`` with extrapolation against the cheapest single run.

Run from the repository root (about 12 minutes: the single runs at 1e-7 and N = 1000 take 7 of them):

    .venv/bin/python benchmarks/bench_extrapolate.py > benchmarks/extrapolate.md

For each optimal two-mass chain and target EPS:

- *single*: the cheapest single fixed-step run that meets EPS: the largest dt whose predicted error is EPS
  itself (``dt_for_accuracy(..., safety=1)``, no margin), run as ``simulate(chain, dt=...)``;
- *--accuracy*: ``simulate(chain, accuracy=EPS)``, which plans (one run, a pair or a triple), runs, combines
  and compares: everything ``lcchain simulate --accuracy EPS`` does after its start-up.

Wall times are in-process (``time.perf_counter`` around the call, the chain's modes given to both), the
median of three after one warm-up call for N <= 100, one call at N = 1000.  "serial" is the sum of the
members' own ngspice wall times plus lcchain's work: what the extrapolation costs on one core (members run
two at a time on this 2-core machine).  Achieved errors are max |result - exact alpha_N| over both end loops.
"""

from __future__ import annotations

import os
import platform
import statistics
import time

from lcchain.compare.accuracy import dt_for_accuracy
from lcchain.runs.simulate import ChainOptions, simulate
from lcchain.spice.ngspice.find import find_simulator
from lcchain.theory.arrivals import stop_time
from lcchain.theory.cases import chain_for_case
from lcchain.theory.spectrum import normal_modes

CASES = [(20, 1e-5), (20, 1e-7), (100, 1e-5), (100, 1e-7), (1000, 1e-5), (1000, 1e-7)]


def timed(repeats: int, call):
    walls, report = [], None
    for _ in range(repeats):
        clock = time.perf_counter()
        report = call()
        walls.append(time.perf_counter() - clock)
    return statistics.median(walls), report


def main() -> None:
    print("# `--accuracy` with extrapolation against the cheapest single run\n")
    print(f"Machine: {os.cpu_count()} cores, Python {platform.python_version()}, "
          f"ngspice {find_simulator().version}. Command: "
          "`.venv/bin/python benchmarks/bench_extrapolate.py > benchmarks/extrapolate.md`.\n")
    print("| N | EPS | single dt | single error | single wall | chosen | dt | predicted | achieved | "
          "each run's error | each run's wall | --accuracy wall | serial | gain (wall) | gain (serial) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for N, eps in CASES:
        chain = chain_for_case("two-mass", N)
        modes = normal_modes(chain)
        repeats = 3 if N <= 100 else 1
        if repeats > 1:
            simulate(ChainOptions(accuracy=eps).request(chain), modes=modes)
        dt1 = dt_for_accuracy(modes, eps, stop_time(modes, 1), safety=1.0)
        wall1, single = timed(repeats, lambda: simulate(ChainOptions(dt=dt1).request(chain), modes=modes))  # noqa: B023
        wall, report = timed(repeats, lambda: simulate(ChainOptions(accuracy=eps).request(chain), modes=modes))  # noqa: B023
        x = report.extrapolation
        members_wall = sum(m.wall_s for m in x.members)
        serial = report.timings["total_s"] - report.timings["execute_s"] + members_wall
        runs = {1: "one run", 2: "pair", 3: "triple"}[x.runs]
        print(f"| {N} | {eps:.0e} | {dt1:.4g} | {single.comparison.max_abs_error:.2e} | {wall1:.2f} s | {runs} | "
              f"{', '.join(f'{h:.4g}' for h in x.steps)} | {report.predicted_error:.2e} | "
              f"{report.comparison.max_abs_error:.2e} | "
              f"{', '.join(f'{m.metrics.max_abs_error:.1e}' for m in x.members)} | "
              f"{', '.join(f'{m.wall_s:.2f}' for m in x.members)} s | {wall:.2f} s | {serial:.2f} s | "
              f"{wall1 / wall:.1f}x | {wall1 / serial:.1f}x |", flush=True)


if __name__ == "__main__":
    main()
