"""``lcchain reference-netlists``: regenerate the reference netlists of netlists/
(:func:`lcchain.app.netlist.reference_netlists`)."""

from __future__ import annotations

import argparse

from .common import EXIT_FAILED, EXIT_OK, Parser, Subcommands, print_notes

__all__ = ["add_parser", "cmd_reference_netlists"]


def add_parser(sub: Subcommands, budget: list[Parser]) -> None:
    p = sub.add_parser("reference-netlists", help="regenerate the reference netlists of netlists/")
    p.add_argument("--out", default="netlists", help="folder (default netlists)")
    p.set_defaults(func=cmd_reference_netlists)


def cmd_reference_netlists(args: argparse.Namespace) -> int:
    from ..app.netlist import ReferenceRequest, reference_netlists

    result = reference_netlists(ReferenceRequest(args.out, written=print))
    print_notes(result.notes)
    return EXIT_FAILED if result.failed else EXIT_OK
