
"""``lcchain spectrum``: the ladder's normal frequencies and mode weights from an AC analysis in ngspice (or
gnucap), beside theory (:func:`lcchain.app.spectrum.spectrum`)."""

from __future__ import annotations

import argparse
import sys
from typing import TYPE_CHECKING

from ..app.options import DEFAULT_ENGINE, engine_names
from ..core.json import LooseJSONObject
from .chains import add_circuit_arguments, add_effect_arguments, chain_options, effects_from_args
from .common import EXIT_FAILED, EXIT_OK, Parser, Subcommands, budget_from_args, emit_json, number_type, print_notes
from .progress import fraction
from .run import error_text
from .simulate import print_units

if TYPE_CHECKING:
    from ..app.spectrum import ModeReport

__all__ = ["add_parser", "cmd_spectrum"]


def add_parser(sub: Subcommands, budget: list[Parser]) -> None:
    p = sub.add_parser("spectrum", parents=budget, help="the ladder's normal frequencies and mode weights from an AC "
                       "analysis in ngspice (or gnucap), beside theory")
    add_circuit_arguments(p)
    p.add_argument("--engine", choices=engine_names(), default=DEFAULT_ENGINE,
                   help=f"the simulator that runs the AC analysis (default {DEFAULT_ENGINE})")
    p.add_argument("--points", type=int, default=None, metavar="P",
                   help="frequencies of the AC sweep, in even segments placed where the poles are dense (default: "
                        "twice the fewest that separate every pole)")
    add_effect_arguments(p)  # --Q (each mode's fitted Q_n beside omega_n Q), the real parts, a plugin's
    p.add_argument("--plot", metavar="FILE", help="Fig. Pk20-100: |P_n| and the spacing against omega_n, the "
                   "circuit's modes on top of theory")
    p.add_argument("--touchstone", metavar="FILE.s2p",
                   help="also the ladder as a two-port (port 1: a break in loop 1 where the AC source sits; port 2: "
                        "its mirror image in loop N), its S-parameters from two AC analyses (one per end) as a "
                        "Touchstone v1 file, --points evenly spaced frequencies (default 401) up to 5 %% above the "
                        "highest normal frequency")
    p.add_argument("--z0", type=number_type("--z0"), default=None, metavar="OHMS",
                   help="--touchstone's reference impedance on both ports, ohms (default 50)")
    p.add_argument("--shapes", action="store_true",
                   help="also every mode with its shape, from a second AC run (ngspice) that drives every loop and "
                        "saves every loop's current, against the chain's exact eigensolution")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=cmd_spectrum)


def cmd_spectrum(args: argparse.Namespace) -> int:
    from ..app.spectrum import SpectrumRequest, spectrum, write_outputs

    result = spectrum(SpectrumRequest(chain_options(args), args.L0, args.C0, engine=args.engine, points=args.points,
                                      Q=args.Q, effects=effects_from_args(args, but=("--Q",)), plot=args.plot,
                                      touchstone=args.touchstone, z0=args.z0, shapes=args.shapes,
                                      budget=budget_from_args(args),
                                      progress=fraction))
    chain, data = result.chain, result.data
    if args.json:
        emit_json(data)
    else:
        coupled = f", coils coupled k = {chain.coupling:g}" if chain.coupled else ""
        lossy = f", losses Q = {args.Q:g}" if args.Q is not None else ""
        timings = data["timings"]
        print(f"{chain.name} chain, N = {chain.N}{coupled}{lossy}: {data['engine']} {data['engine_version']} AC "
              f"analysis, {data['points']} frequencies up to {data['omega_max']:.4g} in {data['segments']} segments, "
              f"{timings['ngspice_s']:.3f} s, fit {timings['fit_s']:.3f} s")
        print_units(args.L0, args.C0, chain.coupling)
        print(f"{'n':>5} {'omega (circuit)':>19} {'omega (theory)':>19} {'rel. error':>10} {'ref. bound':>10} "
              f"{'P_n (circuit)':>14} {'P_n (theory)':>14} {'abs. error':>10} {'spacing':>10} {'f (circuit), Hz':>16}")
        previous = None
        for mode in data["modes"]:
            omega, P = mode["omega"], mode["P"]
            spacing = "" if previous is None or omega is None else f"{omega - previous:10.6f}"
            error = "" if omega is None else f"{mode['omega_error']:10.2e}"  # against the reference beyond float64
            bound = "" if mode["omega_bound"] is None else f"{mode['omega_bound']:10.1e}"
            shown = ("merged" if mode["merged"] else "unseen") if omega is None else f"{omega:19.15f}"
            hz = "" if mode["omega_Hz"] is None else f"{mode['omega_Hz']:16.9e}"
            P_theory = mode["P_theory"]
            theory = "below precision" if P_theory is None else f"{P_theory:14.6e}"
            P_error = "" if P_theory is None or mode["merged"] else f"{abs((P or 0.0) - P_theory):10.2e}"
            print(f"{mode['n']:>5} {shown:>19} {mode['omega_theory']:19.15f} {error:>10} {bound:>10} "
                  f"{'' if P is None else f'{P:14.6e}':>14} {theory:>14} "
                  f"{P_error:>10} {spacing:>10} {hz:>16}")
            previous = omega if omega is not None else previous
        weak = sum(1 for m in data["modes"] if not m["resolved"] and not m["merged"])
        if any(m["resolved"] for m in data["modes"]):
            print(f"max relative error of omega_n = {error_text(data['max_rel_error_omega'])}{_bound(data, 'omega')} "
                  f"(modes with |P_n| >= 1e-6{f'; {weak} weaker modes are placed less well' if weak else ''}"
                  f"{'; merged modes not compared' if data['merged'] else ''}), max absolute error of P_n = "
                  f"{data['max_abs_error_P']:.3e}{_bound(data, 'P')} ({data['seen']} of {len(data['modes'])} modes "
                  "seen at the ends)")  # the circuit's modes: more than N with parasitics
        else:
            print("no mode is resolved: omega_n, P_n and Q_n are not compared")
        if data["Q"] is not None or data["max_rel_error_Q"] is not None:  # the chain's losses, a circuit's resistors
            _print_quality(data)
        if data["merged"]:
            print(f"merged by the losses (half-power bands overlap, said and not compared): {result.merged}")
        if data["max_rel_error_Y11"] is not None:
            print(f"Y_11 against the exact lossy admittance over the sweep: max relative error "
                  f"{data['max_rel_error_Y11']:.3e}")
    if result.report.modes is not None and not args.json:
        _print_survey(result.report.modes)
    two_port = write_outputs(result)
    print_notes(result.outputs.take_notes())
    if two_port is not None and not args.json:
        print(f"two-port: {two_port.frequency.size} frequencies from {two_port.frequency[0]:.6g} to "
              f"{two_port.frequency[-1]:.6g} Hz in z0 = {two_port.z0:g} ohm, max |S - exact| = "
              f"{two_port.error:.3e}, reciprocity |Y12 - Y21| / max |Y| = {two_port.reciprocity:.1e}")
    report = result.report
    if report.failure:  # a comparison that failed is a failed check
        print(f"lcchain: {report.failure}", file=sys.stderr)
        return EXIT_FAILED
    if report.modes is not None and report.modes.failure:  # merged modes are said, as the loop-1 fit's: no failure
        print(f"lcchain: {report.modes.failure}", file=sys.stderr)
        return EXIT_FAILED
    return EXIT_FAILED if result.outputs.failed else EXIT_OK


