"""``lcchain sweep``, ``lcchain batch`` and ``lcchain results``: studies of many runs, in a store."""

from __future__ import annotations

import argparse
import contextlib
import csv
import io
import json
import logging
import sys
import time
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path
from typing import Any

from ..core.analyses import ANALYSIS_KINDS_DATA
from ..core.budget import INTERPRETER_SECONDS, show_seconds
from ..core.errors import ExtraMissingError, ParameterError
from ..core.types import (
    ANALYSIS_KINDS,
    ARRIVAL_METRICS,
    BACKENDS,
    DEFAULT_C0,
    DEFAULT_L0,
    EXCITATIONS,
    EXECUTORS,
    NAMED_CASES,
    STUDY_METRICS,
    TRANSPORT_CHOICES,
    WORST_CASE_METHODS,
)
from ..report.files import FIGURE_FORMATS
from ..spice.engines import DEFAULT_ENGINE, ENGINES
from .common import (
    EXIT_FAILED,
    EXIT_OK,
    Outputs,
    add_parts_arguments,
    budget_from_args,
    emit_json,
    int_list,
    list_entries,
    seconds,
)
from .progress import counter, study_counter

__all__ = ["cmd_sweep", "cmd_batch", "cmd_results", "add_study_arguments"]

STORE_FORMATS = ("sqlite", "sqlite3", "db")


def _floats(option: str) -> Callable[[str], list[float]]:
    def parse(text: str) -> list[float]:
        entries = list_entries(option, text, "numbers")
        try:
            return [float(v) for v in entries]
        except ValueError:
            raise argparse.ArgumentTypeError(f"{option} = {text!r} is not allowed: expected numbers separated by "
                                             "commas") from None

    return parse


def _words(option: str, allowed: Sequence[str]) -> Callable[[str], list[str]]:
    def parse(text: str) -> list[str]:
        values = list_entries(option, text, " | ".join(allowed))
        bad = [v for v in values if v not in allowed]
        if bad:
            raise argparse.ArgumentTypeError(f"{option} = {bad[0]!r} is not allowed: expected a comma list of "
                                             f"{' | '.join(allowed)}")
        return values

    return parse


def _worst_case_method(text: str) -> str:
    if text not in WORST_CASE_METHODS:
        where = " (the scene goes before it: sweep SCENE.toml --worst-case)" if text.endswith(".toml") else ""
        raise argparse.ArgumentTypeError(f"--worst-case = {text!r} is not allowed: expected "
                                         f"{' | '.join(WORST_CASE_METHODS)} or nothing (search){where}")
    return text


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
    p.add_argument("--executor", choices=EXECUTORS, default="process", help="where the runs execute (default process)")
    p.add_argument("--workers", type=int, default=None, help="worker processes (default: one per core)")
    p.add_argument("--scheduler", metavar="tcp://HOST:PORT", help="an existing Dask scheduler (--executor dask)")
    p.add_argument("--transport", choices=TRANSPORT_CHOICES, default="auto",
                   help="how each ngspice run starts: auto (short runs in warm shared-library workers, when there "
                        "are enough of them), process (one ngspice -b each) or warm (every run that can); "
                        "results are the same (lcchain run: with --workers)")
    p.add_argument("--timeout", type=seconds("--timeout"), default=3600.0, metavar="S",
                   help="seconds before a run's ngspice is killed (its record says timeout; default 3600; a batch "
                        "netlist's run also stops at a few times its own price)")


