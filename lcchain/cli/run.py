"""``lcchain run``: run scenes (TOML experiment descriptions) (:func:`lcchain.app.scenes.run_scenes`)."""

from __future__ import annotations

import argparse
import sys
from typing import TYPE_CHECKING

from ..app.studies import StudyOptions
from ..core.analyses import analysis_kind
from ..core.types import ANALYSIS_KINDS
from .common import (
    EXIT_FAILED,
    EXIT_OK,
    Parser,
    Subcommands,
    add_parts_arguments,
    budget_from_args,
    emit_json,
    print_notes,
    summary_stream,
)
from .progress import fraction, study_counter
from .simulate import print_arrivals
from .studies import add_study_arguments

if TYPE_CHECKING:
    from ..app.inputs import Outputs
    from ..app.scenes import SceneResult

__all__ = ["add_parser", "cmd_run", "error_text"]


def add_parser(sub: Subcommands, budget: list[Parser]) -> None:
    p = sub.add_parser("run", parents=budget, help="run a scene (TOML experiment description)")
    p.add_argument("scene", metavar="SCENE.toml", nargs="+", help="one or more scene files, run in order")
    p.add_argument("--json", action="store_true", help="print the report as JSON (a list for several scenes)")
    p.add_argument("--side-by-side", metavar="FILE",
                   help="figure (.png, .svg, .pdf): the scenes' overlays next to each other on shared axes")
    p.add_argument("--netlist-out", metavar="FILE", help="keep the (first sample's) netlist")
    p.add_argument("--waveform-out", metavar="FILE", help="CSV of the first sample's end loops: t,first,last "
                   "(dimensionless) for a transient; frequency_hz and each saved phasor's re() and im() for an AC "
                   "scene")
    add_parts_arguments(p)
    add_study_arguments(p, store=False)
    p.set_defaults(func=cmd_run, executor="serial")


def error_text(value: float | None) -> str:
    """An error as printed: a number, or 'unseen' where a resolved mode was not seen (infinite; None in the
    JSON), 'n/a' where it is NaN: never 'inf'."""
    if value is not None and value != value:
        return "n/a"
    return "unseen" if value is None or value == float("inf") else f"{value:.3e}"


def _ratio_text(value: float | None, digits: int = 4) -> str:
    """A spread as printed: a number, or 'n/a' where fewer than two modes were seen to space (NaN; None in the
    JSON)."""
    return "n/a" if value is None or value != value else f"{value:.{digits}g}"


def _print_spectrum_summary(result: SceneResult) -> None:
    """An AC scene: each sample's modes against its own theory, and the spacings' spread over the samples."""
    report = result.report
    count = len(report["samples"])
    print(result.scene.title)
    print(f"N = {report['N']}, AC sweep of {report['points']} frequencies up to omega = {report['omega_max']:.4g} "
          f"(1/sqrt(L0 C0)), {count} sample{'s' if count > 1 else ''}, {report['engine']} "
          f"{report['engine_version']}, {report['wall_s']['total']:.2f} s")
    if "max_rel_error_omega" in report:
        good = [record for record in report["samples"] if "error" not in record]
        over = f" (the worst of {len(good)} samples, each against its own theory)" if len(good) > 1 else ""
        print(f"max |omega_n - theory| / theory = {error_text(report['max_rel_error_omega'])}, max |P_n - theory| = "
              f"{error_text(report['max_abs_error_P'])}{over}")
        if "max_rel_error_Q" in report:  # one Q for the chain's losses; real parts' losses are the circuit's own
            against = (f"losses Q = {report['Q']:g}: max |Q_n - omega_n Q| / (omega_n Q)" if report.get("Q") is not None
                       else "the circuit's losses: max |Q_n - theory| / theory")
            print(f"{against} = {error_text(report['max_rel_error_Q'])}{over}")
        spread = report["spacing_spread"]
        print(f"spacing spread (max - min) / mean of delta omega_n: {_ratio_text(spread['mean'])} (mean over "
              f"{spread['count']} sample{'s' if spread['count'] > 1 else ''}), largest {_ratio_text(spread['max'])}; "
              f"nominal theory {_ratio_text(spread['theory_nominal'], 3)}")
        print(f"{'sample':>6} {'modes seen':>10} {'max omega error':>16} {'max P error':>12} {'spacing spread':>15}")
        for record in good:
            print(f"{record['sample']:>6} {record['modes_seen']:>10} {error_text(record['max_rel_error_omega']):>16} "
                  f"{error_text(record['max_abs_error_P']):>12} {_ratio_text(record['spacing_spread']):>15}")
    for record in report["samples"]:
        if "error" in record:
            print(f"sample {record['sample']} failed: {record['error']}", file=sys.stderr)


