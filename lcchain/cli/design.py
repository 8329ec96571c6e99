"""``lcchain design``: the optimal one-mass or two-mass chain for N (a row of Table I or II), or a perfect cradle
(:func:`lcchain.app.design.design`)."""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

from ..core.json import LooseJSONObject
from ..core.types import DESIGN_CASES
from .common import EXIT_OK, Parser, Subcommands, budget_from_args, emit_json
from .progress import fraction

if TYPE_CHECKING:
    from ..app.design import PerfectDesign

__all__ = ["add_parser", "cmd_design", "format_table"]

_TABLE_COLUMNS = {
    "one-mass": [("N", "N", "{:>6d}"), ("x*", "x", "{:.4f}"), ("delta*", "delta", "{:.4f}"), ("s*", "s", "{:6.2f}"),
                 ("m1*", "m1", "{:7.3f}"), ("Delta*", "Delta", "{:#.4g}"), ("delta*(1)", "delta_uniform", "{:.4f}")],
    "two-mass": [("N", "N", "{:>6d}"), ("r*", "r", "{:.4f}"), ("w*", "w", "{:.4f}"), ("delta*", "delta", "{:.5f}"),
                 ("s*", "s", "{:6.2f}"), ("m1*", "m1", "{:7.3f}"), ("m2*", "m2", "{:.4f}"), ("K12*", "K12", "{:.4f}")],
}


def add_parser(sub: Subcommands, budget: list[Parser]) -> None:
    p = sub.add_parser("design", parents=budget,
                       help="optimal one-mass or two-mass chain for N (a row of Table I or II), or a perfect cradle")
    p.add_argument("--case", choices=(*DESIGN_CASES, "perfect"), required=True,
                   help="one-mass, two-mass: the paper's optima; perfect: alpha_N = 1 exactly, designed from its "
                        "spectrum (every mass and spring modulated)")
    p.add_argument("--N", type=int, required=True)
    p.add_argument("--walls", type=int, default=0, metavar="J",
                   help="--case perfect only: J >= 1 ties the chain to walls (frequencies n - 1 + 2J)")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=cmd_design)


def _cell(fmt: str, value: object) -> str:
    """``value`` formatted, a float that prints as a negative zero as zero (delta* of N = 3 is -4.4e-16, whose
    "-0.00000" reads as a negative loss)."""
    text = fmt.format(value)
    if isinstance(value, float) and text.lstrip().startswith("-") and float(text) == 0.0:
        return fmt.format(0.0)
    return text


def format_table(case: str, rows: list[LooseJSONObject]) -> str:
    columns = _TABLE_COLUMNS[case]
    cells = [[_cell(fmt, row[key]) for _, key, fmt in columns] for row in rows]
    widths = [max(len(head), *(len(c[i]) for c in cells)) for i, (head, _, _) in enumerate(columns)]
    from ..app.design import DESIGN_TABLES

    table, what = DESIGN_TABLES[case]
    title = f"{table}: {what}"
    lines = [title, "  ".join(h.rjust(w) for (h, _, _), w in zip(columns, widths, strict=True))]
    lines.append("-" * len(lines[-1]))
    lines += ["  ".join(c.rjust(w) for c, w in zip(row, widths, strict=True)) for row in cells]
    return "\n".join(lines)


def _format_perfect(design: PerfectDesign) -> str:
    """A perfect cradle as a reader wants it: what it achieves, how its values spread, then the values."""
    spread = design.spread()
    walls = f", tied to walls (j = {design.walls})" if design.walls else ", free ends"
    lines = [f"Perfect cradle of N = {design.N} masses{walls} (bulk units: central mass and central spring 1)",
             f"  arrival time T = {design.t_arrival:.10g}   1 - alpha_N(T) = {design.delta:.1e}",
             f"  masses  {spread['mass_min']:.6g} .. {spread['mass_max']:.6g} ({spread['distinct_masses']} distinct)",
             f"  springs {spread['spring_min']:.6g} .. {spread['spring_max']:.6g} ({spread['distinct_springs']} "
             f"distinct, walls excluded)",
             "",
             f"{'i':>6}  {'m_i':>22}  {'K_(i-1,i)':>22}"]
    m, K = design.chain.masses, design.chain.springs
    shown = range(design.N + 1) if design.N <= 40 else [*range(10), None, *range(design.N - 9, design.N + 1)]
    for i in shown:
        if i is None:
            lines.append(f"{'...':>6}")
            continue
        mass = f"{float(m[i])!r:>22}" if i < design.N else " " * 22
        lines.append(f"{i + 1:>6}  {mass}  {float(K[i])!r:>22}")
    if design.N > 40:
        lines.append("(all of them: --json)")
    return "\n".join(lines)


def cmd_design(args: argparse.Namespace) -> int:
    from ..app.design import DesignRequest, design, is_perfect

    result = design(DesignRequest(args.case, args.N, args.walls, budget_from_args(args), progress=fraction))
    if args.json:
        emit_json(result.to_dict())
    elif is_perfect(result):
        print(_format_perfect(result))
    else:  # one of the paper's optima: its table's row
        print(format_table(args.case, [result.to_dict()]))
    return EXIT_OK
