"""One unit of work, described: a netlist to run and the theory to compare it with.

A :class:`RunSpec` is frozen and picklable, and it is everything a run needs:
the netlist text (already written: runs never edit it), the vectors to read,
the stop time, the backend, a timeout, and optionally a :class:`Theory` (the
exact linear response of the same circuit).  :func:`lcchain.runs.execute.execute`
turns it into a :class:`~lcchain.runs.execute.RunRecord`, in this process, in a
pool worker or on a Dask worker alike.

An AC run (``analysis="ac"``) has a :class:`SpectrumTheory` instead: the chain whose driven modes its fitted
poles and residues are compared with, or the circuit's own elements when they are no chain's.

A run's :meth:`RunSpec.key` is a hash of everything that determines its
result: the netlist text, the saved vectors, the stop time, the backend, the
theory's inputs, the engine (only when it is not ngspice, so that the keys of
stores made before engines stay the same) and the lcchain and engine versions.
"""

from __future__ import annotations

import hashlib
import json
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from ..core import __version__
from ..core.analyses import analysis_kind
from ..core.checks import choice, instance, integer, real
from ..core.checks import pulse as check_pulse
from ..core.errors import ParameterError
from ..core.json import JSONDict
from ..core.limits import MAX_AC_POINTS, MAX_TRANSITS, MIN_AC_POINTS
from ..core.types import (
    ANALYSIS_KINDS,
    DEFAULT_I0,
    EXCITATION_KINDS,
    METHODS,
    PROBES,
    PULSE_SHAPES,
    AnalysisKind,
    Backend,
    ExcitationKind,
    Method,
    Probes,
    PulseShape,
)
from ..spice.engines import DEFAULT_ENGINE, engine_named

if TYPE_CHECKING:  # a spec's theory is imported with it: a batch's specs have none, and start without numpy
    from ..circuit.elements import Element, Pulse
    from ..theory.chain import Chain
    from ..theory.modes import Modes

__all__ = ["Theory", "SpectrumTheory", "RunSpec", "DEFAULT_TIMEOUT"]

#: Seconds a run may take before ngspice's process group is killed.
DEFAULT_TIMEOUT = 3600.0


def _chain_fingerprint(chain: Chain) -> JSONDict:
    """The chain's values in full (its coupling only when coupled: the keys of stores made before coupling)."""
    return {"masses": [float(m).hex() for m in chain.masses], "springs": [float(k).hex() for k in chain.springs]} | (
        {"coupling": float(chain.coupling).hex()} if chain.coupled else {})


