"""What the study commands share (``sweep``, ``batch``, ``run``, ``sensitivity --check``): their options, what a
study shows while it runs, its summary, and the tables ``results`` prints."""

from __future__ import annotations

import argparse
import sys

from ..app.choices import EXECUTOR_CHOICES
from ..app.studies import StudyHooks, StudyOptions, StudyResult
from ..core.budget import show_seconds
from ..core.json import LooseJSONObject
from ..core.types import TRANSPORT_CHOICES
from .common import EXIT_FAILED, EXIT_OK, budget_from_args, emit_json, plural, registry_name, seconds
from .progress import end_lines, plan_counter, study_counter

__all__ = ["add_study_arguments", "study_options", "study_hooks", "show_study", "table", "format_number", "short"]


def add_study_arguments(p: argparse.ArgumentParser, *, store: bool = True) -> None:
    """Where and how a study runs: the store, the executor, its workers, a timeout."""
    if store:
        p.add_argument("--store", required=True, metavar="FILE.sqlite", help="the results (created, or resumed)")
        p.add_argument("--json", action="store_true",
                       help="print one summary object: total, skipped, ran, ok, failed, refused (and each refusal's "
                            "netlist and reason), store")
        p.add_argument("--wait", action="store_true",
                       help="when another lcchain is writing the store, wait for it to finish (default: refuse)")
        p.add_argument("--retry-failed", action="store_true",
                       help="run again the runs the store holds as failed or timed out")
    # choices: --help lists the registry (plugins included), read only then; the value is checked by the type
    p.add_argument("--executor", type=registry_name("--executor", EXECUTOR_CHOICES), choices=EXECUTOR_CHOICES,
                   metavar="EXECUTOR", default="process",
                   help="where the runs execute: %(choices)s (default %(default)s)")
    p.add_argument("--workers", type=int, default=None, help="worker processes (default: one per core)")
    p.add_argument("--scheduler", metavar="tcp://HOST:PORT", help="an existing Dask scheduler (--executor dask)")
    p.add_argument("--transport", choices=TRANSPORT_CHOICES, default="auto",
                   help="how each ngspice run starts: auto (short runs in warm shared-library workers, when there "
                        "are enough of them), process (one ngspice -b each) or warm (every run that can); "
                        "results are the same (lcchain run: with --workers)")
    p.add_argument("--timeout", type=seconds("--timeout"), default=3600.0, metavar="S",
                   help="seconds before a run's ngspice is killed (its record says timeout; default 3600; a batch "
                        "netlist's run also stops at a few times its own price)")


def study_options(args: argparse.Namespace) -> StudyOptions:
    """Where and how the command's runs execute, and their store."""
    return StudyOptions(args.executor, args.workers, args.scheduler, args.transport, args.timeout,
                        store=getattr(args, "store", None), wait=getattr(args, "wait", False),
                        retry_failed=getattr(args, "retry_failed", False))


def study_hooks(args: argparse.Namespace) -> StudyHooks:
    """What a study shows while it runs: its progress, a resumed store, a wait for another writer."""

    def resumed(skipped: int, todo: int) -> None:
        if skipped:
            again = " (the failed ones again)" if args.retry_failed else ""
            print(f"lcchain: resuming {args.store}: {skipped} of {skipped + todo} runs are stored, {todo} to "
                  f"run{again}", file=sys.stderr, flush=True)

    def waiting(pid: int | None) -> None:
        who = f"another lcchain (pid {pid})" if pid is not None else "another lcchain"
        print(f"lcchain: {who} is writing {args.store}: waiting for it to finish", file=sys.stderr, flush=True)

    return StudyHooks(progress=study_counter("runs"), on_resume=resumed, on_wait=waiting,
                      verbose=bool(getattr(args, "verbose", False)), planning=plan_counter())


