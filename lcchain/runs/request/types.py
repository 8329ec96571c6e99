"""The request types: what a user asks of one simulation, and what a planner decides it will run.

A :class:`Request` is what a user asked for, frozen and picklable: the chain,
its units, how it is driven (:class:`lcchain.circuit.netlist.Drive`), the effects on the ladder, the
analysis (a :class:`Transient`, or an :class:`AC` sweep of the ladder's
spectrum), and where it runs.  A :class:`RequestPlan` is what one of the
planners (:mod:`lcchain.runs.request.transient`, :mod:`lcchain.runs.request.ac`)
made of it.  The helpers below them are what both planners (and
:meth:`RequestPlan.nominal_theory`) read from a request: its nominal circuit,
its realised chains, its netlist title, and whether the chain's theory is the
circuit's.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field, fields, is_dataclass
from typing import TypeVar

from ...circuit.effects import Effect, Losses, PreferredValues, Tolerance
from ...circuit.elements import Element, Pulse, adds_elements, ladder_elements
from ...circuit.ladder import Ladder
from ...circuit.netlist import Drive, SimulationOptions, circuit_elements
from ...compare.accuracy import accuracy_asked
from ...compare.extrapolate import ExtrapolationPlan
from ...core.checks import choice, instance, integer, real, strings
from ...core.errors import ParameterError
from ...core.limits import MAX_AC_POINTS, MAX_DT, MAX_TRANSITS, MIN_AC_POINTS
from ...core.types import (
    DEFAULT_C0,
    DEFAULT_L0,
    METHODS,
    PROBES,
    Backend,
    Method,
    Probes,
)
from ...spice.engines import DEFAULT_ENGINE, ac_engine, engine_named
from ...theory.chain import Chain
from ...theory.modes import Modes
from ..spec import DEFAULT_TIMEOUT, RunSpec, Theory

__all__ = ["Transient", "AC", "Analysis", "Request", "RequestPlan", "nominal_ladder", "chain_follows",
           "request_elements", "realised_chains", "netlist_title", "effect_named"]


#: An effect's type, for :meth:`Request.effect`.
E = TypeVar("E", bound=Effect)


@dataclass(frozen=True)
class Transient:
    """A transient analysis: how long to watch and how finely (give ``dt`` or ``accuracy``).

    Parameters
    ----------
    dt : float, optional
        Fixed maximum step, units of sqrt(L0 C0).
    accuracy : float, optional
        Wanted max |simulation - theory|: lcchain chooses the step (and whether to extrapolate).
    transits : int
        Arrivals to watch.
    method : {"trap", "gear"}
    extrapolate : {1, 2, 3}, optional
        Runs at dt, dt/2, dt/4 combined (:mod:`lcchain.compare.extrapolate`); None: one run for a given dt,
        the cheapest way for an accuracy.
    probes : {"ends", "all"}
        Save loops 1 and N, or every loop.
    """

    dt: float | None = None
    accuracy: float | None = None
    transits: int = 1
    method: Method = "trap"
    extrapolate: int | None = None
    probes: Probes = "ends"

    def __post_init__(self) -> None:
        if (self.dt is None) == (self.accuracy is None):
            raise ParameterError("dt/accuracy", (self.dt, self.accuracy), "exactly one of dt and accuracy")
        if self.dt is not None:
            object.__setattr__(self, "dt", real("dt", self.dt, above=0.0, at_most=MAX_DT, allowed=(
                f"0 < dt <= {MAX_DT:g} (in units of sqrt(L0*C0); the bulk period is 2 pi)")))
        else:  # refused here, not when the run is planned
            object.__setattr__(self, "accuracy", accuracy_asked(self.accuracy))
        # stored as an int: a numpy integer is accepted, and would not go into a run's key (JSON)
        object.__setattr__(self, "transits", integer("transits", self.transits, at_least=1, at_most=MAX_TRANSITS))
        choice("method", self.method, METHODS)
        if self.extrapolate is not None and (isinstance(self.extrapolate, bool) or self.extrapolate not in (1, 2, 3)):
            raise ParameterError("extrapolate", self.extrapolate, "1, 2 or 3 runs (1: no extrapolation)")
        choice("probes", self.probes, PROBES)

    def check(self, request: Request) -> None:
        """Refuse what the request's engine cannot do with a transient (extrapolation)."""
        engine = engine_named(request.engine)
        if not engine.extrapolates and self.extrapolate is not None and self.extrapolate > 1:
            raise ParameterError("extrapolate", self.extrapolate,
                                 f"1 with engine {engine.name} (no extrapolation): {engine.no_extrapolation}")



