"""``lcchain examples``: the example scenes that ship with lcchain: list them, or write one here
(:mod:`lcchain.app.netlist`)."""

from __future__ import annotations

import argparse
from pathlib import Path

from .common import EXIT_FAILED, EXIT_OK, Parser, Subcommands, print_notes

__all__ = ["add_parser", "cmd_examples"]


def add_parser(sub: Subcommands, budget: list[Parser]) -> None:
    p = sub.add_parser("examples", help="the example scenes that ship with lcchain: list them, or write one here")
    p.add_argument("name", nargs="?", metavar="NAME", help="the example to write (default: list them)")
    p.add_argument("-o", "--output", metavar="FILE", help="where to write it (default: NAME.toml here)")
    p.set_defaults(func=cmd_examples)


def cmd_examples(args: argparse.Namespace) -> int:
    """List the example scenes that ship with lcchain, or write one here (or to -o FILE) to run or edit."""
    from ..app.netlist import ExampleRequest, example, examples

    if args.name is None:
        listed = examples()
        width = max(len(name) for name, _ in listed)
        for name, title in listed:
            print(f"{name:<{width}}  {title}")
        print("\nlcchain examples NAME writes NAME.toml here (-o FILE: elsewhere); then: lcchain run NAME.toml")
        return EXIT_OK
    result = example(ExampleRequest(args.name, args.output))
    if result.unchanged:
        print(f"{result.target} is here already, unchanged: lcchain run {result.target}")
        return EXIT_OK
    print_notes(result.notes)
    if not result.failed and not result.to_stdout:
        print(f"wrote {result.target}" + (f": lcchain run {result.target}" if Path(result.target).is_file() else ""))
    return EXIT_FAILED if result.failed else EXIT_OK
