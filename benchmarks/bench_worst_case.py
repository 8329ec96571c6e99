"""Is the worst case the worst?  lcchain's search over the tolerance box against a brute force of every corner.

Run from the repository root:

    .venv/bin/python benchmarks/bench_worst_case.py > benchmarks/worst_case.md

For each small chain (N = 6..9, two-mass and perfect, 5 % parts, peak and energy) the table sets side by side:
the brute force's worst over all 2^(2N-1) corners (written here, independently of lcchain: numpy.linalg.eigh of
the hand-built matrices, the first-arrival peak from a grid and Newton steps, as tests/test_worst_case_search.py
does), the search's worst (:func:`lcchain.theory.worst_case.worst_case_search`), its certificate, and the old
analysis's worst: the corners of the K = 2 most sensitive parts and the two the first-order signs predict
(what ``--worst-case corners`` runs), evaluated in exact theory.  Then N = 50, where no brute force reaches.
"""

from __future__ import annotations

import os
import platform
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from lcchain.circuit.effects import cornered
from lcchain.circuit.ladder import Ladder
from lcchain.circuit.sensitivity import corners, ladder_sensitivity
from lcchain.theory.arrivals import first_arrival
from lcchain.theory.cases import chain_for_case
from lcchain.theory.sensitivity import energy_fraction
from lcchain.theory.worst_case import ToleranceBox, worst_case_search

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))
from helpers.worst_brute import brute_force  # noqa: E402  (the tests' brute force, independent of lcchain)

TOL = 0.05
L0, C0 = 1e-5, 1e-8


def old_corners(chain, metric: str) -> float:
    """The worst of ``--worst-case corners`` (K = 2) in exact theory."""
    sensitivity = ladder_sensitivity(Ladder(chain, L0, C0), metric=metric)
    values = []
    for corner in corners(sensitivity, components=2, tol_L=TOL, tol_C=TOL):
        at = cornered(chain, L0, C0, signs=corner.signs, tol_L=TOL, tol_C=TOL)
        peak = first_arrival(at).peak
        values.append(peak if metric == "peak" else energy_fraction(peak, at))
    return min(values)


def main() -> None:
    load = subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()
    print("# Worst case over the tolerance box: search against brute force\n")
    print("Made by `.venv/bin/python benchmarks/bench_worst_case.py > benchmarks/worst_case.md` "
          f"({platform.processor() or platform.machine()}, {os.cpu_count()} cores shared with colleagues; "
          f"`uptime` at the start: {load}).\n")
    print("5 % parts (every L and every C), free ends: 2N - 1 parts, N inductors and N - 1 capacitors. "
          "Worst = lowest first-arrival metric. *Old* = the corners of the 2 most sensitive parts and the two "
          "predicted by the first-order signs (`--worst-case corners`), in exact theory. *Bound* = the "
          "certificate's: the quadratic model's minimum over the box, proved by branch and bound (to 1e-12 "
          "for these N), less twice the largest |metric - model| seen at the evaluated points (an estimate "
          "of the remainder: a bound under that assumption, not a proof). *Worse* counts corners the brute "
          "force finds below the search's worst (by more than 1e-9).\n")
    print("| chain | N | metric | corners | brute-force worst | search worst | worse | old worst | bound | gap | "
          "evaluations | search s | brute s |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for case in ("two-mass", "perfect"):
        for N in (6, 7, 8, 9):
            chain = chain_for_case(case, N)
            for metric in ("peak", "energy"):
                started = time.perf_counter()
                values, _ = brute_force(np.asarray(chain.masses), np.asarray(chain.springs), TOL, metric)
                brute_s = time.perf_counter() - started
                found = worst_case_search(ToleranceBox(chain, TOL, TOL), metric)
                worse = int(np.sum(values < found.worst - 1e-9))
                print(f"| {case} | {N} | {metric} | {values.size} | {values.min():.6f} | {found.worst:.6f} | "
                      f"{worse} | {old_corners(chain, metric):.6f} | {found.bound:.6f} | {found.gap:.1e} | "
                      f"{found.evaluations} | {found.seconds:.2f} | {brute_s:.2f} |", flush=True)
    print("\n## N = 50 (99 parts: 2^99 corners, no brute force)\n")
    print("| chain | metric | nominal | search worst | old worst | model bound (proved for the model) | "
          "model error (est.) | bound | gap | starts | local optima | evaluations | branch-and-bound boxes | "
          "seconds |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for case in ("two-mass", "perfect"):
        chain = chain_for_case(case, 50)
        for metric in ("peak", "energy"):
            found = worst_case_search(ToleranceBox(chain, TOL, TOL), metric)
            optima = found.local_optima
            print(f"| {case} | {metric} | {found.nominal:.6f} | {found.worst:.6f} | {old_corners(chain, metric):.6f} "
                  f"| {found.model_bound:.6f} | {found.model_error:.1e} | {found.bound:.6f} | {found.gap:.1e} | "
                  f"{found.starts} | {len(optima)} ({optima[0]:.6f} .. {optima[-1]:.6f}) | {found.evaluations} | "
                  f"{found.model_nodes} | {found.seconds:.1f} |", flush=True)
    print(f"\n`uptime` at the end: {subprocess.run(['uptime'], capture_output=True, text=True).stdout.strip()}")


if __name__ == "__main__":
    main()