@dataclass(frozen=True)
class AC:
    """An AC analysis: the ladder driven in loop 1 by a unit AC voltage, swept over its normal frequencies.

    Its modes are fitted (:func:`lcchain.compare.spectral.compare_spectrum`) and compared with the driven modes
    of the same chain: omega_n, and P_n, each mode's coefficient in alpha_N(t); with losses also each mode's
    decay rate against 1/Q.  With effects whose elements are no chain's (real parts, coupled coils with losses)
    the circuit's own poles and residues take the chain's place (:func:`lcchain.compare.poles.compare_poles`):
    its every mode, which the sweep then covers (more than N where a coil or a capacitor resonates by itself).
    The request's drive does not apply (the source is the AC voltage); both end currents are saved.

    Parameters
    ----------
    points : int, optional
        Frequencies up to 5 % above the highest normal frequency, in even segments as fine as the poles they
        hold; default twice the fewest that separate every pole of each realised chain
        (:func:`lcchain.compare.spectral.sweep_grid`).  Fewer are refused before anything runs, naming the minimum.
    """

    points: int | None = None

    def __post_init__(self) -> None:
        if self.points is not None:
            object.__setattr__(self, "points", integer("points", self.points, at_least=MIN_AC_POINTS,
                                                       at_most=MAX_AC_POINTS))

    def check(self, request: Request) -> None:
        """Refuse an engine without an AC analysis, and a transport other than the engine's program."""
        engine = ac_engine(request.engine)  # an engine without an AC analysis is refused here, naming it
        if request.backend not in engine.ac_transports:
            raise ParameterError("backend", request.backend, f"{' | '.join(engine.ac_transports)} with an AC analysis "
                                 "(the engine's program)")
        if request.comments:
            raise ParameterError("comments", list(request.comments), "none with an AC analysis (its netlist has "
                                 "its own header)")



#: The analyses a request can ask for; each refuses what it cannot do (``check``) and has its planner
#: (:data:`lcchain.runs.request.plan.PLANNERS`).
Analysis = Transient | AC


@dataclass(frozen=True)
class Request:
    """Everything a user asks of one simulation, frozen and picklable.

    Parameters
    ----------
    chain : Chain
        The nominal chain (a named case or the user's own), bulk units, before the effects.
    analysis : Transient or AC
    drive : Drive
    effects : tuple of Effect
        In any order; those that change the chain (walls, coupling) apply to the nominal chain, preferred
        values and tolerances make the realised chains, the others add elements (losses).
    L0, C0 : float
        Bulk inductance (H) and capacitance (F).
    backend : {"batch", "shared"}
        The transport (one the engine has).
    engine : str
        The circuit simulator, a name in :data:`lcchain.spice.engines.ENGINES` (``"ngspice"``, ``"gnucap"``).
        An engine without aligned steps (gnucap) refuses ``extrapolate`` > 1 and makes one run for an
        accuracy; what its dialect cannot run (gnucap: a pulse) is refused when the specs are made.
    title : str, optional
        The netlist's first line (default: the chain's name, N and the excitation).
    comments : tuple of str
        ``*`` lines after the title.
    timeout : float
        Seconds before a run's simulator is killed.
    """

    chain: Chain
    analysis: Analysis
    drive: Drive = field(default_factory=Drive)
    effects: tuple[Effect, ...] = ()
    L0: float = DEFAULT_L0
    C0: float = DEFAULT_C0
    backend: Backend = "batch"
    title: str | None = None
    comments: tuple[str, ...] = ()
    timeout: float = DEFAULT_TIMEOUT
    engine: str = DEFAULT_ENGINE

    def __post_init__(self) -> None:
        instance("chain", self.chain, Chain)
        instance("analysis", self.analysis, (Transient, AC))
        instance("drive", self.drive, Drive)
        if not isinstance(self.effects, tuple):
            raise ParameterError("effects", self.effects, "a tuple of lcchain effects")
        kinds = [type(effect) for effect in self.effects]
        for effect in self.effects:
            instance("effects", effect, Effect)
            if kinds.count(type(effect)) > 1:
                raise ParameterError("effects", effect.key, "each effect at most once")
        object.__setattr__(self, "L0", real("L0", self.L0, above=0.0, unit="henry"))
        object.__setattr__(self, "C0", real("C0", self.C0, above=0.0, unit="farad"))
        engine = engine_named(self.engine)  # an Engine itself is registered under its name, which the request keeps
        object.__setattr__(self, "engine", engine.name)
        engine.check_transport("backend", self.backend)
        object.__setattr__(self, "comments", strings("comments", self.comments))
        object.__setattr__(self, "timeout", real("timeout", self.timeout, above=0.0, unit="seconds"))
        self.analysis.check(self)

    @property
    def transient(self) -> Transient:
        """The analysis, where only a transient can be (its steps, transits, probes)."""
        if not isinstance(self.analysis, Transient):
            raise ParameterError("analysis", type(self.analysis).__name__, "a Transient here (an AC request runs "
                                 "through plan_request and execute, or measure_spectrum for one chain)")
        return self.analysis

    def effect(self, kind: type[E]) -> E | None:
        """The request's effect of this type (typed as it), or None."""
        return next((effect for effect in self.effects if isinstance(effect, kind)), None)

    @property
    def Q(self) -> float | None:
        """The losses' quality factor (None: no losses), from the effects' responses."""
        values = [effect.response()["Q"] for effect in self.effects if "Q" in effect.response()]
        return values[0] if values else None

    def nominal(self) -> Chain:
        """The chain with the effects that change it (walls, coupling), before rounding and tolerances."""
        chain = self.chain
        for effect in self.effects:
            if not effect.on_parts:
                chain = effect.realise(chain, self.L0, self.C0)
        return chain

    @property
    def realised(self) -> bool:
        """Whether the runs simulate chains other than the nominal one (rounded or toleranced)."""
        tolerance = self.effect(Tolerance)
        return self.effect(PreferredValues) is not None or (tolerance is not None and tolerance.varies)

    @property
    def samples(self) -> int:
        """How many circuits the request runs."""
        tolerance = self.effect(Tolerance)
        return tolerance.samples if tolerance is not None and tolerance.varies else 1


