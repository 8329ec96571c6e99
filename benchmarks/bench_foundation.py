"""Issue 9's numbers re-measured: E-series rounding, and theory with one BLAS thread against the default.

Run from the repository root:

    .venv/bin/python benchmarks/bench_foundation.py > benchmarks/foundation.md

"Default threads" runs the same code with lcchain's BLAS limit raised to the
machine's core count (lcchain.core.blas.BLAS_THREADS), in a child process.
"""

from __future__ import annotations

import math
import os
import platform
import subprocess
import sys
import time

import numpy as np

from lcchain.circuit.effects import E_SERIES, preferred_value, preferred_values, tolerance_samples
from lcchain.theory.cases import chain_for_case

THREADED = """
import sys, time
import lcchain.core.blas as blas
blas.BLAS_THREADS = {threads}
import numpy as np
from lcchain.theory.design import optimal_two_mass
from lcchain.theory.closed_form import closed_form_modes
from lcchain.theory.spectrum import transmission_amplitude
what, N = sys.argv[1], int(sys.argv[2])
start = time.perf_counter()
if what == "design":
    optimal_two_mass(N)
else:
    modes = closed_form_modes(N, 4.387 * N ** (-1 / 3), 2.406 * N ** (-2 / 3))
    transmission_amplitude(modes, np.linspace(N, N + 4 * N ** (1 / 3), 2000))
print(time.perf_counter() - start)
"""


def loop_preferred_value(value: float, series: str) -> float:
    """The triple loop lcchain used before (one Python loop per component), for comparison."""
    decade = math.floor(math.log10(value))
    best: tuple[float, float] | None = None
    for exponent in (decade - 1, decade, decade + 1):
        scale = 10.0**exponent
        for mantissa in E_SERIES[series]:
            candidate = float(f"{mantissa * scale:.12g}")
            distance = abs(math.log(candidate / value))
            if best is None or distance < best[0]:
                best = (distance, candidate)
    assert best is not None
    return best[1]


def timed(function, *args, repeat: int = 1) -> float:
    start = time.perf_counter()
    for _ in range(repeat):
        function(*args)
    return (time.perf_counter() - start) / repeat


def threaded(what: str, N: int, threads: int) -> float:
    done = subprocess.run([sys.executable, "-c", THREADED.format(threads=threads), what, str(N)],
                          capture_output=True, text=True, check=True)
    return float(done.stdout)


def main() -> None:
    cores = os.cpu_count() or 1
    print("# Foundation numbers (issue 9)\n")
    print("Command: `.venv/bin/python benchmarks/bench_foundation.py > benchmarks/foundation.md`  ")
    print(f"Machine: {platform.machine()}, {cores} cores, Python {platform.python_version()}, numpy {np.__version__}\n")

    print("## E-series rounding\n")
    values = np.random.default_rng(1).uniform(1e-9, 1e-5, 20_000)
    loop = timed(lambda: [loop_preferred_value(v, "E96") for v in values[:2000]]) / 2000
    scalar = timed(lambda: [preferred_value(v, "E96") for v in values[:2000]]) / 2000
    bulk = timed(preferred_values, values, "E96", repeat=5) / values.size
    same = np.array_equal(preferred_values(values[:2000], "E96"),
                          [loop_preferred_value(v, "E96") for v in values[:2000]])
    chain = chain_for_case("two-mass", 1000)
    per_sample = timed(lambda: tolerance_samples(chain, 10e-6, 10e-9, samples=20, seed=1, tol_L=0.01, tol_C=0.01,
                                                 series="E96")) / 20
    print("| what | time |")
    print("|---|---:|")
    print(f"| one value, the former Python triple loop (E96) | {1e6 * loop:.0f} µs |")
    print(f"| one value, `preferred_value` (E96) | {1e6 * scalar:.0f} µs |")
    print(f"| per value, `preferred_values` on 20,000 values (E96) | {1e9 * bulk:.0f} ns |")
    print(f"| per tolerance sample, N = 1000, E96 (nominal rounded once) | {1e3 * per_sample:.1f} ms |")
    print(f"\nVectorised and loop give the same values on 2,000 random components: {same}.\n")

    print(f"## Theory with one BLAS thread (lcchain) against {cores} (the default)\n")
    print(f"| computation | 1 thread s | {cores} threads s |")
    print("|---|---:|---:|")
    for what, N, label in (("design", 20_000, "two-mass design, N = 20000"),
                           ("design", 100_000, "two-mass design, N = 100000"),
                           ("alpha", 1_000_000, "closed-form modes + alpha on 2000 t, N = 10^6")):
        print(f"| {label} | {threaded(what, N, 1):.2f} | {threaded(what, N, cores):.2f} |", flush=True)


if __name__ == "__main__":
    main()
