"""Runs with real parts (issue 30): ngspice against the circuit's own exact theory, its prediction, and the price.

Run from the repository root:

    .venv/bin/python benchmarks/bench_circuit_runs.py > benchmarks/circuit_runs.md

Each row is one ``lcchain.simulate`` of the kicked two-mass ladder at a fixed step (dt = 0.05, one transit), with
real parts: a coil self-capacitance alone (lossless: the circuit's cosine modes predict the error), or with a
winding resistance and a capacitor ESR (lossy: each damped pole's trapezoidal map predicts it).  It reports the
simulator's error against the exact theory of the circuit it ran and the prediction from that circuit's own
modes; what the parts cost the pulse (the exact first arrival's energy loss against the ideal chain's); the
price of the request (``lcchain.studies.plan.request_plan(...).price(1)``, the circuit's theory included) against
the whole call's wall time (its circuit solved from nothing: once, the planner's check and the comparison
sharing it); and the circuit theory alone.
"""

from __future__ import annotations

import os
import platform
import sys
import time

import lcchain
from lcchain.circuit import exact
from lcchain.circuit.effects import CapacitorESR, CoilCapacitance, CoilResistance, Effect
from lcchain.circuit.exact import CircuitTheory
from lcchain.runs.request import Request, Transient, plan_request
from lcchain.studies.plan import request_plan

PARTS: dict[str, tuple[Effect, ...]] = {
    "coil capacitance 0.01": (CoilCapacitance(0.01),),
    "+ coil R 1e-3, ESR 1e-3": (CoilCapacitance(0.01), CoilResistance(1e-3), CapacitorESR(1e-3)),
}
ROWS = [("coil capacitance 0.01", N) for N in (100, 500, 1000, 2000)] + \
    [("+ coil R 1e-3, ESR 1e-3", N) for N in (100, 250, 500)]


def main() -> int:
    print("# Runs with real parts: ngspice against the circuit's own exact theory\n")
    print("Command: `.venv/bin/python benchmarks/bench_circuit_runs.py > benchmarks/circuit_runs.md`  ")
    print(f"Machine: {platform.machine()}, {os.cpu_count()} cores, Python {sys.version.split()[0]}; "
          f"load average at start {os.getloadavg()[0]:.1f}.\n")
    print("| parts | N | states | max abs error | predicted | energy loss | priced s | took s | theory s |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    for name, N in ROWS:
        request = Request(lcchain.chain_for_case("two-mass", N), Transient(dt=0.05), effects=PARTS[name])
        price = request_plan([({"N": N}, request)]).price(1)
        elements = plan_request(request).specs[0].theory.circuit
        assert elements is not None
        start = time.perf_counter()
        theory = CircuitTheory(elements)  # alone, uncached
        alone = time.perf_counter() - start
        exact._LAST.clear()  # simulate solves its circuit from nothing, as a first call does
        start = time.perf_counter()
        report = lcchain.simulate(request)
        took = time.perf_counter() - start
        metrics = report.record.metrics
        assert metrics is not None and metrics.effects is not None
        loss = metrics.effects.energy_loss
        print(f"| {name} | {N} | {theory.states} | {metrics.max_abs_error:.3e} | {metrics.predicted_error:.3e} | "
              f"{loss:.3g} | {price.total_seconds:.2f} | {took:.2f} | {alone:.2f} |")
    print(f"\nLoad average at the end {os.getloadavg()[0]:.1f}.")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
