"""The commands of ``lcchain``: each checks its inputs, outputs and budget first, works, prints, then writes.

A command never writes a file before its work is done (except the netlist of
a simulation, kept before ngspice starts so that a failed run still leaves
it), prints its results before writing the files it was asked for, and
writes each file atomically.
"""

from __future__ import annotations

import argparse
import sys
import warnings
from fractions import Fraction
from pathlib import Path
from typing import Any

from ..core import __version__
from ..core.budget import design_estimate
from ..core.errors import ParameterError
from ..core.limits import MAX_DESIGN_N, MIN_N
from ..report.files import FIGURE_FORMATS, check_output_folder
from .common import (
    EXIT_FAILED,
    EXIT_MISSING,
    EXIT_OK,
    Outputs,
    budget_from_args,
    chain_from_args,
    check_perfect,
    echoed_command,
    effects_from_args,
    emit_json,
)
from .progress import Progress, counter, fraction, study_counter

__all__ = ["cmd_design", "cmd_table", "cmd_asymptotic", "cmd_netlist", "cmd_reference_netlists", "cmd_simulate",
           "cmd_run", "cmd_bench_accuracy", "cmd_doctor", "DEFAULT_DT"]

#: Step when neither --dt nor --accuracy is given, units of sqrt(L0*C0).
DEFAULT_DT = 0.05

_TABLE_COLUMNS = {
    "one-mass": [("N", "N", "{:>6d}"), ("x*", "x", "{:.4f}"), ("delta*", "delta", "{:.4f}"), ("s*", "s", "{:6.2f}"),
                 ("m1*", "m1", "{:7.3f}"), ("Delta*", "Delta", "{:#.4g}"), ("delta*(1)", "delta_uniform", "{:.4f}")],
    "two-mass": [("N", "N", "{:>6d}"), ("r*", "r", "{:.4f}"), ("w*", "w", "{:.4f}"), ("delta*", "delta", "{:.5f}"),
                 ("s*", "s", "{:6.2f}"), ("m1*", "m1", "{:7.3f}"), ("m2*", "m2", "{:.4f}"), ("K12*", "K12", "{:.4f}")],
}


def _format_table(case: str, rows: list[dict[str, Any]]) -> str:
    columns = _TABLE_COLUMNS[case]
    cells = [[fmt.format(row[key]) for _, key, fmt in columns] for row in rows]
    widths = [max(len(head), *(len(c[i]) for c in cells)) for i, (head, _, _) in enumerate(columns)]
    title = "Table I: one optimised mass" if case == "one-mass" else "Table II: two optimised masses and their spring"
    lines = [title, "  ".join(h.rjust(w) for (h, _, _), w in zip(columns, widths, strict=True))]
    lines.append("-" * len(lines[-1]))
    lines += ["  ".join(c.rjust(w) for c, w in zip(row, widths, strict=True)) for row in cells]
    return "\n".join(lines)


def _check_design_sizes(args: argparse.Namespace, sizes: list[int]) -> None:
    """Refuse designs out of range or beyond the budget, before any of them starts."""
    for N in sizes:
        if not MIN_N <= N <= MAX_DESIGN_N:
            raise ParameterError("--N", N, f"an integer from {MIN_N} to {MAX_DESIGN_N}")
    budget = budget_from_args(args)
    total = [design_estimate(args.case, N) for N in sizes]
    seconds = sum(e.seconds for e in total)
    memory = max(e.memory for e in total)
    from ..core.budget import Estimate

    what = total[0].what if len(total) == 1 else f"{len(total)} {args.case} designs up to N = {max(sizes)}"
    Estimate(what, memory, seconds).check(budget, "--N", ",".join(map(str, sizes)) if len(sizes) > 1 else sizes[0])


def _format_perfect(design: Any) -> str:
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
    from ..theory.design import optimal_design

    if args.case == "perfect":
        from ..theory.perfect import perfect_design

        check_perfect(args.N, args.walls, budget_from_args(args))
        perfect = perfect_design(args.N, args.walls)
        if args.json:
            emit_json(perfect.to_dict())
        else:
            print(_format_perfect(perfect))
        return EXIT_OK
    if args.walls:
        raise ParameterError("--walls", args.walls, "0 unless --case perfect (J >= 1: a perfect cradle tied to walls)")
    _check_design_sizes(args, [args.N])
    bar = fraction(f"{args.case} design, N = {args.N}") if args.N >= 10_000 else None
    design = optimal_design(args.case, args.N, progress=bar)
    if bar is not None:
        bar(1.0)
    if args.json:
        emit_json(design.to_dict())
    else:
        print(_format_table(args.case, [design.to_dict()]))
    return EXIT_OK


