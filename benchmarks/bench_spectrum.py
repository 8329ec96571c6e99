"""The spectrum from an AC analysis: accuracy and cost against N, and with losses.

Run from the repository root:

    .venv/bin/python benchmarks/bench_spectrum.py --plot benchmarks/spectrum.png > benchmarks/spectrum.md

``--plot`` draws the curves of error and cost against N (two-mass and perfect chains, log-log).

For each chain, `lcchain spectrum`'s default sweep (twice the fewest frequencies that separate every pole, in
even segments placed where the poles are dense) runs in ngspice and is fitted
(:func:`lcchain.compare.spectrum.fit_spectrum`); errors are against lcchain's exact modes (the tests check the
same against an independent dense eigen-solution).  With losses (`--Q`), each mode's Q_n against omega_n Q, and
the fitted alpha_N(t) against the exact lossy response.

Seconds are measured in this process with repeats (:func:`_repeats`: 5 up to N = 200, 3 up to 1000, 2 beyond), the
least of each (the machine is shared): the engine's process, and lcchain's own time around it in the run (reading
the engine's output, the fit, the comparison with theory: ``timings["fit_s"]``).  The engine is found once, outside
the clocks.

Beside each, the survey of every loop (`lcchain spectrum --shapes`, :func:`lcchain.runs.survey.measure_modes`):
a second ngspice run that drives every loop and saves every loop's current, each mode's frequency, shape and Q_n
against the chain's exact eigensolution.  Each row gives the 1-minute load average when it ended (the machine is
shared: its timings are the engine's and the fit's on the same loaded cores, so their ratio is what to read).
"""

from __future__ import annotations

import argparse
import math
import os
import platform
import resource
import time
from pathlib import Path
from typing import Any

import numpy as np

import lcchain
from lcchain.compare.spectral import spectrum_estimate
from lcchain.core.errors import ParameterError
from lcchain.runs.spectrum import OMEGA_WEIGHT_FLOOR, SpectrumOptions, measure_spectrum
from lcchain.runs.survey import OMEGA_TARGET, SEPARATION, SHAPE_TARGET, ModeReport, measure_modes
from lcchain.spice.engines import find_engine
from lcchain.theory.cases import chain_for_case

CASES = [("two-mass", N) for N in (20, 50, 100, 200, 500, 1000, 2000)] + [
    ("perfect", N) for N in (20, 60, 100, 200, 400, 1000)] + [("one-mass", 100), ("one-mass", 1000),
                                                            ("uniform-bounded", 100)]
LOSSY = [("two-mass", N, Q) for N in (20, 100) for Q in (10.0, 100.0, 1000.0, 1e4)] + [
    ("uniform-bounded", 24, 100.0), ("two-mass", 200, 1000.0), ("two-mass", 400, 1000.0), ("two-mass", 1000, 1000.0),
    ("two-mass", 2000, 1000.0), ("perfect", 400, 1e4), ("perfect", 1000, 1e4)]
#: The lossy rows whose survey is left out (its run saves N vectors: at N = 2000 minutes of the shared machine).
SURVEY_MAX_N = 1000


def _repeats(N: int) -> int:
    """Runs of each case whose least seconds are kept."""
    return 5 if N <= 200 else 3 if N <= 1000 else 2


def _least(runs: list[dict[str, float]]) -> dict[str, float]:
    """The least of each timing over the runs."""
    return {key: min(run[key] for run in runs) for key in runs[0]}


def _load() -> str:
    return f"{os.getloadavg()[0]:.1f}"


def _peak_mb() -> str:
    """Peak resident memory so far, MB: this process (the fit), the engines it started."""
    own = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    children = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024
    return f"{own:.0f} / {children:.0f}"


def _survey_cells(survey: ModeReport, t: dict[str, float]) -> str:
    """Resolved modes, errors over the measured ones ('-': none measured, every mode merged), seconds."""
    return (f"{int(survey.resolved.sum())} | {_finite(survey.max_rel_error_omega)} | "
            f"{_finite(survey.max_shape_error)} | {t['engine_s']:.3f} | {t['fit_s']:.3f} | "
            f"{t['fit_s'] / t['engine_s']:.2f}")


def _finite(value: float | None) -> str:
    return "-" if value is None or not math.isfinite(value) else f"{value:.1e}"


