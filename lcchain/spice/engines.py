"""The engines lcchain can run its ladders in, by name: one registry, :data:`ENGINES`.

Adding an engine is one module (a subclass of :class:`lcchain.spice.engine.Engine`) and one line here, or, from
a package of its own, an entry point in the ``lcchain.engines`` group.
Everything else (``--engine``, ``[analysis] engine``, ``RunSpec.engine``, ``doctor``) reads this dict.
"""

from __future__ import annotations

from ..core.checks import choice
from ..core.errors import ParameterError
from ..core.registry import Registry
from ..core.types import DEFAULT_ENGINE
from .engine import Engine
from .gnucap import Gnucap
from .job import Progress, RunJob
from .ngspice.engine import Ngspice
from .result import RunResult
from .simulator import Simulator

__all__ = ["ENGINES", "DEFAULT_ENGINE", "engine_named", "ac_engine", "find_engine", "run_engine"]

def _admit(name: str, loaded: object) -> Engine:
    """An ``lcchain.engines`` entry point's object: an Engine (or an Engine subclass, made with no arguments)
    whose name is the entry point's."""
    engine = loaded() if isinstance(loaded, type) and issubclass(loaded, Engine) else loaded
    if not isinstance(engine, Engine):
        raise TypeError(f"{loaded!r} is not an lcchain.spice.engine.Engine")
    if engine.name != name:
        raise TypeError(f"its name is {engine.name!r}, not the entry point's")
    return engine


#: Engine name -> implementation; the first is the default.  Then the engines of the ``lcchain.engines`` entry
#: points of installed packages, read the first time the registry is.
ENGINES: Registry[Engine] = Registry("lcchain.engines", {"ngspice": Ngspice(), "gnucap": Gnucap()}, _admit,
                                     "an lcchain.spice.engine.Engine, named as the entry point",
                                     name_of=lambda part: str(getattr(part, "name", "")))


def engine_named(name: object, field: str = "engine") -> Engine:
    """The registered engine of that name, or ``name`` itself when it is an :class:`Engine` (or an Engine
    subclass, made with no arguments): registered under its own ``name`` the first time, as
    ``simulate(..., engine=MyEngine())`` gives it (a :class:`~lcchain.core.errors.ParameterError` naming
    ``field``)."""
    if isinstance(name, str):
        if name in ENGINES.held:  # an own engine (no plugin can take its name): no entry point is read for it
            return ENGINES[name]
        return ENGINES[choice(field, name, tuple(ENGINES))]
    return ENGINES.accept(field, name)


def ac_engine(name: object, field: str = "engine") -> Engine:
    """The registered engine of that name if it has an AC analysis (:attr:`Engine.runs_ac`), else a
    :class:`~lcchain.core.errors.ParameterError` naming ``field`` and the engines that have one."""
    found = engine_named(name, field)
    if not found.runs_ac:
        having = " | ".join(key for key, engine in ENGINES.items() if engine.runs_ac)
        raise ParameterError(field, found.name, f"an engine with an AC analysis: {having}")
    return found


def find_engine(engine: str = DEFAULT_ENGINE, backend: str = "batch") -> Simulator:
    """Locate an engine for a transport and ask its version once.

    Raises
    ------
    ParameterError
        An unknown engine, or a transport the engine does not have.
    SimulatorMissingError
        The engine is not installed; the message says how to install it.
    """
    found = engine_named(engine)
    found.check_transport("backend", backend)
    return found.find(backend)


def run_engine(job: RunJob, simulator: Simulator, progress: Progress | None = None) -> RunResult:
    """Run a transient (a checked :class:`~lcchain.spice.job.RunJob`) in the simulator's engine
    (:meth:`lcchain.spice.engine.Engine.run`)."""
    return engine_named(simulator.engine, "simulator.engine").run(job, simulator, progress)