def add_sweep_arguments(p: argparse.ArgumentParser) -> None:
    from .common import number_type

    p.add_argument("scene", nargs="?", metavar="SCENE.toml", help="vary a scene instead of cases (with --vary)")
    p.add_argument("--netlist", metavar="FILE.cir",
                   help="vary a netlist lcchain did not write instead (with --vary NAME=...): each variant checked, "
                        "priced and run as lcchain batch runs a netlist")
    p.add_argument("--case", type=_words("--case", NAMED_CASES), help="chains, comma separated: an axis")
    p.add_argument("--N", type=int_list("--N"), help="sizes, comma separated: an axis")
    step = p.add_mutually_exclusive_group()
    step.add_argument("--dt", type=_floats("--dt"), help="steps, comma separated: an axis")
    step.add_argument("--accuracy", type=_floats("--accuracy"), help="accuracies, comma separated: an axis")
    p.add_argument("--extrapolate", type=int, choices=(1, 2, 3), metavar="{1,2,3}",
                   help="runs per point at dt, dt/2, dt/4, each a task, combined in the store (default: 1 with "
                        "--dt; with --accuracy the cheapest of 1, 2, 3, as lcchain simulate chooses)")
    p.add_argument("--transits", type=int_list("--transits"), help="transits, comma separated (default 1)")
    p.add_argument("--excitation", type=_words("--excitation", EXCITATIONS),
                   help="kick and/or displacement, comma separated (default kick)")
    p.add_argument("--analysis", choices=tuple(ANALYSIS_KINDS_DATA), default=ANALYSIS_KINDS[0],
                   help="transient (default), or ac: each chain's spectrum (normal frequencies and end weights "
                        "against theory) from an AC sweep")
    p.add_argument("--points", type=int, help="with --analysis ac: frequencies of each sweep (default: twice the "
                                              "fewest that separate every pole)")
    p.add_argument("--L0", type=number_type("--L0"), default=DEFAULT_L0,
                   help=f"bulk inductance, henry (default {DEFAULT_L0:g})")
    p.add_argument("--C0", type=number_type("--C0"), default=DEFAULT_C0,
                   help=f"bulk capacitance, farad (default {DEFAULT_C0:g})")
    p.add_argument("--backend", choices=BACKENDS, default=BACKENDS[0])
    p.add_argument("--engine", choices=tuple(ENGINES),
                   help="the circuit simulator of every run (default ngspice; with SCENE.toml its "
                        "[analysis] engine says it)")
    p.add_argument("--vary", action="append", default=[], metavar="KEY=V1,V2,...",
                   help="with SCENE.toml: a dotted scene key and its values (repeat for more axes; keys joined "
                        "by + take the same values together); with --netlist: a .param or an R, L, C, K element "
                        "and 1k,2.2k,... or lin:START:STOP:N or log:START:STOP:N (lists and grids multiply), or "
                        "normal:MEAN:SIGMA (SIGMA may be 5%%), uniform:LO:HI or tolerance:NOMINAL:P%% (drawn "
                        "--samples times, seeded by --seed)")
    add_parts_arguments(p, netlist=True)  # --tolerance, --series, --samples (each a task of its own), --seed
    p.add_argument("--worst-case", nargs="?", const="search", default=None, type=_worst_case_method,
                   metavar="{search,corners}",
                   help="with SCENE.toml (kicked, with [effects.tolerance]): the worst first arrival. search "
                        "(default): every part anywhere within its tolerance, searched in exact theory with a "
                        "certificate; its worst point runs in ngspice beside the nominal and the quick corners. "
                        "corners: only the corners of the --components parts that move the metric most and the "
                        "two the sensitivities' signs predict (a quick look, not a search)")
    p.add_argument("--components", type=int, default=None, metavar="K",
                   help="--worst-case: the quick corners move the K most sensitive parts together, 2^K corners "
                        "(default 2)")
    p.add_argument("--metric", choices=ARRIVAL_METRICS, default=None,
                   help="--worst-case: search, rank and judge by the first arrival's current peak (default) or "
                        "its energy fraction peak^2 L_N/L_1; the worst is the lowest")
    add_study_arguments(p)


#: Loggers of Dask and the libraries under it: their records reach the terminal only with -v.
_DASK_LOGGERS = ("distributed", "dask", "tornado", "bokeh", "asyncio")


class _NotDask(logging.Filter):
    def filter(self, record: logging.LogRecord) -> bool:
        return not record.name.startswith(_DASK_LOGGERS)


@contextlib.contextmanager
def _dask_quiet(verbose: bool) -> Iterator[None]:
    """Dask logs its cluster's life at INFO through the root logger: shown with -v only."""
    if verbose:
        yield
        return
    quiet = _NotDask()
    handlers = list(logging.getLogger().handlers)
    for handler in handlers:
        handler.addFilter(quiet)
    try:
        yield
    finally:
        for handler in handlers:
            handler.removeFilter(quiet)


def _check_study_options(args: argparse.Namespace, outputs: Outputs) -> None:
    """Everything a study's options can be checked for without running it: before the store is touched."""
    from ..studies.executors import check_executor

    outputs.check("--store", args.store, STORE_FORMATS)
    check_executor(args.executor, args.workers, args.scheduler)


def _workers(args: argparse.Namespace) -> int:
    """The workers a study runs on: --workers, or one per core (serial: one)."""
    from ..studies.executors import default_workers

    return 1 if args.executor == "serial" else args.workers or default_workers()


