"""One request, and the one planner that turns it into run specs.

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

Each analysis type plans itself (its ``plan`` method): what differs between a
transient and an AC sweep (the netlist's analysis line, the price, the theory)
is in its own planner, and the specs say how they run
(:data:`lcchain.runs.execute.ANALYSIS_RUNS`).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import TypeVar

import numpy as np

from ..circuit.effects import Effect, Losses, PreferredValues, Tolerance
from ..circuit.elements import Element, Pulse, adds_elements, ladder_elements
from ..circuit.exact import circuit_cost, circuit_states, circuit_theory, circuit_unknowns
from ..circuit.ladder import Ladder
from ..circuit.netlist import (
    SimulationOptions,
    ac_circuit_elements,
    ac_netlist_text,
    check_frequency_scale,
    check_run_length,
    circuit_elements,
    netlist_text,
    probe_names,
)
from ..compare.accuracy import dt_for_accuracy, predicted_error, warn_if_unreliable
from ..compare.extrapolate import (
    ExtrapolationPlan,
    member_steps,
    plan_for_accuracy,
    predicted_extrapolated_error,
    refusal,
    runs_for_step,
)
from ..compare.grid import Segment
from ..compare.poles import CIRCUIT_SPECTRUM_MAX_MODES, CircuitModes
from ..compare.spectral import SPECTRUM_MAX_N, check_lossy, spectrum_estimate, sweep_grid
from ..core.blas import fixed_blas_threads
from ..core.budget import (
    RUN_START_SECONDS,
    Budget,
    Estimate,
    max_points,
    run_estimate,
    sample_theory_seconds,
)
from ..core.checks import choice, instance, integer, real, strings
from ..core.checks import pulse as check_pulse
from ..core.errors import ParameterError
from ..core.limits import EXACT_MAX_N, MAX_AC_POINTS, MAX_DT, MAX_I0, MAX_TRANSITS, MIN_AC_POINTS, MIN_I0
from ..core.types import (
    DEFAULT_C0,
    DEFAULT_I0,
    DEFAULT_L0,
    EXCITATION_KINDS,
    METHODS,
    PROBES,
    PULSE_SHAPES,
    Backend,
    ExcitationKind,
    Method,
    Probes,
    PulseShape,
)
from ..spice.engines import DEFAULT_ENGINE, ac_engine, engine_named
from ..theory.arrivals import arrival_window
from ..theory.chain import Chain
from ..theory.exact import driven_modes
from ..theory.modes import Modes
from ..theory.response import loop_weights
from ..theory.spectrum import normal_modes
from .execute import circuit_modes, pulse_centre
from .spec import DEFAULT_TIMEOUT, RunSpec, SpectrumTheory, Theory

__all__ = ["Drive", "Transient", "AC", "Analysis", "Request", "RequestPlan", "plan_request", "ACCURACY_LOOPS"]

#: With probes = "all", the step's error is predicted on at most this many loops, evenly spaced, ends included.
ACCURACY_LOOPS = 64


#: An effect's type, for :meth:`Request.effect`.
E = TypeVar("E", bound=Effect)


@dataclass(frozen=True)
class Drive:
    """How loop 1 is set in motion.

    Parameters
    ----------
    kind : {"kick", "displacement", "pulse"}
        An initial current I0 in L_1, an initial charge I0 sqrt(L0 C0) in loop 1, or a voltage pulse in loop 1.
    I0 : float
        Scale of the excitation, ampere (> 0).
    pulse : (shape, width), optional
        With ``kind="pulse"`` only: ``"gaussian"`` or ``"rect"``, width in units of sqrt(L0 C0).
    """

    kind: ExcitationKind = "kick"
    I0: float = DEFAULT_I0
    pulse: tuple[PulseShape, float] | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "I0", real("I0", self.I0, at_least=MIN_I0, at_most=MAX_I0, unit="ampere"))
        spec = check_pulse(self.kind, self.pulse, EXCITATION_KINDS, PULSE_SHAPES)
        object.__setattr__(self, "pulse", spec)


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
        integer("transits", self.transits, at_least=1, at_most=MAX_TRANSITS)
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

    def plan(self, request: Request, budget: Budget, modes: Modes | None, design_seconds: float) -> RequestPlan:
        """The transient's runs (:func:`plan_request`)."""
        return _plan_transient(request, budget, modes, design_seconds)


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
            integer("points", self.points, at_least=MIN_AC_POINTS, at_most=MAX_AC_POINTS)

    def check(self, request: Request) -> None:
        """Refuse an engine without an AC analysis, and a transport other than the engine's program."""
        engine = ac_engine(request.engine)  # an engine without an AC analysis is refused here, naming it
        if request.backend not in engine.ac_transports:
            raise ParameterError("backend", request.backend, f"{' | '.join(engine.ac_transports)} with an AC analysis "
                                 "(the engine's program)")
        if request.comments:
            raise ParameterError("comments", list(request.comments), "none with an AC analysis (its netlist has "
                                 "its own header)")

    def plan(self, request: Request, budget: Budget, modes: Modes | None, design_seconds: float) -> RequestPlan:
        """The AC sweep's runs, one per realised chain (:func:`plan_request`)."""
        return _plan_ac(request, budget, modes, design_seconds)


