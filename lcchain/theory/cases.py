"""Chains by name: the cases the command line and scenes accept."""

from __future__ import annotations

from collections.abc import Callable

from ..core.errors import ParameterError
from ..core.types import NAMED_CASES
from .chain import Chain
from .design import optimal_one_mass, optimal_two_mass
from .perfect import perfect_design

__all__ = ["chain_for_case", "NAMED_CASES", "CASE_CHAINS"]

#: Each named case's chain of N masses (``walls``: the perfect cradle's j; the others take 0).  To add a case:
#: a function (N, walls) -> Chain here, its name in :data:`lcchain.core.types.Case` (docs/extending.md).
CASE_CHAINS: dict[str, Callable[[int, int], Chain]] = {
    "one-mass": lambda N, walls: optimal_one_mass(N).chain,
    "two-mass": lambda N, walls: optimal_two_mass(N).chain,
    "uniform-free": lambda N, walls: Chain.uniform_free(N),
    "uniform-bounded": lambda N, walls: Chain.uniform_bounded(N),
    "perfect": lambda N, walls: perfect_design(N, walls).chain,
}


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
    if walls and case != "perfect":
        raise ParameterError("walls", walls, 'walls = 0 unless case = "perfect" (j >= 1: a perfect cradle tied to '
                             "walls)")
    if case not in CASE_CHAINS:
        raise ParameterError("case", case, " | ".join(NAMED_CASES))
    return CASE_CHAINS[case](N, walls)
