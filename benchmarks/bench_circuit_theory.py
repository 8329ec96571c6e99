"""The circuit's own exact theory (lcchain.circuit.exact): accuracy and cost against N.

Run from the repository root:

    .venv/bin/python benchmarks/bench_circuit_theory.py > benchmarks/circuit_theory.md

For each chain, the circuit theory of the ladder's elements (kicked in loop 1) is built and evaluated at
10^4 times over three transits; it is compared with the chain theory (lcchain.linear_response), which
applies to these circuits, as max |circuit - chain| / I0 over both end loops.  Lossy rows: proportional
losses Q = 100.  Targets (issue 30): a lossless N = 2000 response at 10^4 times under 10 s; a lossy N = 500
under 10 s.
"""

from __future__ import annotations

import os
import platform
import sys
import time

import numpy as np

import lcchain
from lcchain.circuit.effects import Losses
from lcchain.circuit.elements import ladder_elements
from lcchain.circuit.exact import CircuitTheory
from lcchain.circuit.ladder import Ladder
from lcchain.theory.response import linear_response

ROWS = [("two-mass", N, None) for N in (100, 500, 1000, 2000)] + [("perfect", 500, None)] + \
    [("two-mass", N, 100.0) for N in (100, 250, 500)]


def main() -> int:
    print("# The circuit's own exact theory: accuracy and cost against N\n")
    print("Command: `.venv/bin/python benchmarks/bench_circuit_theory.py > benchmarks/circuit_theory.md`  ")
    print(f"Machine: {platform.machine()}, {os.cpu_count()} cores, Python {sys.version.split()[0]}; "
          f"load average at start {os.getloadavg()[0]:.1f}.\n")
    print("| chain | N | Q | states | build s | 10^4 times s | total s | max abs error vs chain theory |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|")
    for case, N, Q in ROWS:
        chain = lcchain.chain_for_case(case, N)
        ladder = Ladder(chain, 1e-5, 1e-8)
        t = np.linspace(0.0, 3.0 * N, 10_000)
        start = time.perf_counter()
        theory = CircuitTheory(ladder_elements(ladder, (Losses(Q),) if Q else (), kick=1.0))
        built = time.perf_counter()
        got = theory.currents(t * ladder.time_unit, ["L1", f"L{N}"])
        done = time.perf_counter()
        error = float(np.max(np.abs(got - linear_response(chain, t, Q=Q))))
        print(f"| {case} | {N} | {Q or '-'} | {theory.states} | {built - start:.2f} | {done - built:.2f} | "
              f"{done - start:.2f} | {error:.1e} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