#: The analyses a request can ask for; each plans itself (``plan``) and refuses what it cannot do (``check``).
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
        own = None if _chain_follows(request, ladder) else _circuit(request, ladder)
        return Theory(self.nominal, ladder.time_unit, I0=drive.I0, excitation=drive.kind,
                      Q=request.Q if own is None else None, pulse=drive.pulse, transit_time=self.transit_time,
                      modes=self.modes, circuit=own)

    def options(self, index: int = 0) -> SimulationOptions:
        """The analysis of run ``index`` of a sample (0: the coarsest)."""
        analysis = self.request.transient
        return SimulationOptions(dt=self.steps[index], tstop=self.tstop, method=analysis.method,
                                 aligned=self.runs > 1)


def _cost(request: Request, N: int, elements: tuple[Element | Pulse, ...] | None = None) -> dict[str, int]:
    """The numbers a run costs by (:func:`lcchain.core.budget.run_estimate`): with the circuit's elements, the
    simulator's unknowns are its nodes and coils (the circuit's theory is priced beside it)."""
    saved = N if request.transient.probes == "all" else 2
    unknowns = (3 if request.Q is not None else 2) * N if elements is None else circuit_unknowns(elements)
    return {"saved": saved, "compared": saved, "unknowns": unknowns,
            "exact_N": N if (request.realised or request.transient.probes == "all") else 0}


def _check_circuit(request: Request, ladder: Ladder, elements: tuple[Element | Pulse, ...]) -> None:
    """Refuse, before anything runs, a nominal circuit whose exact theory float64 cannot give, naming the effect's
    parameter that wrote the element the theory names (found from what each effect writes, not from its type)."""
    try:
        circuit_theory(elements)
    except ParameterError as error:
        plain = {element.name for element in ladder_elements(ladder, ())}
        for effect in request.effects:
            names = {element.name for element in ladder_elements(ladder, (effect,))} - plain
            kinds = {name[0] for name in names}
            if error.field in names or error.field in kinds:
                parameters = list(getattr(effect, "__dataclass_fields__", {}))
                where = f"effects.{effect.key}" + (f".{parameters[0]}" if len(parameters) == 1 else "")
                raise ParameterError(where, getattr(effect, parameters[0]) if len(parameters) == 1 else effect,
                                     f"a circuit whose exact theory float64 can give ({error.field}: "
                                     f"{error.allowed})") from None
        raise


def _circuit(request: Request, ladder: Ladder) -> tuple[Element | Pulse, ...]:
    """The elements a transient's netlist is written with, for the circuit's own theory."""
    drive = request.drive
    return circuit_elements(ladder, excitation=drive.kind, I0=drive.I0, pulse=drive.pulse, effects=request.effects)


def _accuracy_weights(request: Request, nominal: Chain) -> list[np.ndarray] | None:
    if request.transient.probes != "all":
        return None
    # Interior loops can have 4x the ends' error: predict it on up to ACCURACY_LOOPS of them.
    _, every = loop_weights(nominal)
    loops = np.unique(np.linspace(0, every.shape[1] - 1, min(ACCURACY_LOOPS, every.shape[1])).round().astype(int))
    return [every[:, i] for i in loops]


