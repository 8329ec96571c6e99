"""``lcchain results``: a store's runs: a table, --json, --csv, a --summary, or a --plot, netCDF or Parquet of the
study (:func:`lcchain.app.results.results`)."""

from __future__ import annotations

import argparse
import csv
import io
import sys
from typing import TYPE_CHECKING

from ..core.json import LooseJSONObject
from ..core.types import STUDY_METRICS
from .common import EXIT_FAILED, EXIT_OK, Parser, Subcommands, budget_from_args, emit_json, plural, print_notes
from .studies import format_number, short, table

if TYPE_CHECKING:
    from ..app.results import Results

__all__ = ["add_parser", "cmd_results"]


def add_parser(sub: Subcommands, budget: list[Parser]) -> None:
    p = sub.add_parser("results", parents=budget,
                       help="a store's runs: a table, --json, --csv, or a --plot of the study")
    p.add_argument("store", metavar="STORE.sqlite")
    out = p.add_mutually_exclusive_group()
    out.add_argument("--json", action="store_true", help="a list in task order: index, key, status, params, ...")
    out.add_argument("--csv", action="store_true")
    p.add_argument("--summary", action="store_true",
                   help="the transmitted peak's distribution per combination of the axes (n, mean, std, worst, "
                        "5th percentile, median, best); with --json or --csv in that form")
    p.add_argument("--plot", metavar="FILE",
                   help="figure: Fig. delta for a sweep over N, histograms of the samples (one per combination)")
    p.add_argument("--metric", metavar="{" + ",".join(STUDY_METRICS) + "} or NAME",
                   help="what --summary and the samples' --plot show: the first arrival's peak I_N/I_1(0) "
                        "(default); after a kick the energy fraction at that peak, peak^2 L_N/L_1, or the energy "
                        "lost, 1 - that (drawn on a log scale); of an AC analysis: omega (max relative error of "
                        "omega_n), P (max absolute error of P_n), spacing ((max - min) / mean of delta omega_n); "
                        "of a batch of netlists, the NAME of one of their .meas cards (--summary only)")
    p.add_argument("--netcdf", metavar="FILE.nc", help="write the study as a netCDF file: the study's axes as "
                   "dimensions, the metrics as variables (needs lcchain[data])")
    p.add_argument("--parquet", metavar="FILE.parquet", help="write one row per run, the axes as columns "
                   "(needs lcchain[data] and pyarrow)")
    p.add_argument("--waveforms", action="store_true",
                   help="--netcdf also holds every run's saved vectors and their time (a group a kind of run, its runs "
                        "one after another: a CF ragged array)")
    p.set_defaults(func=cmd_results)


def cmd_results(args: argparse.Namespace) -> int:
    from ..app.results import ResultsRequest, results

    found = results(ResultsRequest(args.store, json=args.json, csv=args.csv, summary=args.summary, plot=args.plot,
                                   metric=args.metric, netcdf=args.netcdf, parquet=args.parquet,
                                   waveforms=args.waveforms, budget=budget_from_args(args)))
    stored = found.stored
    if args.summary:
        _print_summary(found, args)
    elif args.json:
        emit_json(found.runs_json)
    elif args.csv:
        rows = found.rows
        columns = list(dict.fromkeys(key for row in rows for key in row))
        text = io.StringIO()
        writer = csv.DictWriter(text, fieldnames=columns, lineterminator="\n")
        writer.writeheader()
        writer.writerows(rows)
        sys.stdout.write(text.getvalue())
    elif args.plot or args.netcdf or args.parquet:  # the files are what was asked for: not every run
        if found.written:
            combined = sum(run.kind == "combined" for run in stored)
            tasks = len({run.key for run in stored if run.kind != "combined"})
            print(f"{args.store}: {plural(tasks, 'run')}"
                  + (f" and {combined} extrapolated from them" if combined else "")
                  + f" written to {', '.join(found.written)}")
    else:
        _print_runs(found, args.store)
    print_notes(found.notes)
    return EXIT_FAILED if found.failed else EXIT_OK


def _print_summary(found: Results, args: argparse.Namespace) -> None:
    """Per combination of the study's axes: the first-arrival metric's distribution over the samples."""
    groups = found.groups
    if args.json:
        emit_json(groups)
        return
    keys = list(dict.fromkeys(key for group in groups for key in group["params"]))
    stats = ["n", "failed", "mean", "std", "min", "p05", "median", "max"]
    # an axis named as a statistic (a .param mean) is vary_mean here, as a varied name that is a run's own field is
    # in the runs' table: a CSV header with one name twice loses a column in csv.DictReader and pandas
    columns = [f"vary_{key}" if key in stats else key for key in keys]
    def rows_with(digits: str) -> list[list[str]]:
        return [[format_number(group["params"].get(key)) for key in keys]
                + [str(group[s]) if s in ("n", "failed") else format_number(group[s], digits) for s in stats]
                for group in groups]

    # the table: 4 significant digits (a perfect cradle's loss is 2e-4, which 4 decimals showed as 0.0002 or
    # 0.0000); the CSV: the shortest text that reads back the same float
    rows = rows_with("" if args.csv else ".4g")
    if args.csv:
        text = io.StringIO()
        writer = csv.writer(text, lineterminator="\n")
        writer.writerow([*columns, *stats])
        writer.writerows(rows)
        sys.stdout.write(text.getvalue())
        return
    what = {"peak": "first-arrival peak (max I_N/I_1(0))", "energy": "first-arrival energy fraction (peak^2 L_N/L_1)",
            "loss": "first-arrival energy lost (1 - peak^2 L_N/L_1)",
            "omega": "AC: max |omega_n - theory| / theory (relative)", "P": "AC: max |P_n - theory| (absolute)",
            "spacing": "AC: spacing spread (max - min) / mean of delta omega_n"}.get(args.metric or "peak", "")
    if found.measured or not what:
        what = f"the netlists' measurement {args.metric} (.meas; runs that could not measure it left out)"
    by = f"by {', '.join(map(short, keys))}" if keys else "over all its runs"
    shared = ", ".join(f"{short(k)} = {format_number(v)}" for k, v in found.constants.items())
    print(f"{args.store}: {what} {by}" + (f" ({shared} throughout)" if shared else "") +
          "; n finished runs, std over them (ddof 1; none for one run)")
    print(table([*map(short, columns), *stats], rows))