def _run(args: argparse.Namespace, plan: Any, outputs: Outputs,
         after: Callable[[bool], dict[str, Any]] | None = None, max_seconds: float | None = None,
         pool: Any = None) -> int:
    """Run a study's plan into --store and print its summary; ``after(json)`` adds what the study itself says
    (printed, or returned to join the JSON object); ``max_seconds``: the study's time budget left (runs not
    started within it stay pending)."""
    from ..studies.run import run_plan

    workers = _workers(args)
    plan.check(budget_from_args(args), workers, args.executor)

    def resumed(skipped: int, todo: int) -> None:
        if skipped:
            again = " (the failed ones again)" if args.retry_failed else ""
            print(f"lcchain: resuming {args.store}: {skipped} of {skipped + todo} runs are stored, {todo} to "
                  f"run{again}", file=sys.stderr, flush=True)

    def waiting(pid: int | None) -> None:
        who = f"another lcchain (pid {pid})" if pid is not None else "another lcchain"
        print(f"lcchain: {who} is writing {args.store}: waiting for it to finish", file=sys.stderr, flush=True)

    verbose = bool(getattr(args, "verbose", False))
    with _dask_quiet(verbose):
        summary = run_plan(plan, args.store, executor=args.executor, workers=workers, scheduler=args.scheduler,
                           progress=study_counter("runs"), on_resume=resumed, retry_failed=args.retry_failed,
                           wait=args.wait, on_wait=waiting, verbose=verbose, transport=args.transport,
                           max_seconds=max_seconds, pool=pool)
    if args.json:
        emit_json({**summary.to_dict(), **(after(True) if after is not None else {})})
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
        print(f"{summary.total} runs in {args.store}: {summary.ran} ran now, {summary.skipped} already stored; "
              f"{summary.ok} ok, {summary.failed} failed{refused}{combined} ({summary.wall_s:.1f} s){hint}")
        for netlist, reason in summary.refusals:
            print(f"refused {netlist}: {reason}")
        if after is not None:
            after(False)
    return EXIT_OK if summary.complete else EXIT_FAILED


def cmd_sweep(args: argparse.Namespace) -> int:
    from ..studies.plan import parse_vary, scene_sweep_plan

    outputs = Outputs()
    _check_study_options(args, outputs)
    budget = budget_from_args(args)
    if args.worst_case is not None or args.components is not None or args.metric is not None:
        return _worst_case(args, outputs, budget)
    if args.netlist is not None:
        return _netlist_sweep(args, outputs, budget)
    if args.scene:
        given = [o for o, v in (("--case", args.case), ("--N", args.N), ("--dt", args.dt),
                                ("--accuracy", args.accuracy), ("--extrapolate", args.extrapolate),
                                ("--engine", args.engine), ("--points", args.points), *_scene_says(args))
                 if v is not None]
        if given:
            raise ParameterError(given[0], getattr(args, given[0].lstrip("-")), "nothing with SCENE.toml (the scene "
                                 "says the chain and the analysis, [analysis] kind = \"ac\" included; vary its keys "
                                 "with --vary, e.g. analysis.extrapolate=1,2)")
        plan = scene_sweep_plan(args.scene, [parse_vary(v) for v in args.vary], samples=args.samples,
                                seed=args.seed, tolerance=args.tolerance, series=args.series, budget=budget,
                                workers=_workers(args))
    else:
        if args.vary:
            raise ParameterError("--vary", args.vary, "nothing without SCENE.toml (without one, the axes are --case, "
                                 "--N, --dt or --accuracy, --transits and --excitation lists)")
        if not args.case or not args.N:
            raise ParameterError("--case" if not args.case else "--N", None, "--case and --N lists (or SCENE.toml)")
        parts = any(v is not None for v in (args.samples, args.seed, args.tolerance, args.series))
        if not parts and args.analysis == "transient" and args.executor == "process" and _workers(args) > 1:
            from ..studies.pools import started_pool

            # the pool's workers start now and design the chains while the driver plans (issue 35)
            with started_pool(_workers(args)) as pool:
                return _run(args, _transient_sweep(args, budget, pool), outputs, pool=pool)
        plan = _parts_sweep(args, budget) if parts else _SWEEPS[args.analysis](args, budget)
    return _run(args, plan, outputs)


def _netlist_sweep(args: argparse.Namespace, outputs: Outputs, budget: Any) -> int:
    """``sweep --netlist FILE --vary NAME=...``: a foreign netlist's values varied, each variant run as a batch's
    netlist; as for a batch, --max-time is the whole budget (runs not started within it stay pending)."""
    from ..studies.plan import netlist_sweep_plan
    from ..studies.vary import parse_netlist_vary

    started = time.monotonic()
    given = [o for o, v in (("SCENE.toml", args.scene), ("--case", args.case), ("--N", args.N), ("--dt", args.dt),
                            ("--accuracy", args.accuracy), ("--extrapolate", args.extrapolate),
                            ("--engine", args.engine), ("--points", args.points), ("--tolerance", args.tolerance),
                            ("--series", args.series), ("--transits", args.transits),
                            ("--excitation", args.excitation),
                            ("--analysis", None if args.analysis == "transient" else args.analysis))
             if v is not None]
    if given:
        value = args.scene if given[0] == "SCENE.toml" else getattr(args, given[0].lstrip("-"))
        raise ParameterError(given[0], value, "nothing with --netlist (the netlist says its circuit and its "
                             "analysis; vary its .param or element values with --vary NAME=...)")
    plan = netlist_sweep_plan(args.netlist, [parse_netlist_vary(v) for v in args.vary], samples=args.samples,
                              seed=args.seed, backend=args.backend, timeout=args.timeout, budget=budget,
                              progress=counter("variants"))
    left = budget.max_seconds - INTERPRETER_SECONDS - (time.monotonic() - started)
    return _run(args, plan, outputs, max_seconds=max(left, 0.0))


