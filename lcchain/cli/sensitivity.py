"""``lcchain sensitivity``: which components move the first-arrival peak, and by how much (and a check in
ngspice)."""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

from ..app.studies import StudyOptions
from ..core.types import ARRIVAL_METRICS
from .chains import add_circuit_arguments, chain_options
from .common import EXIT_FAILED, EXIT_OK, Parser, Subcommands, budget_from_args, emit_json, print_notes
from .progress import fraction, study_counter
from .studies import add_study_arguments

if TYPE_CHECKING:
    from ..app.sensitivity import Sensitivity

__all__ = ["add_parser", "add_sensitivity_arguments", "cmd_sensitivity"]

#: Rows of the table unless --top says otherwise.
DEFAULT_TOP = 10



def add_parser(sub: Subcommands, budget: list[Parser]) -> None:
    p = sub.add_parser("sensitivity", parents=budget, help="which components move the first-arrival peak: dp/dL_i "
                       "and dp/dC_j from exact theory, ranked (--check M: against ngspice finite differences)")
    add_circuit_arguments(p)
    add_sensitivity_arguments(p)
    p.set_defaults(func=cmd_sensitivity)


def add_sensitivity_arguments(p: argparse.ArgumentParser) -> None:
    from ..core.limits import SENSITIVITY_CHECK_ACCURACY as CHECK_ACCURACY  # not studies/: --help stays light
    from .common import number_type

    p.add_argument("--metric", choices=ARRIVAL_METRICS, default="peak",
                   help="the first arrival's current peak p = max I_N/I_1(0) (default), or its energy fraction "
                        "e = p^2 L_N/L_1, which a mismatch of the end inductors does not move")
    p.add_argument("--top", type=int, default=DEFAULT_TOP, metavar="K",
                   help=f"rows of the table: the K most sensitive components (default {DEFAULT_TOP}; 0: all)")
    p.add_argument("--plot", metavar="FILE", help="figure (.png, .svg, .pdf): dp/d ln x along the chain")
    p.add_argument("--json", action="store_true")
    p.add_argument("--check", type=int, default=0, metavar="M",
                   help="run ngspice with each of the M most sensitive components at 1 +- h and compare the "
                        "central difference with the theory (exit 1 when one disagrees beyond its error bar)")
    p.add_argument("--accuracy", type=number_type("--accuracy"), default=CHECK_ACCURACY, metavar="EPS",
                   help=f"--check: each run's wanted max |simulation - theory| (default {CHECK_ACCURACY:g})")
    p.add_argument("--store", metavar="FILE.sqlite", help="--check: keep its runs in this store (resumed if it "
                   "exists; default: a temporary one)")
    add_study_arguments(p, store=False)


def _print(result: Sensitivity) -> None:
    sensitivity, top, checks = result.sensitivity, result.top, result.checks
    from ..app.sensitivity import METRIC_NAMES

    ladder = sensitivity.ladder
    chain = ladder.chain
    symbol, what = METRIC_NAMES[sensitivity.metric]
    print(f"{chain.name} chain, N = {chain.N}: {what} = {sensitivity.value:.6f} at t = {sensitivity.time:.4f} "
          f"sqrt(L0 C0) = {sensitivity.time_s:.4g} s (L0 = {ladder.L0:g} H, C0 = {ladder.C0:g} F)")
    print(f"{len(top)} of {len(sensitivity.components)} components, most sensitive first (a part at 1 + tol moves "
          f"{symbol} by about tol x d{symbol}/dlnx):")
    print(f"{'component':>10} {'value':>12} {f'd{symbol}/dx':>13} {f'd{symbol}/dlnx':>11}")
    for part in top:
        unit = "H" if part.kind == "L" else "F"
        print(f"{part.name:>10} {part.value:10.4g} {unit} {part.derivative:11.4g}/{unit} {part.relative:+11.6f}")
    if checks:
        print(f"ngspice central differences ({symbol}(1+h) - {symbol}(1-h)) / 2h, error bar = runs' error + "
              "truncation at h:")
        print(f"{'component':>10} {'h':>6} {'theory':>11} {'ngspice':>11} {'|diff|':>9} {'error bar':>9}  ")
        for check in checks:
            print(f"{check.component.name:>10} {check.step:6.3g} {check.component.relative:+11.6f} "
                  f"{check.fd:+11.6f} {abs(check.fd - check.component.relative):9.2e} {check.error_bar:9.2e}  "
                  f"{('ok' if check.resolved else 'ok, unresolved') if check.passed else 'FAILED'}")
        passed = sum(check.passed for check in checks)
        unresolved = sum(not check.resolved for check in checks)
        below = (f" ({unresolved} unresolved: the error bar is not below a tenth of the sensitivity)"
                 if unresolved else "")
        print(f"check: {passed} of {len(checks)} agree with the theory within their error bars{below}: "
              f"{'pass' if passed == len(checks) else 'FAIL'}")


def cmd_sensitivity(args: argparse.Namespace) -> int:
    from ..app.sensitivity import SensitivityRequest, sensitivity, write_plot

    study = StudyOptions(args.executor, args.workers, args.scheduler, args.transport, args.timeout, store=args.store)
    result = sensitivity(SensitivityRequest(chain_options(args), args.L0, args.C0, metric=args.metric, top=args.top,
                                            check=args.check, accuracy=args.accuracy, plot=args.plot, study=study,
                                            budget=budget_from_args(args), progress=fraction,
                                            study_progress=study_counter("runs")))
    print_notes(result.notes)
    if args.json:
        data = result.sensitivity.to_dict()
        data["components"] = [part.to_dict() for part in result.top]
        if args.check:
            data["check"] = [check.to_dict() for check in result.checks]
            data["passed"] = bool(result.checks) and all(check.passed for check in result.checks)
        emit_json(data)
    else:
        _print(result)
    failed = write_plot(result)
    print_notes(result.outputs.take_notes())
    return EXIT_FAILED if failed or not result.passed else EXIT_OK
