"""``lcchain bench accuracy``: what each digit costs per method and N (:func:`lcchain.app.bench.bench_accuracy`)."""

from __future__ import annotations

import argparse

from .common import EXIT_OK, Parser, Subcommands, budget_from_args, int_list
from .progress import counter

__all__ = ["add_parser", "cmd_bench_accuracy"]


def add_parser(sub: Subcommands, budget: list[Parser]) -> None:
    p = sub.add_parser("bench", help="benchmarks (accuracy: what each digit costs per method and N)")
    bench = p.add_subparsers(dest="bench", metavar="BENCH", parser_class=sub._parser_class)
    bench.required = True
    b = bench.add_parser("accuracy", parents=budget,
                         help="sweep dt x method x stepping, DOP853 and the modal sum as peers")
    b.add_argument("--N", type=int_list("--N"), help="chain sizes (default 20,100,1000; --quick: 20,100)")
    b.add_argument("--quick", action="store_true", help="fewer steps and tolerances (under 2 minutes)")
    b.add_argument("--out", default="benchmarks/accuracy", help="output folder (default benchmarks/accuracy)")
    b.set_defaults(func=cmd_bench_accuracy)


def cmd_bench_accuracy(args: argparse.Namespace) -> int:
    from ..app.bench import AccuracyBenchRequest, bench_accuracy, write_bench

    result = bench_accuracy(AccuracyBenchRequest(None if args.N is None else tuple(args.N), quick=args.quick,
                                                 out=args.out, budget=budget_from_args(args),
                                                 progress=counter("bench accuracy")))
    print(result.markdown, end="")
    for path in write_bench(args.out, result):
        print(f"wrote {path}")
    return EXIT_OK
