"""``lcchain asymptotic``: N -> infinity, the maximum of alpha_inf(tau, sigma) and the scaling laws
(:func:`lcchain.app.design.asymptotic`)."""

from __future__ import annotations

import argparse
from fractions import Fraction

from ..core.types import DESIGN_CASES
from .common import EXIT_OK, Parser, Subcommands, emit_json

__all__ = ["add_parser", "cmd_asymptotic"]


def add_parser(sub: Subcommands, budget: list[Parser]) -> None:
    p = sub.add_parser("asymptotic", help="N -> infinity: maximum of alpha_inf(tau, sigma) and the scaling laws")
    p.add_argument("--case", choices=DESIGN_CASES, default="two-mass")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=cmd_asymptotic)


def cmd_asymptotic(args: argparse.Namespace) -> int:
    from ..app.design import AsymptoticRequest, asymptotic

    result = asymptotic(AsymptoticRequest(args.case))
    optimum = result.optimum
    if args.json:
        emit_json(optimum.to_dict())
        return EXIT_OK
    print(f"{args.case}: alpha* = {optimum.alpha:.6f}  delta* = {optimum.delta:.6f}  "
          f"sigma* = {optimum.sigma:.5f}  tau* = {optimum.tau:.5f}")
    for key, value in optimum.to_dict()["coefficients"].items():
        law = {"y": "sqrt(2) - {c} N^{p}", "m2": "1/2 + {c} N^{p}"}.get(key, "{c} N^{p}")
        power = Fraction(result.exponents[key]).limit_denominator(6)
        print(f"  {key:>6} ~ " + law.format(c=f"{value:.5g}", p=f"({power})"))
    return EXIT_OK