def _parts_sweep(args: argparse.Namespace, budget: Any) -> Any:
    """``sweep --case C --N N --tolerance 1% --series E24 --samples 200``: a Monte Carlo of real parts with no scene
    file, the scene made from the options (:func:`lcchain.studies.plan.case_scene`), each list of them an axis."""
    from ..studies.plan import case_scene, scene_sweep_plan

    if args.analysis == "ac":
        raise ParameterError("--analysis", "ac", "transient with --tolerance, --series or --samples and no scene "
                             "(an AC Monte Carlo: a scene file with [analysis] kind = \"ac\")")
    if args.points is not None:
        raise ParameterError("--points", args.points, "nothing without --analysis ac")
    steps = ("analysis.accuracy", args.accuracy) if args.accuracy else ("analysis.dt", args.dt or [0.05])
    axes = [("chain.case", args.case), ("chain.N", args.N), steps, ("analysis.transits", args.transits or [1]),
            ("excitation.kind", args.excitation or ["kick"])]
    base = case_scene(args.case[0], args.N[0], dt=args.dt[0] if args.dt else None,
                      accuracy=args.accuracy[0] if args.accuracy else None, L0=args.L0, C0=args.C0,
                      engine=args.engine or DEFAULT_ENGINE)
    if args.extrapolate is not None:
        base["analysis"]["extrapolate"] = args.extrapolate
    base["analysis"]["backend"] = args.backend
    varies = [(key, list(values)) for key, values in axes if len(values) > 1]
    for key, values in axes:
        if len(values) == 1:
            section, name = key.split(".")
            base[section][name] = values[0]
    return scene_sweep_plan(base, varies, samples=args.samples, seed=args.seed, tolerance=args.tolerance,
                            series=args.series, budget=budget, workers=_workers(args))


def _scene_says(args: argparse.Namespace) -> tuple[tuple[str, Any], ...]:
    """The options a scene file says itself (its analysis, drive and transport): given with SCENE.toml, refused."""
    return (("--analysis", None if args.analysis == "transient" else args.analysis), ("--transits", args.transits),
            ("--excitation", args.excitation), ("--backend", None if args.backend == "batch" else args.backend))


def _worst_case(args: argparse.Namespace, outputs: Outputs, budget: Any) -> int:
    """``sweep SCENE --worst-case``: the corners run like the scene's samples, then which is worst."""
    from ..studies.store import Store
    from ..studies.worst_case import DEFAULT_COMPONENTS, worst_case_plan, worst_case_summary

    if args.worst_case is None:
        option = "--components" if args.components is not None else "--metric"
        raise ParameterError(option, getattr(args, option.lstrip("-")), "only with --worst-case")
    if not args.scene:
        raise ParameterError("SCENE.toml", None, "a scene file with --worst-case")
    given = [o for o, v in (("--case", args.case), ("--N", args.N), ("--dt", args.dt), ("--accuracy", args.accuracy),
                            ("--extrapolate", args.extrapolate), ("--engine", args.engine), ("--vary", args.vary),
                            ("--samples", args.samples), ("--seed", args.seed), ("--points", args.points),
                            ("--tolerance", args.tolerance), ("--series", args.series), ("--netlist", args.netlist),
                            *_scene_says(args))
             if v is not None and v != []]
    if given:
        raise ParameterError(given[0], getattr(args, given[0].lstrip("-")), "nothing with --worst-case (the scene "
                             "says the circuit and its [effects.tolerance]; the corners replace the samples)")
    plan, setup = worst_case_plan(args.scene, components=args.components if args.components is not None else
                                  DEFAULT_COMPONENTS, metric=args.metric or "peak", budget=budget,
                                  workers=_workers(args), method=args.worst_case)

    def after(as_json: bool) -> dict[str, Any]:
        with Store(args.store, "read") as store:
            summary = worst_case_summary(store.runs(), setup)
        if as_json:
            return {"worst_case": summary}
        _print_worst_case(summary)
        return {}

    return _run(args, plan, outputs, after)


def _print_worst_case(summary: dict[str, Any]) -> None:
    what = summary["metric"]
    rows = [[row["corner"], f"{row['sim']:.6f}", f"{row['theory']:.6f}", f"{row['predicted']:.6f}"]
            for row in summary["corners"]]
    print(_table(["corner", f"{what} (ngspice)", f"{what} (theory)", "first order"], rows))
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