def cmd_table(args: argparse.Namespace) -> int:
    from ..theory.design import optimal_design

    _check_design_sizes(args, args.N)
    rows = []
    progress = Progress(f"{args.case} table")
    for i, N in enumerate(args.N):
        progress.update(i, len(args.N), unit="rows")
        rows.append(optimal_design(args.case, N).to_dict())
    progress.update(len(args.N), len(args.N), unit="rows")
    if args.json:
        emit_json(rows)
    elif args.csv:
        keys = list(rows[0])
        print(",".join(keys))
        for row in rows:
            print(",".join(repr(row[k]) if isinstance(row[k], float) else str(row[k]) for k in keys))
    else:
        print(_format_table(args.case, rows))
    return EXIT_OK


def cmd_asymptotic(args: argparse.Namespace) -> int:
    from ..theory.asymptotic import EXPONENTS, asymptotic_optimum

    optimum = asymptotic_optimum(args.case)
    if args.json:
        emit_json(optimum.to_dict())
        return EXIT_OK
    print(f"{args.case}: alpha* = {optimum.alpha:.6f}  delta* = {optimum.delta:.6f}  "
          f"sigma* = {optimum.sigma:.5f}  tau* = {optimum.tau:.5f}")
    exponents = EXPONENTS[args.case]
    for key, value in optimum.to_dict()["coefficients"].items():
        law = {"y": "sqrt(2) - {c} N^{p}", "m2": "1/2 + {c} N^{p}"}.get(key, "{c} N^{p}")
        power = Fraction(exponents[key]).limit_denominator(6)
        print(f"  {key:>6} ~ " + law.format(c=f"{value:.5g}", p=f"({power})"))
    return EXIT_OK


def cmd_netlist(args: argparse.Namespace) -> int:
    from ..circuit.netlist import make_netlist

    outputs = Outputs(inputs={"--chain": args.chain})
    outputs.check("--output", args.output)
    chain = chain_from_args(args)
    command = echoed_command("lcchain netlist", args.argv_echo)
    dt = args.dt if args.dt is not None else DEFAULT_DT
    effects = effects_from_args(args)
    for effect in effects:  # walls and the like change the chain itself; the others add elements
        chain = effect.realise(chain, args.L0, args.C0)
    text, _, _ = make_netlist(chain, dt=dt, transits=args.transits, excitation=args.excitation,
                              L0=args.L0, C0=args.C0, title=args.title, comments=(f"made by: {command}",),
                              effects=effects)
    if args.output:
        outputs.text("--output", text)  # "-" too: stdout
    else:
        sys.stdout.write(text)
    return EXIT_FAILED if outputs.failed else EXIT_OK


def cmd_examples(args: argparse.Namespace) -> int:
    """List the example scenes that ship with lcchain, or write one here (or to -o FILE) to run or edit."""
    from ..scenes.bundled import example_names, example_text, example_title

    if args.name is None:
        names = example_names()
        width = max(len(name) for name in names)
        for name in names:
            print(f"{name:<{width}}  {example_title(name)}")
        print("\nlcchain examples NAME writes NAME.toml here (-o FILE: elsewhere); then: lcchain run NAME.toml")
        return EXIT_OK
    text = example_text(args.name)
    target = args.output or f"{args.name}.toml"
    if args.output is None and (Path(target).exists() or Path(target).is_symlink()):
        if _holds(Path(target), text):  # the same example written before: nothing to do
            print(f"{target} is here already, unchanged: lcchain run {target}")
            return EXIT_OK
        raise ParameterError("NAME", args.name, f"an example whose file is not here yet: {target} exists (your own "
                             "copy?); write it elsewhere with -o FILE")
    outputs = Outputs()
    outputs.check("-o", target)
    outputs.text("-o", text)
    if not outputs.failed and outputs.to_stdout is None:
        print(f"wrote {target}" + (f": lcchain run {target}" if Path(target).is_file() else ""))
    return EXIT_FAILED if outputs.failed else EXIT_OK


def _holds(path: Path, text: str) -> bool:
    """Whether a regular file holds exactly this text (a special file or a link is never read)."""
    try:
        return not path.is_symlink() and path.is_file() and path.stat().st_size == len(text.encode()) \
            and path.read_text(encoding="utf-8") == text
    except (OSError, UnicodeDecodeError):
        return False


def cmd_reference_netlists(args: argparse.Namespace) -> int:
    from ..circuit.reference import REFERENCE_SET, reference_netlist

    folder = check_output_folder("--out", args.out, parents=True)
    outputs = Outputs()
    for reference in REFERENCE_SET:
        outputs.check(reference.name, str(folder / reference.name), make_folder=True)
    folder.mkdir(parents=True, exist_ok=True)  # only now: every check has passed
    for reference in REFERENCE_SET:
        outputs.text(reference.name, reference_netlist(reference))
        print(folder / reference.name)
    return EXIT_FAILED if outputs.failed else EXIT_OK