@dataclass(frozen=True)
class Theory:
    """What a run's loop currents are compared with: the exact response of the same circuit.

    Parameters
    ----------
    chain : Chain
        The simulated chain (a tolerance sample's own realised chain, with its
        coupling), bulk units: the netlist is written from the same chain.
    time_unit : float
        sqrt(L0 C0), seconds.
    I0 : float
        The excitation's current, ampere.
    excitation : {"kick", "displacement", "pulse"}
    Q : float, optional
        Quality factor of the series resistors (None: no losses).
    pulse : (shape, width), optional
        With ``excitation="pulse"``: ``"gaussian"`` or ``"rect"``, width in
        units of sqrt(L0 C0).
    probes : {"ends", "all"}
        Which loop currents the netlist saves (loops 1 and N, or every loop).
    transits : int
        Arrivals to compare.
    dt : float, optional
        The fixed step of the run (units of sqrt(L0 C0)), for the error split;
        None for adaptive stepping.
    method : {"trap", "gear"}
    predicted_error : float, optional
        The error model's prediction, reported beside the achieved error.
    transit_time : float, optional
        The transit time that centres the arrival windows (a tolerance study
        uses the nominal chain's for every sample); default: the chain's own.
    aligned : bool
        The run's steps are aligned (:attr:`lcchain.circuit.netlist.SimulationOptions.aligned`): no
        breakpoint at t = dt, which the error split's model must know.
    modes : Modes, optional
        The chain's modes when already computed (not part of the key).
    circuit : tuple of Element and Pulse, optional
        The elements the netlist is written with (:func:`lcchain.circuit.netlist.circuit_elements`), when they
        are no chain's (a real part, an effect's own element, coupled coils with losses): the run is then
        compared with the circuit's own exact theory (:class:`lcchain.circuit.exact.CircuitTheory`), and
        ``chain`` (with ``Q`` None) is the ideal ladder whose alpha_N(t) says what the effects cost the pulse.
        None: the chain's theory is the circuit's (the fast path, the paper's reference).
    """

    chain: Chain
    time_unit: float
    I0: float = DEFAULT_I0
    excitation: ExcitationKind = "kick"
    Q: float | None = None
    pulse: tuple[PulseShape, float] | None = None
    probes: Probes = "ends"
    transits: int = 1
    dt: float | None = None
    method: Method = "trap"
    predicted_error: float | None = None
    transit_time: float | None = None
    aligned: bool = False
    modes: Modes | None = field(default=None, compare=False, repr=False)
    circuit: tuple[Element | Pulse, ...] | None = None

    def __post_init__(self) -> None:
        from ..circuit.elements import Element, Pulse
        from ..theory.chain import Chain
        from ..theory.modes import Modes

        instance("chain", self.chain, Chain)
        real("time_unit", self.time_unit, above=0.0, unit="seconds")
        real("I0", self.I0, above=0.0, unit="ampere")
        if self.circuit is not None:
            if not isinstance(self.circuit, tuple) or not self.circuit \
                    or not all(isinstance(e, (Element, Pulse)) for e in self.circuit):
                raise ParameterError("circuit", type(self.circuit).__name__, "a tuple of lcchain elements")
            if self.Q is not None:
                raise ParameterError("Q", self.Q, "None with a circuit (its resistors are among its elements)")
        if self.Q is not None:
            real("Q", self.Q, above=0.0)
            if self.chain.coupled:
                raise ParameterError("Q", self.Q, "no losses with coupled coils: lcchain has no exact theory for "
                                     "them (the damping is not proportional to the mass matrix)")
        check_pulse(self.excitation, self.pulse, EXCITATION_KINDS, PULSE_SHAPES)
        choice("probes", self.probes, PROBES)
        object.__setattr__(self, "transits", integer("transits", self.transits, at_least=1, at_most=MAX_TRANSITS))
        if self.dt is not None:
            real("dt", self.dt, above=0.0)
        choice("method", self.method, METHODS)
        if not isinstance(self.aligned, bool):
            raise ParameterError("aligned", self.aligned, "True or False")
        if self.modes is not None and (not isinstance(self.modes, Modes) or self.modes.N != self.chain.N):
            raise ParameterError("modes", type(self.modes).__name__, f"the Modes of this chain (N = {self.chain.N})")

    @property
    def unknowns(self) -> int:
        """The simulator's unknowns for the run's circuit: 2N (3N with losses), or the circuit's own count."""
        if self.circuit is not None:
            from ..circuit.exact import circuit_unknowns  # scipy's: not for a spec without a circuit (issue 35)

            return circuit_unknowns(self.circuit)
        return (3 if self.Q is not None else 2) * self.chain.N

    def circuit_cost(self, times: float) -> tuple[float, float]:
        """(seconds, bytes) of the circuit's own theory at ``times`` times beside the run; (0, 0) for the chain's
        (priced by :func:`lcchain.core.budget.sample_theory_seconds`)."""
        from ..circuit.exact import circuit_cost  # scipy's: not for a spec without a circuit (issue 35)

        return (0.0, 0.0) if self.circuit is None else circuit_cost(self.circuit, int(times) + 1)

    def fingerprint(self) -> JSONDict:
        """Everything that determines the comparison, as plain JSON (the chain's values in full)."""
        return {
            **_chain_fingerprint(self.chain),
            "time_unit": float(self.time_unit).hex(), "I0": float(self.I0).hex(), "excitation": self.excitation,
            "Q": None if self.Q is None else float(self.Q).hex(),
            "pulse": None if self.pulse is None else [self.pulse[0], float(self.pulse[1]).hex()],
            "probes": self.probes, "transits": self.transits,
            "dt": None if self.dt is None else float(self.dt).hex(), "method": self.method,
            "transit_time": None if self.transit_time is None else float(self.transit_time).hex(),
        } | ({"aligned": True} if self.aligned else {}) | (
            {} if self.circuit is None else {"circuit": [element.card() for element in self.circuit]})


