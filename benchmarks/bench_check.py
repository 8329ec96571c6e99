"""``lcchain check`` on three circuits nobody here wrote: ngspice's error, its prediction, the reference's cost.

Run from the repository root (it prints ``benchmarks/check.md``):

    .venv/bin/python benchmarks/bench_check.py > benchmarks/check.md

For each circuit (a series RLC band-pass driven by a PULSE, a doubly terminated 5th-order Butterworth LC ladder
driven by a SIN, a lumped transmission line of 200 LC sections driven by a step through its matching resistor),
ngspice runs at its default step (TMAX = min(TSTEP, TSTOP/50)) and at a step 10 times smaller; each run is
compared with the exact response (:func:`lcchain.runs.check.check_text`): measured max error, predicted error
(the trapezoidal model at the run's largest step), the exact reference's cost (solve and evaluation, seconds,
and its states).  Then the step each relative accuracy (1e-3, 1e-6, 1e-9 of each vector's scale) needs, and,
where the run stays under 500,000 points, ngspice run at that step and its measured relative error.  Last, gnucap
(``lcchain check --engine gnucap``) at the same two steps, beside ngspice.
"""

from __future__ import annotations

import os
import platform
import subprocess
import sys
import time

from lcchain.runs.check import CheckOptions, check_text

BANDPASS = """series RLC band-pass driven by a PULSE
V1 in 0 PULSE(0 1 0 1u 1u 20u 100u)
R1 in a 50
L1 a b 1m
C1 b out 100n
R2 out 0 10
.tran 0.1u 200u{tmax}
.end
"""

BUTTERWORTH = """5th-order Butterworth LC ladder, doubly terminated 1 ohm, cutoff 1 kHz, SIN drive
.param wc = 6283.185307179586
V1 in 0 SIN(0 1 700 0 0 0)
RS in n1 1
C1 n1 0 {{0.618/wc}}
L2 n1 n2 {{1.618/wc}}
C3 n2 0 {{2/wc}}
L4 n2 n3 {{1.618/wc}}
C5 n3 0 {{0.618/wc}}
RL n3 0 1
.tran 1u 5m{tmax}
.end
"""


def _line(tmax: str) -> str:
    lines = ["lumped transmission line of 200 LC sections, Z0 = 50 ohm, step through a matching resistor",
             "V1 in 0 PULSE(0 1 0 1n 1n 1 1)", "RS in n0 50"]
    for k in range(200):
        lines += [f"L{k + 1} n{k} n{k + 1} 250n", f"C{k + 1} n{k + 1} 0 100p"]
    lines += ["RL n200 0 50", ".save v(n0) v(n100) v(n200) i(v1)", f".tran 1n 2u{tmax}", ".end"]
    return "\n".join(lines) + "\n"


CIRCUITS = [
    ("RLC band-pass, PULSE", lambda tmax: BANDPASS.format(tmax=tmax), 200e-6, 0.1e-6),
    ("Butterworth 5th order, SIN", lambda tmax: BUTTERWORTH.format(tmax=tmax), 5e-3, 1e-6),
    ("line of 200 LC sections, step", _line, 2e-6, 1e-9),
]
ACCURACIES = (1e-3, 1e-6, 1e-9)
MAX_VERIFIED_POINTS = 500_000


def main() -> None:
    load = subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()
    print("# lcchain check: ngspice against the exact response\n")
    print("Command: `.venv/bin/python benchmarks/bench_check.py > benchmarks/check.md`  ")
    print(f"Machine: {platform.machine()}, {os.cpu_count()} cores shared with other sessions, Python "
          f"{platform.python_version()}; load at the start: `{load}`\n")
    print("Errors are the largest over the saved vectors, each in its own units (V or A); relative: over the "
          "vector's scale (its exact reference's largest magnitude). Predicted: the trapezoidal rule's model at "
          "the run's largest step (`lcchain.compare.check.predicted_errors`). Reference: the exact response's "
          "solve and evaluation at ngspice's points (seconds, wall, on the shared machine; the first row includes "
          "loading scipy's LAPACK) and its states.\n")
    print("| circuit | TMAX s | points | ngspice max abs error | predicted | measured / predicted | relative "
          "| reference s | states |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    needs = []
    ngspice_errors = {}
    for name, text, tstop, default in CIRCUITS:
        for tmax in (default, default / 10):
            card = "" if tmax == default else f" 0 {tmax!r}"
            result = check_text(text(card), name, options=CheckOptions(accuracy=1e-6))
            ngspice_errors[name, tmax] = result.max_abs_error
            ratio = result.max_abs_error / result.predicted_error if result.predicted_error else float("nan")
            print(f"| {name} | {tmax:.3g} | {result.points} | {result.max_abs_error:.3g} | "
                  f"{result.predicted_error:.3g} | {ratio:.2f} | {result.max_rel_error:.3g} | "
                  f"{result.reference_seconds:.3g} | {result.states} |")
        for accuracy in ACCURACIES:
            started = time.perf_counter()
            result = check_text(text(""), name, options=CheckOptions(accuracy=accuracy))
            search = time.perf_counter() - started
            step = result.suggested_step
            verified = ""
            if step is not None and tstop / step <= MAX_VERIFIED_POINTS:
                run = check_text(text(f" 0 {step!r}"), name, options=CheckOptions(accuracy=accuracy))
                verified = f"{run.max_rel_error:.3g} ({run.points} points)"
            needs.append((name, accuracy, step, verified, search))
    print("\n## The step each accuracy needs\n")
    print("Largest fixed step whose predicted relative error is at most 0.8 x the accuracy "
          "(`lcchain.compare.check.step_for_accuracy`, bisection on log h), and ngspice's measured relative error "
          f"when run with it as TMAX (when that is at most {MAX_VERIFIED_POINTS:,} points).\n")
    print("| circuit | accuracy | step s | ngspice at that step: relative error | check's wall s (run + search) |")
    print("|---|---:|---:|---:|---:|")
    for name, accuracy, step, verified, search in needs:
        shown = "none: below the reference's rounding" if step is None else f"{step:.3g}"
        print(f"| {name} | {accuracy:g} | {shown} | {verified or 'not run'} | {search:.2f} |")
    print("\n## gnucap against the same reference\n")
    print("`lcchain check --engine gnucap`: gnucap runs lcchain's copy of each netlist, written from its numbers "
          "(`lcchain.spice.gnucap_check`), at a fixed print step h = TMAX with dtmax h, method=trap; its error "
          "against the same exact reference at its own points, the same prediction at its largest step, and "
          "ngspice's error at the same TMAX (the table above) beside it. gnucap s: its wall time.\n")
    print("| circuit | TMAX s | points | gnucap max abs error | predicted | measured / predicted | ngspice max abs "
          "error | gnucap s |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|")
    for name, text, _, default in CIRCUITS:
        for tmax in (default, default / 10):
            card = "" if tmax == default else f" 0 {tmax!r}"
            result = check_text(text(card), name, options=CheckOptions(accuracy=1e-6, engine="gnucap"))
            ratio = result.max_abs_error / result.predicted_error if result.predicted_error else float("nan")
            print(f"| {name} | {tmax:.3g} | {result.points} | {result.max_abs_error:.3g} | "
                  f"{result.predicted_error:.3g} | {ratio:.2f} | {ngspice_errors[name, tmax]:.3g} | "
                  f"{result.simulator_seconds:.3g} |")
    load = subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()
    print(f"\nLoad at the end: `{load}`")


if __name__ == "__main__":
    sys.exit(main())