class _FitClock:
    """The loop-1 fit alone (:func:`lcchain.compare.spectral._fitted`: the fit from theory's poles, or its fallback),
    timed around each call: the rest of lcchain's time beside the engine is reading its output and comparing."""

    def __init__(self) -> None:
        import lcchain.compare.spectral as spectral

        self.seconds = 0.0
        self._fitted = spectral._fitted

        def timed(*args: Any) -> Any:
            clock = time.perf_counter()
            try:
                return self._fitted(*args)
            finally:
                self.seconds = time.perf_counter() - clock

        spectral._fitted = timed


def _separated_Q_error(report: Any, Q: float) -> tuple[int, float]:
    """The loop-1 fit's Q error over the resolved modes at least SEPARATION widths 1/Q from both neighbours."""
    omega = np.asarray(report.omega_theory)
    gaps = np.diff(omega)
    nearest = np.minimum(np.r_[np.inf, gaps], np.r_[gaps, np.inf])
    held = np.asarray(report.resolved) & (nearest * Q >= SEPARATION) & (omega > 0)
    if not held.any():
        return 0, float("nan")
    with np.errstate(divide="ignore", invalid="ignore"):  # the zero mode: not held
        error = np.abs(np.asarray(report.Q) - omega * Q) / (omega * Q)
    return int(held.sum()), float(np.max(np.where(np.isnan(error), np.inf, error)[held]))


def _error(value: float) -> str:
    return "-" if value is None else f"{value:.1e}"


