"""``lcchain table``: Table I (one-mass) or II (two-mass) for a list of N (:func:`lcchain.app.design.table`)."""

from __future__ import annotations

import argparse

from ..core.types import DESIGN_CASES
from .common import EXIT_OK, Parser, Subcommands, budget_from_args, emit_json, int_list
from .design import format_table
from .progress import Progress

__all__ = ["add_parser", "cmd_table"]


def add_parser(sub: Subcommands, budget: list[Parser]) -> None:
    p = sub.add_parser("table", parents=budget, help="Table I (one-mass) or II (two-mass) for a list of N")
    p.add_argument("--case", choices=DESIGN_CASES, required=True)
    p.add_argument("--N", type=int_list("--N"), default=[3, 4, 5, 6, 7, 8, 9, 10, 12, 14, 16, 18, 20, 100, 1000])
    out = p.add_mutually_exclusive_group()
    out.add_argument("--json", action="store_true")
    out.add_argument("--csv", action="store_true")
    p.set_defaults(func=cmd_table)


def cmd_table(args: argparse.Namespace) -> int:
    from ..app.design import TableRequest, table

    progress = Progress(f"{args.case} table")
    rows = table(TableRequest(args.case, tuple(args.N), budget_from_args(args),
                              progress=lambda done, total: progress.update(done, total, unit="rows")))
    if args.json:
        emit_json(rows)
    elif args.csv:
        keys = list(rows[0])
        print(",".join(keys))
        for row in rows:
            print(",".join(repr(row[k]) if isinstance(row[k], float) else str(row[k]) for k in keys))
    else:
        print(format_table(args.case, rows))
    return EXIT_OK
