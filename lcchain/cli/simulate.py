"""``lcchain simulate``: run the ladder in ngspice (or gnucap) and compare with alpha_N(t)
(:func:`lcchain.app.simulate.simulate`)."""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

from ..app.options import BACKEND_CHOICES, DEFAULT_ENGINE, Chain, engine_names
from ..core.json import LooseJSONObject
from ..core.physical import units_sentence
from ..core.types import METHODS
from .chains import add_chain_arguments, add_effect_arguments, chain_options, effects_from_args, engine_list
from .common import (
    EXIT_FAILED,
    EXIT_OK,
    Parser,
    Subcommands,
    budget_from_args,
    emit_json,
    number_type,
    plural,
    print_notes,
    summary_stream,
)
from .progress import fraction

if TYPE_CHECKING:
    from ..app.simulate import EnginesComparison

__all__ = ["add_parser", "cmd_simulate", "print_arrivals", "print_units"]


def add_parser(sub: Subcommands, budget: list[Parser]) -> None:
    p = sub.add_parser("simulate", parents=budget, help="run the ladder in ngspice (or gnucap) and compare with "
                       "alpha_N(t)")
    add_chain_arguments(p)
    p.add_argument("--backend", choices=BACKEND_CHOICES, default="batch", metavar="BACKEND",
                   help="how ngspice runs: %(choices)s (default %(default)s)")
    p.add_argument("--engine", type=engine_list, default=(DEFAULT_ENGINE,), metavar="ENGINE[,ENGINE]",
                   help=f"the circuit simulator: {' or '.join(engine_names())} (default {DEFAULT_ENGINE}); gnucap "
                        "runs one fixed-step run (no --extrapolate); several, comma-separated, run the same netlist in "
                        "each and report their difference beside each one's error against theory")
    p.add_argument("--method", choices=METHODS, default="trap")
    p.add_argument("--accuracy", type=number_type("--accuracy"), metavar="EPS",
                   help="wanted max |simulation - theory|: lcchain picks the largest dt that meets it "
                        "(instead of --dt); a run that misses it exits 1")
    p.add_argument("--extrapolate", type=int, choices=(1, 2, 3), metavar="{1,2,3}",
                   help="combine this many runs at dt, dt/2, dt/4 (Richardson: the dt^2 and dt^4 errors cancel); "
                        "with --accuracy and without this option, lcchain picks the cheapest of 1, 2 and 3")
    p.add_argument("--plot", metavar="FILE", help="figure (.png, .svg, .pdf): theory and simulation, residual below")
    p.add_argument("--netlist-out", metavar="FILE", help="keep the netlist (written before ngspice starts)")
    p.add_argument("--waveform-out", metavar="FILE", help="CSV t,first,last (dimensionless)")
    p.add_argument("--json", action="store_true")
    add_effect_arguments(p)
    p.set_defaults(func=cmd_simulate)


def print_arrivals(arrivals: list[LooseJSONObject]) -> None:
    physical = all("t_sim_s" in a for a in arrivals)
    extra = f" {'t theory (s)':>13} {'t sim (s)':>13}" if physical else ""
    print(f"{'arrival':>7} {'end':>5} {'t theory':>12} {'t sim':>12} {'peak theory':>12} {'peak sim':>12}{extra}")
    for a in arrivals:
        seconds = f" {a['t_theory_s']:13.6e} {a['t_sim_s']:13.6e}" if physical else ""
        print(f"{a['index']:>7} {a['end']:>5} {a['t_theory']:12.4f} {a['t_sim']:12.4f} "
              f"{a['peak_theory']:12.6f} {a['peak_sim']:12.6f}{seconds}")


def print_units(L0: float, C0: float, coupling: float = 0.0) -> None:
    print(f"units: {units_sentence(L0, C0, coupling)}")


def _print_extrapolation(x: LooseJSONObject) -> None:
    plan = x["plan"]
    why = ""
    if plan is not None and len(plan["considered"]) > 1:
        options = ", ".join(f"{plural(o['runs'], 'run')} ~{o['estimated_seconds']:.2g} s"
                            for o in plan["considered"])
        why = f", the cheapest predicted to meet the accuracy ({options})"
    print(f"extrapolated from {x['runs']} runs{why}:")
    print(f"{'run':>5} {'dt':>10} {'weight':>9} {'points':>9} {'wall s':>8} {'max |run - theory|':>19}")
    for i, (member, weight) in enumerate(zip(x["members"], x["weights"], strict=True), 1):
        print(f"{i:>5} {member['dt']:>10.4g} {weight:>9.4g} {member['points']:>9} {member['wall_s']:>8.3f} "
              f"{member['max_abs_error']:>19.3e}")
    print(f"combined on run 1's time points (degree-7 splines through the finer runs; interpolation error "
          f"{x['interpolation_error']:.1e})")