def _transient_sweep(args: argparse.Namespace, budget: Any, pool: Any = None) -> Any:
    from ..studies.plan import sweep_plan

    if args.points is not None:
        raise ParameterError("--points", args.points, "nothing without --analysis ac (a transient's steps are --dt "
                             "or --accuracy)")
    return sweep_plan(cases=args.case, Ns=args.N, dts=args.dt or ([] if args.accuracy else [0.05]),
                      accuracies=args.accuracy or [], transits=args.transits or [1],
                      excitations=args.excitation or ["kick"], L0=args.L0, C0=args.C0, backend=args.backend,
                      timeout=args.timeout, budget=budget, extrapolate=args.extrapolate, workers=_workers(args),
                      engine=args.engine or DEFAULT_ENGINE, pool=pool)


def _ac_sweep(args: argparse.Namespace, budget: Any) -> Any:
    from ..studies.plan import spectrum_sweep_plan

    given = [o for o in ("--dt", "--accuracy", "--extrapolate", "--transits", "--excitation")
             if getattr(args, o.lstrip("-")) is not None] + (["--backend"] if args.backend != "batch" else [])
    if given:
        raise ParameterError(given[0], getattr(args, given[0].lstrip("-")), "nothing with --analysis ac (a "
                             "transient's option; an AC sweep has --points)")
    return spectrum_sweep_plan(cases=args.case, Ns=args.N, points=args.points, L0=args.L0, C0=args.C0,
                               timeout=args.timeout, budget=budget, workers=_workers(args),
                               engine=args.engine or DEFAULT_ENGINE)


#: How ``lcchain sweep --case ... --N ...`` plans each ``--analysis``.
_SWEEPS: dict[str, Callable[[argparse.Namespace, Any], Any]] = {"transient": _transient_sweep, "ac": _ac_sweep}


def cmd_batch(args: argparse.Namespace) -> int:
    """A batch's --max-time is its whole budget: each run's own limits come from its price (batch_plan), and no run
    starts once the budget is spent (the runs left stay pending in the store). A netlist lcchain will not run is
    stored as refused and the others run (exit 1); with --strict the first refusal stops the batch (exit 2)."""
    from ..studies.plan import batch_plan

    started = time.monotonic()
    outputs = Outputs()
    _check_study_options(args, outputs)
    budget = budget_from_args(args)
    plan = batch_plan(args.netlist, allow_control=args.allow_control, timeout=args.timeout, budget=budget,
                      strict=args.strict, check=getattr(args, "check", False))
    left = budget.max_seconds - INTERPRETER_SECONDS - (time.monotonic() - started)
    return _run(args, plan, outputs, max_seconds=max(left, 0.0))


def _flat(run: dict[str, Any]) -> dict[str, Any]:
    from ..spice.measure import MEASUREMENTS
    from ..studies.exports import measurement_column

    row = {"index": run["index"], "kind": run["kind"], "status": run["status"], **run["params"],
           "digest": run["digest"], "max_abs_error": run.get("max_abs_error"), "wall_s": run["wall_s"]}
    if "max_rel_error_omega" in run:  # an AC run: its spectral metrics instead of a transient's
        from ..compare.spectral import SPECTRAL_METRICS  # here: a transient's CSV needs no AC fit (nor scipy)

        del row["max_abs_error"]
        row.update({name: run.get(name) for name in SPECTRAL_METRICS}, points=run["points"])
    arrivals = run.get("arrivals") or []
    if arrivals:
        row.update(t_sim=arrivals[0]["t_sim"], peak_sim=arrivals[0]["peak_sim"], peak_theory=arrivals[0]["peak_theory"])
    for name, value in (run.get(MEASUREMENTS) or {}).items():
        row[measurement_column(name, row)] = value
    if "error" in run:
        row["error"] = run["error"].splitlines()[0]
    return row


def _short(key: str) -> str:
    """A column title for a dotted key: its last part (``effects.tolerance.L+effects.tolerance.C`` -> ``L+C``)."""
    return "+".join(part.rsplit(".", 1)[-1] for part in key.split("+"))


def _number(value: Any, digits: str = ".3g") -> str:
    """A table cell: blank for no value, never ``None`` or ``-0``."""
    if value is None:
        return ""
    if isinstance(value, float):
        return format(value + 0.0 if value != 0 else 0.0, digits)
    return str(value)


def _table(titles: list[str], rows: list[list[str]]) -> str:
    widths = [max(len(t), *(len(r[i]) for r in rows)) if rows else len(t) for i, t in enumerate(titles)]
    lines = ["  ".join(t.rjust(w) for t, w in zip(titles, widths, strict=True))]
    lines += ["  ".join(c.rjust(w) for c, w in zip(row, widths, strict=True)) for row in rows]
    return "\n".join(lines)


