"""The circuit's own exact theory (lcchain.circuit.exact): accuracy and cost against N.

Run from the repository root:

    .venv/bin/python benchmarks/bench_circuit_theory.py > benchmarks/circuit_theory.md

For each chain, the circuit theory of the ladder's elements (kicked in loop 1) is built and evaluated at
10^4 times over three transits; it is compared with the chain theory (lcchain.linear_response), which
applies to these circuits, as max |circuit - chain| / I0 over both end loops.  Lossy rows: proportional
losses Q = 100.  Targets (issue 30): a lossless N = 2000 response at 10^4 times under 10 s; a lossy N = 500
under 10 s.

Hard cases (issue 30, item 6): the uniform ladder between walls, whose every matrix the sine vectors diagonalise,
against its closed form (tests/helpers/uniform.py, exact through critical damping) at 2001 times over three
transits: a coil self-resonance 1.001x the band top, an ESL resonance at it, Q = 1 and 1e6, the lowest mode damped
within 1e-10 of critical, coupling 0.999 of its limit and (N = 2000) within 1e-9 of it.
"""

from __future__ import annotations

import os
import platform
import sys
import time

import numpy as np

import lcchain
from lcchain.circuit.effects import CapacitorESL, CapacitorESR, CoilCapacitance, Effect, Losses
from lcchain.circuit.elements import ladder_elements
from lcchain.circuit.exact import CircuitTheory
from lcchain.circuit.ladder import Ladder
from lcchain.core.errors import ParameterError
from lcchain.theory.chain import MAX_COUPLING
from lcchain.theory.response import linear_response

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "tests"))
from helpers.uniform import uniform_currents  # noqa: E402  (the tests' independent closed form)

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
    hard()
    return 0


R_TOP, ESL_TOP, K_NEAR = 1.0 / (4.0 * 1.001 ** 2), 0.25, 0.999 * MAX_COUPLING


def _critical(N: int) -> float:
    """Q damping the uniform bounded ladder's lowest mode (omega_1 = 2 sin(pi / (2 (N + 1)))) critically."""
    return 1.0 / (4.0 * np.sin(np.pi / (2 * (N + 1))))


HARD: list[tuple[str, int, tuple[Effect, ...], float, dict[str, float]]] = [
    ("self-resonance 1.001x band top", 2000, (CoilCapacitance(R_TOP),), 0.0, {"coil_capacitance": R_TOP}),
    ("ESL resonance at band top", 2000, (CapacitorESL(ESL_TOP),), 0.0, {"esl": ESL_TOP}),
    ("coupling 0.999 max", 2000, (), K_NEAR, {}),
    ("coupling (1 - 1e-9) max", 2000, (), 0.5 * (1 - 1e-9), {}),
    ("Q = 1", 500, (Losses(1.0),), 0.0, {"Q": 1.0}),
    ("Q = 1e6", 500, (Losses(1e6),), 0.0, {"Q": 1e6}),
    ("lowest mode 1e-10 from critical", 500, (Losses(_critical(500) * (1 + 1e-10)),), 0.0,
     {"Q": _critical(500) * (1 + 1e-10)}),
    ("lowest mode critical", 500, (Losses(_critical(500)),), 0.0, {"Q": _critical(500)}),
    ("ESL at band top, ESR 0.01, coupling 0.999 max", 500, (CapacitorESL(ESL_TOP), CapacitorESR(0.01)), K_NEAR,
     {"esl": ESL_TOP, "esr": 0.01}),
    ("lowest mode critical", 8, (Losses(_critical(8)),), 0.0, {"Q": _critical(8)}),
]


def hard() -> None:
    print("\n## Hard cases: the uniform ladder between walls against its closed form\n")
    print("| case | N | states | build s | 2001 times s | max abs error vs closed form / I0 |")
    print("|---|---:|---:|---:|---:|---:|")
    for name, N, effects, coupling, keywords in HARD:
        chain = lcchain.chain_for_case("uniform-bounded", N)
        ladder = Ladder(chain.with_coupling(coupling) if coupling else chain, 1e-5, 1e-8)
        t = np.linspace(0.0, 3.0 * N, 2001)
        start = time.perf_counter()
        try:
            theory = CircuitTheory(ladder_elements(ladder, effects, kick=1.0))
        except ParameterError as refused:
            print(f"| {name} | {N} | - | {time.perf_counter() - start:.2f} | - | refused: {refused.field} "
                  f"({str(refused).split('so float64 loses ')[-1].split(',')[0]}) |")
            continue
        built = time.perf_counter()
        got = theory.currents(t * ladder.time_unit, ["L1", f"L{N}"])
        done = time.perf_counter()
        error = float(np.max(np.abs(got - uniform_currents(N, t, [1, N], coupling=coupling, **keywords))))
        print(f"| {name} | {N} | {theory.states} | {built - start:.2f} | {done - built:.2f} | {error:.1e} |")


if __name__ == "__main__":
    sys.exit(main())
