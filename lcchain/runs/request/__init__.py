"""One request, and the planners that turn it into run specs.

A :class:`Request` is what a user asked for, frozen and picklable: the chain,
its units, how it is driven, the effects on the ladder, the analysis (a
:class:`Transient`, or an :class:`AC` sweep of the ladder's spectrum), and
where it runs.  :func:`plan_request` turns it into a :class:`RequestPlan`: the
realised chains (one per tolerance sample), the stop time, the step or the
steps of an extrapolation, and one :class:`~lcchain.runs.spec.RunSpec` per run,
each with the exact theory of its own circuit.  :func:`lcchain.simulate`, scenes
(``Scene.request()``), sweeps, the bench and the report all plan through it, so
the step is chosen in one place, and a run's netlist and its theory are both
made from the same realised chain and the same effects (they cannot disagree).

The modules: :mod:`~lcchain.runs.request.types` (the request and plan types),
one planner per analysis (:mod:`~lcchain.runs.request.transient`,
:mod:`~lcchain.runs.request.ac`: what differs between a transient and an AC
sweep, the netlist's analysis line, the price, the theory), and
:mod:`~lcchain.runs.request.plan`, whose :data:`~lcchain.runs.request.plan.PLANNERS`
finds the planner from the request's analysis object.  The specs say how they
run (:data:`lcchain.runs.execute.ANALYSIS_RUNS`).
"""

from __future__ import annotations

# Re-exported by name (no __all__): the API reference documents each on its own module's page.  Drive is the
# netlist's (lcchain.circuit.netlist), a request's as well.
from ...circuit.netlist import Drive as Drive
from .plan import plan_request as plan_request
from .transient import ACCURACY_LOOPS as ACCURACY_LOOPS
from .types import AC as AC
from .types import Analysis as Analysis
from .types import Request as Request
from .types import RequestPlan as RequestPlan
from .types import Transient as Transient
