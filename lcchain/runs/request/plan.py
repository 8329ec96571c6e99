"""The one entry to planning: :func:`plan_request` hands a request to its analysis's planner (:data:`PLANNERS`)."""

from __future__ import annotations

from collections.abc import Callable

from ...core.blas import fixed_blas_threads
from ...core.budget import Budget
from ...core.checks import instance
from ...theory.modes import Modes
from .ac import plan_ac
from .transient import plan_transient
from .types import AC, Analysis, Request, RequestPlan, Transient

__all__ = ["PLANNERS", "Planner", "plan_request"]

#: A planner: a request, its budget, the nominal chain's modes if known, the price of designing the chain.
Planner = Callable[[Request, Budget, Modes | None, float], RequestPlan]

#: Each analysis type's planner, found from the request's analysis object (a new analysis: its type in
#: :mod:`lcchain.runs.request.types`, its planner module beside :mod:`~lcchain.runs.request.transient`, one line here).
PLANNERS: dict[type[Analysis], Planner] = {Transient: plan_transient, AC: plan_ac}


@fixed_blas_threads
def plan_request(request: Request, budget: Budget | None = None, *, modes: Modes | None = None,
                 design_seconds: float = 0.0) -> RequestPlan:
    """The runs of a request, their steps chosen and their specs built, within a budget (no simulation).

    Parameters
    ----------
    request : Request
    budget : Budget, optional
        The most memory and time the request may take (default :class:`~lcchain.core.budget.Budget`).
    modes : Modes, optional
        The nominal chain's modes, when already computed.
    design_seconds : float
        What making the nominal chain costs, added to the request's price (a scene designs its chain).

    Raises
    ------
    ParameterError
        A request that cannot run: a component scale ngspice cannot take, exact theory beyond
        :data:`lcchain.core.limits.EXACT_MAX_N`, losses with coupled coils.
    BudgetError
        The estimated cost (per run, and all samples together) is beyond ``budget``.
    """
    instance("request", request, Request)
    instance("budget", budget, Budget, optional=True)
    instance("modes", modes, Modes, optional=True)
    planner = PLANNERS[type(request.analysis)]
    return planner(request, budget if budget is not None else Budget(), modes, design_seconds)
