"""Chains by name: the cases the command line and scenes accept."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from ..core.errors import ParameterError
from ..core.limits import MAX_CIRCUIT_N, MAX_PERFECT_N
from ..core.types import NAMED_CASES
from .chain import Chain
from .design import optimal_one_mass, optimal_two_mass
from .perfect import perfect_design

__all__ = ["chain_for_case", "NAMED_CASES", "ChainCase", "CHAIN_CASES", "named_case"]


@dataclass(frozen=True)
class ChainCase:
    """A named case: how it makes its chain of N masses, and what it takes.

    Attributes
    ----------
    chain : callable
        ``chain(N, walls) -> Chain``.
    walls : bool
        Whether it takes walls (the perfect cradle's j >= 1); the others take 0.
    max_N : int
        The most masses a scene may ask of it.
    """

    chain: Callable[[int, int], Chain]
    walls: bool = False
    max_N: int = MAX_CIRCUIT_N


#: Each named case, by name.  To add a case: its :class:`ChainCase` here, its name in
#: :data:`lcchain.core.types.Case` (docs/extending.md).  A case that is not here (``custom``) is a scene's own
#: masses and springs.
CHAIN_CASES: dict[str, ChainCase] = {
    "one-mass": ChainCase(lambda N, walls: optimal_one_mass(N).chain),
    "two-mass": ChainCase(lambda N, walls: optimal_two_mass(N).chain),
    "uniform-free": ChainCase(lambda N, walls: Chain.uniform_free(N)),
    "uniform-bounded": ChainCase(lambda N, walls: Chain.uniform_bounded(N)),
    "perfect": ChainCase(lambda N, walls: perfect_design(N, walls).chain, walls=True, max_N=MAX_PERFECT_N),
}


def named_case(case: str) -> ChainCase | None:
    """The named case of that name, or None (a scene's ``custom`` chain, or a name no case has)."""
    return CHAIN_CASES.get(case)


def chain_for_case(case: str, N: int, walls: int = 0) -> Chain:
    """The chain of a named case.

    Parameters
    ----------
    case : {"one-mass", "two-mass", "uniform-free", "uniform-bounded", "perfect"}
        ``one-mass`` and ``two-mass`` are the optimal designs for this N
        (Tables I and II, computed by :mod:`lcchain.theory.design`); ``perfect``
        is the perfect cradle of N masses in bulk units (central mass and
        central spring 1, :func:`lcchain.perfect_design`; N = 3, 4, 5 are the
        paper's exact fractions, N = 4 with masses (5/3, 1, 1, 5/3)).
    N : int
        Number of masses (cells of the ladder).
    walls : int
        ``perfect`` only: j >= 1 designs the perfect cradle tied to walls,
        frequencies (n - 1 + 2 j) dw.
    """
    named = named_case(case)
    if walls and not (named is not None and named.walls):
        walled = " | ".join(name for name, kind in CHAIN_CASES.items() if kind.walls)
        raise ParameterError("walls", walls, f'walls = 0 unless case = "{walled}" (j >= 1: a perfect cradle tied to '
                             "walls)")
    if named is None:
        raise ParameterError("case", case, " | ".join(NAMED_CASES))
    return named.chain(N, walls)