def _print_survey(modes: ModeReport) -> None:
    """``spectrum --shapes``: every mode from the survey of every loop, beside the exact eigensolution."""
    for name, value in modes.rows():
        print(f"{name}: {value:.3e}" if isinstance(value, float) else f"{name}: {value}")
    lossy = modes.losses is not None
    print(f"{'n':>5} {'omega (survey)':>19} {'rel. error':>10} {'shape error':>11} {'P_n (shape)':>14} "
          f"{'P_n (theory)':>14}" + (f" {'Q_n':>12} {'rel. error':>10}" if lossy else ""))
    merged = modes.merged_modes
    for n in range(modes.N):
        if merged[n]:  # said, not measured: theory's P_n beside no value and no error
            print(f"{n + 1:>5} {'merged':>19} {'':>10} {'':>11} {'':>14} {modes.P_theory[n]:14.6e}")
            continue
        quality = f" {modes.Q[n]:12.6g} {modes.Q_error[n]:10.2e}" if lossy else ""
        print(f"{n + 1:>5} {modes.omega[n]:19.15f} {modes.omega_error[n]:10.2e} {modes.shape_error[n]:11.2e} "
              f"{modes.P[n]:14.6e} {modes.P_theory[n]:14.6e}{quality}")


def _bound(data: LooseJSONObject, name: str) -> str:
    """The reference's own bound on a metric, as printed beside its error ('' where it states none)."""
    bound = data.get(f"reference_bound_{name}")
    return "" if bound is None else f" (reference bound {bound:.1e})"


def _print_quality(data: LooseJSONObject) -> None:
    """``lcchain spectrum --Q``: each seen mode's Q_n beside omega_n Q, and the fitted response's error."""
    if not any(mode["resolved"] and mode["omega_theory"] > 0 for mode in data["modes"]):  # no Q_n to compare (a
        return  # circuit's zero mode alone: its other modes merged)
    print(f"{'n':>5} {'Q_n (circuit)':>19} {'Q_n (theory)':>19} {'rel. error':>10}")
    for mode in data["modes"]:
        if mode["Q"] is not None and mode["Q_theory"] is not None:
            error = abs(mode["Q"] - mode["Q_theory"]) / (mode["Q_theory"] or 1.0)
            print(f"{mode['n']:>5} {mode['Q']:19.12g} {mode['Q_theory']:19.12g} {error:10.2e}")
    response = data["max_abs_error_response"]
    print(f"max relative error of Q_n = {error_text(data['max_rel_error_Q'])}{_bound(data, 'Q')}, of the poles = "
          f"{error_text(data['max_rel_error_pole'])}"
          + ("" if response is None else f"; fitted alpha_N(t) - exact lossy response: max {response:.3e}"))