def _print_summary(stored: list[Any], args: argparse.Namespace) -> None:
    """Per combination of the study's axes: the first-arrival metric's distribution over the samples."""
    from ..studies.summary import peak_groups, study_constants

    groups = [group.to_dict() for group in peak_groups(stored, args.metric)]
    if args.json:
        emit_json(groups)
        return
    keys = list(dict.fromkeys(key for group in groups for key in group["params"]))
    stats = ["n", "failed", "mean", "std", "min", "p05", "median", "max"]
    def rows_with(digits: str) -> list[list[str]]:
        return [[_number(group["params"].get(key)) for key in keys]
                + [str(group[s]) if s in ("n", "failed") else _number(group[s], digits) for s in stats]
                for group in groups]

    # the table: 4 significant digits (a perfect cradle's loss is 2e-4, which 4 decimals showed as 0.0002 or
    # 0.0000); the CSV: the shortest text that reads back the same float
    rows = rows_with("" if args.csv else ".4g")
    if args.csv:
        text = io.StringIO()
        writer = csv.writer(text, lineterminator="\n")
        writer.writerow([*keys, *stats])
        writer.writerows(rows)
        sys.stdout.write(text.getvalue())
        return
    what = {"peak": "first-arrival peak (max I_N/I_1(0))", "energy": "first-arrival energy fraction (peak^2 L_N/L_1)",
            "loss": "first-arrival energy lost (1 - peak^2 L_N/L_1)",
            "omega": "AC: max |omega_n - theory| / theory (relative)", "P": "AC: max |P_n - theory| (absolute)",
            "spacing": "AC: spacing spread (max - min) / mean of delta omega_n"}.get(
                args.metric, f"the netlists' measurement {args.metric} (.meas; runs that could not measure it "
                "left out)")
    by = f"by {', '.join(map(_short, keys))}" if keys else "over all its runs"
    shared = ", ".join(f"{_short(k)} = {_number(v)}" for k, v in study_constants(stored).items())
    print(f"{args.store}: {what} {by}" + (f" ({shared} throughout)" if shared else "") +
          "; n finished runs, std over them (ddof 1)")
    print(_table([*map(_short, keys), *stats], rows))


def _check_metric(metric: str, stored: list[Any]) -> None:
    """A metric the store's runs cannot give is refused before anything prints (not an empty table)."""
    from ..studies.summary import check_metric

    check_metric(metric, stored)


def _require(module: str, option: str) -> None:
    import importlib.util

    if importlib.util.find_spec(module) is None:
        raise ExtraMissingError(module, "data", option, more=(module,))


def _write_atomic(path: Path, writer: Any) -> None:
    """Write through a hidden temporary name in the same folder, renamed over ``path`` only when complete."""
    from ..report.files import atomic_path

    with atomic_path(path) as partial:
        writer(partial)


def _with_seconds(runs: list[dict[str, Any]], store: Any) -> list[dict[str, Any]]:
    """``results --json``: each arrival's times also in seconds (``t_sim_s``, ``t_theory_s``) where the study
    states one L0 and one C0 (a sweep's description); a batch of netlists or a study of scenes states none."""
    from ..core.physical import seconds

    try:
        described = json.loads(store.meta().get("description") or "{}")
    except ValueError:
        return runs
    given = [described.get(key) if isinstance(described, dict) else None for key in ("L0", "C0")]
    if not all(isinstance(v, (int, float)) and not isinstance(v, bool) and v > 0 for v in given):
        return runs
    L0, C0 = float(given[0]), float(given[1])  # type: ignore[arg-type]  # numbers: checked above
    for run in runs:
        for arrival in run.get("arrivals") or ():
            for key in ("t_sim", "t_theory"):
                if isinstance(arrival.get(key), (int, float)):
                    arrival[f"{key}_s"] = seconds(arrival[key], L0, C0)
    return runs


def _write_netcdf(parts: dict[str, Any], path: Path) -> list[Path]:
    """CF netCDF (:func:`lcchain.studies.netcdf.cf_datasets`) through whichever engine is there: netCDF4 or
    h5netcdf write one file, the waveforms in groups, compressed; scipy's netCDF3 has no groups, so each waveform
    group goes to a file of its own beside FILE (``FILE.stem.transient.nc``). Returns the files written."""
    import importlib.util

    needs = {"netCDF4": ("netCDF4",), "h5netcdf": ("h5netcdf", "h5py")}  # h5netcdf is nothing without h5py
    engine = next((e for e, modules in needs.items() if all(importlib.util.find_spec(m) for m in modules)), "scipy")
    groups = {name: part for name, part in parts.items() if name}
    root = parts[""]
    if engine == "scipy":
        written = [path]
        root = root.rename({name: _netcdf3_name(str(name)) for name in root.variables
                            if _netcdf3_name(str(name)) != name})
        _write_atomic(path, lambda partial: root.to_netcdf(partial, engine=engine))
        for name, part in groups.items():
            target = path.with_name(f"{path.stem}.{name}.nc")
            _write_atomic(target, lambda partial, part=part: part.to_netcdf(partial, engine=engine))
            written.append(target)
        return written

    def write(partial: Path) -> None:
        root.to_netcdf(partial, engine=engine, mode="w")
        for name, part in groups.items():
            encoding = {str(v): {"zlib": True, "complevel": 4} for v in part.variables
                        if part[v].dtype.kind in "fiu"}
            part.to_netcdf(partial, engine=engine, mode="a", group=name, encoding=encoding)

    _write_atomic(path, write)
    return [path]