def _print_arrivals(arrivals: list[dict[str, Any]]) -> None:
    physical = all("t_sim_s" in a for a in arrivals)
    extra = f" {'t theory (s)':>13} {'t sim (s)':>13}" if physical else ""
    print(f"{'arrival':>7} {'end':>5} {'t theory':>12} {'t sim':>12} {'peak theory':>12} {'peak sim':>12}{extra}")
    for a in arrivals:
        seconds = f" {a['t_theory_s']:13.6e} {a['t_sim_s']:13.6e}" if physical else ""
        print(f"{a['index']:>7} {a['end']:>5} {a['t_theory']:12.4f} {a['t_sim']:12.4f} "
              f"{a['peak_theory']:12.6f} {a['peak_sim']:12.6f}{seconds}")


def with_physical_units(data: dict[str, Any], L0: float, C0: float) -> dict[str, Any]:
    """A report's JSON with its bulk numbers also in SI (issue 33): ``physical`` (the units' scales,
    :func:`lcchain.core.physical.physical_scales`), ``dt_s`` and ``tstop_s``, each arrival's ``t_theory_s`` and
    ``t_sim_s``, each mode's ``omega_Hz`` and ``omega_theory_Hz``; the bulk keys stay as they are."""
    from ..core.physical import hertz, physical_scales, seconds

    data["physical"] = physical_scales(L0, C0)
    for key in ("dt", "tstop"):
        if isinstance(data.get(key), (int, float)):
            data[f"{key}_s"] = seconds(data[key], L0, C0)
    for arrival in data.get("arrivals") or ():
        for key in ("t_theory", "t_sim"):
            value = arrival.get(key)
            arrival[f"{key}_s"] = None if value is None else seconds(value, L0, C0)
    for mode in data.get("modes") or ():
        for key in ("omega", "omega_theory"):
            value = mode.get(key)
            mode[f"{key}_Hz"] = None if value is None else hertz(value, L0, C0)
    if isinstance(data.get("omega_max"), (int, float)):
        data["omega_max_Hz"] = hertz(data["omega_max"], L0, C0)
    return data


def _print_units(L0: float, C0: float) -> None:
    from ..core.physical import units_sentence

    print(f"units: {units_sentence(L0, C0)}")


def _print_extrapolation(x: dict[str, Any]) -> None:
    plan = x["plan"]
    why = ""
    if plan is not None and len(plan["considered"]) > 1:
        options = ", ".join(f"{o['runs']} run{'s' if o['runs'] > 1 else ''} ~{o['estimated_seconds']:.2g} s"
                            for o in plan["considered"])
        why = f", the cheapest predicted to meet the accuracy ({options})"
    print(f"extrapolated from {x['runs']} runs{why}:")
    print(f"{'run':>5} {'dt':>10} {'weight':>9} {'points':>9} {'wall s':>8} {'max |run - theory|':>19}")
    for i, (member, weight) in enumerate(zip(x["members"], x["weights"], strict=True), 1):
        print(f"{i:>5} {member['dt']:>10.4g} {weight:>9.4g} {member['points']:>9} {member['wall_s']:>8.3f} "
              f"{member['max_abs_error']:>19.3e}")
    print(f"combined on run 1's time points (degree-7 splines through the finer runs; interpolation error "
          f"{x['interpolation_error']:.1e})")


def _simulation_request(args: argparse.Namespace, chain: Any, *, dt: float | None, accuracy: float | None,
                        extrapolate: int | None, engine: str, backend: Any) -> Any:
    """What ``simulate`` asks for: the chain, the step, and the effects its options ask for (``--Q``,
    ``--coil-capacitance``, ...: :func:`~lcchain.cli.common.effects_from_args`), as one Request."""
    import dataclasses

    from ..runs.simulate import simulation_request

    effects = effects_from_args(args)
    request = simulation_request(chain, dt=dt, accuracy=accuracy, extrapolate=extrapolate, transits=args.transits,
                                 excitation=args.excitation, L0=args.L0, C0=args.C0, backend=backend,
                                 method=args.method, title=args.title, engine=engine)
    return dataclasses.replace(request, effects=effects) if effects else request


def _print_effects(cost: dict[str, Any]) -> None:
    """What the effects cost the pulse: the circuit's exact first arrival against the ideal chain's."""
    energy = "" if cost["energy_loss"] is None else (
        f", energy {cost['energy_circuit']:.4f} against {cost['energy_ideal']:.4f} "
        f"(the effects take {100 * cost['energy_loss']:.3g} % of it)")
    print(f"what the effects cost the pulse (exact circuit against the ideal chain, no simulator): first arrival "
          f"peak {cost['peak_circuit']:.4f} against {cost['peak_ideal']:.4f}{energy}, "
          f"arriving {cost['delay']:+.3g} sqrt(L0 C0) later")


