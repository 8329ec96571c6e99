"""Chains by name: the cases the command line and scenes accept."""

from __future__ import annotations

from ..core.errors import ParameterError
from ..core.types import NAMED_CASES
from .chain import Chain
from .design import optimal_one_mass, optimal_two_mass

__all__ = ["chain_for_case", "NAMED_CASES"]


def chain_for_case(case: str, N: int) -> Chain:
    """The chain of a named case.

    Parameters
    ----------
    case : {"one-mass", "two-mass", "uniform-free", "uniform-bounded", "perfect"}
        ``one-mass`` and ``two-mass`` are the optimal designs for this N
        (Tables I and II, computed by :mod:`lcchain.design`); ``perfect``
        needs N = 3, 4 or 5.
    N : int
        Number of masses (cells of the ladder).
    """
    if case == "one-mass":
        return optimal_one_mass(N).chain
    if case == "two-mass":
        return optimal_two_mass(N).chain
    if case == "uniform-free":
        return Chain.uniform_free(N)
    if case == "uniform-bounded":
        return Chain.uniform_bounded(N)
    if case == "perfect":
        return Chain.perfect(N)
    raise ParameterError("case", case, " | ".join(NAMED_CASES))