def _netcdf3_name(name: str) -> str:
    """``i(l1)`` -> ``i_l1``: netCDF3 names hold letters, digits and ``_.@+-`` only."""
    import re

    return re.sub(r"[^A-Za-z0-9_.@+-]+", "_", name).strip("_") or "_"


#: The widest parameter cell of ``results``' table (longer values are cut in their middle).
_LONGEST_CELL = 24


def _print_runs(store: Any, stored: list[Any], name: str) -> None:
    """One row per task: its axes, status, and what it gave: errors against theory, or (no theory: a batch of
    netlists) its vectors, points and the simulator's time; a failure's reason."""
    from ..studies.summary import study_axes

    runs = [run.to_dict() for run in stored]

    def counted(rows: list[dict[str, Any]]) -> str:
        counts = {s: sum(r["status"] == s for r in rows) for s in ("ok", "failed", "timeout", "refused", "pending")}
        return ", ".join(f"{n} {s}" for s, n in counts.items() if n)

    combined = [run for run in runs if run["kind"] == "combined"]
    tasks = list({run["key"]: run for run in runs if run["kind"] != "combined"}.values())  # shared members once
    print(f"{name}: {len(tasks)} runs: {counted(tasks)}" +
          (f"; {len(combined)} extrapolated from them: {counted(combined)}" if combined else ""))
    axes = study_axes(stored)
    spectral = any(run.spectral for run in stored)
    theory = not spectral and any(run.judged for run in stored)
    columns = (["points", "modes seen", "omega error", "P error", "spacing"] if spectral
               else ["error", "predicted", "peak"] if theory else ["vectors", "points"])
    measured = list(dict.fromkeys(name for run in stored for name in run.measurements))
    columns += measured
    rows = []
    shortened = False

    def axis_cell(value: Any) -> str:  # a long parameter (a worst case's signs, a path) cut in its middle
        nonlocal shortened
        text = _number(value)
        if len(text) <= _LONGEST_CELL:
            return text
        shortened = True
        half = (_LONGEST_CELL - 1) // 2
        return f"{text[:half]}…{text[-half:]}"

    for run, shown in zip(stored, runs, strict=True):
        cells = [str(run.index), run.status, *(axis_cell(run.params.get(key)) for key in axes)]
        if spectral:
            cells += [_number(run.points), _number(shown.get("modes_seen")), _number(shown.get("max_rel_error_omega")),
                      _number(shown.get("max_abs_error_P")), _number(shown.get("spacing_spread"), ".4g")]
        elif theory:
            arrivals = shown.get("arrivals") or []
            cells += [_number(shown.get("max_abs_error")), _number(shown.get("predicted_error")),
                      _number(arrivals[0].get("peak_sim"), ".6f") if arrivals else ""]
        else:
            names = store.vector_names(run.key) if run.status == "ok" else None
            cells += [" ".join(names) if names else "", _number(run.points)]
        cells += [_number(run.measurements.get(name), ".6g") if run.measurements.get(name) is not None
                  else "-" if name in run.measurements else "" for name in measured]
        missing = [f"{name}: {why}" for name, why in run.measure_reasons.items()]
        reason = run.reason or "; ".join(missing)
        seconds = run.wall_s if run.kind != "combined" and run.status != "refused" else None  # nothing ran
        cells += [_number(seconds, ".3f"), (reason.splitlines() or [""])[0][:70]]
        rows.append(cells)
    print(_table(["#", "status", *map(_short, axes), *columns, "time (s)", "reason"], rows))
    if shortened:
        print(f"parameters longer than {_LONGEST_CELL} characters are cut in their middle here; --json and --csv "
              "give them whole")
    if spectral:
        print("points: frequencies of the AC sweep; omega error: max |omega_n - theory| / theory over the modes "
              "resolved at the ends; P error: max |P_n - theory| (absolute); spacing: (max - min) / mean of "
              "delta omega_n = omega_(n+1) - omega_n; time: the simulator's own wall time")
    elif theory:
        print("error: max |I_sim - I_theory| / I0 over the saved loops (predicted: the accuracy model's); peak: the "
              "first arrival's max I_N/I_1(0) in the simulator; time: the simulator's own wall time")
    else:
        print("points: time points, or an .ac netlist's frequencies; time: the simulator's own wall time of each "
              "run")
    if measured:
        print(f"{', '.join(measured)}: the netlists' .meas results as ngspice printed them (SI units); -: ngspice "
              "could not make it (the reason says why)")


