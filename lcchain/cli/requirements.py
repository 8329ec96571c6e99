"""``lcchain requirements``: how good must the parts be for the cradle to work."""

from __future__ import annotations

import argparse

from .chains import add_circuit_arguments, chain_options
from .common import EXIT_FAILED, EXIT_OK, Parser, Subcommands, budget_from_args, emit_json, print_notes
from .progress import fraction

__all__ = ["add_parser", "add_requirements_arguments", "cmd_requirements"]

#: ngspice runs per part unless --check says otherwise.
DEFAULT_CHECKS = 2



def add_parser(sub: Subcommands, budget: list[Parser]) -> None:
    p = sub.add_parser("requirements", parents=budget, help="how good must the parts be: the first arrival's "
                       "energy against a coil's self-capacitance and resistance, a capacitor's ESR and ESL, and "
                       "coupling, from the circuit's exact theory, with ngspice points")
    add_circuit_arguments(p)
    add_requirements_arguments(p)
    p.set_defaults(func=cmd_requirements)


def add_requirements_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--part", metavar="PART[,PART]",
                   help="the parts to sweep, comma-separated: coil_capacitance, coil_resistance, capacitor_esr, "
                        "capacitor_esl, coupling (default: all)")
    p.add_argument("--check", type=int, default=DEFAULT_CHECKS, metavar="M",
                   help=f"ngspice runs on each curve (default {DEFAULT_CHECKS}; 0: the exact curves alone)")
    p.add_argument("--plot", metavar="FILE", help="figure (.png, .svg, .pdf): each part's curve, ngspice's points "
                   "and the limits")
    p.add_argument("--json", action="store_true")


def cmd_requirements(args: argparse.Namespace) -> int:
    from ..app.requirements import RequirementsRequest, requirements, write_plot

    found = requirements(RequirementsRequest(chain_options(args), args.L0, args.C0, part=args.part,
                                             check=args.check, plot=args.plot, budget=budget_from_args(args),
                                             progress=fraction))
    chain, ladder, ideal, results, points = found.chain, found.ladder, found.ideal, found.results, found.points
    if args.json:
        emit_json({"chain": chain.name, "N": chain.N, "L0": ladder.L0, "C0": ladder.C0,
                   "ideal": {"time": ideal.time, "peak": ideal.peak, "energy": ideal.energy},
                   "targets": list(found.targets), "parts": [r.to_dict(ladder) for r in results],
                   "check": [point.to_dict() for point in points]})
    else:
        print(f"{chain.name} chain, N = {chain.N}, L0 = {ladder.L0:g} H, C0 = {ladder.C0:g} F: the ideal ladder's "
              f"first arrival carries e = {ideal.energy:.6f} of the kick's energy at t = {ideal.time:.2f} sqrt(L0 C0)")
        print("The largest parasitic that keeps the first arrival's energy loss (1 - e/e_ideal) under each target, "
              "from the circuit's exact theory:")
        for result in results:
            print(f"  {result.part.key} ({result.part.what}):")
            for k, target in enumerate(found.targets):
                print(f"    loss < {target:.1%}: {result.statement(k, ladder)}")
        if points:
            print("ngspice on the curves (fixed step 0.01 sqrt(L0 C0)):")
            print(f"  {'part':<17} {'value':>10} {'loss, ngspice':>14} {'loss, theory':>13} {'|diff|':>9}")
            for point in points:
                print(f"  {point.part:<17} {point.value:10.3g} {point.loss:14.6g} {point.theory:13.6g} "
                      f"{abs(point.loss - point.theory):9.2e}")
    failed = write_plot(found)
    print_notes(found.outputs.take_notes())
    return EXIT_FAILED if failed or not found.passed else EXIT_OK