@dataclass(frozen=True, eq=False)
class RequestPlan:
    """What a request will run, decided before any simulator starts.

    Attributes
    ----------
    request : Request
    nominal : Chain
        The chain with walls and coupling, before rounding and tolerances.
    chains : tuple of Chain
        The realised chains, one per tolerance sample (else the nominal, or its preferred-value rounding).
    modes : Modes
        Normal modes of the nominal chain (transit time, step choice).
    transit_time, tstop : float
        Units of sqrt(L0 C0): the end-to-end travel time and the end of the analysis (the window of the last
        transit, shifted by a pulse's centre).
    steps : tuple of float
        Each sample's runs: (dt,), or (dt, dt/2[, dt/4]) extrapolated, coarsest first.
    predicted_error : float, optional
        The extrapolation's predicted error (None for one run: its theory holds its own, where the model
        applies).
    reason : str
        Why extrapolation was not used where it was asked or considered ("" otherwise).
    accuracy_plan : ExtrapolationPlan, optional
        With an accuracy: the options weighed and the one chosen.
    specs : tuple of RunSpec
        ``len(steps)`` per chain (an AC sweep: one), in the order of ``chains``.
    points : int, optional
        An AC sweep's frequencies (None for a transient).
    omega_max : float, optional
        An AC sweep's last angular frequency, units of 1/sqrt(L0 C0) (None for a transient).

    An AC sweep has no stop time nor steps: ``tstop`` is 0 and ``steps`` empty.
    """

    request: Request
    nominal: Chain
    chains: tuple[Chain, ...]
    modes: Modes
    transit_time: float
    tstop: float
    steps: tuple[float, ...]
    predicted_error: float | None
    reason: str
    accuracy_plan: ExtrapolationPlan | None
    specs: tuple[RunSpec, ...]
    points: int | None = None
    omega_max: float | None = None

    @property
    def dt(self) -> float:
        """The coarsest run's step."""
        return self.steps[0]

    @property
    def runs(self) -> int:
        """Runs per sample."""
        return len(self.specs) // len(self.chains)

    @property
    def ladder(self) -> Ladder:
        """The nominal circuit."""
        return Ladder(self.nominal, self.request.L0, self.request.C0)

    def nominal_theory(self) -> Theory:
        """The exact theory of the nominal circuit's end loops (before rounding and tolerances): the circuit's own
        when its effects are no chain's, else the chain's (the value a study's samples spread around)."""
        request, ladder = self.request, self.ladder
        drive = request.drive
        own = None if chain_follows(request, ladder) else request_elements(request, ladder)
        return Theory(self.nominal, ladder.time_unit, I0=drive.I0, excitation=drive.kind,
                      Q=request.Q if own is None else None, pulse=drive.pulse, transit_time=self.transit_time,
                      modes=self.modes, circuit=own)

    def options(self, index: int = 0) -> SimulationOptions:
        """The analysis of run ``index`` of a sample (0: the coarsest)."""
        analysis = self.request.transient
        return SimulationOptions(dt=self.steps[index], tstop=self.tstop, method=analysis.method,
                                 aligned=self.runs > 1)