def show_study(args: argparse.Namespace, result: StudyResult) -> int:
    """Print a study's summary (and a worst case's findings): a line, or one JSON object, on a line of its own
    (a progress bar its time budget left unfinished on the terminal is ended first)."""
    end_lines()
    summary = result.summary
    extra = {} if result.worst_case is None else {"worst_case": result.worst_case}
    if args.json:
        emit_json({**summary.to_dict(), **extra})
    else:
        combined = ""
        if summary.combined or summary.combined_failed:
            combined = (f"; {summary.combined} extrapolated result{'s' if summary.combined != 1 else ''} combined "
                        "from them" +
                        (f", {summary.combined_failed} failed" if summary.combined_failed else ""))
        hint = ""
        if summary.refused:
            hint = "; the refused ones follow, each with why (stored: the same command does not run them)"
        if summary.failed:
            hint = (f"; 'lcchain results {args.store}' says why, and the same command with --retry-failed runs "
                    "them again")
        if summary.pending:
            spent = show_seconds(budget_from_args(args).max_seconds)
            hint += f"; {summary.pending} not run: the --max-time of {spent} was spent, and the same command runs them"
        refused = f", {summary.refused} refused" if summary.refused else ""
        print(f"{plural(summary.total, 'run')} in {args.store}: {summary.ran} ran now, "
              f"{summary.skipped} already stored; "
              f"{summary.ok} ok, {summary.failed} failed{refused}{combined} ({summary.wall_s:.1f} s){hint}")
        for netlist, reason in summary.refusals:
            print(f"refused {netlist}: {reason}")
        if result.worst_case is not None:
            _print_worst_case(result.worst_case)
    return EXIT_OK if summary.complete else EXIT_FAILED


def _print_worst_case(summary: LooseJSONObject) -> None:
    what = summary["metric"]
    rows = [[row["corner"], f"{row['sim']:.6f}", f"{row['theory']:.6f}", f"{row['predicted']:.6f}"]
            for row in summary["corners"]]
    print(table(["corner", f"{what} (ngspice)", f"{what} (theory)", "first order"], rows))
    quick = summary["corner_analysis"]
    if quick["worst"] is not None:
        print(f"{quick['label']}: worst {quick['worst']['corner']}, {what} {quick['worst']['sim']:.6f} (ngspice)")
    search = summary.get("search")
    if search is not None:
        where = ("a vertex, every part at +- its tolerance" if search["vertex"] else "a point inside the box")
        sim = f", ngspice {search['sim']:.6f}" if "sim" in search else ""
        print(f"search of the whole tolerance box (exact theory): worst {what} {search['worst']:.6f}{sim}, "
              f"nominal {search['nominal']:.6f}; at {where}: signs {search['signs']} (L_1..L_N, C_0_1..C_N_N+1)")
        optima = search["local_optima"]
        print(f"  {search['starts']} starts ended at {len(optima)} distinct local optima ({optima[0]:.6f} .. "
              f"{optima[-1]:.6f}); {search['evaluations']} exact evaluations, {search['seconds']:.2f} s")
        print(f"  certificate: the quadratic model about the nominal is >= {search['model_bound']:.6f} over the box "
              f"(proved for the model); the {what} is >= {search['bound']:.6f} if it stays within "
              f"{search['model_error']:.2e} of the model (twice the largest distance seen at the evaluated "
              f"points: an estimate, not a proof); gap {search['gap']:.2e}")
    if "worst" not in summary:
        return
    worst = summary["worst"]
    if "nominal" in summary:
        change, nominal = summary["worst_change"], summary["nominal"]["sim"]
        print(f"worst corner: {worst['corner']}, {what} {worst['sim']:.6f} against the nominal {nominal:.6f} "
              f"({change:+.2e}, {100 * change / nominal:+.3g} %)")
    mc = summary.get("monte_carlo")
    if mc is not None:
        print(f"Monte Carlo ({mc['samples']} samples, exact theory): worst {what} {mc['worst']:.6f}, "
              f"{'within' if mc['within'] else 'BEYOND'} the worst corner's {mc['worst_corner_theory']:.6f}")


def short(key: str) -> str:
    """A column title for a dotted key: its last part (``effects.tolerance.L+effects.tolerance.C`` -> ``L+C``)."""
    return "+".join(part.rsplit(".", 1)[-1] for part in key.split("+"))


def format_number(value: object, digits: str = ".3g") -> str:
    """A table cell: blank for no value, never ``None`` or ``-0``."""
    if value is None:
        return ""
    if isinstance(value, float) and value != value:  # nothing compared (every mode merged): no error
        return "n/a"
    if isinstance(value, float):
        return format(value + 0.0 if value != 0 else 0.0, digits)
    return str(value)


def table(titles: list[str], rows: list[list[str]]) -> str:
    widths = [max(len(t), *(len(r[i]) for r in rows)) if rows else len(t) for i, t in enumerate(titles)]
    lines = ["  ".join(t.rjust(w) for t, w in zip(titles, widths, strict=True))]
    lines += ["  ".join(c.rjust(w) for c, w in zip(row, widths, strict=True)) for row in rows]
    return "\n".join(lines)
