"""An AC analysis of lcchain's own ladder: complex vectors against frequency, in any engine that has one.

:func:`run_ac` checks its arguments and dispatches by ``simulator.engine`` to
:meth:`lcchain.spice.engine.Engine.run_ac` (ngspice: :mod:`lcchain.spice.ngspice`; gnucap:
:mod:`lcchain.spice.gnucap`), which runs the AC netlist (:func:`lcchain.circuit.netlist.ac_netlist_text`) with
the runner's discipline and returns the frequencies and the complex vectors, checked
(:func:`lcchain.spice.acdata.ac_result`): every vector present, as many points as asked, all finite.
"""

from __future__ import annotations

from collections.abc import Sequence

from ..core.checks import integer, real
from ..core.errors import ParameterError
from .acdata import AcResult
from .engines import DEFAULT_ENGINE, ac_engine, find_engine
from .simulator import Simulator
from .text import canonical_vector_name

__all__ = ["AcResult", "run_ac"]


def run_ac(netlist: str, vectors: Sequence[str], points: int, *, simulator: Simulator | None = None,
           timeout: float = 600.0, engine: str | None = None, foreign: bool = False,
           max_output_bytes: float | None = None, max_resident_bytes: float | None = None) -> AcResult:
    """Run lcchain's AC netlist in an engine and return its complex vectors.

    Parameters
    ----------
    netlist : str
        Written by :func:`lcchain.circuit.netlist.ac_netlist_text` (ngspice's dialect).
    vectors : sequence of str
        E.g. ``("i(l1)", "i(l20)")``.
    points : int
        The frequencies its ``.ac`` line asks for.
    simulator : Simulator, optional
        The engine's batch transport (its ``engine`` chooses the engine); found for ``engine`` when omitted.
    timeout : float
        Seconds after which the engine's process group is killed.
    engine : str, optional
        Only without a simulator, or equal to its engine (default ``"ngspice"``).
    foreign : bool
        A netlist lcchain did not write (already through :func:`lcchain.spice.foreign.allowed_netlist`): it runs in
        the sandbox (an engine that ``runs_foreign``), stopped when its output outgrows ``max_output_bytes`` or its
        memory ``max_resident_bytes``; with no ``vectors`` named, every vector it saved is read.

    Raises
    ------
    ParameterError
        Bad arguments, or an engine without an AC analysis (naming ``engine``).
    SimulationError
        The engine failed, timed out, or its output is not the analysis asked for.
    """
    if not isinstance(netlist, str) or ".ac " not in netlist.lower():
        raise ParameterError("netlist", type(netlist).__name__, "an AC netlist written by lcchain")
    names = [canonical_vector_name(v) for v in vectors]
    points = integer("points", points, at_least=1)
    timeout = real("timeout", timeout, above=0.0, unit="seconds")
    if simulator is None:
        simulator = find_engine(ac_engine(engine or DEFAULT_ENGINE).name)
    elif engine is not None and engine != simulator.engine:
        raise ParameterError("engine", engine, f"the simulator's own engine, {simulator.engine!r}")
    return ac_engine(simulator.engine).run_ac(netlist, names, points, simulator=simulator, timeout=timeout,
                                              foreign=foreign, max_output_bytes=max_output_bytes,
                                              max_resident_bytes=max_resident_bytes)