def _plot(rows: list[dict[str, Any]], path: Path) -> None:
    """Error and cost against N for each case measured at several N (log-log)."""
    from matplotlib.figure import Figure

    figure = Figure(figsize=(10, 5), layout="constrained")
    error_ax, cost_ax = figure.subplots(1, 2)
    for k, case in enumerate(dict.fromkeys(row["case"] for row in rows)):
        series = [row for row in rows if row["case"] == case]
        if len(series) < 3:
            continue
        N = [row["N"] for row in series]
        colour = f"C{k}"
        error_ax.loglog(N, [row["omega"] for row in series], "o-", color=colour, label=f"{case}: ω_n (relative)")
        error_ax.loglog(N, [max(row["P"], 1e-17) for row in series], "s--", color=colour, mfc="none",
                        label=f"{case}: P_n (absolute)")
        cost_ax.loglog(N, [row["ngspice"] for row in series], "o-", color=colour, label=f"{case}: ngspice")
        cost_ax.loglog(N, [row["fit"] for row in series], "s--", color=colour, mfc="none", label=f"{case}: fit")
        error_ax.loglog(N, [max(row["shape"], 1e-17) for row in series], "^:", color=colour,
                        label=f"{case}: shape (survey)")
        cost_ax.loglog(N, [row["survey_engine"] for row in series], "^-", color=colour, alpha=0.5,
                       label=f"{case}: ngspice (survey)")
        cost_ax.loglog(N, [row["survey_fit"] for row in series], "v:", color=colour, label=f"{case}: fit (survey)")
    error_ax.axhline(1e-9, color="k", linewidth=0.8, linestyle=":", label="target 1e-9")
    error_ax.set(xlabel="N (masses)", ylabel="largest error against exact theory",
                 title="accuracy of the circuit's spectrum")
    cost_ax.set(xlabel="N (masses)", ylabel="seconds", title="cost (default sweep)")
    for ax in (error_ax, cost_ax):
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=2, frameon=False)
    figure.savefig(path, dpi=120)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--plot", type=Path, help="also draw error and cost against N here (PNG)")
    parser.add_argument("--lossy", action="store_true", help="only the table with losses")
    args = parser.parse_args()
    if args.lossy:
        _lossy(find_engine())
        return
    rows: list[dict[str, Any]] = []
    print("# The spectrum from an AC analysis: accuracy and cost against N, and with losses\n")
    print("Command: `.venv/bin/python benchmarks/bench_spectrum.py --plot benchmarks/spectrum.png > "
          "benchmarks/spectrum.md` "
          f"({platform.machine()}, 2 cores, ngspice from Debian, lcchain {lcchain.__version__}).\n")
    print(f"omega error: max |omega_circuit - omega_theory| / omega_theory over the modes weighing |P_n| >= "
          f"{OMEGA_WEIGHT_FLOOR:g} at the ends (the others are nearly cancelled poles); P error: max |P_circuit - "
          "P_theory| over every mode, an unseen one counted with P = 0; response: max |alpha_N(t) of the fitted "
          "modes - exact alpha_N(t)| over the first transit. Seconds, the least of 5 runs up to N = 200, 3 up to 1000, "
          "2 beyond (the engine found once, outside the clocks): ngspice's process, lcchain's own time around it in "
          "the run (reading its output, the fit, the comparison: 'fit s'), the whole call (theory included), and what "
          "the budget priced beforehand.\n")
    print(f"Survey (every loop driven, every loop's current saved): resolved = modes with omega within "
          f"{OMEGA_TARGET:g} and shape within {SHAPE_TARGET:g} of the exact eigensolution (shape error: max over "
          "loops |u_kn - u_kn exact| / max_k |u_kn exact|, the largest over modes); seconds: its ngspice process "
          "and its fit; peak MB: this process / the largest engine process so far.\n")
    print("| chain | N | points | segments | modes seen | resolved | omega error | P error | response | "
          "fit sweeps | ngspice s | fit s | fit / ngspice | total s | priced s | survey points | survey resolved | "
          "survey omega error | shape error | survey ngspice s | survey fit s | survey fit / ngspice | spacing "
          "deviation | peak MB | load |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
          "---:|---:|---:|---:|")
    simulator = find_engine()
    for case, N in CASES:
        chain = chain_for_case(case, N)
        runs = []
        for _ in range(_repeats(N)):
            clock = time.perf_counter()
            report = measure_spectrum(chain, simulator=simulator)
            runs.append(report.timings | {"call_s": time.perf_counter() - clock})
        t = _least(runs)
        total = t["call_s"]
        print(f"| {case} | {N} | {report.points} | {report.segments} | {int(report.seen.sum())} | "
              f"{int(np.sum(report.resolved))} | {report.max_rel_error_omega:.1e} | {report.max_abs_error_P:.1e} | "
              f"{_error(report.response_error)} | {report.fit.sweeps} | {t['ngspice_s']:.3f} | {t['fit_s']:.3f} | "
              f"{t['fit_s'] / t['ngspice_s']:.2f} | "
              f"{total:.2f} | {spectrum_estimate(report.points, N).seconds:.2f} | ", end="", flush=True)
        surveys = [measure_modes(chain, simulator=simulator) for _ in range(_repeats(N))]
        survey, s = surveys[-1], _least([dict(run.timings) for run in surveys])
        print(f"{survey.points} | {_survey_cells(survey, s)} | {survey.spacing_deviation:.1e} | {_peak_mb()} | "
              f"{_load()} |", flush=True)
        rows.append({"case": case, "N": N, "omega": report.max_rel_error_omega, "P": report.max_abs_error_P,
                     "ngspice": t["ngspice_s"], "fit": t["fit_s"], "shape": survey.max_shape_error,
                     "survey_engine": s["engine_s"], "survey_fit": s["fit_s"]})
    print("\nThe default spectrum's whole cost, (ngspice + fit) / N^2, seconds: " + ", ".join(
        f"{row['case']} N = {row['N']}: {(row['ngspice'] + row['fit']) / row['N'] ** 2:.1e}"
        for row in rows if row["N"] >= 500) + "; its fit / ngspice, largest over every row: " + max(
        (f"{row['fit'] / row['ngspice']:.2f} ({row['case']} N = {row['N']})" for row in rows),
        key=lambda text: float(text.split()[0])) + ".")
    print("\nThe survey's whole cost, (its ngspice + its fit) / N^2, seconds: " + ", ".join(
        f"{row['case']} N = {row['N']}: {(row['survey_engine'] + row['survey_fit']) / row['N'] ** 2:.1e}"
        for row in rows if row["N"] >= 500) + "; its fit / ngspice, largest over every row: " + max(
        (f"{row['survey_fit'] / row['survey_engine']:.2f} ({row['case']} N = {row['N']})" for row in rows),
        key=lambda text: float(text.split()[0])) + ".")
    if args.plot:
        _plot(rows, args.plot)
    _lossy(simulator)


