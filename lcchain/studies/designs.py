"""Rows of the paper's tables as units of work (issue 23): each row of Tables I and II is one optimal design
(:func:`lcchain.theory.design.optimal_design`), independent of the others, and the cold report spends much of
its time on them; :class:`lcchain.studies.background.Background` designs them on every core."""

from __future__ import annotations

import time

from ..core.json import LooseJSONObject
from ..core.types import DesignCase
from ..theory.design import optimal_design
from .background import Job

__all__ = ["design_row", "design_cost", "design_task"]


def design_row(case: DesignCase, N: int) -> LooseJSONObject:
    """One row of Table I or II: ``Design.to_dict()`` and the ``seconds`` its design took."""
    start = time.perf_counter()
    row = optimal_design(case, N).to_dict()
    return {**row, "seconds": time.perf_counter() - start}


def design_cost(case: str, N: int) -> float:
    """Rough seconds a design takes, for the order rows are sent to a pool in (measured on 2 cores: two-mass
    12 s at N = 1e5 and 0.4 s at N = 1000, one-mass 10 s at N = 5e5; every design pays about 0.2 s)."""
    return _COST_PER_MASS[case] * N + 0.2


#: A design's seconds per mass (the measurements of :func:`design_cost`).
_COST_PER_MASS = {"one-mass": 2e-5, "two-mass": 1.2e-4}


def design_task(case: DesignCase, N: int) -> Job[LooseJSONObject]:
    """The design of (case, N) as a :class:`~lcchain.studies.background.Job` keyed ``("row", case, N)``."""
    return Job(("row", case, N), design_cost(case, N), design_row, (case, N))
