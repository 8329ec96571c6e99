"""``lcchain requirements``: how good must the parts be for the cradle to work."""

from __future__ import annotations

import argparse
from typing import Any

from ..core.errors import ParameterError
from ..report.files import FIGURE_FORMATS
from .common import EXIT_FAILED, EXIT_OK, Outputs, budget_from_args, chain_from_args, emit_json
from .progress import fraction

__all__ = ["add_requirements_arguments", "cmd_requirements"]

#: ngspice runs per part unless --check says otherwise.
DEFAULT_CHECKS = 2


def add_requirements_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--part", metavar="PART[,PART]",
                   help="the parts to sweep, comma-separated: coil_capacitance, coil_resistance, capacitor_esr, "
                        "capacitor_esl, coupling (default: all)")
    p.add_argument("--check", type=int, default=DEFAULT_CHECKS, metavar="M",
                   help=f"ngspice runs on each curve (default {DEFAULT_CHECKS}; 0: the exact curves alone)")
    p.add_argument("--plot", metavar="FILE", help="figure (.png, .svg, .pdf): each part's curve, ngspice's points "
                   "and the limits")
    p.add_argument("--json", action="store_true")


def _parts(text: str | None) -> list[Any]:
    from ..circuit.requirements import PARTS

    if text is None:
        return list(PARTS)
    known = {part.key: part for part in PARTS}
    names = [name.strip() for name in text.split(",")]
    for name in names:
        if name not in known:
            raise ParameterError("--part", name, f"{' | '.join(known)}, or several separated by commas")
    if len(set(names)) != len(names):
        raise ParameterError("--part", text, "each part once")
    return [known[name] for name in names]


def cmd_requirements(args: argparse.Namespace) -> int:
    from ..circuit.ladder import Ladder
    from ..circuit.requirements import LOSS_TARGETS, first_arrival_energy, requirement
    from ..studies.requirements import check_points, point_agrees, requirements_estimate

    outputs = Outputs(inputs={"--chain": args.chain})
    outputs.check("--plot", args.plot, FIGURE_FORMATS)
    if args.check < 0:
        raise ParameterError("--check", args.check, "an integer >= 0 (0: no ngspice runs)")
    parts = _parts(args.part)
    chain = chain_from_args(args, max_N=2000)
    budget = budget_from_args(args)
    requirements_estimate(chain, parts, args.check).check(budget, "--N", chain.N)
    ladder = Ladder(chain, args.L0, args.C0)
    ideal = first_arrival_energy(ladder)
    results = [requirement(ladder, part, progress=fraction(f"{part.key}: its curve")) for part in parts]
    points = check_points(ladder, results, args.check, budget=budget, progress=fraction("ngspice on the curves")) \
        if args.check else []
    if args.json:
        emit_json({"chain": chain.name, "N": chain.N, "L0": ladder.L0, "C0": ladder.C0,
                   "ideal": {"time": ideal.time, "peak": ideal.peak, "energy": ideal.energy},
                   "targets": list(LOSS_TARGETS), "parts": [r.to_dict(ladder) for r in results],
                   "check": [point.to_dict() for point in points]})
    else:
        print(f"{chain.name} chain, N = {chain.N}, L0 = {ladder.L0:g} H, C0 = {ladder.C0:g} F: the ideal ladder's "
              f"first arrival carries e = {ideal.energy:.6f} of the kick's energy at t = {ideal.time:.2f} sqrt(L0 C0)")
        print("The largest parasitic that keeps the first arrival's energy loss (1 - e/e_ideal) under each target, "
              "from the circuit's exact theory:")
        for result in results:
            print(f"  {result.part.key} ({result.part.what}):")
            for k, target in enumerate(LOSS_TARGETS):
                print(f"    loss < {target:.1%}: {result.statement(k, ladder)}")
        if points:
            print("ngspice on the curves (fixed step 0.01 sqrt(L0 C0)):")
            print(f"  {'part':<17} {'value':>10} {'loss, ngspice':>14} {'loss, theory':>13} {'|diff|':>9}")
            for point in points:
                print(f"  {point.part:<17} {point.value:10.3g} {point.loss:14.6g} {point.theory:13.6g} "
                      f"{abs(point.loss - point.theory):9.2e}")
    if args.plot:
        from ..report.requirements import requirements_figure

        outputs.write("--plot", lambda path: requirements_figure(
            results, points, path=path,
            title=f"{chain.name} chain, N = {chain.N}: the first arrival's energy loss against each part"))
    failed = not all(point_agrees(point) for point in points)
    return EXIT_FAILED if failed or outputs.failed else EXIT_OK
