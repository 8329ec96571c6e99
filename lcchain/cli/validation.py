"""``lcchain figures`` and ``lcchain report``: the paper's figures and the validation report."""

from __future__ import annotations

import argparse
from typing import Any

from .common import EXIT_FAILED, EXIT_OK
from .progress import counter

__all__ = ["add_figures_arguments", "add_report_arguments", "cmd_figures", "cmd_report"]


def _add_cache(p: argparse.ArgumentParser) -> None:
    p.add_argument("--no-cache", action="store_true",
                   help="recompute every row of Tables I and II (by default rows computed once are kept in "
                        "$XDG_CACHE_HOME/lcchain, or ~/.cache/lcchain, and reused by the same lcchain code)")


def add_figures_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--out", required=True, metavar="DIR", help="folder for the figures (created if missing)")
    p.add_argument("--quick", action="store_true", help="coarser N grids (under a minute)")
    p.add_argument("--format", choices=("png", "svg", "pdf"), default="png")
    _add_cache(p)


def add_report_arguments(p: argparse.ArgumentParser) -> None:
    p.description = ("The validation report: the paper reproduced and the circuit validated in every engine "
                     "installed. Cold (no row cached): about 97 s of CPU, done on both cores; estimated 54 s on an "
                     "idle 2-core machine, measured 91 s with another program using one of its cores "
                     "(benchmarks/report_cold.md). With its rows cached: 49 s of CPU less.")
    p.add_argument("--out", required=True, metavar="DIR",
                   help="folder for index.html and report.json (created if missing)")
    p.add_argument("--quick", action="store_true",
                   help="the paper's printed rows and a few more, and the circuit's runs up to N = 100 (cold: "
                        "about 31 s of CPU, estimated 17 s on an idle 2-core machine, measured 42 s with one core "
                        "busy)")
    _add_cache(p)


def _cache(args: argparse.Namespace) -> Any:
    from ..report.figure_data import default_cache_dir

    return None if args.no_cache else default_cache_dir()


def cmd_figures(args: argparse.Namespace) -> int:
    from ..report.build import build_figures
    from ..report.files import check_output_folder

    check_output_folder("--out", args.out)
    paths = build_figures(args.out, quick=args.quick, fmt=args.format, cache=_cache(args),
                          progress=counter("figures"))
    for path in paths:
        print(path)
    return EXIT_OK


def cmd_report(args: argparse.Namespace) -> int:
    from ..app.validation import make_report
    from ..report.files import check_output_folder

    check_output_folder("--out", args.out)
    command = "lcchain report" + (" --quick" if args.quick else "")
    report = make_report(args.out, quick=args.quick, cache=_cache(args), progress=counter("report"),
                         command=command)
    checks = report["checks"]
    failed = [c for c in checks if not c["passed"]]
    print(f"{args.out}/index.html: {len(checks) - len(failed)} of {len(checks)} checks passed "
          f"({report['seconds']:.0f} s)")
    for check in failed:
        print(f"  FAILED {check['name']}: max error {check['max_abs_error']} > tolerance {check['tolerance']}")
    return EXIT_OK if not failed else EXIT_FAILED
