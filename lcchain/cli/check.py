"""``lcchain check FILE``: a linear netlist's simulation against its exact response
(:func:`lcchain.app.check.check`)."""

from __future__ import annotations

import argparse

from ..app.options import engine_names
from ..core.analyses import analysis_kind
from .common import EXIT_FAILED, EXIT_OK, Parser, Subcommands, budget_from_args, emit_json, number_type, plural

__all__ = ["add_parser", "add_check_arguments", "cmd_check"]



def add_parser(sub: Subcommands, budget: list[Parser]) -> None:
    p = sub.add_parser("check", parents=budget,
                       help="a linear netlist (R L C K, V/I with DC PULSE SIN PWL EXP) run in a simulator and "
                            "compared with its exact response: the error of every saved vector, the error the step "
                            "predicts, the step an accuracy needs")
    add_check_arguments(p, engine_names())
    p.set_defaults(func=cmd_check)


def add_check_arguments(p: argparse.ArgumentParser, engines: tuple[str, ...]) -> None:
    p.add_argument("netlist", metavar="FILE", help="a netlist with one .tran or .ac analysis (the allow-list of "
                   "lcchain batch: R L C K V I E F G H B elements, X sub-circuits, .param, .func, .ic, .options, "
                   ".save, .include in its folder)")
    p.add_argument("--accuracy", type=number_type("--accuracy"), default=None, metavar="A",
                   help="relative to each saved vector's scale (its exact reference's largest magnitude): exit 1 "
                        "when a vector's error exceeds it, and the step suggested is the one it needs (default: "
                        "1e-6, for the suggestion only)")
    p.add_argument("--engine", default="ngspice", choices=engines,
                   help="the simulator: ngspice runs the netlist in its sandbox; gnucap runs lcchain's copy of it, "
                        "written from its numbers")
    p.add_argument("--timeout", type=number_type("--timeout"), default=600.0, metavar="SECONDS",
                   help="stop the simulator after this long (default 600)")
    p.add_argument("--allow-control", action="store_true",
                   help="run the netlist as it is (.control blocks, .model cards, diodes...), still in the sandbox; "
                        "what is not linear has no exact reference")
    p.add_argument("--json", action="store_true", help="the result as JSON")


def _g(value: float | None, unit: str = "") -> str:
    return "-" if value is None else f"{value:.3g}{(' ' + unit) if unit else ''}"


def cmd_check(args: argparse.Namespace) -> int:
    """Exit 0 when the run succeeded (and, with --accuracy, every vector is within it), 1 when the simulator failed
    or a vector's relative error exceeds --accuracy, 2 for bad input, 3 when the simulator is missing."""
    from ..app.check import CheckRequest, check

    result = check(CheckRequest(args.netlist, accuracy=args.accuracy, engine=args.engine, timeout=args.timeout,
                                allow_control=args.allow_control, budget=budget_from_args(args)))
    if args.json:
        emit_json(result.to_dict())
        return EXIT_OK if result.passed else EXIT_FAILED
    method = "" if analysis_kind(result.analysis).swept else f", method {result.method}"  # a sweep takes no step
    print(f"{result.netlist}: {result.analysis}, {result.points} points, {result.engine} {result.engine_version} "
          f"({result.simulator_seconds:.3g} s){method}")
    if result.reference:
        print(f"no exact reference ({result.reference}): the run ran, nothing compared")
        return EXIT_OK
    states, unknowns = result.states or 0, result.unknowns or 0  # both set when there is a reference
    print(f"exact reference: {plural(states, 'state')} of {plural(unknowns, 'unknown')}, "
          f"{_g(result.reference_seconds)} s")
    width = max(len(v.name) for v in result.vectors) if result.vectors else 6
    print(f"{'vector':>{width}}  {'max_abs_error':>14}  {'scale':>11}  {'relative':>9}  {'predicted':>11}")
    for v in result.vectors:
        print(f"{v.name:>{width}}  {_g(v.max_abs_error, v.unit):>14}  {_g(v.scale, v.unit):>11}  "
              f"{_g(v.max_rel_error):>9}  {_g(v.predicted_error, v.unit):>11}")
    print(f"max_abs_error {_g(result.max_abs_error)} (each vector in its own units), relative "
          f"{_g(result.max_rel_error)}")
    if not analysis_kind(result.analysis).swept:  # a transient's step
        print(f"largest step of the run {_g(result.run_step, 's')}: predicted error {_g(result.predicted_error)} "
              f"({result.prediction})")
        need = ("none: the predicted error stays above it down to tstop * 1e-9 (the exact reference's rounding, "
                f"{_g(result.rounding)}, may be the floor)") if result.suggested_step is None else \
            f"{result.suggested_step:.3g} s (the .tran card's TMAX: .tran TSTEP TSTOP TSTART " \
            f"{result.suggested_step:.3g})"
        print(f"step for a relative accuracy of {result.accuracy:g}: {need}")
    for note in result.notes:
        print(f"note: {note}")
    if not result.passed:
        print(f"relative error {_g(result.max_rel_error)} exceeds --accuracy {result.accuracy:g}")
        return EXIT_FAILED
    return EXIT_OK
