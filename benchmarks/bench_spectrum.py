"""The spectrum from an AC analysis: accuracy and cost against N.

Run from the repository root:

    .venv/bin/python benchmarks/bench_spectrum.py > benchmarks/spectrum.md

For each chain, `lcchain spectrum`'s default sweep (twice the fewest frequencies that separate every pole)
runs in ngspice and is fitted (:func:`lcchain.compare.spectrum.fit_spectrum`); errors are against lcchain's
exact modes (the tests check the same against an independent dense eigen-solution).
"""

from __future__ import annotations

import platform
import time

import numpy as np

import lcchain
from lcchain.runs.spectrum import OMEGA_WEIGHT_FLOOR, measure_spectrum
from lcchain.theory.cases import chain_for_case

CASES = [("two-mass", N) for N in (20, 50, 100, 200, 300)] + [("perfect", N) for N in (20, 50, 100, 200, 400)] + [
    ("one-mass", 100), ("uniform-bounded", 100)]


def main() -> None:
    print("# The spectrum from an AC analysis: accuracy and cost against N\n")
    print("Command: `.venv/bin/python benchmarks/bench_spectrum.py > benchmarks/spectrum.md` "
          f"({platform.machine()}, 2 cores, ngspice from Debian, lcchain {lcchain.__version__}).\n")
    print(f"omega error: max |omega_circuit - omega_theory| / omega_theory over the modes weighing |P_n| >= "
          f"{OMEGA_WEIGHT_FLOOR:g} at the ends (the others are nearly cancelled poles); P error: max |P_circuit - "
          "P_theory| over every mode, an unseen one counted with P = 0. Seconds: ngspice's process, the fit, the "
          "whole call (theory included).\n")
    print("| chain | N | points | modes seen | resolved | omega error | P error | ngspice s | fit s | total s |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for case, N in CASES:
        clock = time.perf_counter()
        report = measure_spectrum(chain_for_case(case, N))
        total = time.perf_counter() - clock
        t = report.timings
        print(f"| {case} | {N} | {report.points} | {report.seen.size} | {int(np.sum(report.resolved))} | "
              f"{report.max_rel_error_omega:.1e} | {report.max_abs_error_P:.1e} | {t['ngspice_s']:.2f} | "
              f"{t['fit_s']:.2f} | {total:.2f} |", flush=True)
    print("\nThe points grow like N^2 for the optimised chains: their smallest spacing, at the top of the band, "
          "shrinks like 1/N^2, and the sweep is evenly spaced. A perfect cradle's spacing is constant, so its sweep "
          "grows like N only.")


if __name__ == "__main__":
    main()
