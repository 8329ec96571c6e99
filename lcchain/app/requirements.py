"""``lcchain requirements`` as functions: how good must the parts be, from the circuit's exact theory, with
ngspice points on the curves."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from ..core.budget import Budget
from ..core.errors import ParameterError
from ..report.files import FIGURE_FORMATS
from .inputs import ChainOptions, Outputs, make_chain

if TYPE_CHECKING:
    from ..circuit.ladder import Ladder
    from ..circuit.requirements import Arrival, Part, Requirement
    from ..studies.requirements import CheckPoint
    from ..theory.chain import Chain

__all__ = ["RequirementsRequest", "Requirements", "requirements", "write_plot", "parts_named"]


@dataclass(frozen=True)
class RequirementsRequest:
    """The chain and its units, the parts to sweep (``part``: comma-separated keys; None: all), ``check`` ngspice
    runs on each curve, ``plot`` a figure; ``progress(label)`` gives a callback of the fraction done."""

    chain: ChainOptions
    L0: float
    C0: float
    part: str | None = None
    check: int = 2
    plot: str | None = None
    budget: Budget = field(default_factory=Budget)
    progress: Callable[[str], Callable[[float], None]] | None = None


@dataclass(frozen=True)
class Requirements:
    """The ladder, its ideal first arrival, each part's requirement, ngspice's points and the loss targets."""

    request: RequirementsRequest
    chain: Chain
    ladder: Ladder
    ideal: Arrival
    results: list[Requirement]
    points: list[CheckPoint]
    targets: tuple[float, ...]
    outputs: Outputs

    @property
    def passed(self) -> bool:
        """Every ngspice point agrees with the exact curve."""
        from ..studies.requirements import point_agrees

        return all(point_agrees(point) for point in self.points)


def parts_named(text: str | None) -> list[Part]:
    """The parts ``--part`` names (comma-separated keys; None: all)."""
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


def requirements(request: RequirementsRequest) -> Requirements:
    from ..circuit.ladder import Ladder
    from ..circuit.requirements import LOSS_TARGETS, first_arrival_energy, requirement
    from ..studies.requirements import check_points, requirements_estimate

    def progress(label: str) -> Callable[[float], None] | None:
        return None if request.progress is None else request.progress(label)

    outputs = Outputs(inputs={"--chain": request.chain.chain} if request.chain.chain else {})
    outputs.check("--plot", request.plot, FIGURE_FORMATS)
    if request.check < 0:
        raise ParameterError("--check", request.check, "an integer >= 0 (0: no ngspice runs)")
    parts = parts_named(request.part)
    chain = make_chain(request.chain, request.budget, max_N=2000)
    budget = request.budget
    requirements_estimate(chain, parts, request.check).check(budget, "--N", chain.N)
    ladder = Ladder(chain, request.L0, request.C0)
    ideal = first_arrival_energy(ladder)
    results = [requirement(ladder, part, progress=progress(f"{part.key}: its curve")) for part in parts]
    points = check_points(ladder, results, request.check, budget=budget,
                          progress=progress("ngspice on the curves")) if request.check else []
    return Requirements(request, chain, ladder, ideal, results, points, tuple(LOSS_TARGETS), outputs)


def write_plot(result: Requirements) -> bool:
    """Draw ``--plot`` (after the result was shown); returns whether it could not be written."""
    chain = result.chain
    if result.request.plot:
        from ..report.requirements import requirements_figure

        result.outputs.write("--plot", lambda path: requirements_figure(
            result.results, result.points, path=path,
            title=f"{chain.name} chain, N = {chain.N}: the first arrival's energy loss against each part"))
    return bool(result.outputs.failed)