def cmd_simulate(args: argparse.Namespace) -> int:
    from ..report.files import write_text
    from ..runs.simulate import simulate

    outputs = Outputs(inputs={"--chain": args.chain})
    outputs.check("--plot", args.plot, FIGURE_FORMATS)
    outputs.check("--netlist-out", args.netlist_out)
    outputs.check("--waveform-out", args.waveform_out)
    if args.json and outputs.to_stdout:
        raise ParameterError(outputs.to_stdout, "-", "a file name with --json (both would write to stdout)")
    chain = chain_from_args(args)
    if args.accuracy is not None and args.dt is not None:
        raise ParameterError("--accuracy", args.accuracy, "either --dt or --accuracy, not both")
    dt = None if args.accuracy is not None else (args.dt if args.dt is not None else DEFAULT_DT)

    kept: list[str] = []

    def keep_netlist(spec: Any) -> None:  # before ngspice starts: a failed run still leaves it
        if args.netlist_out == "-":  # stdout holds one netlist: the first run's
            if not kept:
                outputs.text("--netlist-out", spec.netlist)
            kept.append("-" if not kept else "(not written: - holds the first run's)")
            return
        if args.netlist_out:  # several runs (extrapolation): FILE holds the first, FILE-run2.cir ... the others
            path = Path(args.netlist_out)
            target = path if not kept else path.with_name(f"{path.stem}-run{len(kept) + 1}{path.suffix}")
            if kept and (target.exists() or target.is_symlink()):  # a name the user did not give: never replaced
                print(f"lcchain: warning: --netlist-out: {target} exists and was left as it is; run "
                      f"{len(kept) + 1}'s netlist was not written", file=sys.stderr)
                kept.append(f"{target} (not written)")
                return
            write_text(target, spec.netlist)
            kept.append(str(target))

    if len(args.engine) > 1:
        return _simulate_engines(args, chain, dt, keep_netlist)
    engine = args.engine[0]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        request = _simulation_request(args, chain, dt=dt, accuracy=args.accuracy, extrapolate=args.extrapolate,
                                      engine=engine, backend=args.backend)
        report = simulate(request, progress=fraction(engine), budget=budget_from_args(args), on_spec=keep_netlist)
    for warning in caught:
        print(f"lcchain: warning: {warning.message}", file=sys.stderr)
    data = with_physical_units(report.to_dict(), args.L0, args.C0)
    with outputs.summary():
        _print_simulation(args, chain, data)
    return _simulation_outputs(args, chain, report, data, outputs, kept)


def _print_simulation(args: argparse.Namespace, chain: Any, data: dict[str, Any]) -> None:
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
        _print_units(args.L0, args.C0)
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
        _print_arrivals(data["arrivals"])
        if "effects" in data:
            _print_effects(data["effects"])


def _simulation_outputs(args: argparse.Namespace, chain: Any, report: Any, data: dict[str, Any],
                        outputs: Outputs, kept: list[str]) -> int:
    if len(kept) > 1:
        print(f"--netlist-out: the {len(kept)} runs' netlists are in {', '.join(kept)} (dt = "
              f"{', '.join(f'{h:.4g}' for h in data['extrapolation']['dt'])})", file=sys.stderr)
    outputs.text("--waveform-out", report.waveforms.to_csv())
    if args.plot:
        from ..report.plots import overlay

        w, c = report.waveforms, report.comparison
        outputs.write("--plot", lambda path: overlay(
            w.t, w.last, w.t, c.theory_last, residual=w.last - c.theory_last, first_sim=w.first,
            first_theory=c.theory_first, arrivals=[a.to_dict() for a in c.arrivals],
            title=f"{chain.name} chain, N = {chain.N}, dt = {report.options.dt:.4g}, {args.excitation}",
            ylabel=r"$I_1,\ I_N\;/\;I_1(0)$" if args.excitation == "kick" else r"$Q_1,\ Q_N\;/\;Q_1(0)$",
            path=path, time_unit=data["physical"]["time_unit_s"]))
    if report.accuracy_met is False:
        steps = ", ".join(f"{h:.4g}" for h in data["extrapolation"]["dt"])
        print(f"lcchain: --accuracy {args.accuracy:g} was not met: the run reached {data['max_abs_error']:.3g} "
              f"(dt = {steps}, predicted {data['predicted_error']:.3g})", file=sys.stderr)
        return EXIT_FAILED
    return EXIT_FAILED if outputs.failed else EXIT_OK