def _print_scene_summary(result: SceneResult) -> None:
    if analysis_kind(result.report.get("analysis", ANALYSIS_KINDS[0])).swept:  # an AC scene's spectra
        _print_spectrum_summary(result)
        return
    report = result.report
    count = len(report["samples"])
    print(result.scene.title)
    steps = report.get("steps") or [report["dt"]]
    if len(steps) > 1:
        print(f"each sample extrapolated from {len(steps)} runs at dt = {', '.join(f'{h:.4g}' for h in steps)}")
    print(f"N = {report['N']}, dt = {report['dt']:.4g}, {count} sample{'s' if count > 1 else ''}, "
          f"{report['engine']} {report['engine_version']}, {report['wall_s']['total']:.2f} s")
    if "max_abs_error" in report:
        good = sum("error" not in record for record in report["samples"])
        over = f" (the worst of {good} samples, each against its own theory)" if good > 1 else ""
        print(f"max |simulation - theory| = {report['max_abs_error']:.3e}{over}")
        if good > 1:
            print(f"arrivals of sample {report['arrivals_sample']} (every sample's are in the report's samples):")
        print_arrivals(report["arrivals"])
    if "transmitted_peak" in report:
        p = report["transmitted_peak"]
        print(f"transmitted peak over {p['count']} samples: mean {p['mean']:.5f}, std {p['std']:.5f}, "
              f"worst {p['worst']:.5f} (nominal theory {p['theory_nominal']:.5f})")
    for record in report["samples"]:
        if "error" in record:
            print(f"sample {record['sample']} failed: {record['error']}", file=sys.stderr)
    if report.get("accuracy_met") is False:
        print(f"lcchain: {result.scene.source or 'the scene'}: analysis.accuracy "
              f"{result.scene.analysis.accuracy:g} was not met: the runs reached {report['max_abs_error']:.3g}",
              file=sys.stderr)


def cmd_run(args: argparse.Namespace) -> int:
    from ..app.scenes import PartOverrides, RunRequest, run_scenes

    def shown(result: SceneResult, outputs: Outputs) -> None:
        print_notes(outputs.take_notes())  # a scene's file not written
        if not args.json:
            with summary_stream(outputs):
                _print_scene_summary(result)
            for path in result.files:
                print(f"wrote {path}", file=sys.stderr if outputs.to_stdout else sys.stdout)

    parts = PartOverrides(tolerance=args.tolerance, series=args.series, samples=args.samples, seed=args.seed)
    study = StudyOptions(args.executor, args.workers, args.scheduler, args.transport, args.timeout)
    run = run_scenes(RunRequest(tuple(args.scene), parts, netlist_out=args.netlist_out,
                                waveform_out=args.waveform_out, side_by_side=args.side_by_side, json=args.json,
                                study=study, budget=budget_from_args(args), progress=fraction,
                                study_progress=study_counter), shown)
    print_notes(run.outputs.take_notes())  # --side-by-side not written
    if run.side_by_side and not args.json:
        print(f"wrote {run.side_by_side}", file=sys.stderr if run.outputs.to_stdout else sys.stdout)
    if args.json:
        reports = [r.report for r in run.results]
        emit_json(reports[0] if len(reports) == 1 else reports)
    return EXIT_OK if run.ok else EXIT_FAILED
