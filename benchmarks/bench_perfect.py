"""Perfect cradles (issue 13): what a design costs as N grows, and how exact it stays.

Run from the repository root:

    .venv/bin/python benchmarks/bench_perfect.py > benchmarks/perfect.md

Each design is timed alone (one BLAS thread, as lcchain runs it).  Its spectrum
is then recomputed by an independent solver, numpy's dense SVD of the chain's
scaled incidence matrix (up to N = 5000: beyond, O(N^3) memory and minutes),
else by lcchain's own tridiagonal eigenvalues (``spectrum_of``); the error is
the largest relative one over the N frequencies (a free chain's zero mode
measured against the spacing).
"""

from __future__ import annotations

import math
import os
import platform
import time

import numpy as np

from lcchain.theory.perfect import perfect_design, spectrum_of

FREE = [10, 100, 500, 1000, 2000, 5000, 10000, 20000]
WALLS = [(100, 1), (500, 1), (1000, 1), (2000, 1), (5000, 1), (10000, 1), (20000, 1), (200, 3), (500, 5)]
SVD_MAX_N = 5000


def svd_frequencies(masses: np.ndarray, springs: np.ndarray) -> np.ndarray:
    N = masses.size
    A = np.zeros((N, N + 1))
    idx = np.arange(N)
    A[idx, idx] = -np.sqrt(springs[:-1] / masses)
    A[idx, idx + 1] = np.sqrt(springs[1:] / masses)
    return np.sort(np.linalg.svd(A, compute_uv=False))[-N:]


def row(N: int, walls: int) -> str:
    start = time.perf_counter()
    design = perfect_design(N, walls)
    seconds = time.perf_counter() - start
    m, K = design.chain.masses, design.chain.springs
    check = "SVD" if N <= SVD_MAX_N else "eigvalsh"
    measured = svd_frequencies(m, K) if N <= SVD_MAX_N else spectrum_of(design.chain)
    wanted = design.frequencies
    scale = np.where(wanted > 0, wanted, wanted[1] - wanted[0])
    error = float(np.max(np.abs(measured - wanted) / scale))
    spread = design.spread()
    return (f"| {N} | {walls} | {seconds:.2f} | {error:.1e} ({check}) | {abs(design.delta):.1e} | "
            f"{spread['mass_max']:.4g} | {spread['spring_min']:.4g} – {spread['spring_max']:.4g} | "
            f"{spread['distinct_masses']} / {spread['distinct_springs']} |")


def main() -> None:
    print("# Perfect cradles: cost and exactness against N\n")
    print("Command: `.venv/bin/python benchmarks/bench_perfect.py > benchmarks/perfect.md`  ")
    print(f"Machine: {platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}, "
          f"numpy {np.__version__}\n")
    print("Free ends (walls j = 0) are closed form (Krawtchouk); walls (j >= 1): the half Stieltjes recursion "
          "with extended exponents, O(N^2).  Each design is then checked (its spectrum recomputed, its mode "
          "density, alpha_N(T)), also O(N^2); the time includes it.\n")
    print("| N | walls j | design s | max relative error of the spectrum | 1 - alpha_N(T) | largest mass | "
          "springs | distinct masses / springs |")
    print("|---:|---:|---:|---:|---:|---:|---:|---:|")
    for N in FREE:
        print(row(N, 0), flush=True)
    for N, walls in WALLS:
        print(row(N, walls), flush=True)
    print(f"\nT = pi / dw in bulk units; for free chains T / N -> {math.pi / 2:.4f} (the uniform chain's "
          "speed of sound is 1 bulk spacing per sqrt(m/K)).")


if __name__ == "__main__":
    main()