def effect_named(request: Request, ladder: Ladder, wrote: Callable[[set[str]], bool]) -> tuple[str, object] | None:
    """The field a refusal names for the first of the request's effects whose own elements (their names, beyond the
    bare ladder's) ``wrote`` accepts, and its value: ``effects.<key>.<parameter>`` and the number for an effect of
    one parameter, ``effects.<key>`` and the effect otherwise; None when none did.  Found from what each effect
    writes, not from its type."""
    plain = {element.name for element in ladder_elements(ladder, ())}
    for effect in request.effects:
        if wrote({element.name for element in ladder_elements(ladder, (effect,))} - plain):
            parameters: list[str] = [f.name for f in fields(effect)] if is_dataclass(effect) else []  # no ClassVar
            if len(parameters) == 1:
                return f"effects.{effect.key}.{parameters[0]}", getattr(effect, parameters[0])
            return f"effects.{effect.key}", effect
    return None


def nominal_ladder(request: Request) -> tuple[Chain, Ladder, bool]:
    """The nominal chain, its circuit, and whether the runs need the circuit's own theory (:func:`chain_follows`);
    a scale ngspice cannot take stops here."""
    nominal = request.nominal()
    ladder = Ladder(nominal, request.L0, request.C0)  # a scale ngspice cannot take stops here
    return nominal, ladder, not chain_follows(request, ladder)


def chain_follows(request: Request, ladder: Ladder) -> bool:
    """Whether the chain's theory (with the losses' Q) is the circuit's, whatever the effects' types.

    It is when the elements the effects write are the chain's own ladder, element for element, with resistors
    proportional to the coils (the losses' Q), and the coils are not coupled while lossy (the damping is then not
    proportional to the mass matrix).  Otherwise (a capacitor across a coil, a resistor not proportional to its
    coil, a part in series with a capacitor, any effect's own element) the runs are compared with the circuit's
    own exact theory, :class:`lcchain.circuit.exact.CircuitTheory`, of the very elements the netlist is written
    with: no effect can be compared with a theory that does not follow it.
    """
    if request.Q is not None and ladder.chain.coupled:
        return False
    chain_only = (Losses(request.Q),) if request.Q is not None else ()
    adders = tuple(effect for effect in request.effects if adds_elements(effect))
    if adders == chain_only:  # only the chain's own losses add elements: the same ladder by construction
        return True
    return ladder_elements(ladder, request.effects) == ladder_elements(ladder, chain_only)


def request_elements(request: Request, ladder: Ladder) -> tuple[Element | Pulse, ...]:
    """The elements a transient's netlist is written with, for the circuit's own theory."""
    drive = request.drive
    return circuit_elements(ladder, excitation=drive.kind, I0=drive.I0, pulse=drive.pulse, effects=request.effects)


def realised_chains(request: Request, nominal: Chain) -> list[Chain]:
    """The realised chains: one per tolerance sample, else the nominal or its rounding."""
    series = request.effect(PreferredValues)
    tolerance = request.effect(Tolerance)
    name = series.series if series is not None else None
    if tolerance is not None and tolerance.varies:
        return tolerance.draw(nominal, request.L0, request.C0, series=name)
    if series is not None:
        chain = series.realise(nominal, request.L0, request.C0)
        return [Chain(chain.masses, chain.springs, name=f"{nominal.name} {name}", coupling=chain.coupling)]
    return [nominal]


def netlist_title(request: Request, nominal: Chain, what: str) -> str:
    return request.title if request.title is not None else f"lcchain {nominal.name} chain N={nominal.N}, {what}"