def cmd_spectrum(args: argparse.Namespace) -> int:
    from ..circuit.effects import Losses
    from ..runs.spectrum import measure_spectrum

    outputs = Outputs(inputs={"--chain": args.chain})
    outputs.check("--plot", args.plot, FIGURE_FORMATS)
    outputs.check("--touchstone", args.touchstone, ("s2p",))
    if args.z0 is not None and not args.touchstone:
        raise ParameterError("--z0", args.z0, "only with --touchstone FILE (the two-port's reference impedance)")
    if args.z0 is not None and not args.z0 > 0:
        raise ParameterError("--z0", args.z0, "a reference impedance > 0 ohms")
    chain = chain_from_args(args)
    # the effect options the parser has (--Q is measure_spectrum's own, refused under its name there): effects
    # that are no chain's are compared with the circuit's own poles and residues
    effects = tuple(effect for effect in effects_from_args(args) if not isinstance(effect, Losses))
    report = measure_spectrum(chain, Q=args.Q, points=args.points, L0=args.L0, C0=args.C0,
                              budget=budget_from_args(args), engine=args.engine,
                              progress=fraction(f"{args.engine} AC analysis, then the fit"), effects=effects,
                              shapes=args.shapes)
    data = with_physical_units(report.to_dict(), args.L0, args.C0)
    if args.json:
        emit_json(data)
    else:
        coupled = f", coils coupled k = {chain.coupling:g}" if chain.coupled else ""
        lossy = f", losses Q = {args.Q:g}" if args.Q is not None else ""
        timings = data["timings"]
        print(f"{chain.name} chain, N = {chain.N}{coupled}{lossy}: {data['engine']} {data['engine_version']} AC "
              f"analysis, {data['points']} frequencies up to {data['omega_max']:.4g} in {data['segments']} segments, "
              f"{timings['ngspice_s']:.3f} s, fit {timings['fit_s']:.3f} s")
        _print_units(args.L0, args.C0)
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
            print(f"max relative error of omega_n = {_error(data['max_rel_error_omega'])}{_bound(data, 'omega')} "
                  f"(modes with |P_n| >= 1e-6{f'; {weak} weaker modes are placed less well' if weak else ''}"
                  f"{'; merged modes not compared' if data['merged'] else ''}), max absolute error of P_n = "
                  f"{data['max_abs_error_P']:.3e}{_bound(data, 'P')} ({data['seen']} of {chain.N} modes seen at the "
                  "ends)")
        else:
            print("no mode is resolved: omega_n, P_n and Q_n are not compared")
        if data["Q"] is not None or data["max_rel_error_Q"] is not None:  # the chain's losses, a circuit's resistors
            _print_quality(data)
        if data["merged"]:
            from ..runs.spectrum import merged_text

            print(f"merged by the losses (half-power bands overlap, said and not compared): "
                  f"{merged_text(report.merged_modes)}")
        if data["max_rel_error_Y11"] is not None:
            print(f"Y_11 against the exact lossy admittance over the sweep: max relative error "
                  f"{data['max_rel_error_Y11']:.3e}")
    if report.modes is not None and not args.json:
        _print_survey(report.modes)
    if args.plot:
        from ..report.plots import spectrum

        outputs.write("--plot", lambda path: spectrum(
            report.theory.omega, report.P_theory, report.omega, report.P,
            title=f"{chain.name} chain, N = {chain.N}: {report.engine} AC against theory", path=path,
            frequency_unit=data["physical"]["frequency_unit_Hz"]))
    if args.touchstone:
        _write_touchstone(args, chain, effects, outputs)
    if report.failure:  # a comparison that failed is a failed check
        print(f"lcchain: {report.failure}", file=sys.stderr)
        return EXIT_FAILED
    if report.modes is not None and not report.modes.resolved.all():
        print(f"lcchain: the survey of every loop resolved {int(report.modes.resolved.sum())} of {chain.N} modes",
              file=sys.stderr)
        return EXIT_FAILED
    return EXIT_FAILED if outputs.failed else EXIT_OK


def _print_survey(modes: Any) -> None:
    """``spectrum --shapes``: every mode from the survey of every loop, beside the exact eigensolution."""
    for name, value in modes.rows():
        print(f"{name}: {value:.3e}" if isinstance(value, float) else f"{name}: {value}")
    lossy = modes.losses is not None
    print(f"{'n':>5} {'omega (survey)':>19} {'rel. error':>10} {'shape error':>11} {'P_n (shape)':>14} "
          f"{'P_n (theory)':>14}" + (f" {'Q_n':>12} {'rel. error':>10}" if lossy else ""))
    for n in range(modes.N):
        quality = f" {modes.Q[n]:12.6g} {modes.Q_error[n]:10.2e}" if lossy else ""
        print(f"{n + 1:>5} {modes.omega[n]:19.15f} {modes.omega_error[n]:10.2e} {modes.shape_error[n]:11.2e} "
              f"{modes.P[n]:14.6e} {modes.P_theory[n]:14.6e}{quality}")


def _bound(data: dict[str, Any], name: str) -> str:
    """The reference's own bound on a metric, as printed beside its error ('' where it states none)."""
    bound = data.get(f"reference_bound_{name}")
    return "" if bound is None else f" (reference bound {bound:.1e})"


