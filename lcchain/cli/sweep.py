"""``lcchain sweep``: many runs: the product of comma-list axes, or a scene or a netlist varied, or a scene's
worst case (:func:`lcchain.app.sweep.sweep`)."""

from __future__ import annotations

import argparse
from collections.abc import Callable, Collection, Iterator

from ..app.options import BACKEND_CHOICES, CASE_CHOICES, engine_names
from ..core.analyses import ANALYSIS_KINDS_DATA
from ..core.types import (
    ANALYSIS_KINDS,
    ARRIVAL_METRICS,
    DEFAULT_C0,
    DEFAULT_L0,
    EXCITATIONS,
    WORST_CASE_METHODS,
)
from .common import Parser, Subcommands, add_parts_arguments, budget_from_args, int_list, list_entries, number_type
from .progress import counter
from .studies import add_study_arguments, show_study, study_hooks, study_options

__all__ = ["add_parser", "add_sweep_arguments", "cmd_sweep"]


def add_parser(sub: Subcommands, budget: list[Parser]) -> None:
    p = sub.add_parser("sweep", parents=budget, help="many runs: the product of comma-list axes, or a scene or a "
                       "netlist varied")
    add_sweep_arguments(p)
    p.set_defaults(func=cmd_sweep)


def _floats(option: str) -> Callable[[str], list[float]]:
    def parse(text: str) -> list[float]:
        entries = list_entries(option, text, "numbers")
        try:
            return [float(v) for v in entries]
        except ValueError:
            raise argparse.ArgumentTypeError(f"{option} = {text!r} is not allowed: expected numbers separated by "
                                             "commas") from None

    return parse


def _words(option: str, allowed: Collection[str]) -> Callable[[str], list[str]]:
    def parse(text: str) -> list[str]:
        values = list_entries(option, text, " | ".join(allowed))
        bad = [v for v in values if v not in allowed]
        if bad:
            raise argparse.ArgumentTypeError(f"{option} = {bad[0]!r} is not allowed: expected a comma list of "
                                             f"{' | '.join(allowed)}")
        return values

    return parse


class _EachOf:
    """A comma list option's choices: ``--help`` lists the names (read only then), and a list (what its type
    returned, each entry checked there) is among them when each entry is."""

    def __init__(self, names: Collection[str]) -> None:
        self._names = names

    def __contains__(self, value: object) -> bool:
        return isinstance(value, list) and all(entry in self._names for entry in value)

    def __iter__(self) -> Iterator[str]:
        return iter(self._names)


def _worst_case_method(text: str) -> str:
    if text not in WORST_CASE_METHODS:
        where = " (the scene goes before it: sweep SCENE.toml --worst-case)" if text.endswith(".toml") else ""
        raise argparse.ArgumentTypeError(f"--worst-case = {text!r} is not allowed: expected "
                                         f"{' | '.join(WORST_CASE_METHODS)} or nothing (search){where}")
    return text


def add_sweep_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("scene", nargs="?", metavar="SCENE.toml", help="vary a scene instead of cases (with --vary)")
    p.add_argument("--netlist", metavar="FILE.cir",
                   help="vary a netlist lcchain did not write instead (with --vary NAME=...): each variant checked, "
                        "priced and run as lcchain batch runs a netlist")
    p.add_argument("--case", type=_words("--case", CASE_CHOICES), choices=_EachOf(CASE_CHOICES), metavar="CASE",
                   help="chains, comma separated: an axis (%(choices)s)")
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
    p.add_argument("--L0", type=number_type("--L0"),
                   help=f"bulk inductance, henry (default {DEFAULT_L0:g})")
    p.add_argument("--C0", type=number_type("--C0"),
                   help=f"bulk capacitance, farad (default {DEFAULT_C0:g})")
    p.add_argument("--backend", choices=BACKEND_CHOICES, default="batch", metavar="BACKEND",
                   help="how ngspice runs: %(choices)s (default %(default)s)")
    p.add_argument("--engine", choices=engine_names(),
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


def cmd_sweep(args: argparse.Namespace) -> int:
    from ..app.sweep import SweepRequest, sweep

    request = SweepRequest(scene=args.scene, netlist=args.netlist, case=args.case, N=args.N, dt=args.dt,
                           accuracy=args.accuracy, extrapolate=args.extrapolate, transits=args.transits,
                           excitation=args.excitation, analysis=args.analysis, points=args.points, L0=args.L0,
                           C0=args.C0, backend=args.backend, engine=args.engine, vary=args.vary,
                           tolerance=args.tolerance, series=args.series, samples=args.samples, seed=args.seed,
                           worst_case=args.worst_case, components=args.components, metric=args.metric,
                           study=study_options(args), budget=budget_from_args(args),
                           variants_progress=counter("variants"))
    return show_study(args, sweep(request, study_hooks(args)))