@dataclass(frozen=True)
class SpectrumTheory:
    """What an AC run's poles and residues are compared with: the driven modes of the same circuit.

    Parameters
    ----------
    chain : Chain
        The simulated chain (a tolerance sample's own), bulk units: the netlist is written from it.
    time_unit : float
        sqrt(L0 C0), seconds.
    impedance : float
        sqrt(L0 / C0), ohm: the admittances I/V times it are dimensionless.
    omega_max : float
        The sweep's last angular frequency, units of 1/sqrt(L0 C0).
    modes : Modes, optional
        The chain's driven modes (:func:`lcchain.theory.exact.driven_modes`) when already computed (not part of
        the key).
    Q : float, optional
        The losses' quality factor (:class:`lcchain.circuit.effects.Losses`): every mode decays at 1/Q and the fit
        finds each one's decay rate.  None: a lossless ladder.
    circuit : tuple of Element and Pulse, optional
        The AC netlist's elements with its source's place (:func:`lcchain.circuit.netlist.ac_circuit_elements`)
        when they are no chain's (a real part, an effect's own element, coupled coils with losses): the run's
        poles and residues are then compared with the circuit's own
        (:meth:`lcchain.circuit.exact.CircuitTheory.admittances`, :func:`lcchain.compare.poles.compare_poles`),
        its losses among its elements (``Q`` None), and ``chain`` is the ideal ladder.  None: the chain's.
    """

    chain: Chain
    time_unit: float
    impedance: float
    omega_max: float
    modes: Modes | None = field(default=None, compare=False, repr=False)
    Q: float | None = None
    circuit: tuple[Element | Pulse, ...] | None = None

    def __post_init__(self) -> None:
        from ..circuit.elements import Element, Pulse
        from ..theory.chain import Chain
        from ..theory.modes import Modes

        instance("chain", self.chain, Chain)
        real("time_unit", self.time_unit, above=0.0, unit="seconds")
        real("impedance", self.impedance, above=0.0, unit="ohm")
        real("omega_max", self.omega_max, above=0.0)
        if self.Q is not None:
            real("Q", self.Q, above=0.0)
        if self.modes is not None and (not isinstance(self.modes, Modes) or self.modes.N != self.chain.N):
            raise ParameterError("modes", type(self.modes).__name__, f"the Modes of this chain (N = {self.chain.N})")
        if self.circuit is not None:
            if not isinstance(self.circuit, tuple) or not any(isinstance(e, Pulse) for e in self.circuit) \
                    or not all(isinstance(e, (Element, Pulse)) for e in self.circuit):
                raise ParameterError("circuit", type(self.circuit).__name__, "a tuple of lcchain elements with the "
                                     "source's place (ac_circuit_elements)")
            if self.Q is not None:
                raise ParameterError("Q", self.Q, "None with a circuit (its resistors are among its elements)")

    def fingerprint(self) -> JSONDict:
        """Everything that determines the comparison, as plain JSON (the circuit's cards only when it has one: the
        keys of chains' runs are unchanged)."""
        return {"analysis": "ac", **_chain_fingerprint(self.chain), "time_unit": float(self.time_unit).hex(),
                "impedance": float(self.impedance).hex(), "omega_max": float(self.omega_max).hex()} | (
                    {} if self.Q is None else {"Q": float(self.Q).hex()}) | (
                    {} if self.circuit is None else {"circuit": [element.card() for element in self.circuit]})