def _error(value: float | None) -> str:
    """An error as printed: a number, or 'unseen' where a resolved mode was not seen (infinite; None in the
    JSON), 'n/a' where it is NaN: never 'inf'."""
    if value is not None and value != value:
        return "n/a"
    return "unseen" if value is None or value == float("inf") else f"{value:.3e}"


def _write_touchstone(args: argparse.Namespace, chain: Any, effects: tuple[Any, ...], outputs: Outputs) -> None:
    """``spectrum --touchstone FILE.s2p``: the ladder's two-port from two AC analyses (one per end), checked
    against the circuit's exact admittances (:mod:`lcchain.runs.twoport`), as Touchstone v1."""
    import numpy as np

    from ..circuit.effects import Losses
    from ..report.touchstone import touchstone_text
    from ..runs.request import AC, Request
    from ..runs.twoport import DEFAULT_Z0, two_port, two_port_theory

    z0 = DEFAULT_Z0 if args.z0 is None else args.z0
    losses = (Losses(args.Q),) if args.Q is not None else ()
    request = Request(chain, AC(args.points), effects=effects + losses, L0=args.L0, C0=args.C0, engine=args.engine)
    measured = two_port(request, z0)
    exact = two_port_theory(request, measured.frequency, z0)
    error = float(np.max(np.abs(measured.S - exact.S)))
    comments = [f"lcchain {__version__}: {chain.name} chain, N = {chain.N}, L0 = {args.L0:g} H, C0 = {args.C0:g} F, "
                f"{measured.engine} {measured.engine_version} AC analyses",
                "port 1: a break in loop 1 (the AC source's place, between coil 1 and the rail); current into coil 1",
                "port 2: its mirror image in loop N; current into coil N from that end (-i(lN) in the netlist)",
                f"max |S - S of the circuit's exact admittances| = {error:.3e}"]
    outputs.text("--touchstone", touchstone_text(measured.frequency, measured.S, z0, comments))
    if not args.json:
        print(f"two-port: {measured.frequency.size} frequencies from {measured.frequency[0]:.6g} to "
              f"{measured.frequency[-1]:.6g} Hz in z0 = {z0:g} ohm, max |S - exact| = {error:.3e}, "
              f"reciprocity |Y12 - Y21| / max |Y| = {measured.reciprocity:.1e}")


def _print_quality(data: dict[str, Any]) -> None:
    """``lcchain spectrum --Q``: each seen mode's Q_n beside omega_n Q, and the fitted response's error."""
    if not any(mode["resolved"] for mode in data["modes"]):
        return
    print(f"{'n':>5} {'Q_n (circuit)':>19} {'Q_n (theory)':>19} {'rel. error':>10}")
    for mode in data["modes"]:
        if mode["Q"] is not None and mode["Q_theory"] is not None:
            error = abs(mode["Q"] - mode["Q_theory"]) / (mode["Q_theory"] or 1.0)
            print(f"{mode['n']:>5} {mode['Q']:19.12g} {mode['Q_theory']:19.12g} {error:10.2e}")
    response = data["max_abs_error_response"]
    print(f"max relative error of Q_n = {_error(data['max_rel_error_Q'])}{_bound(data, 'Q')}, of the poles = "
          f"{_error(data['max_rel_error_pole'])}"
          + ("" if response is None else f"; fitted alpha_N(t) - exact lossy response: max {response:.3e}"))


def _simulate_engines(args: argparse.Namespace, chain: Any, dt: float | None, keep_netlist: Any) -> int:
    """``simulate --engine A,B``: the same netlist in every engine, each against theory, and their difference."""
    from ..compare.metrics import residual_difference
    from ..runs.simulate import simulate

    if args.extrapolate is not None and args.extrapolate > 1:
        raise ParameterError("--extrapolate", args.extrapolate, "1 with several engines (they run one netlist)")
    if args.plot or args.waveform_out:
        option = "--plot" if args.plot else "--waveform-out"
        raise ParameterError(option, getattr(args, option[2:].replace("-", "_")), "one engine (--engine NAME)")
    if args.backend != "batch":
        raise ParameterError("--backend", args.backend, "batch with several engines")
    reports: list[Any] = []
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        for engine in args.engine:
            # the first engine's step (given, or chosen for --accuracy) is every engine's: one netlist
            step = dt if not reports else reports[0].options.dt
            request = _simulation_request(args, chain, dt=step, accuracy=args.accuracy if not reports else None,
                                          extrapolate=1, engine=engine, backend="batch")
            reports.append(simulate(request, progress=fraction(engine), budget=budget_from_args(args),
                                    on_spec=None if reports else keep_netlist))
    for warning in sorted({str(w.message) for w in caught}):
        print(f"lcchain: warning: {warning}", file=sys.stderr)
    first = reports[0]
    differences = {}
    for other in reports[1:]:
        pair = f"{first.run.engine} - {other.run.engine}"
        a, b = first.waveforms, other.waveforms
        differences[pair] = max(
            residual_difference(a.t, a.first - first.comparison.theory_first, b.t,
                                b.first - other.comparison.theory_first),
            residual_difference(a.t, a.last - first.comparison.theory_last, b.t,
                                b.last - other.comparison.theory_last))
    data = {"engines": [report.to_dict() for report in reports], "max_abs_difference": differences,
            "netlist_sha256": first.run.netlist_sha256}
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
        print(f"{record['engine']:<10} {record['engine_version']:<12} {record['points']:>8} "
              f"{record['wall_s']:>8.3f} {record['max_abs_error']:>19.3e} {record['predicted_error']:>10.3e}")
    for pair, value in differences.items():
        print(f"max |{pair}| = {value:.3e} (loops 1 and N; the second engine's residual interpolated onto the "
              "first's time points)")
    return EXIT_OK


