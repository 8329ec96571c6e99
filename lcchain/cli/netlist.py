"""``lcchain netlist``: the SPICE netlist of the equivalent LC ladder (:func:`lcchain.app.netlist.netlist`)."""

from __future__ import annotations

import argparse
import sys

from .chains import add_chain_arguments, add_effect_arguments, chain_options, effects_from_args
from .common import EXIT_FAILED, EXIT_OK, Parser, Subcommands, budget_from_args, print_notes

__all__ = ["add_parser", "cmd_netlist"]


def add_parser(sub: Subcommands, budget: list[Parser]) -> None:
    p = sub.add_parser("netlist", help="SPICE netlist of the equivalent LC ladder")
    add_chain_arguments(p)
    add_effect_arguments(p)
    p.add_argument("-o", "--output", metavar="FILE", help="write here instead of stdout")
    p.set_defaults(func=cmd_netlist)


def cmd_netlist(args: argparse.Namespace) -> int:
    from ..app.inputs import echoed_command
    from ..app.netlist import NetlistRequest, netlist

    result = netlist(NetlistRequest(chain_options(args), args.L0, args.C0, excitation=args.excitation,
                                    title=args.title, transits=args.transits, dt=args.dt,
                                    effects=effects_from_args(args),
                                    command=echoed_command("lcchain netlist", args.argv_echo), output=args.output,
                                    budget=budget_from_args(args)))
    if not args.output:
        sys.stdout.write(result.text)
    print_notes(result.notes)
    return EXIT_FAILED if result.failed else EXIT_OK