def _choose_steps(request: Request, nominal: Chain, modes: Modes, tstop: float, points: float
                  ) -> tuple[tuple[float, ...], float | None, str, ExtrapolationPlan | None]:
    """Each sample's steps, the extrapolation's predicted error, why not extrapolated, and the accuracy's plan."""
    analysis, drive, Q = request.transient, request.drive, request.Q
    engine = engine_named(request.engine)
    refused = refusal(method=analysis.method, pulse=drive.pulse) or (
        "" if engine.extrapolates else f"engine {engine.name}: {engine.no_extrapolation}")
    asked = analysis.extrapolate
    plan = None
    predicted = None
    if analysis.dt is not None:
        runs, reason = runs_for_step(asked, refused)
        steps = member_steps(float(analysis.dt), runs)
    else:
        assert analysis.accuracy is not None
        weights = _accuracy_weights(request, nominal)
        if weights is not None:
            # one run: the single-run model knows interior loops
            steps = (dt_for_accuracy(modes, analysis.accuracy, tstop, method=analysis.method, weights=weights,
                                     max_points=points),)
            reason = "probes = \"all\": the extrapolation's prediction covers the end loops only" \
                if (asked or 0) > 1 else (refused if asked is None else "")
        else:
            plan = plan_for_accuracy(modes, analysis.accuracy, tstop, extrapolate=asked, refused=refused, Q=Q,
                                     method=analysis.method, max_points=points)
            steps = member_steps(plan.dt, plan.runs)
            reason = refused if (refused and asked != 1) else plan.reason
            predicted = plan.predicted_error if plan.runs > 1 else None
    if drive.pulse is not None and steps[0] > drive.pulse[1] / 8:
        # the accuracy model is for free oscillation; resolve the pulse too
        steps = member_steps(drive.pulse[1] / 8, len(steps))
        predicted = None
    if len(steps) > 1 and predicted is None:
        predicted = predicted_extrapolated_error(modes, steps[0], len(steps), tstop, Q=Q)
    return steps, predicted, reason, plan


def _chains(request: Request, nominal: Chain) -> list[Chain]:
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


def _title(request: Request, nominal: Chain, what: str) -> str:
    return request.title if request.title is not None else f"lcchain {nominal.name} chain N={nominal.N}, {what}"


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
    return request.analysis.plan(request, budget if budget is not None else Budget(), modes, design_seconds)


def _nominal_ladder(request: Request) -> tuple[Chain, Ladder, bool]:
    """The nominal chain, its circuit, and whether the runs need the circuit's own theory (:func:`_chain_follows`);
    a scale ngspice cannot take stops here."""
    nominal = request.nominal()
    ladder = Ladder(nominal, request.L0, request.C0)  # a scale ngspice cannot take stops here
    return nominal, ladder, not _chain_follows(request, ladder)


def _chain_follows(request: Request, ladder: Ladder) -> bool:
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