def _print_spectrum_summary(result: Any) -> None:
    """An AC scene: each sample's modes against its own theory, and the spacings' spread over the samples."""
    report = result.report
    count = len(report["samples"])
    print(result.scene.title)
    print(f"N = {report['N']}, AC sweep of {report['points']} frequencies up to omega = {report['omega_max']:.4g} "
          f"(1/sqrt(L0 C0)), {count} sample{'s' if count > 1 else ''}, {report['engine']} "
          f"{report['engine_version']}, {report['wall_s']['total']:.2f} s")
    if "max_rel_error_omega" in report:
        good = [record for record in report["samples"] if "error" not in record]
        over = f" (the worst of {len(good)} samples, each against its own theory)" if len(good) > 1 else ""
        print(f"max |omega_n - theory| / theory = {_error(report['max_rel_error_omega'])}, max |P_n - theory| = "
              f"{report['max_abs_error_P']:.3e}{over}")
        if "max_rel_error_Q" in report:
            print(f"losses Q = {report['Q']:g}: max |Q_n - omega_n Q| / (omega_n Q) = "
                  f"{_error(report['max_rel_error_Q'])}{over}")
        spread = report["spacing_spread"]
        print(f"spacing spread (max - min) / mean of delta omega_n: {spread['mean']:.4g} (mean over {spread['count']}"
              f" sample{'s' if spread['count'] > 1 else ''}), largest {spread['max']:.4g}; nominal theory "
              f"{spread['theory_nominal']:.3g}")
        print(f"{'sample':>6} {'modes seen':>10} {'max omega error':>16} {'max P error':>12} {'spacing spread':>15}")
        for record in good:
            print(f"{record['sample']:>6} {record['modes_seen']:>10} {_error(record['max_rel_error_omega']):>16} "
                  f"{record['max_abs_error_P']:>12.3e} {record['spacing_spread']:>15.4g}")
    for record in report["samples"]:
        if "error" in record:
            print(f"sample {record['sample']} failed: {record['error']}", file=sys.stderr)


def _print_scene_summary(result: Any) -> None:
    if result.report.get("analysis") == "ac":
        _print_spectrum_summary(result)
        return
    report = result.report
    count = len(report["samples"])
    print(result.scene.title)
    steps = report.get("steps") or [report["dt"]]
    if len(steps) > 1:
        print(f"each sample extrapolated from {len(steps)} runs at dt = {', '.join(f'{h:.4g}' for h in steps)}")
    print(f"N = {report['N']}, dt = {report['dt']:.4g}, {count} sample{'s' if count > 1 else ''}, "
          f"{report['engine']} {report['engine_version']}, {report['wall_s']['total']:.2f} s")
    if "max_abs_error" in report:
        good = sum("error" not in record for record in report["samples"])
        over = f" (the worst of {good} samples, each against its own theory)" if good > 1 else ""
        print(f"max |simulation - theory| = {report['max_abs_error']:.3e}{over}")
        if good > 1:
            print(f"arrivals of sample {report['arrivals_sample']} (every sample's are in the report's samples):")
        _print_arrivals(report["arrivals"])
    if "transmitted_peak" in report:
        p = report["transmitted_peak"]
        print(f"transmitted peak over {p['count']} samples: mean {p['mean']:.5f}, std {p['std']:.5f}, "
              f"worst {p['worst']:.5f} (nominal theory {p['theory_nominal']:.5f})")
    for record in report["samples"]:
        if "error" in record:
            print(f"sample {record['sample']} failed: {record['error']}", file=sys.stderr)
    if report.get("accuracy_met") is False:
        print(f"lcchain: {result.scene.source or 'the scene'}: analysis.accuracy "
              f"{result.scene.analysis.accuracy:g} was not met: the runs reached {report['max_abs_error']:.3g}",
              file=sys.stderr)


