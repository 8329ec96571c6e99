"""``lcchain bom``: the ladder's bill of materials (:func:`lcchain.app.bom.bom`)."""

from __future__ import annotations

import argparse
import csv
import io
import re
import sys

from ..app.options import E_SERIES_NAMES
from ..core.physical import si_text
from .chains import add_circuit_arguments, add_effect_arguments, chain_options, effects_from_args
from .common import EXIT_OK, Parser, Subcommands, budget_from_args

__all__ = ["add_parser", "add_bom_arguments", "cmd_bom", "tolerance"]

_TOLERANCE = re.compile(r"^\s*([0-9]*\.?[0-9]+(?:[eE][-+]?[0-9]+)?)\s*(%)?\s*$")


def tolerance(text: str) -> float:
    """An argparse type: a part's relative tolerance, ``1%`` or ``0.01``, from 0 to below 100 %."""
    match = _TOLERANCE.match(text)
    value = None if match is None else float(match.group(1)) / (100.0 if match.group(2) else 1.0)
    if value is None or not 0.0 <= value < 1.0:
        raise argparse.ArgumentTypeError(f"--tolerance = {text!r} is not allowed: expected a relative tolerance "
                                         "such as 1% or 0.01 (0 to below 100 %)")
    return value



def add_parser(sub: Subcommands, budget: list[Parser]) -> None:
    p = sub.add_parser("bom", help="bill of materials: the ladder's distinct inductors and capacitors (rounded to "
                       "a preferred-number series with --series) with their counts, as a table or --csv")
    add_circuit_arguments(p)
    add_bom_arguments(p)
    add_effect_arguments(p)
    p.set_defaults(func=cmd_bom)


def add_bom_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--series", choices=E_SERIES_NAMES, default=None,
                   help="round every L and C to this preferred-number series (default: the exact values)")
    p.add_argument("--tolerance", type=tolerance, default=None, metavar="TOL",
                   help="every part's tolerance, 1%% or 0.01, shown in its column")
    p.add_argument("--csv", action="store_true", help="CSV: kind,value,unit,count,tolerance,parts")


def cmd_bom(args: argparse.Namespace) -> int:
    from ..app.bom import BomRequest, bom

    result = bom(BomRequest(chain_options(args), args.L0, args.C0, series=args.series,
                            effects=effects_from_args(args), budget=budget_from_args(args)))
    chain, parts = result.chain, result.parts
    shown = "" if args.tolerance is None else f"{100 * args.tolerance:g}%"
    if args.csv:
        text = io.StringIO()
        writer = csv.writer(text, lineterminator="\n")
        writer.writerow(["kind", "value", "unit", "count", "tolerance", "parts", "bought"])
        for part in parts:
            writer.writerow([part.kind, repr(part.value), part.unit, part.count, shown if part.bought else "",
                             " ".join(part.names), "yes" if part.bought else "no: a property of the parts"])
        sys.stdout.write(text.getvalue())
        return EXIT_OK
    series = f", coils and capacitors in {args.series} values" if args.series else ", exact values"
    coupled = f", coils coupled k = {chain.coupling:g}" if chain.coupled else ""
    bought = [part for part in parts if part.bought]
    print(f"{chain.name} chain, N = {chain.N}{coupled}: L0 = {si_text(args.L0, 'H')}, C0 = {si_text(args.C0, 'F')}"
          f"{series}; {sum(p.count for p in bought)} parts, {len(bought)} distinct")
    print(f"{'kind':<10} {'value':>14} {'count':>6} {'tolerance':>9}  parts")
    for part in parts:
        if part is next((p for p in parts if not p.bought), None):
            print("the parts' own properties, which the circuit models as elements (nothing to buy):")
        names = " ".join(part.names)
        names = names if len(names) <= 60 else names[:57] + "..."
        print(f"{part.kind:<10} {si_text(part.value, part.unit):>14} {part.count:>6} "
              f"{shown if part.bought else '':>9}  {names}")
    return EXIT_OK