def _plan_transient(request: Request, budget: Budget, modes: Modes | None, design_seconds: float) -> RequestPlan:
    analysis, drive = request.transient, request.drive
    nominal, ladder, circuit = _nominal_ladder(request)
    N, samples = nominal.N, request.samples
    if N > EXACT_MAX_N and (request.realised or analysis.probes == "all" or circuit):
        why = ("every loop's response" if analysis.probes == "all" else "tolerances or preferred values"
               if request.realised else "the circuit's own theory (effects that are no chain's)")
        raise ParameterError("N", N, f"N <= {EXACT_MAX_N} with {why} (the theory needs the exact modes of each "
                             "realised chain)")
    if modes is not None and modes.N != N:
        raise ParameterError("modes", f"modes of N = {modes.N}", f"the modes of this chain (N = {N})")
    modes = modes if modes is not None else normal_modes(nominal)
    T = modes.transit_time()
    tstop = arrival_window(analysis.transits, T)[1] + pulse_centre(drive.kind, drive.pulse)
    check_run_length(nominal, tstop, ladder.time_unit, analysis.dt)
    elements = _circuit(request, ladder) if circuit else None
    cost = _cost(request, N, elements)
    points = max_points(budget, saved=cost["saved"], compared=cost["compared"], unknowns=cost["unknowns"])
    steps, predicted, reason, accuracy_plan = _choose_steps(request, nominal, modes, tstop, points)
    one = run_estimate(points=tstop / steps[-1], **cost)
    one = replace(one, seconds=one.seconds * engine_named(request.engine).relative_cost)  # the engine's own speed
    if elements is not None:  # the circuit's own theory beside each run: its eigen-solution and its response
        seconds, memory = circuit_cost(elements, int(tstop / steps[-1]) + 1)
        one = Estimate(one.what + f" and the circuit's exact theory ({circuit_states(elements)} states)",
                       one.memory + memory, one.seconds + seconds)
    name, value = ("dt", analysis.dt) if analysis.dt is not None else ("accuracy", analysis.accuracy)
    one.check(budget, name, value, "a larger step, a coarser accuracy or fewer transits")
    per_sample = sum(steps[-1] / h for h in steps)  # the members' costs relative to the finest
    compare = sample_theory_seconds(N)  # each realised chain's own modes (or the nominal's) and its comparison
    every = Estimate(f"{samples * len(steps)} runs of up to {one.what}", one.memory,
                     design_seconds + samples * (one.seconds * per_sample + RUN_START_SECONDS * len(steps) + compare))
    every.check(budget, "effects.tolerance.samples" if samples > 1 else name, samples if samples > 1 else value,
                "fewer samples")
    if elements is not None:
        _check_circuit(request, ladder, elements)
    chains = _chains(request, nominal)  # the samples are drawn once the request is known to fit
    single = None
    if len(steps) == 1 and drive.pulse is None and request.Q is None and analysis.probes == "ends" and not circuit:
        # the accuracy model's prediction for the nominal chain's one run (samples: their own chains differ)
        single = predicted_error(modes, steps[0], tstop, method=analysis.method)
        warn_if_unreliable(method=analysis.method, transits=analysis.transits, predicted=single)
    specs = []
    aligned = len(steps) > 1
    probes = tuple(probe_names(N, analysis.probes))
    title = _title(request, nominal, drive.kind)
    for chain in chains:
        sample = ladder if chain is nominal else Ladder(chain, request.L0, request.C0)
        own = None if elements is None else elements if chain is nominal else _circuit(request, sample)
        for i, h in enumerate(steps):
            options = SimulationOptions(dt=h, tstop=tstop, method=analysis.method, aligned=aligned)
            text = netlist_text(sample, options, excitation=drive.kind, I0=drive.I0, probes=analysis.probes,
                                title=title, comments=request.comments, pulse=drive.pulse, effects=request.effects)
            # the circuit's own theory carries its losses among its elements; the chain is then the ideal ladder
            theory = Theory(chain, ladder.time_unit, I0=drive.I0, excitation=drive.kind,
                            Q=request.Q if own is None else None, pulse=drive.pulse, probes=analysis.probes,
                            transits=analysis.transits, dt=h, method=analysis.method,
                            predicted_error=single if chain is nominal else None, transit_time=T, aligned=aligned,
                            modes=modes if chain is nominal else None, circuit=own)
            label = f"{chain.name} N={N} dt={h:.4g}" + (f" run {i + 1} of {len(steps)}" if aligned else "")
            specs.append(RunSpec(text, probes, tstop * ladder.time_unit, backend=request.backend,
                                 timeout=request.timeout, theory=theory, foreign=False, label=label,
                                 engine=request.engine))
    return RequestPlan(request, nominal, tuple(chains), modes, T, tstop, tuple(steps), predicted, reason,
                       accuracy_plan, tuple(specs))


#: An AC sweep: its segments, its frequencies in all, its last angular frequency (:func:`sweep_grid`).
_Grid = tuple[list[Segment], int, float]