def _print_effects(cost: LooseJSONObject) -> None:
    """What the effects cost the pulse: the circuit's exact first arrival against the ideal chain's."""
    loss = cost["energy_loss"]
    energy = "" if loss is None else (
        f", energy {cost['energy_circuit']:.4f} against {cost['energy_ideal']:.4f} "
        f"(the effects {'take' if loss >= 0 else 'add'} {100 * abs(loss):.3g} % of it)")
    delay = cost["delay"]
    print(f"what the effects cost the pulse (exact circuit against the ideal chain, no simulator): first arrival "
          f"peak {cost['peak_circuit']:.4f} against {cost['peak_ideal']:.4f}{energy}, "
          f"arriving {abs(delay):.3g} sqrt(L0 C0) {'later' if delay >= 0 else 'earlier'}")


def _print_simulation(args: argparse.Namespace, chain: Chain, data: LooseJSONObject) -> None:
    if args.json:
        emit_json(data)
    else:
        coupled = f", coils coupled k = {chain.coupling:g}" if chain.coupled else ""
        runs = data["extrapolation"]["runs"]
        simulated = (f"{data['points']} points in {data['timings']['simulator_wall_s']:.3f} s of wall time "
                     f"({data['wall_s']:.3f} s summed over its {runs} runs)" if runs > 1
                     else f"{data['points']} points in {data['wall_s']:.3f} s")
        print(f"{chain.name} chain, N = {chain.N}{coupled}: {data['engine']} {data['engine_version']} "
              f"({data['backend']}), {simulated}")
        print_units(args.L0, args.C0, chain.coupling)
        extrapolation = data["extrapolation"]
        if extrapolation["runs"] > 1:
            _print_extrapolation(extrapolation)
        elif extrapolation["reason"]:
            print(f"one run, not extrapolated: {extrapolation['reason']}")
        step = "dt = " + ", ".join(f"{h:.4g}" for h in extrapolation["dt"])
        predicted = "no prediction" if data["predicted_error"] is None else \
            f"predicted {data['predicted_error']:.3e}"
        against = "the circuit's exact theory" if "effects" in data else "theory"
        print(f"max |simulation - {against}| = {data['max_abs_error']:.3e} ({step}, {predicted})")
        if data["integration_error"] is not None:
            print(f"  integration error (simulation - trapezoidal model) = {data['integration_error']:.3e}, "
                  f"physics error (model - exact theory) = {data['physics_error']:.3e}")
        print_arrivals(data["arrivals"])
        if "effects" in data:
            _print_effects(data["effects"])


def cmd_simulate(args: argparse.Namespace) -> int:
    from ..app.simulate import EnginesComparison, SimulateRequest, simulate, write_outputs

    request = SimulateRequest(chain_options(args), args.L0, args.C0, excitation=args.excitation, title=args.title,
                              transits=args.transits, dt=args.dt, accuracy=args.accuracy,
                              extrapolate=args.extrapolate, engines=tuple(args.engine), backend=args.backend,
                              method=args.method, effects=effects_from_args(args), plot=args.plot,
                              netlist_out=args.netlist_out, waveform_out=args.waveform_out, json=args.json,
                              budget=budget_from_args(args), progress=fraction)
    result = simulate(request)
    if isinstance(result, EnginesComparison):
        return _print_engines(args, result)
    print_notes(f"warning: {warning}" for warning in result.warnings)
    print_notes(result.outputs.take_notes())  # said while it ran: a run's netlist not kept
    with summary_stream(result.outputs):
        _print_simulation(args, result.chain, result.data)
    failed = write_outputs(result)
    print_notes(result.outputs.take_notes())
    return EXIT_FAILED if failed else EXIT_OK


def _print_engines(args: argparse.Namespace, result: EnginesComparison) -> int:
    """``simulate --engine A,B``: each engine against theory, and their difference."""
    chain, reports, data, differences = result.chain, result.reports, result.data, result.differences
    print_notes(f"warning: {warning}" for warning in result.warnings)
    first = reports[0]
    if args.json:
        emit_json(data)
        return EXIT_OK
    coupled = f", coils coupled k = {chain.coupling:g}" if chain.coupled else ""
    print(f"{chain.name} chain, N = {chain.N}{coupled}, dt = {first.options.dt:.4g}: the same netlist in "
          f"{len(reports)} engines")
    print(f"{'engine':<10} {'version':<12} {'points':>8} {'wall s':>8} {'max |sim - theory|':>19} "
          f"{'predicted':>10}")
    for report in reports:
        record = report.to_dict()
        predicted = record["predicted_error"]  # none for a lossy chain, or a displaced one with real parts
        print(f"{record['engine']:<10} {record['engine_version']:<12} {record['points']:>8} "
              f"{record['wall_s']:>8.3f} {record['max_abs_error']:>19.3e} "
              f"{'none' if predicted is None else format(predicted, '.3e'):>10}")
    for pair, value in differences.items():
        print(f"max |{pair}| = {value:.3e} (loops 1 and N; the second engine's residual interpolated onto the "
              "first's time points)")
    return EXIT_OK
