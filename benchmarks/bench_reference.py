"""The AC reference and its own bounds (issue 32 item 2): what it costs, how sharp it says it is, and the errors
it lets be measured.

Run from the repository root:

    .venv/bin/python benchmarks/bench_reference.py > benchmarks/reference.md

Part 1 times :func:`lcchain.theory.exact.driven_modes` split in its steps (LAPACK, the extended-precision
bisection, the double-double certification, the residue product) at one BLAS thread, and prints the largest
bounds.  Part 2 runs ``lcchain spectrum`` (ngspice) on the issue's cases and prints each error beside its
reference's bound.  Part 3 sets the transient comparison's reference (alpha_N(t) from LAPACK's modes or the
closed form) beside the certified one: it is far sharper than a transient run measures, so it is kept.
"""

from __future__ import annotations

import os
import platform
import time

import numpy as np

from lcchain.circuit.effects import Losses
from lcchain.runs.request import AC, Request
from lcchain.runs.spectrum import spectrum
from lcchain.theory.arrivals import stop_time
from lcchain.theory.cases import chain_for_case
from lcchain.theory.exact import driven_modes, exact_modes, sharp_frequencies_extended
from lcchain.theory.modes import cosine_sum
from lcchain.theory.reference import certify_frequencies, transfer_weights
from lcchain.theory.spectrum import normal_modes

COSTS = [("two-mass", 37), ("one-mass", 150), ("one-mass", 613), ("two-mass", 1000), ("two-mass", 2000)]
RUNS = [("one-mass", 150, None), ("one-mass", 613, None), ("two-mass", 37, None), ("two-mass", 37, 100.0),
        ("two-mass", 37, 15.0), ("two-mass", 37, 3.0)]


def timed(function, *args):
    start = time.perf_counter()
    value = function(*args)
    return value, time.perf_counter() - start


def main() -> None:
    print("# The AC reference and its own error bounds\n")
    print(f"`.venv/bin/python benchmarks/bench_reference.py > benchmarks/reference.md`, {platform.machine()}, "
          f"load average {os.getloadavg()[0]:.2f} at the start (2 cores shared with other work).\n")
    print("## Cost of the reference (seconds) and its largest bounds\n")
    print("| chain | N | LAPACK | bisection (longdouble) | certification (double-double) | residue product "
          "| omega bound (rel.) | P bound (abs.) |")
    print("|---|---|---|---|---|---|---|---|")
    for case, N in COSTS:
        chain = chain_for_case(case, N)
        modes, t0 = timed(exact_modes, chain)
        extended, t1 = timed(sharp_frequencies_extended, chain, modes.omega)
        (_, _, bound), t2 = timed(certify_frequencies, chain, extended)
        (_, P_bound), t3 = timed(transfer_weights, chain, extended, bound)
        print(f"| {case} | {N} | {t0:.2f} | {t1:.2f} | {t2:.2f} | {t3:.2f} | {np.max(bound):.2e} | "
              f"{np.max(P_bound):.2e} |")
    print("\n## Errors an AC run measures, beside the reference's bound (ngspice)\n")
    print("| chain | N | Q | omega_n rel. error | its bound | P_n abs. error | its bound | Q_n rel. error | its bound "
          "| merged | Y_11 rel. error |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for case, N, Q in RUNS:
        effects = () if Q is None else (Losses(Q),)
        report = spectrum(Request(chain_for_case(case, N), AC(), effects=effects))
        bounds = report.reference_bounds
        resolved = report.resolved.any()
        lossy = Q is not None and resolved
        bound_Q, bound_omega, bound_P = (bounds[f"reference_bound_{key}"] for key in ("Q", "omega", "P"))
        print(f"| {case} | {N} | {'-' if Q is None else f'{Q:g}'} | "
              f"{f'{report.max_rel_error_omega:.2e}' if resolved else 'none resolved'} | "
              f"{'-' if bound_omega is None else f'{bound_omega:.1e}'} | "
              f"{f'{report.max_abs_error_P:.2e}' if resolved else '-'} | "
              f"{'-' if bound_P is None else f'{bound_P:.1e}'} | "
              f"{f'{report.max_rel_error_Q:.2e}' if lossy else '-'} | "
              f"{'-' if bound_Q is None else f'{bound_Q:.1e}'} | "
              f"{int(report.merged_modes.sum())} | "
              f"{'-' if report.envelope_error is None else f'{report.envelope_error:.1e}'} |")
    print("\n## The transient's reference (alpha_N(t), lcchain.theory.spectrum.normal_modes) against this one\n")
    print("max |alpha_N(t) of the transient's modes - alpha_N(t) of the certified ones| over three transits (6001 "
          "times); a transient run is measured to 7e-11 at best (lcchain.core.limits.ACCURACY_FLOOR = 1e-9):\n")
    print("| chain | N | transient's method | difference |")
    print("|---|---|---|---|")
    for case, N in [("two-mass", 37), ("one-mass", 150), ("one-mass", 613), ("two-mass", 1000)]:
        chain = chain_for_case(case, N)
        modes, sharp = normal_modes(chain), driven_modes(chain)
        t = np.linspace(0.0, 3 * stop_time(modes, 1), 6001)
        difference = cosine_sum(modes.transfer, modes.omega, t) - cosine_sum(sharp.transfer, sharp.omega, t)
        print(f"| {case} | {N} | {modes.method} | {np.max(np.abs(difference)):.1e} |")
    print(f"\nload average {os.getloadavg()[0]:.2f} at the end.")


if __name__ == "__main__":
    main()
