"""``lcchain figures``: the paper's figures, recomputed: one file per figure, named by its label
(:func:`lcchain.app.figures.figures`)."""

from __future__ import annotations

import argparse

from .common import EXIT_OK, Parser, Subcommands
from .progress import counter

__all__ = ["add_parser", "add_cache_argument", "add_figures_arguments", "cmd_figures"]


def add_parser(sub: Subcommands, budget: list[Parser]) -> None:
    p = sub.add_parser("figures", help="the paper's figures, recomputed: one file per figure, named by its label")
    add_figures_arguments(p)
    p.set_defaults(func=cmd_figures)


def add_cache_argument(p: argparse.ArgumentParser) -> None:
    p.add_argument("--no-cache", action="store_true",
                   help="recompute every row of Tables I and II (by default rows computed once are kept in "
                        "$XDG_CACHE_HOME/lcchain, or ~/.cache/lcchain, and reused by the same lcchain code)")


def add_figures_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--out", required=True, metavar="DIR", help="folder for the figures (created if missing)")
    p.add_argument("--quick", action="store_true", help="coarser N grids (under a minute)")
    p.add_argument("--format", choices=("png", "svg", "pdf"), default="png")
    add_cache_argument(p)


def cmd_figures(args: argparse.Namespace) -> int:
    from ..app.figures import FiguresRequest, figures

    paths = figures(FiguresRequest(args.out, quick=args.quick, format=args.format, cache=not args.no_cache,
                                   progress=counter("figures")))
    for path in paths:
        print(path)
    return EXIT_OK
