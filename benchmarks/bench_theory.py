"""Theory benchmark: cost of the optimal designs and of alpha_N(t) against N.

Run from the repository root:

    .venv/bin/python benchmarks/bench_theory.py > benchmarks/theory.md

Targets (issue 2, on a 2-core machine): the Table II row for N = 100000 in
under 30 s, the Table I row for N = 500000 in under 60 s, alpha_N(t) on 2000
time points for N = 10^6 in under 5 s.
"""

import os
import platform
import time

import numpy as np

from lcchain.theory.closed_form import closed_form_modes
from lcchain.theory.design import optimal_one_mass, optimal_two_mass
from lcchain.theory.spectrum import transmission_amplitude


def timed(function, *args):
    start = time.perf_counter()
    value = function(*args)
    return value, time.perf_counter() - start


def main():
    print("# Theory benchmark\n")
    print("Command: `.venv/bin/python benchmarks/bench_theory.py > benchmarks/theory.md`  ")
    print(f"Machine: {platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}, "
          f"numpy {np.__version__}\n")
    print("## Optimal designs (a row of Table I / II)\n")
    print("| case | N | wall s | delta* | s* |")
    print("|---|---:|---:|---:|---:|")
    for case, sizes, function in (("two-mass", (100, 1000, 10_000, 100_000), optimal_two_mass),
                                  ("one-mass", (100, 1000, 10_000, 100_000, 500_000), optimal_one_mass)):
        for N in sizes:
            design, wall = timed(function, N)
            print(f"| {case} | {N} | {wall:.2f} | {design.delta:.6f} | {design.s:.3f} |", flush=True)
    print("\n## Modes (closed form) and alpha_N(t) on 2000 points\n")
    print("| N | modes s | alpha(2000 t) s |")
    print("|---:|---:|---:|")
    for N in (10_000, 100_000, 1_000_000):
        r, w = 4.387 * N ** (-1 / 3), 2.406 * N ** (-2 / 3)
        modes, t_modes = timed(closed_form_modes, N, r, w)
        t = np.linspace(N, N + 4 * N ** (1 / 3), 2000)
        _, t_alpha = timed(transmission_amplitude, modes, t)
        print(f"| {N} | {t_modes:.2f} | {t_alpha:.2f} |", flush=True)


if __name__ == "__main__":
    main()
