"""``lcchain design``, ``lcchain table`` and ``lcchain asymptotic`` as functions: the paper's optimal chains, the
perfect cradle, and the N -> infinity optimum with its scaling laws."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Literal, TypeGuard

from ..core.budget import Budget, Estimate, design_estimate
from ..core.errors import ParameterError
from ..core.json import LooseJSONObject
from ..core.limits import MAX_DESIGN_N, MIN_N
from ..core.types import DESIGN_CASES, DesignCase
from ..theory.design import DESIGN_TABLES
from .inputs import check_perfect

if TYPE_CHECKING:
    from ..theory.asymptotic import AsymptoticOptimum
    from ..theory.design import Design
    from ..theory.perfect import PerfectDesign as PerfectDesign  # named for the command line, which prints it

__all__ = ["DESIGN_TABLES", "DesignRequest", "TableRequest", "Asymptotic", "AsymptoticRequest", "design", "table",
           "asymptotic", "check_design_sizes", "is_perfect"]


@dataclass(frozen=True)
class DesignRequest:
    """One design: ``case`` one-mass or two-mass (the paper's optima) or perfect (a perfect cradle, tied to
    ``walls`` walls); ``progress`` is called with the fraction done of a large design (N >= 10 000)."""

    case: DesignCase | Literal["perfect"]
    N: int
    walls: int = 0
    budget: Budget = field(default_factory=Budget)
    progress: Callable[[str], Callable[[float], None]] | None = None


@dataclass(frozen=True)
class TableRequest:
    """Table I (one-mass) or II (two-mass) for the sizes ``Ns``; ``progress(done, total)`` after each row."""

    case: DesignCase
    Ns: tuple[int, ...]
    budget: Budget = field(default_factory=Budget)
    progress: Callable[[int, int], None] | None = None


@dataclass(frozen=True)
class Asymptotic:
    """The N -> infinity optimum (:class:`lcchain.theory.asymptotic.AsymptoticOptimum`) and the exponents of its
    scaling laws (coefficient name -> power of N)."""

    optimum: AsymptoticOptimum
    exponents: dict[str, float]


def check_design_sizes(case: str, sizes: list[int], budget: Budget) -> None:
    """Refuse designs out of range or beyond the budget, before any of them starts."""
    for N in sizes:
        if not MIN_N <= N <= MAX_DESIGN_N:
            raise ParameterError("--N", N, f"an integer from {MIN_N} to {MAX_DESIGN_N}")
    total = [design_estimate(case, N) for N in sizes]
    seconds = sum(e.seconds for e in total)
    memory = max(e.memory for e in total)
    what = total[0].what if len(total) == 1 else f"{len(total)} {case} designs up to N = {max(sizes)}"
    Estimate(what, memory, seconds).check(budget, "--N", ",".join(map(str, sizes)) if len(sizes) > 1 else sizes[0])


def design(request: DesignRequest) -> Design | PerfectDesign:
    """The design: a :class:`lcchain.theory.perfect.PerfectDesign` for ``case = "perfect"``, else a
    :class:`lcchain.theory.design.Design`."""
    from ..theory.design import optimal_design

    case = next((case for case in DESIGN_CASES if case == request.case), None)  # one of the paper's optima
    if case is None:  # the perfect cradle, designed from its spectrum
        from ..theory.perfect import perfect_design

        check_perfect(request.N, request.walls, request.budget)
        return perfect_design(request.N, request.walls)
    if request.walls:
        raise ParameterError("--walls", request.walls, "0 unless --case perfect (J >= 1: a perfect cradle tied to "
                             "walls)")
    check_design_sizes(case, [request.N], request.budget)
    bar = request.progress(f"{case} design, N = {request.N}") \
        if request.progress is not None and request.N >= 10_000 else None
    result = optimal_design(case, request.N, progress=bar)
    if bar is not None:
        bar(1.0)
    return result


def is_perfect(result: Design | PerfectDesign) -> TypeGuard[PerfectDesign]:
    """Whether :func:`design` gave a perfect cradle (else one of the paper's optima)."""
    from ..theory.perfect import PerfectDesign

    return isinstance(result, PerfectDesign)


def table(request: TableRequest) -> list[LooseJSONObject]:
    """The table's rows, one design per size, as :meth:`lcchain.theory.design.Design.to_dict` gives them."""
    from ..theory.design import optimal_design

    sizes = list(request.Ns)
    check_design_sizes(request.case, sizes, request.budget)
    rows = []
    for i, N in enumerate(sizes):
        if request.progress is not None:
            request.progress(i, len(sizes))
        rows.append(optimal_design(request.case, N).to_dict())
    if request.progress is not None:
        request.progress(len(sizes), len(sizes))
    return rows


@dataclass(frozen=True)
class AsymptoticRequest:
    """The N -> infinity optimum of one design ``case``."""

    case: DesignCase = "two-mass"


def asymptotic(request: AsymptoticRequest) -> Asymptotic:
    """The maximum of alpha_inf(tau, sigma) and the scaling laws of the optimum's parameters."""
    from ..theory.asymptotic import EXPONENTS, asymptotic_optimum

    return Asymptotic(asymptotic_optimum(request.case), EXPONENTS[request.case])