def _lossy(simulator: Any) -> None:
    """The table with losses."""
    clock_fit = _FitClock()
    print("\n## With losses (`--Q`)\n")
    print("Command: `.venv/bin/python benchmarks/bench_spectrum.py --lossy` (this section alone; the whole file "
          "without it).\n")
    print("Q error: max |Q_n - omega_n Q| / (omega_n Q) over the resolved modes of nonzero frequency; pole error: "
          "max |p_n - p_theory| / |p_theory|, p_theory = -1/(2Q) + j sqrt(omega_n^2 - 1/(4Q^2)). An unseen resolved "
          "mode makes both infinite. Q error (separated): the same over the resolved modes at least "
          f"{SEPARATION:g} widths 1/Q from both neighbours (how many: 'separated'). Seconds, the least of 3 runs up to "
          "N = 200, of 2 beyond, 1 at N = 2000: ngspice's process; the loop-1 fit alone ('loop-1 fit s': from theory's "
          "poles, or its fallback); lcchain's whole time around the engine ('fit s': reading its output, the fit, "
          "the comparison, with losses Y_11 against the exact admittance over the sweep); the whole call; the price "
          "(`spectrum_estimate`). Y_11 error: max |Y_11 - exact| / |exact| over the sweep; Y_11 bound: the exact "
          "admittance's own error bound (float64 with a first-order running error bound, long double where that "
          "bound is above a tenth of the error, double-double where long double's still is: "
          "`compare.spectral.compare_envelope`).\n")
    print(f"Survey: 'survey merged' the modes the losses merge, by the loop-1 fit's rule (said, not measured: their "
          "theory is subtracted before the fit); resolved, omega and shape errors over the measured modes ('-': none "
          f"measured); Q error over the modes at least {SEPARATION:g} widths 1/Q from both neighbours (separated); "
          "currents error: max over the sweep of max_k |g_k - exact| / max_k |exact| of the loops' currents, with "
          "merged modes (float64 reference); seconds, the least of as many runs as the loop-1 fit's; '-' on the "
          "left: the loop-1 fit refuses the chain at that Q.\n")
    print("| chain | N | Q | points | modes seen | merged | omega error | P error | Q error | separated | "
          "Q error (separated) | pole error | response | Y_11 error | Y_11 bound | ngspice s | loop-1 fit s | "
          "loop-1 fit / ngspice | fit s | fit / ngspice | total s | priced s | survey merged | survey resolved | "
          "survey omega error | shape error | survey ngspice s | survey fit s | survey fit / ngspice | separated | "
          "survey Q error | currents error | load |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
          "---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    ratios: list[tuple[float, float, float, str]] = []
    for case, N, Q in LOSSY:
        runs = []
        try:
            for _ in range(1 if N > 1000 else 3 if N <= 200 else 2):
                clock = time.perf_counter()
                report = measure_spectrum(chain_for_case(case, N), SpectrumOptions(Q=Q), simulator=simulator)
                runs.append(report.timings | {"call_s": time.perf_counter() - clock, "loop1_s": clock_fit.seconds})
        except ParameterError:
            print(f"| {case} | {N} | {Q:g} | - | - | - | - | - | - | - | - | - | - | - | - | - | - | - | - | - | - | "
                  "- | ", end="", flush=True)
        else:
            t = _least(runs)
            separated, error = _separated_Q_error(report, Q)
            price = spectrum_estimate(report.points, N, losses=True).seconds
            seen = int(report.seen.sum())  # none seen (every mode merged): no error to print, '-'
            errors = [f"{value:.1e}" if seen else "-" for value in (
                report.max_rel_error_omega, report.max_abs_error_P, report.max_rel_error_Q, report.max_rel_error_pole)]
            print(f"| {case} | {N} | {Q:g} | {report.points} | {seen} | "
                  f"{int(report.merged_modes.sum())} | {' | '.join(errors[:3])} | {separated} | {_finite(error)} | "
                  f"{errors[3]} | {_error(report.response_error)} | "
                  f"{_error(report.envelope_error)} | {_error(report.envelope_bound)} | {t['ngspice_s']:.3f} | "
                  f"{t['loop1_s']:.3f} | {t['loop1_s'] / t['ngspice_s']:.2f} | {t['fit_s']:.3f} | "
                  f"{t['fit_s'] / t['ngspice_s']:.2f} | {t['call_s']:.2f} | {price:.2f} | ", end="", flush=True)
            ratios.append((t["loop1_s"] / t["ngspice_s"], t["fit_s"] / t["ngspice_s"], math.nan, f"{case} N = {N}, "
                           f"Q = {Q:g}"))
        if N > SURVEY_MAX_N:
            print(f"- | - | - | - | - | - | - | - | - | - | {_load()} |", flush=True)
            continue
        surveys = [measure_modes(chain_for_case(case, N), Q=Q, simulator=simulator)
                   for _ in range(3 if N <= 200 else 2)]
        survey, s = surveys[-1], _least([dict(run.timings) for run in surveys])
        print(f"{int(survey.merged_modes.sum())} | {_survey_cells(survey, s)} | {int(survey.separated.sum())} | "
              f"{_finite(survey.max_rel_error_Q)} | {_finite(survey.envelope_error)} | {_load()} |", flush=True)
        if ratios and ratios[-1][3].startswith(f"{case} N = {N}, Q = {Q:g}"):
            ratios[-1] = ratios[-1][:2] + (s["fit_s"] / s["engine_s"], ratios[-1][3])
    if ratios:
        worst = [max(ratios, key=lambda row: row[k] if math.isfinite(row[k]) else -1.0) for k in range(3)]
        above = [f"{row[3]} ({row[2]:.2f})" for row in ratios if math.isfinite(row[2]) and row[2] > 1.0]
        print(f"\nLargest over the rows: loop-1 fit / ngspice {worst[0][0]:.2f} ({worst[0][3]}); lcchain's whole "
              f"time around the engine / ngspice {worst[1][1]:.2f} ({worst[1][3]}); the survey's fit / its ngspice "
              f"{worst[2][2]:.2f} ({worst[2][3]}); survey rows above 1: {', '.join(above) or 'none'}.")
    print("\nThe sweep is cut into even segments, each as fine as the spacing of the predicted poles it holds, so the "
          "frequencies grow like N for every chain (an even sweep grows like N^2 for the optimised chains, whose "
          "spacing shrinks like 1/N^2 at the top of the band: two-mass N = 2000 would need 9 million). ngspice's "
          "time is then frequencies x unknowns, O(N^2). Without losses the fit starts from theory's poles: Y_11 and "
          "Y_N1 together by variable projection in windows of 32 modes (one up to 16), the windows' residues from one "
          "banded solve refined once on the whole residual, O(frequencies x N) = O(N^2) a sweep with a constant far "
          "below ngspice's, one or two sweeps; a mode is seen when the samples place its pole (standard error at "
          "most 1e-3 of a quarter gap). With losses the same fit starts from theory's lossy poles (every decay "
          "rate 1/Q) and residues, complex sections with real residues, every other mode's model subtracted from a "
          "window's samples from the first pass (windows of 16 modes, 2 neighbours a side, 6 smooth terms, no banded "
          "solve; the whole model's sections kept while the poles stay); the modes closer than their width 1/Q "
          "merge: their theory is subtracted, they are said and never seen (two-mass N = 100 at Q = 10: every mode, "
          "nothing to fit). "
          "Taken on the shared 2-core machine (the load column); the curves are in "
          "benchmarks/spectrum.png.")
    print("\nThe survey's samples are the same segments at 4 per spacing (half the loop-1 fit's default): its "
          "ngspice run saves N vectors, frequencies x N complex values, O(N^2), cut into several runs of at most "
          "2^22 values each so that the raw file stays small. Its fit forms each window's right-hand sides and "
          "solves one banded system with the N loops as right-hand sides, O(N^2) too; the poles move on 16 random "
          "combinations of the loops. With losses the modes they merge (the loop-1 fit's rule, "
          "`compare.spectral.merged_modes`) are decided before the fit: their theory is subtracted from the samples, "
          "O(frequencies x merged x N), and only the others' poles move; with every mode merged nothing is fitted, "
          "and the loops' currents are compared with the chain's exact ones (`theory.spectrum.loop_currents`, "
          "O(frequencies x N)). 'peak MB' of the engines counts the forked child before it becomes ngspice (the "
          "Python process's size at that moment), not ngspice's own memory.")


if __name__ == "__main__":
    main()