def _sample_grid(chain: Chain, request: Request, analysis: AC) -> tuple[Ladder, Modes, _Grid]:
    """A realised chain's circuit, its driven modes and its sweep (segments as fine as its own poles)."""
    driven = driven_modes(chain)
    return Ladder(chain, request.L0, request.C0), driven, sweep_grid(driven.omega, analysis.points)


def _check_ac_price(one: Estimate, request: Request, budget: Budget, N: int, frequencies: int,
                    design_seconds: float, extra: tuple[str, float, float] | None = None) -> None:
    """Check one AC run's estimate (the sweep and its fit, at the engine's relative cost, plus ``extra``: what,
    seconds, bytes of a circuit's own theory) and the request's samples of it against ``budget``, each refusal
    naming the option that shrinks it: the chain's and the circuit's planners price alike."""
    analysis = request.analysis
    assert isinstance(analysis, AC)
    samples = request.samples
    one = replace(one, seconds=one.seconds * ac_engine(request.engine).ac_relative_cost)
    if extra is not None:
        what, seconds, memory = extra
        one = Estimate(one.what + what, one.memory + memory, one.seconds + seconds)
    name, value = ("points", frequencies) if analysis.points is not None else ("N", N)
    one.check(budget, name, value, "fewer frequencies (--points) or a smaller chain")
    every = Estimate(f"{samples} runs of {one.what}", one.memory,
                     design_seconds + samples * (one.seconds + RUN_START_SECONDS + sample_theory_seconds(N)))
    every.check(budget, "effects.tolerance.samples" if samples > 1 else name, samples if samples > 1 else value,
                "fewer samples")


def _plan_ac(request: Request, budget: Budget, modes: Modes | None, design_seconds: float) -> RequestPlan:
    """One AC sweep per realised chain, each against its own driven modes, on a grid placed from its own poles;
    priced (frequencies x unknowns, and the fit) on the nominal grid before the samples are drawn, and again on
    the largest sample's grid once their poles are known."""
    analysis = request.analysis
    assert isinstance(analysis, AC)  # its own plan method calls this
    nominal, ladder, circuit = _nominal_ladder(request)
    N = nominal.N
    if N > SPECTRUM_MAX_N:
        raise ParameterError("N", N, f"N <= {SPECTRUM_MAX_N} for an AC analysis (exact modes of the chain, and the "
                             "fit's dense least squares)")
    if modes is not None and modes.N != N:
        raise ParameterError("modes", f"modes of N = {modes.N}", f"the modes of this chain (N = {N})")
    if circuit:
        return _plan_circuit_ac(request, budget, modes, design_seconds, nominal, ladder)
    theory = driven_modes(nominal)
    check_frequency_scale(nominal, float(np.max(theory.omega)), ladder.time_unit)
    if request.Q is not None:  # before the grid: its own refusals (points) would hide the cause
        check_lossy("effects.losses.Q", request.Q, theory)
    segments, points, omega_max = sweep_grid(theory.omega, analysis.points)

    def price(frequencies: int) -> None:
        one = spectrum_estimate(frequencies, N, losses=request.Q is not None)
        _check_ac_price(one, request, budget, N, frequencies, design_seconds)

    price(points)
    chains = _chains(request, nominal)
    drawn = [(ladder, theory, (segments, points, omega_max)) if chain is nominal else
             _sample_grid(chain, request, analysis) for chain in chains]  # a sample's sweep: from its own poles
    largest = max(grid[1] for _, _, grid in drawn)
    if largest > points:
        price(largest)
    title = _title(request, nominal, "AC")
    probes = tuple(probe_names(N, "ends"))
    specs = []
    for chain, (sample, driven, grid) in zip(chains, drawn, strict=True):
        text = ac_netlist_text(sample, segments=grid[0], title=title, effects=request.effects)
        spectrum = SpectrumTheory(chain, ladder.time_unit, ladder.impedance, grid[2], modes=driven, Q=request.Q)
        specs.append(RunSpec(text, probes, 0.0, backend=request.backend, timeout=request.timeout, theory=spectrum,
                             foreign=False, label=f"{chain.name} N={N} AC {grid[1]} frequencies",
                             engine=request.engine, analysis="ac", points=grid[1]))
    modes = modes if modes is not None else normal_modes(nominal)
    return RequestPlan(request, nominal, tuple(chains), modes, modes.transit_time(), 0.0, (), None, "", None,
                       tuple(specs), points, omega_max)