def _price_results(store: Any, args: argparse.Namespace) -> None:
    """Refuse, before the runs are read, a ``results`` whose reading and exports exceed --max-memory or
    --max-time (:func:`lcchain.core.budget.export_estimate`): the waveforms of a 259-corner store ran to 2.5 GiB
    and a MemoryError."""
    from ..core.budget import export_estimate

    waveforms = bool(args.netcdf and args.waveforms)
    size = store.export_size(waveforms=waveforms)
    files = bool(args.netcdf or args.parquet or args.plot)
    estimate = export_estimate(runs=size.runs, cells=size.cells if files else 0, metrics=size.metrics,
                               stored=size.stored, dense=float(size.cells) * size.longest * size.per_point,
                               files=files, text=bool(args.json or args.csv))
    option, value = ("--netcdf", args.netcdf) if args.netcdf else ("STORE", args.store)
    estimate.check(budget_from_args(args), option, value,
                   "--netcdf without --waveforms, or a larger --max-memory" if waveforms else "")


def cmd_results(args: argparse.Namespace) -> int:
    from ..spice.measure import valid_measure_name
    from ..studies.store import Store

    outputs = Outputs(inputs={"STORE": args.store})
    outputs.check("--plot", args.plot, FIGURE_FORMATS)
    outputs.check("--netcdf", args.netcdf, ("nc",))
    outputs.check("--parquet", args.parquet, ("parquet",))
    if args.waveforms and not args.netcdf:
        raise ParameterError("--waveforms", True, "only with --netcdf FILE (the waveforms go into that file)")
    if args.metric not in STUDY_METRICS and not valid_measure_name(args.metric):  # no store needed to see it
        raise ParameterError("--metric", args.metric, f"one of {' | '.join(STUDY_METRICS)}, or the name of a "
                             ".meas of the store's netlists")
    if args.parquet:
        _require("pyarrow", "--parquet")
    with Store(args.store, "read", option="STORE") as store:  # read-only: nothing is created or changed
        _price_results(store, args)
        stored = store.runs()
        if args.summary or args.plot:
            _check_metric(args.metric, stored)  # before any file is written
        if args.plot and args.metric not in STUDY_METRICS:
            raise ParameterError("--metric", args.metric, f"one of {', '.join(STUDY_METRICS)} with --plot (a "
                                 "measurement's distribution is printed by --summary --metric NAME)")
        beside: list[str] = []  # scipy's netCDF3 has no groups: the waveforms' own files
        if args.netcdf:
            from ..studies.netcdf import cf_datasets

            parts = cf_datasets(store, waveforms=args.waveforms)
            outputs.write("--netcdf", lambda path: beside.extend(str(p) for p in _write_netcdf(parts, path)[1:]))
        if args.parquet:
            frame = store.to_dataframe()
            outputs.write("--parquet", lambda path: _write_atomic(path, frame.to_parquet))
        if args.plot:
            from ..report.files import save_figure
            from ..report.studies import study_figure

            figure = study_figure(store, args.metric)
            outputs.write("--plot", lambda path: save_figure(figure, path, dpi=150))
        runs = [run.to_dict() for run in stored]
        if args.summary:
            _print_summary(stored, args)
        elif args.json:
            emit_json(_with_seconds(runs, store))
        elif args.csv:
            rows = [_flat(run) for run in runs]
            columns = list(dict.fromkeys(key for row in rows for key in row))
            text = io.StringIO()
            writer = csv.DictWriter(text, fieldnames=columns, lineterminator="\n")
            writer.writeheader()
            writer.writerows(rows)
            sys.stdout.write(text.getvalue())
        elif args.plot or args.netcdf or args.parquet:  # the files are what was asked for: not every run
            written = [path for option, path in (("--plot", args.plot), ("--netcdf", args.netcdf),
                                                  ("--parquet", args.parquet)) if path and option not in outputs.failed]
            written += beside
            if written:
                combined = sum(run.kind == "combined" for run in stored)
                tasks = len({run.key for run in stored if run.kind != "combined"})
                print(f"{args.store}: {tasks} runs" + (f" and {combined} extrapolated from them" if combined else "")
                      + f" written to {', '.join(written)}")
        else:
            _print_runs(store, stored, args.store)
    return EXIT_FAILED if outputs.failed else EXIT_OK
