"""How much coupling between neighbouring coils does a cradle tolerate? First-arrival peak against k.

Run from the repository root:

    .venv/bin/python benchmarks/bench_coupling.py > benchmarks/coupling.md

(it also draws benchmarks/coupling.png). For the optimal two-mass chain and the
perfect cradle, N = 100: the exact first-arrival peak of the coupled chain
(modes of K u = omega^2 M u) at each k, and ngspice's peak and error at the
step lcchain chooses for --accuracy 1e-5, beside the predicted error. The
tolerated coupling is the |k| at which the theory's peak has fallen by 1 % and
by 0.1 % from its k = 0 value (bisection on the exact theory).
"""

from __future__ import annotations

import platform
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from scipy.optimize import brentq  # noqa: E402

import lcchain  # noqa: E402
from lcchain.theory.arrivals import first_arrival  # noqa: E402
from lcchain.theory.cases import chain_for_case  # noqa: E402
from lcchain.theory.exact import exact_modes  # noqa: E402

N = 100
KS = (-0.2, -0.1, -0.05, -0.02, -0.01, 0.0, 0.01, 0.02, 0.05, 0.1, 0.2)
ACCURACY = 1e-5
OUT = Path(__file__).resolve().parent / "coupling.png"


def peak(chain, k: float) -> float:
    return first_arrival(chain.with_coupling(k)).peak


def tolerated(chain, drop: float, sign: float) -> float:
    """|k| at which the peak has fallen by ``drop`` (relative) from k = 0, towards the sign given."""
    target = peak(chain, 0.0) * (1 - drop)
    ks = sign * np.linspace(0.0, 0.45, 91)
    values = [peak(chain, k) - target for k in ks]
    for a, b, fa, fb in zip(ks[:-1], ks[1:], values[:-1], values[1:], strict=True):
        if fa > 0 >= fb:
            return abs(brentq(lambda k: peak(chain, k) - target, a, b, xtol=1e-6))
    return float("nan")


def main() -> None:
    print("# Coupled coils: how much mutual inductance a cradle tolerates\n")
    print(f"Command: `.venv/bin/python benchmarks/bench_coupling.py > benchmarks/coupling.md` "
          f"({platform.node() and 'this machine'}, ngspice from Debian, lcchain {lcchain.__version__}).\n")
    print(f"N = {N}. Peak: the first arrival at loop N (exact theory of the coupled chain). ngspice runs each "
          f"coupled ladder (`lcchain simulate --case CASE --N {N} --coupling K --accuracy {ACCURACY:g}`); "
          "'error' is max |simulation - theory| over the first transit, 'predicted' the accuracy model's.\n")
    fig, ax = plt.subplots(figsize=(6.4, 4.0), layout="constrained")
    summary = []
    for case in ("two-mass", "perfect"):
        chain = chain_for_case(case, N)
        print(f"## {case}\n")
        print("| k | peak (theory) | peak (ngspice) | error | predicted | runs | wall s |")
        print("|---:|---:|---:|---:|---:|---:|---:|")
        dense = np.linspace(min(KS), max(KS), 81)
        (line,) = ax.plot(dense, [peak(chain, k) for k in dense], label=f"{case}, theory")
        sims = []
        for k in KS:
            clock = time.perf_counter()
            report = lcchain.simulate_chain(chain.with_coupling(k), lcchain.ChainOptions(accuracy=ACCURACY))
            wall = time.perf_counter() - clock
            first = report.comparison.arrivals[0]
            runs = report.extrapolation.runs if report.extrapolation is not None else 1
            sims.append(first.peak_sim)
            print(f"| {k:+.2f} | {first.peak_theory:.6f} | {first.peak_sim:.6f} | "
                  f"{report.comparison.max_abs_error:.2e} | {report.predicted_error:.2e} | {runs} | {wall:.1f} |")
        ax.plot(KS, sims, "o", mfc="none", color=line.get_color(), label=f"{case}, ngspice")
        row = [case, peak(chain, 0.0)] + [tolerated(chain, drop, sign) for drop in (0.001, 0.01) for sign in (-1, 1)]
        summary.append(row)
        print()
    print("## Tolerated coupling\n")
    print("|k| at which the first-arrival peak has fallen from its uncoupled value (exact theory, N = 100):\n")
    print("| chain | peak at k = 0 | -0.1 % (k < 0) | -0.1 % (k > 0) | -1 % (k < 0) | -1 % (k > 0) |")
    print("|---|---:|---:|---:|---:|---:|")
    def shown(k: float) -> str:
        return "never (|k| < 0.45)" if np.isnan(k) else f"{k:.4f}"

    for case, p0, *ks in summary:
        print(f"| {case} | {p0:.6f} | " + " | ".join(shown(k) for k in ks) + " |")
    ax.set_xlabel("coupling k of neighbouring coils")
    ax.set_ylabel("first-arrival peak at loop N")
    ax.set_title(f"Coupled coils, N = {N}")
    ax.legend(loc="lower center", fontsize=8)
    ax.grid(alpha=0.3)
    fig.savefig(OUT, dpi=120)
    print(f"\nFigure: `benchmarks/{OUT.name}` (lines: exact theory; circles: ngspice).")
    print("\n## Cost of the coupled modes\n")
    print("The coupled chain's modes solve the dense generalised problem K u = omega^2 M u (`scipy.linalg.eigh`, "
          "O(N^3)); the uncoupled chain's, a symmetric tridiagonal one. Seconds for `exact_modes`, two-mass chain, "
          "best of 3:\n")
    print("| N | uncoupled | coupled (k = 0.02) |")
    print("|---:|---:|---:|")
    for n in (100, 500, 1000, 2000):
        plain = chain_for_case("two-mass", n)
        times = []
        for chain in (plain, plain.with_coupling(0.02)):
            best = float("inf")
            for _ in range(3):
                clock = time.perf_counter()
                exact_modes(chain)
                best = min(best, time.perf_counter() - clock)
            times.append(best)
        print(f"| {n} | {times[0]:.4f} | {times[1]:.3f} |")
    print("\nHence COUPLED_MAX_N = 2000 (`lcchain.core.limits`): a coupled chain beyond it is refused, naming N.")


if __name__ == "__main__":
    main()
