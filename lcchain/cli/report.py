"""``lcchain report``: the validation report: the paper reproduced and the circuit validated, in DIR/index.html
and DIR/report.json (:func:`lcchain.app.validation.report`)."""

from __future__ import annotations

import argparse

from .common import EXIT_FAILED, EXIT_OK, Parser, Subcommands
from .figures import add_cache_argument
from .progress import counter

__all__ = ["add_parser", "add_report_arguments", "cmd_report"]


def add_parser(sub: Subcommands, budget: list[Parser]) -> None:
    p = sub.add_parser("report", help="the validation report: the paper reproduced and the circuit validated, in "
                       "DIR/index.html and DIR/report.json (exit 1 when a check fails)")
    add_report_arguments(p)
    p.set_defaults(func=cmd_report)


def add_report_arguments(p: argparse.ArgumentParser) -> None:
    p.description = ("The validation report: the paper reproduced and the circuit validated in every engine "
                     "installed. Cold (no row cached): measured 48 s on a quiet 2-core machine (about 94 s of "
                     "CPU, done on both cores; 91 s with another program using one of the cores; "
                     "benchmarks/report_cold.md). With its rows cached: 49 s of CPU less.")
    p.add_argument("--out", required=True, metavar="DIR",
                   help="folder for index.html and report.json (created if missing)")
    p.add_argument("--quick", action="store_true",
                   help="the paper's printed rows and a few more, and the circuit's runs up to N = 100 (cold: "
                        "measured 17 s on a quiet 2-core machine, about 32 s of CPU; 42 s with one core busy)")
    add_cache_argument(p)


def cmd_report(args: argparse.Namespace) -> int:
    from ..app.validation import ReportRequest
    from ..app.validation import report as make_report

    command = "lcchain report" + (" --quick" if args.quick else "")
    report = make_report(ReportRequest(args.out, quick=args.quick, cache=not args.no_cache,
                                       progress=counter("report"), command=command))
    checks = report["checks"]
    failed = [c for c in checks if not c["passed"]]
    print(f"{args.out}/index.html: {len(checks) - len(failed)} of {len(checks)} checks passed "
          f"({report['seconds']:.0f} s)")
    for check in failed:
        print(f"  FAILED {check['name']}: max error {check['max_abs_error']} > tolerance {check['tolerance']}")
    return EXIT_OK if not failed else EXIT_FAILED
