"""What a run's job costs lcchain before the simulator starts (issue 34, item 4: one job per run).

A run is asked for by a frozen, checked :class:`lcchain.spice.job.RunJob`; its transport runs a
:class:`lcchain.spice.job.TransportJob` made of the checked text (refused unless canonical).  This prints, per
call, the CPU time of each (the median of ``ROUNDS`` rounds of ``CALLS`` calls), beside one
:func:`lcchain.spice.text.require_canonical` of the same text, the check the transports made before.

Run from the repository root:

    .venv/bin/python benchmarks/bench_run_job.py > benchmarks/run_job.md
"""

from __future__ import annotations

import os
import statistics
import time
from collections.abc import Callable

import lcchain
from lcchain.runs.simulate import ChainOptions, simulation_spec
from lcchain.spice.job import RunJob, TransportJob
from lcchain.spice.text import require_canonical

ROUNDS = 7
CALLS = 500


def per_call(work: Callable[[], object]) -> float:
    """Median CPU seconds of one call."""
    rounds = []
    for _ in range(ROUNDS):
        start = time.process_time()
        for _ in range(CALLS):
            work()
        rounds.append((time.process_time() - start) / CALLS)
    return statistics.median(rounds)


def row(N: int) -> str:
    """The table's row for the perfect chain of N masses."""
    spec, _, _ = simulation_spec(lcchain.chain_for_case("perfect", N), ChainOptions(dt=0.05, transits=1))
    text, vectors, tstop = spec.netlist, spec.vectors, spec.tstop
    job = RunJob(text, vectors, tstop, foreign=False)
    make = per_call(lambda: RunJob(text, vectors, tstop, foreign=False))
    checked = per_call(lambda: TransportJob.checked(text, job))
    alone = per_call(lambda: require_canonical(text))
    lines = per_call(lambda: TransportJob.checked(text, job).lines)
    return (f"| perfect N = {N} | {len(text)} | {make * 1e6:.1f} | {checked * 1e6:.1f} | {alone * 1e6:.1f} | "
            f"{(lines - checked) * 1e6:.1f} |")


def main() -> None:
    print("# A run's job: its cost before the simulator starts\n")
    print("Command: `.venv/bin/python benchmarks/bench_run_job.py > benchmarks/run_job.md`; "
          f"load average at the start: {' '.join(f'{x:.2f}' for x in os.getloadavg())} (2 cores); "
          f"CPU time per call, the median of {ROUNDS} rounds of {CALLS} calls.\n")
    print("| chain | netlist (chars) | `RunJob(...)` (us) | `TransportJob.checked(...)` (us) | "
          "`require_canonical` alone (us) | `.lines` digest (us) |")
    print("|---|---|---|---|---|---|")
    for N in (10, 100, 1000):
        print(row(N))
    print("\nThe batch transport makes the job once and checks the text it writes once more (as before: "
          "`require_canonical` twice per run, and `measure_control`); the shared and warm transports also read "
          "`.lines`, which the shared one computed before too, and the warm one now computes after the job's own "
          "check (one `require_canonical` more per warm run).")


if __name__ == "__main__":
    main()
