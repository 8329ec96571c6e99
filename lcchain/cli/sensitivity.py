"""``lcchain sensitivity``: which components move the first-arrival peak, and by how much (and a check in
ngspice)."""

from __future__ import annotations

import argparse
import contextlib
import sys
from typing import Any

from ..core.errors import ParameterError
from ..core.types import ARRIVAL_METRICS
from ..report.files import FIGURE_FORMATS
from ..spice.scratch import scratch_folder
from .common import EXIT_FAILED, EXIT_OK, Outputs, budget_from_args, chain_from_args, emit_json
from .progress import fraction, study_counter
from .studies import STORE_FORMATS, _workers, add_study_arguments

__all__ = ["add_sensitivity_arguments", "cmd_sensitivity"]

#: Rows of the table unless --top says otherwise.
DEFAULT_TOP = 10


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


def _checks(args: argparse.Namespace, sensitivity: Any, outputs: Outputs) -> list[Any]:
    """The --check runs through a plan and a store (the user's, or a temporary one), read back as rows."""
    from ..studies.run import run_plan
    from ..studies.sensitivity import check_plan, check_rows
    from ..studies.store import Store

    plan, steps = check_plan(sensitivity, args.check, accuracy=args.accuracy, budget=budget_from_args(args),
                             timeout=args.timeout)
    workers = _workers(args)
    plan.check(budget_from_args(args), workers, args.executor, "--check")
    with contextlib.ExitStack() as stack:
        store = args.store or str(stack.enter_context(scratch_folder("check", watch=True)) / "check.sqlite")
        summary = run_plan(plan, store, executor=args.executor, workers=workers, scheduler=args.scheduler,
                           progress=study_counter("runs"), transport=args.transport)
        with Store(store, "read") as stored:
            rows = check_rows(stored.runs(), steps, sensitivity.metric)
    if summary.failed or summary.combined_failed:
        where = f"'lcchain results {args.store}' says why" if args.store else "keep them with --store FILE to see why"
        print(f"lcchain: {summary.failed + summary.combined_failed} of the check's runs failed ({where})",
              file=sys.stderr)
    return rows


#: How each metric is named in the table: its symbol and what it is.
_NAMES = {"peak": ("p", "first-arrival peak p = max I_N/I_1(0)"),
          "energy": ("e", "first-arrival energy fraction e = p^2 L_N/L_1")}


def _print(sensitivity: Any, top: list[Any], checks: list[Any]) -> None:
    ladder = sensitivity.ladder
    chain = ladder.chain
    symbol, what = _NAMES[sensitivity.metric]
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
    from ..circuit.ladder import Ladder
    from ..circuit.sensitivity import ladder_sensitivity
    from ..core.budget import sensitivity_estimate
    from ..studies.executors import check_executor
    from ..theory.sensitivity import SENSITIVITY_MAX_N

    outputs = Outputs(inputs={"--chain": args.chain})
    outputs.check("--plot", args.plot, FIGURE_FORMATS)
    outputs.check("--store", args.store, STORE_FORMATS)
    if args.top < 0:
        raise ParameterError("--top", args.top, "an integer >= 0 (0: every component)")
    if args.check < 0:
        raise ParameterError("--check", args.check, "an integer >= 0 (0: no ngspice runs)")
    if args.store and not args.check:
        raise ParameterError("--store", args.store, "only with --check M (the store keeps its runs)")
    check_executor(args.executor, args.workers, args.scheduler)
    chain = chain_from_args(args, max_N=SENSITIVITY_MAX_N)
    sensitivity_estimate(chain.N).check(budget_from_args(args), "N", chain.N)  # --N, or the --chain FILE
    shown = fraction(f"sensitivities of {chain.N} masses")  # one O(N^3) step: 5 s at N = 2000
    shown(0.0)
    sensitivity = ladder_sensitivity(Ladder(chain, args.L0, args.C0), metric=args.metric)
    shown(1.0)
    top = list(sensitivity.components[: args.top or None])
    checks = _checks(args, sensitivity, outputs) if args.check else []
    if args.json:
        data = sensitivity.to_dict()
        data["components"] = [part.to_dict() for part in top]
        if args.check:
            data["check"] = [check.to_dict() for check in checks]
            data["passed"] = bool(checks) and all(check.passed for check in checks)
        emit_json(data)
    else:
        _print(sensitivity, top, checks)
    if args.plot:
        from ..report.sensitivity import sensitivity_chart

        N = chain.N
        position = {part.name: part.slot + 1 if part.kind == "L" else part.slot - N + 0.5
                    for part in sensitivity.components}
        inductors = [(part.slot + 1, part.relative) for part in sensitivity.components if part.kind == "L"]
        capacitors = [(part.slot - N, part.relative) for part in sensitivity.components if part.kind == "C"]
        checked = [(position[c.component.name], c.fd, c.error_bar) for c in checks]
        outputs.write("--plot", lambda path: sensitivity_chart(
            sorted(inductors), sorted(capacitors), checked=checked,
            title=f"{chain.name} chain, N = {N}: sensitivity of the {_NAMES[args.metric][1]} = "
                  f"{sensitivity.value:.4f}", metric=_NAMES[args.metric][0],
            path=path))
    failed = args.check and (len(checks) < args.check or not all(check.passed for check in checks))
    return EXIT_FAILED if failed or outputs.failed else EXIT_OK