def cmd_run(args: argparse.Namespace) -> int:
    from ..app.scenes import run_scene
    from ..report.scenes import check_scene_outputs
    from ..scenes.load import load_scene
    from ..scenes.run import overlay_panel

    if len(args.scene) > 1 and (args.netlist_out or args.waveform_out):
        option = "--netlist-out" if args.netlist_out else "--waveform-out"
        raise ParameterError(option, args.netlist_out or args.waveform_out, "one scene only (got "
                             f"{len(args.scene)})")
    scenes = [_with_parts(load_scene(path), args) for path in args.scene]  # every file checked before anything runs
    outputs = Outputs()
    outputs.check("--side-by-side", args.side_by_side, FIGURE_FORMATS)
    for option in ("--netlist-out", "--waveform-out"):
        value = getattr(args, option[2:].replace("-", "_"))
        if value == "":
            raise ParameterError(option, "", "a file name")
        if value == "-":
            outputs.claim_stdout(option)
    if args.json and outputs.to_stdout:
        raise ParameterError(outputs.to_stdout, "-", "a file name with --json (both would write to stdout)")
    check_scene_outputs(scenes, {"--netlist-out": args.netlist_out, "--waveform-out": args.waveform_out,
                                 "--side-by-side": args.side_by_side},
                        inputs=[("SCENE", path) for path in args.scene])
    budget = budget_from_args(args)
    results, failed_files = [], []
    for scene in scenes:
        label = Path(scene.source).name if scene.source else "scene"

        def unwritten(error: OSError, source: str | None = scene.source) -> None:
            failed_files.append(source)
            print(f"lcchain: could not write {error.filename or 'an output'} of {source}: "
                  f"{error.strerror or error}", file=sys.stderr)

        result = run_scene(scene, netlist_out=args.netlist_out, waveform_out=args.waveform_out, budget=budget,
                           progress=fraction(label), executor=args.executor, workers=args.workers,
                           scheduler=args.scheduler, transport=args.transport,
                           study_progress=study_counter(f"samples of {label}"), write_error=unwritten)
        results.append(result)
        if not args.json:
            with outputs.summary():
                _print_scene_summary(result)
            for path in result.files:
                print(f"wrote {path}", file=sys.stderr if outputs.to_stdout else sys.stdout)
    if args.side_by_side:
        from ..report.plots import side_by_side

        panels = [p for p in (overlay_panel(r) for r in results) if p is not None]
        if panels:
            outputs.write("--side-by-side", lambda path: side_by_side(panels, path=path))
            if not args.json and "--side-by-side" not in outputs.failed:
                print(f"wrote {args.side_by_side}", file=sys.stderr if outputs.to_stdout else sys.stdout)
        else:
            print(f"lcchain: no scene ran, so {args.side_by_side} was not drawn", file=sys.stderr)
    if args.json:
        reports = [r.report for r in results]
        emit_json(reports[0] if len(reports) == 1 else reports)
    ok = all(r.ok for r in results) and not failed_files and not outputs.failed
    return EXIT_OK if ok else EXIT_FAILED


def _with_parts(scene: Any, args: argparse.Namespace) -> Any:
    """The scene with ``--tolerance``, ``--series``, ``--samples`` and ``--seed`` set, when any is given."""
    from ..scenes.load import override_parts, parse_scene

    parts = {"tolerance": args.tolerance, "series": args.series, "samples": args.samples, "seed": args.seed}
    if all(value is None for value in parts.values()):
        return scene
    return parse_scene(override_parts(scene.to_dict(), **parts), source=scene.source)


def cmd_bench_accuracy(args: argparse.Namespace) -> int:
    from ..report.bench import write_accuracy_bench
    from ..studies.bench import bench_accuracy, bench_estimate

    check_output_folder("--out", args.out, parents=True)  # the folder itself is made when the results are written
    bench_estimate(args.N, quick=args.quick).check(budget_from_args(args), "bench accuracy",
                                                   "--quick" if args.quick else "the full sweep", "--quick or --N")
    result = bench_accuracy(args.N, quick=args.quick, progress=counter("bench accuracy"))
    print(result["markdown"], end="")
    for path in write_accuracy_bench(args.out, result):
        print(f"wrote {path}")
    return EXIT_OK


def cmd_doctor(args: argparse.Namespace) -> int:
    from ..spice.doctor import doctor

    checks = doctor()
    for check in checks:
        mark = "ok  " if check.ok else "FAIL" if check.required else "warn"
        print(f"[{mark}] {check.name}: {check.detail}")
        if not check.ok and check.fix:
            print(f"       fix: {check.fix}")
    return EXIT_OK if all(c.ok for c in checks if c.required) else EXIT_MISSING