#: The widest parameter cell of ``results``' table (longer values are cut in their middle).
_LONGEST_CELL = 24


def _print_runs(found: Results, name: str) -> None:
    """One row per task: its axes, status, and what it gave: errors against theory, or (no theory: a batch of
    netlists) its vectors, points and the simulator's time; a failure's reason."""
    stored, runs = found.stored, found.runs

    def counted(rows: list[LooseJSONObject]) -> str:
        counts = {s: sum(r["status"] == s for r in rows) for s in ("ok", "failed", "timeout", "refused", "pending")}
        return ", ".join(f"{n} {s}" for s, n in counts.items() if n)

    combined = [run for run in runs if run["kind"] == "combined"]
    tasks = list({run["key"]: run for run in runs if run["kind"] != "combined"}.values())  # shared members once
    print(f"{name}: {plural(len(tasks), 'run')}: {counted(tasks)}" +
          (f"; {len(combined)} extrapolated from them: {counted(combined)}" if combined else ""))
    axes = found.axes
    spectral = any(run.spectral for run in stored)
    theory = not spectral and any(run.judged for run in stored)
    columns = (["points", "modes seen", "omega error", "P error", "spacing"] if spectral
               else ["error", "predicted", "peak"] if theory else ["vectors", "points"])
    measured = list(dict.fromkeys(name for run in stored for name in run.measurements))
    columns += measured
    rows = []
    shortened = False

    def axis_cell(value: object) -> str:  # a long parameter (a worst case's signs, a path) cut in its middle
        nonlocal shortened
        text = format_number(value)
        if len(text) <= _LONGEST_CELL:
            return text
        shortened = True
        half = (_LONGEST_CELL - 1) // 2
        return f"{text[:half]}…{text[-half:]}"

    for run, shown in zip(stored, runs, strict=True):
        cells = [str(run.index), run.status, *(axis_cell(run.params.get(key)) for key in axes)]
        if spectral:
            cells += [format_number(run.points), format_number(shown.get("modes_seen")),
                      format_number(shown.get("max_rel_error_omega")), format_number(shown.get("max_abs_error_P")),
                      format_number(shown.get("spacing_spread"), ".4g")]
        elif theory:
            arrivals = shown.get("arrivals") or []
            cells += [format_number(shown.get("max_abs_error")), format_number(shown.get("predicted_error")),
                      format_number(arrivals[0].get("peak_sim"), ".6f") if arrivals else ""]
        else:
            names = found.vectors.get(run.key) if run.status == "ok" else None
            cells += [" ".join(names) if names else "", format_number(run.points)]
        cells += [format_number(run.measurements.get(name), ".6g") if run.measurements.get(name) is not None
                  else "-" if name in run.measurements else "" for name in measured]
        missing = [f"{name}: {why}" for name, why in run.measure_reasons.items()]
        reason = run.reason or "; ".join(missing)
        seconds = run.wall_s if run.kind != "combined" and run.status != "refused" else None  # nothing ran
        cells += [format_number(seconds, ".3f"), (reason.splitlines() or [""])[0][:70]]
        rows.append(cells)
    print(table(["#", "status", *map(short, axes), *columns, "time (s)", "reason"], rows))
    if shortened:
        print(f"parameters longer than {_LONGEST_CELL} characters are cut in their middle here; --json and --csv "
              "give them whole")
    if spectral:
        print("points: frequencies of the AC sweep; omega error: max |omega_n - theory| / theory over the modes "
              "resolved at the ends; P error: max |P_n - theory| (absolute); spacing: (max - min) / mean of "
              "delta omega_n = omega_(n+1) - omega_n; time: the simulator's own wall time")
    elif theory:
        print("error: max |I_sim - I_theory| / I0 over the saved loops (predicted: the accuracy model's); peak: the "
              "first arrival's max I_N/I_1(0) in the simulator; time: the simulator's own wall time")
    else:
        print("points: time points, or an .ac netlist's frequencies; time: the simulator's own wall time of each "
              "run")
    if measured:
        print(f"{', '.join(measured)}: the netlists' .meas results as ngspice printed them (SI units); -: ngspice "
              "could not make it (the reason says why)")