def _circuit_grid(chain: Chain, request: Request, analysis: AC, ladder: Ladder | None = None
                  ) -> tuple[Ladder, tuple[Element | Pulse, ...], CircuitModes, _Grid]:
    """A realised chain's circuit, its AC elements with the source's place, their exact modes and its sweep
    (segments as fine as the circuit's own poles, up to 5 % above the highest)."""
    sample = ladder if ladder is not None else Ladder(chain, request.L0, request.C0)
    elements = ac_circuit_elements(sample, request.effects)
    exact = circuit_modes(elements, chain.N, sample.time_unit, sample.impedance)
    if exact.N > CIRCUIT_SPECTRUM_MAX_MODES:
        raise ParameterError("N", chain.N, f"a circuit of at most {CIRCUIT_SPECTRUM_MAX_MODES} modes for an AC "
                             f"analysis with effects that are no chain's (this one has {exact.N}: its fit is dense)")
    # no range of decay rates is refused here: the fit tells apart modes whose resonances overlap (measured:
    # two-mass N = 20 with R = 0.01, two modes 0.018 apart whose decay rates add up to more, Q_n to 3e-13)
    return sample, elements, exact, sweep_grid(exact.omega, analysis.points)


def _plan_circuit_ac(request: Request, budget: Budget, modes: Modes | None, design_seconds: float, nominal: Chain,
                     ladder: Ladder) -> RequestPlan:
    """The AC sweeps of a circuit whose effects are no chain's: each realised chain's circuit against its own
    exact poles and residues (:class:`lcchain.compare.poles.CircuitModes`), on a grid placed from them, which
    covers every mode of the circuit (a coil's self-resonance, a capacitor's ESL resonance: as many as the
    circuit has, which may be more than N).  Priced as a chain's sweep of as many modes as the circuit has, plus
    the circuit's theory."""
    analysis = request.analysis
    assert isinstance(analysis, AC)
    N = nominal.N  # N and the modes checked by _plan_ac
    _, elements, exact, (segments, points, omega_max) = _circuit_grid(nominal, request, analysis, ladder)
    check_frequency_scale(nominal, float(np.max(exact.omega)), ladder.time_unit)

    def price(frequencies: int, count: int) -> None:
        seconds, memory = circuit_cost(elements, 1)
        _check_ac_price(spectrum_estimate(frequencies, max(N, count), losses=exact.lossy), request, budget, N,
                        frequencies, design_seconds,
                        extra=(f" and the circuit's exact theory ({circuit_states(elements)} states)", seconds, memory))

    price(points, exact.N)
    chains = _chains(request, nominal)
    drawn = [(ladder, elements, exact, (segments, points, omega_max)) if chain is nominal else
             _circuit_grid(chain, request, analysis) for chain in chains]
    largest = max(grid[1] for *_, grid in drawn)
    if largest > points:
        price(largest, max(own.N for _, _, own, _ in drawn))
    title = _title(request, nominal, "AC")
    probes = tuple(probe_names(N, "ends"))
    specs = []
    for chain, (sample, own, _, grid) in zip(chains, drawn, strict=True):
        text = ac_netlist_text(sample, segments=grid[0], title=title, effects=request.effects)
        # the circuit's theory carries its losses among its elements; the chain is the ideal ladder
        spectrum = SpectrumTheory(chain, ladder.time_unit, ladder.impedance, grid[2], circuit=own)
        specs.append(RunSpec(text, probes, 0.0, backend=request.backend, timeout=request.timeout, theory=spectrum,
                             foreign=False, label=f"{chain.name} N={N} AC {grid[1]} frequencies (circuit)",
                             engine=request.engine, analysis="ac", points=grid[1]))
    modes = modes if modes is not None else normal_modes(nominal)
    return RequestPlan(request, nominal, tuple(chains), modes, modes.transit_time(), 0.0, (), None, "", None,
                       tuple(specs), points, omega_max)
