"""Chains by name: the cases the command line and scenes accept."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from ..core.errors import ParameterError
from ..core.limits import MAX_CIRCUIT_N, MAX_PERFECT_N
from ..core.registry import Registry
from ..core.types import CASES, NAMED_CASES
from .chain import Chain

__all__ = ["chain_for_case", "NAMED_CASES", "ChainCase", "CHAIN_CASES", "named_case", "scene_cases"]


@dataclass(frozen=True)
class ChainCase:
    """A named case: how it makes its chain of N masses, and what it takes.

    Attributes
    ----------
    name : str
        The name scenes and ``--case`` give it.
    chain : callable
        ``chain(N, walls) -> Chain``.
    walls : bool
        Whether it takes walls (the perfect cradle's j >= 1); the others take 0.
    max_N : int
        The most masses a scene may ask of it.
    """

    name: str
    chain: Callable[[int, int], Chain]
    walls: bool = False
    max_N: int = MAX_CIRCUIT_N


# The designs import scipy: a case imports its design when it makes a chain, so that the command line's choices
# (lcchain.app.options.CASE_CHOICES, read by ``--help``) cost no scipy.
def _one_mass(N: int, walls: int) -> Chain:
    from .design import optimal_one_mass

    return optimal_one_mass(N).chain


def _two_mass(N: int, walls: int) -> Chain:
    from .design import optimal_two_mass

    return optimal_two_mass(N).chain


def _perfect(N: int, walls: int) -> Chain:
    from .perfect import perfect_design

    return perfect_design(N, walls).chain


_OWN_CASES = (
    ChainCase("one-mass", _one_mass),
    ChainCase("two-mass", _two_mass),
    ChainCase("uniform-free", lambda N, walls: Chain.uniform_free(N)),
    ChainCase("uniform-bounded", lambda N, walls: Chain.uniform_bounded(N)),
    ChainCase("perfect", _perfect, walls=True, max_N=MAX_PERFECT_N),
)


def _admit(name: str, loaded: object) -> ChainCase:
    """An ``lcchain.cases`` entry point's object (or a case given as itself): a ChainCase of that name."""
    if not isinstance(loaded, ChainCase) or loaded.name != name or not name:
        raise TypeError(f"{loaded!r} is not a ChainCase named {name!r}")
    return loaded


#: Each named case, by name, then those of the ``lcchain.cases`` entry points.  To add a case: its
#: :class:`ChainCase` here, its name in :data:`lcchain.core.types.Case` (docs/extending.md; a test checks the
#: two agree).  A case that is not here (``custom``) is a scene's own masses and springs.
CHAIN_CASES: Registry[ChainCase] = Registry("lcchain.cases", {case.name: case for case in _OWN_CASES}, _admit,
                                            "an lcchain.theory.cases.ChainCase, named as the entry point",
                                            name_of=lambda part: str(getattr(part, "name", "")))


def scene_cases() -> tuple[str, ...]:
    """What a scene's ``chain.case`` may be: the registry's cases (plugins included), then the literal's cases
    that no registered case makes (``custom``: the scene's own masses and springs)."""
    return (*CHAIN_CASES, *(case for case in CASES if case not in CHAIN_CASES))


def named_case(case: str | ChainCase) -> ChainCase | None:
    """The named case of that name (or the case itself, registered the first time), or None (a scene's
    ``custom`` chain, or a name no case has)."""
    if isinstance(case, str):
        return CHAIN_CASES.get(case)
    return CHAIN_CASES.accept("case", case)


def chain_for_case(case: str | ChainCase, N: int, walls: int = 0) -> Chain:
    """The chain of a named case.

    Parameters
    ----------
    case : {"one-mass", "two-mass", "uniform-free", "uniform-bounded", "perfect"} or ChainCase
        ``one-mass`` and ``two-mass`` are the optimal designs for this N
        (Tables I and II, computed by :mod:`lcchain.theory.design`); ``perfect``
        is the perfect cradle of N masses in bulk units (central mass and
        central spring 1, :func:`lcchain.perfect_design`; N = 3, 4, 5 are the
        paper's exact fractions, N = 4 with masses (5/3, 1, 1, 5/3)).
        A :class:`ChainCase` of one's own is used as given (registered under its ``name`` the first time).
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
        raise ParameterError("case", case, " | ".join(CHAIN_CASES))
    return named.chain(N, walls)
