"""The spectrum from gnucap's AC analysis beside ngspice's: accuracy and cost (the "gnucap" section of spectrum.md).

Run from the repository root, after bench_spectrum.py (it appends its section):

    .venv/bin/python benchmarks/bench_spectrum_gnucap.py >> benchmarks/spectrum.md

Each chain's default sweep runs in both engines (``measure_spectrum(..., SpectrumOptions(engine=...))``) and is
fitted the same way; errors are against lcchain's exact modes.  ``timings["ngspice_s"]`` is the process time of
whichever engine ran (the key predates engines).  The last column is gnucap's process time over ngspice's, the
measurement behind :attr:`lcchain.spice.gnucap.Gnucap.ac_relative_cost`.
"""

from __future__ import annotations

import os

from lcchain.runs.spectrum import SpectrumOptions, measure_spectrum
from lcchain.theory.cases import chain_for_case

CASES = [("two-mass", 20), ("two-mass", 100), ("perfect", 100), ("uniform-bounded", 100), ("two-mass", 200)]


def main() -> None:
    print("\n## gnucap\n")
    print("Command: `.venv/bin/python benchmarks/bench_spectrum_gnucap.py >> benchmarks/spectrum.md` (single runs, "
          f"load {os.getloadavg()[0]:.1f} at the start). Errors as above; seconds: the engine's process and lcchain's "
          "time around it.\n")
    print("| chain | N | points | engine | omega error | P error | engine s | fit s | gnucap s / ngspice s |")
    print("|---|---:|---:|---|---:|---:|---:|---:|---:|")
    for case, N in CASES:
        chain = chain_for_case(case, N)
        reports = {engine: measure_spectrum(chain, SpectrumOptions(engine=engine)) for engine in ("ngspice", "gnucap")}
        ratio = reports["gnucap"].timings["ngspice_s"] / reports["ngspice"].timings["ngspice_s"]
        for engine, report in reports.items():
            t = report.timings
            print(f"| {case} | {N} | {report.points} | {engine} {report.engine_version} | "
                  f"{report.max_rel_error_omega:.1e} | {report.max_abs_error_P:.1e} | {t['ngspice_s']:.2f} | "
                  f"{t['fit_s']:.2f} | {f'{ratio:.1f}' if engine == 'gnucap' else ''} |", flush=True)


if __name__ == "__main__":
    main()
