"""What a circuit simulator must do for lcchain: the :class:`Engine` protocol.

An engine is one simulator program (ngspice, gnucap).  It is separate from
the *transport* that carries a run to it (:data:`lcchain.core.types.Backend`:
a child process, or ngspice's shared library in a child): an engine says
which transports it has.

To add an engine, write one module in :mod:`lcchain.spice` with a subclass of
:class:`Engine` that implements the four members below (and a fifth, ``run_ac``, if it has an AC analysis),
and add one line to :data:`lcchain.spice.engines.ENGINES`:

``name``
    The registry key (``--engine NAME``, ``[analysis] engine``).
``find(backend)``
    Locate the program for a transport and ask its version once; return a
    frozen :class:`~lcchain.spice.simulator.Simulator` whose ``engine`` is
    ``name``, or raise :class:`~lcchain.core.errors.SimulatorMissingError`
    (exit status 3) saying how to install it.
``dialect(netlist, vectors)``
    lcchain's own netlist (ngspice's dialect, as
    :func:`lcchain.circuit.netlist.netlist_text` writes it: L, C, R, B, V, K
    lines, ``IC=``, ``.options``, ``.tran step stop 0 maxstep uic``,
    ``.save``, ``.end``) as the text the engine runs; a line it cannot
    translate exactly raises :class:`~lcchain.core.errors.ParameterError`
    naming ``engine`` and what it cannot do.  It works on text: ``spice``
    knows nothing of chains.
``run(job, simulator, progress=None)``
    Run a transient (a :class:`~lcchain.spice.job.RunJob`: the netlist, the
    vectors, ``tstop`` and the run's limits, checked when it was made) and
    return a validated :class:`~lcchain.spice.result.RunResult` whose ``data``
    is a :class:`~lcchain.spice.result.TransientData` (time and the named real
    vectors, finite, ending at ``tstop``), or raise
    :class:`~lcchain.core.errors.SimulationError`; the child runs in a
    process group of its own, is killed on a timeout or an interrupt, and
    leaves nothing behind.
``run_ac(job, simulator)``
    Only for an engine with ``runs_ac``: run lcchain's AC netlist (an
    :class:`~lcchain.spice.job.AcJob`; :func:`lcchain.circuit.netlist.ac_netlist_text`: a ``V ... DC 0 AC 1``
    source, ``.options noopac``, ``.ac lin P f1 f2``, ``.save``) with the same
    discipline and return :func:`lcchain.spice.acdata.ac_result` of its
    columns (frequency in Hz, complex vectors by canonical name): the same
    :class:`~lcchain.spice.result.RunResult`, whose ``data`` is an
    :class:`~lcchain.spice.result.AcData`.  :func:`lcchain.spice.ac.run_ac`,
    the entry point, dispatches by ``simulator.engine``.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Sequence
from typing import ClassVar

from ..core.errors import ParameterError, SimulatorMissingError
from ..core.types import AnalysisKind, Backend
from .job import AcJob, Progress, RunJob
from .result import RunResult
from .simulator import Simulator

__all__ = ["Engine"]


class Engine(ABC):
    """A circuit simulator lcchain can run its ladders in (see the module's docstring for the recipe).

    Attributes
    ----------
    name : str
        Registry key.
    transports : tuple of str
        The backends it runs on (:data:`lcchain.core.types.BACKENDS`), the default first.
    install : str
        How to install it on Debian (quoted when it is missing).
    checks_cards : bool
        Whether ``lcchain check`` may run a foreign linear netlist in it as a netlist lcchain writes from the
        netlist's cards read as numbers (:mod:`lcchain.spice.gnucap_check`), when it does not ``runs_foreign``.
    runs_foreign : bool
        Whether it runs netlists lcchain did not write (the allow-list and the sandbox are ngspice's).
    extrapolates : bool
        Whether its runs can be members of a Richardson extrapolation: aligned steps whose grid
        :func:`lcchain.compare.extrapolate.aligned_grid` predicts (ngspice's, measured).
    no_extrapolation : str
        Why not, when it cannot (quoted in the refusal of ``--extrapolate``).
    steps_modelled : bool
        Whether :func:`lcchain.compare.accuracy.split_error` models its steps (ngspice's start-up ramp,
        measured), so that a run's error splits into integration and physics; otherwise the run reports its
        error and its prediction, and no split.
    relative_cost : float
        Its wall time per run over ngspice's for the same ladder and step: the budget's model of a run
        (:func:`lcchain.core.budget.run_estimate`, ngspice's, measured) is scaled by it.
    runs_ac : bool
        Whether it has an AC analysis (:meth:`run_ac`); an engine without one is refused by
        :func:`lcchain.spice.engines.ac_engine`, naming ``engine``.
    ac_relative_cost : float
        Its wall time per AC point over ngspice's (the spectrum's price is scaled by it).
    ac_transports : tuple of str
        The transports its AC analysis runs on (a request or a spec on another is refused, naming ``backend``).
    threaded_transports : tuple of str
        The transports whose runs may go side by side in threads of one process (the members of an
        extrapolation); runs on the others go one after the other.
    warm_below_seconds : float
        Runs predicted under this many seconds may go to its warm transport (:meth:`warm`) when a study chooses
        (``--transport auto``); 0: it has none.
    warm_analyses : tuple of str
        The analyses (:data:`lcchain.core.types.ANALYSIS_KINDS`) its warm transport runs.
    """

    name: ClassVar[str]
    transports: ClassVar[tuple[Backend, ...]]
    install: ClassVar[str]
    runs_foreign: ClassVar[bool] = False
    checks_cards: ClassVar[bool] = False
    extrapolates: ClassVar[bool] = False
    no_extrapolation: ClassVar[str] = "lcchain's model of aligned steps is ngspice's"
    steps_modelled: ClassVar[bool] = False
    relative_cost: ClassVar[float] = 1.0
    runs_ac: ClassVar[bool] = False
    ac_relative_cost: ClassVar[float] = 1.0
    ac_transports: ClassVar[tuple[Backend, ...]] = ()
    threaded_transports: ClassVar[tuple[Backend, ...]] = ()
    warm_below_seconds: ClassVar[float] = 0.0
    warm_analyses: ClassVar[tuple[AnalysisKind, ...]] = ()

    @abstractmethod
    def find(self, backend: str = "batch") -> Simulator:
        """Locate the engine for a transport and ask its version once."""

    @abstractmethod
    def dialect(self, netlist: str, vectors: Sequence[str]) -> str:
        """lcchain's netlist text in the engine's own dialect, saving ``vectors`` (canonical names)."""

    @abstractmethod
    def run(self, job: RunJob, simulator: Simulator, progress: Progress | None = None) -> RunResult:
        """Run a transient of lcchain's netlist text (ngspice's dialect) in the engine, within the job's limits
        (``timeout``, ``max_output_bytes``, ``max_resident_bytes``; see :func:`lcchain.spice.ngspice.runner.run`).
        ``progress`` hears the fraction of ``tstop`` simulated, 0.0 first and 1.0 after a successful run."""

    def run_ac(self, job: AcJob, simulator: Simulator) -> RunResult:
        """Run an AC netlist (ngspice's dialect) in the engine: ``job.points`` frequencies, the complex
        ``job.vectors`` (none: every vector saved).  ``job.foreign``: a netlist lcchain did not write, already
        through the allow-list, for an engine that ``runs_foreign`` only.  An engine without ``runs_ac`` keeps
        this refusal."""
        raise ParameterError("engine", self.name, "an engine with an AC analysis (its runs_ac)")

    @property
    def default_transport(self) -> Backend:
        """The transport a run uses unless told otherwise: the first of :attr:`transports`."""
        return self.transports[0]

    def user_transports(self) -> tuple[str, ...]:
        """The transports a user may name for this engine (``--backend``, ``analysis.backend``): its
        :attr:`transports`, and for an engine whose transports are a registry (ngspice's), that registry's
        plugins too."""
        return self.transports

    def takes_transport(self, name: str) -> bool:
        """Whether a user may name ``name`` for this engine (one of :meth:`user_transports`): a lookup, which an
        engine whose transports are a registry answers for its own names without reading the plugins."""
        return name in self.user_transports()

    def check_transport(self, field: str, name: object) -> str:
        """``name``, a transport a user may name for this engine (:meth:`takes_transport`).

        Raises
        ------
        ParameterError
            Naming ``field``, the value and this engine's transports.
        """
        if not isinstance(name, str) or not self.takes_transport(name):
            raise ParameterError(field, name, f"{' | '.join(self.user_transports())} (the transports of engine "
                                 f"{self.name})")
        return name

    def transport_for(self, backend: str) -> str:
        """The transport to find this engine again for a simulator on ``backend``: the same one when the engine
        offers it, else (a warm simulator, chosen per run by a study) the default one."""
        return backend if self.takes_transport(backend) else self.default_transport

    def warm(self, simulator: Simulator, workers: int = 1) -> Simulator:
        """Its warm transport for ``simulator`` (on the default transport): the same program kept loaded between
        runs, which must give the same bits (keys and results do not depend on it).  Only for an engine with
        ``warm_below_seconds``; raises :class:`~lcchain.core.errors.SimulatorMissingError` when it is not here.
        ``workers``: how many threads will run on it (an engine may start that many loaded programs now, and
        find them started when asked again)."""
        raise SimulatorMissingError(f"engine {self.name} has no warm transport")

    def prestart(self, workers: int) -> None:
        """Start ``workers`` of its warm programs before the engine is found (:meth:`find` on the default
        transport), on a guess of where they will run, so that their start overlaps the finding; :meth:`warm`
        adopts those the found engine can use and ends the others, and :meth:`release` ends them all.  A hint:
        an engine may start nothing."""
        return None

    def release(self, kill: bool = False) -> None:
        """End what :meth:`warm` keeps running (a study calls it when it ends, ``kill`` on an interrupt)."""
        return None  # an engine without a warm transport keeps nothing running

    def __repr__(self) -> str:
        return f"<engine {self.name}>"