@dataclass(frozen=True)
class RunSpec:
    """Everything one ngspice run needs, frozen and picklable.

    Parameters
    ----------
    netlist : str
        The complete netlist text, run as it is.
    vectors : tuple of str
        Vectors to read (``"i(l1)"``, ``"v(n3)"``); loop currents first when
        there is a theory (loop 1 ... loop N, as :attr:`Theory.probes` says).
    tstop : float
        End of the ``.tran`` analysis, seconds (an AC run: 0).
    backend : {"batch", "shared"}
    timeout : float
        Seconds before ngspice's process group is killed (the record says ``"timeout"``).
    theory : Theory or SpectrumTheory, optional
        What to compare with (a transient's, or an AC run's); None runs the netlist and only reads its vectors.
    cwd : str, optional
        The netlist's own folder, for netlists that ``.include`` files next to
        them (each must lie inside it; they are inlined before ngspice starts).
    trusted : bool
        Run the netlist as it is, ``.control`` blocks and outside includes
        included (``lcchain batch --allow-control``); otherwise every line must
        pass :func:`lcchain.spice.foreign.allowed_netlist`.
    foreign : bool
        Not written by lcchain (the default, and what every netlist from
        outside is): ngspice runs it in the sandbox of
        :mod:`lcchain.spice.sandbox`. lcchain's planners set False for their
        own netlists, which they know to hold nothing but the ladder. Not part
        of the key (where a run happens does not change its result).
    max_output_bytes : float, optional
        Stop the run when ngspice's raw file grows past this (the memory
        budget of a foreign netlist); not part of the key.
    max_resident_bytes : float, optional
        Stop the run when the simulator's processes hold more than this
        resident (a foreign netlist's limit from its price); not part of the key.
    label : str
        A name for progress lines and reports (not part of the key).
    engine : str
        The circuit simulator (:data:`lcchain.spice.engines.ENGINES`): ``"ngspice"`` (default) or
        ``"gnucap"``, which runs only lcchain's own netlists (``foreign=False``); the netlist is checked
        here against the engine's dialect, so what the engine cannot run is refused before any run.
    analysis : {"transient", "ac"}
        What the netlist's analysis is: its vectors are real against time, or complex against frequency.
    points : int, optional
        An AC run's frequencies (required with ``analysis="ac"``).
    check : bool
        Also compare every saved vector with the netlist's exact response (``lcchain batch --check``,
        :func:`lcchain.runs.check.reference_measurements`): the largest error is stored as the measurement
        ``check_max_abs_error`` (None, with the reason, when the netlist has no exact reference).
    """

    netlist: str
    vectors: tuple[str, ...]
    tstop: float
    backend: Backend = "batch"
    timeout: float = DEFAULT_TIMEOUT
    theory: Theory | SpectrumTheory | None = None
    cwd: str | None = None
    trusted: bool = False
    foreign: bool = True
    max_output_bytes: float | None = None
    label: str = field(default="", compare=False)
    engine: str = DEFAULT_ENGINE
    analysis: AnalysisKind = "transient"
    points: int | None = None
    max_resident_bytes: float | None = None
    check: bool = False

    def __post_init__(self) -> None:
        choice("analysis", self.analysis, ANALYSIS_KINDS)
        if not isinstance(self.netlist, str) or not self.netlist.strip():
            raise ParameterError("netlist", self.netlist, "non-empty netlist text")
        vectors: object = self.vectors
        if isinstance(vectors, str) or not isinstance(vectors, (tuple, list)) \
                or not all(isinstance(v, str) for v in vectors):
            raise ParameterError("vectors", vectors, "a tuple of vector names")
        object.__setattr__(self, "vectors", tuple(self.vectors))
        if analysis_kind(self.analysis).swept:
            object.__setattr__(self, "points", integer("points", self.points, at_least=1 if self.foreign else
                                                       MIN_AC_POINTS, at_most=MAX_AC_POINTS))
            if self.trusted is not False:
                raise ParameterError("trusted", self.trusted, "False with an AC analysis (it runs through the "
                                     "allow-list and the sandbox: no .control blocks, includes inlined)")
            object.__setattr__(self, "tstop", real("tstop", self.tstop, at_least=0.0, at_most=0.0,
                                                   allowed="0 (an AC run has no stop time)"))
            transports = engine_named(self.engine).ac_transports
            if self.backend not in transports:
                raise ParameterError("backend", self.backend, f"{' | '.join(transports)} with an AC analysis (the "
                                     "engine's program; the shared library runs transients only)")
        else:
            if self.points is not None:
                raise ParameterError("points", self.points, "None for a transient (points are an AC run's)")
            object.__setattr__(self, "tstop", real("tstop", self.tstop, above=0.0, unit="seconds"))
        object.__setattr__(self, "timeout", real("timeout", self.timeout, above=0.0, unit="seconds"))
        instance("theory", self.theory, SpectrumTheory if analysis_kind(self.analysis).swept else Theory, optional=True)
        for name in ("trusted", "foreign", "check"):
            if not isinstance(getattr(self, name), bool):
                raise ParameterError(name, getattr(self, name), "True or False")
        for name in ("max_output_bytes", "max_resident_bytes"):
            if getattr(self, name) is not None:
                real(name, getattr(self, name), above=0.0, unit="bytes")
        engine = engine_named(self.engine)
        engine.check_transport("backend", self.backend)
        if not engine.runs_foreign and (self.foreign or self.trusted):
            raise ParameterError("engine", self.engine, "ngspice for a netlist lcchain did not write (foreign or "
                                 f"trusted): {self.engine} runs only lcchain's own netlists")
        engine.dialect(self.netlist, self.vectors)  # what the engine cannot run is refused now, naming it

    def key(self, engine_version: str) -> str:
        """SHA-256 of everything that determines the run's record, for this version of its engine.

        The version is hashed under the name ``"ngspice"``, and the engine's name and the hash of the text
        it runs (its dialect) only when it is not ngspice: the keys of ngspice runs are those of stores made
        before there were engines.
        """
        data: JSONDict = {
            "netlist": self.netlist, "vectors": list(self.vectors), "tstop": float(self.tstop).hex(),
            "backend": self.backend, "cwd": self.cwd, "trusted": self.trusted, "lcchain": __version__,
            "ngspice": engine_version,
            "theory": None if self.theory is None else self.theory.fingerprint(),
        }
        if analysis_kind(self.analysis).keyed:  # only then: the keys of transients are those made before AC runs
            data["analysis"], data["points"] = self.analysis, self.points
        if self.check:  # only then: the keys of runs made without it stay
            data["check"] = True
        if self.engine != DEFAULT_ENGINE:  # and the text it runs: a change of its dialect is a new run
            data["engine"] = self.engine
            dialect = engine_named(self.engine).dialect(self.netlist, self.vectors)
            data["dialect"] = hashlib.sha256(dialect.encode("utf-8")).hexdigest()
        return hashlib.sha256(json.dumps(data, sort_keys=True).encode("utf-8")).hexdigest()
