"""The transient's planner: a :class:`~lcchain.runs.request.types.Transient` request's stop time, its step or the
steps of an extrapolation, its price, and one :class:`~lcchain.runs.spec.RunSpec` per realised chain and step, each
with the exact theory of its own circuit (:func:`plan_transient`)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace

import numpy as np

from ...circuit.elements import Element, Pulse
from ...circuit.exact import circuit_cost, circuit_states, circuit_theory, circuit_unknowns
from ...circuit.ladder import Ladder
from ...circuit.netlist import NetlistOutput, SimulationOptions, check_run_length, netlist_text, probe_names
from ...compare.accuracy import SAFETY, dt_for_accuracy, predicted_error, warn_if_unreliable
from ...compare.extrapolate import (
    AccuracyOptions,
    ExtrapolationPlan,
    member_steps,
    plan_for_accuracy,
    predicted_extrapolated_error,
    refusal,
    runs_for_step,
)
from ...core.budget import RUN_START_SECONDS, Budget, Estimate, max_points, run_estimate, sample_theory_seconds
from ...core.errors import ParameterError
from ...core.limits import EXACT_MAX_N
from ...spice.engines import engine_named
from ...spice.pricing import POINTS_PER_CYCLE
from ...theory.arrivals import arrival_window
from ...theory.chain import Chain
from ...theory.modes import Modes
from ...theory.response import loop_weights
from ...theory.spectrum import normal_modes
from ..execute import circuit_predicted_error, pulse_centre
from ..spec import RunSpec, Theory
from .types import (
    Request,
    RequestPlan,
    effect_named,
    netlist_title,
    nominal_ladder,
    realised_chains,
    request_elements,
)

__all__ = ["plan_transient", "ACCURACY_LOOPS"]

#: With probes = "all", the step's error is predicted on at most this many loops, evenly spaced, ends included.
ACCURACY_LOOPS = 64


def _run_points(modes: Modes, tstop: float, step: float) -> float:
    """The time points ngspice takes: one per ``step`` at least, and as many as its fastest mode's cycles call for
    (:data:`lcchain.spice.pricing.POINTS_PER_CYCLE`, as a foreign netlist's ringing is priced): a cradle tied to
    stiff walls (``--walls 1000000``: a mode near 2e6) steps far below its dt, and was priced at 1.5 s for a run
    of 40 s, past --max-time."""
    fastest = float(modes.omega[-1])  # ascending, in units of 1/sqrt(L0 C0), as tstop's (a chain has N >= 3)
    return max(tstop / step, POINTS_PER_CYCLE * fastest / (2.0 * np.pi) * tstop)


def plan_transient(request: Request, budget: Budget, modes: Modes | None, design_seconds: float) -> RequestPlan:
    """The transient's runs (:func:`lcchain.runs.request.plan.plan_request`)."""
    analysis, drive = request.transient, request.drive
    nominal, ladder, circuit = nominal_ladder(request)
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
    elements = request_elements(request, ladder) if circuit else None
    cost = _cost(request, N, elements)
    points = max_points(budget, saved=cost["saved"], compared=cost["compared"], unknowns=cost["unknowns"])
    steps, predicted, reason, accuracy_plan = _choose_steps(request, nominal, modes, tstop, points)

    def priced(steps: tuple[float, ...]) -> None:
        one = run_estimate(points=_run_points(modes, tstop, steps[-1]), **cost)
        one = replace(one, seconds=one.seconds * engine_named(request.engine).relative_cost)  # the engine's speed
        if elements is not None:  # the circuit's own theory beside each run: its eigen-solution and its response
            seconds, memory = circuit_cost(elements, int(tstop / steps[-1]) + 1)
            one = Estimate(one.what + f" and the circuit's exact theory ({circuit_states(elements)} states)",
                           one.memory + memory, one.seconds + seconds)
        name, value = ("dt", analysis.dt) if analysis.dt is not None else ("accuracy", analysis.accuracy)
        one.check(budget, name, value, "a larger step, a coarser accuracy or fewer transits")
        per_sample = sum(steps[-1] / h for h in steps)  # the members' costs relative to the finest
        compare = sample_theory_seconds(N)  # each realised chain's own modes (or the nominal's) and its comparison
        every = Estimate(f"{samples * len(steps)} runs of up to {one.what}", one.memory, design_seconds + samples * (
            one.seconds * per_sample + RUN_START_SECONDS * len(steps) + compare))
        every.check(budget, "effects.tolerance.samples" if samples > 1 else name, samples if samples > 1 else value,
                    "fewer samples")

    priced(steps)
    if elements is not None:
        _check_circuit(request, ladder, elements)
        if analysis.accuracy is not None and len(steps) == 1 and drive.pulse is None:
            # the step the chain's modes chose, made finer until the circuit's own modes predict the accuracy met
            # (its parts' resonances ignored, N = 6 with every part asked for 1e-4 reached 2.8e-3 and failed)
            finer = _step_for_circuit(elements, ladder, request, steps[0], tstop, analysis.accuracy)
            if finer != steps[0]:
                steps = (finer,)
                priced(steps)
    chains = realised_chains(request, nominal)  # the samples are drawn once the request is known to fit
    own_predictions: dict[int, float] = {}
    if analysis.accuracy is not None and any(chain is not nominal for chain in chains) and drive.pulse is None \
            and analysis.probes == "ends" and not circuit and (request.Q is None or len(steps) > 1):
        # an accuracy is every realised chain's (each sample, a rounding to a series): the nominal chain's step,
        # made finer until each one's own modes predict it met (a 5 % tolerance reached 1.4e-3 at an accuracy of
        # 1e-3 with the nominal's step)
        refined, own_predictions = _steps_for_samples(chains, steps, tstop, request, analysis.accuracy)
        if refined != steps:
            steps = refined
            priced(steps)
            if predicted is not None:
                predicted = predicted_extrapolated_error(modes, steps[0], len(steps), tstop, Q=request.Q)
    single = None
    if len(steps) == 1 and drive.pulse is None and request.Q is None and analysis.probes == "ends" and not circuit:
        # the accuracy model's prediction for the nominal chain's one run (samples: their own chains differ)
        single = predicted_error(modes, steps[0], tstop, method=analysis.method)
        warn_if_unreliable(method=analysis.method, transits=analysis.transits, predicted=single)
    specs = []
    aligned = len(steps) > 1
    probes = tuple(probe_names(N, analysis.probes))
    title = netlist_title(request, nominal, drive.kind)
    for chain in chains:
        sample = ladder if chain is nominal else Ladder(chain, request.L0, request.C0)
        own = None if elements is None else elements if chain is nominal else request_elements(request, sample)
        for i, h in enumerate(steps):
            options = SimulationOptions(dt=h, tstop=tstop, method=analysis.method, aligned=aligned)
            text = netlist_text(sample, options, drive, effects=request.effects,
                                output=NetlistOutput(title=title, comments=request.comments, probes=analysis.probes))
            # the circuit's own theory carries its losses among its elements; the chain is then the ideal ladder
            theory = Theory(chain, ladder.time_unit, I0=drive.I0, excitation=drive.kind,
                            Q=request.Q if own is None else None, pulse=drive.pulse, probes=analysis.probes,
                            transits=analysis.transits, dt=h, method=analysis.method,
                            predicted_error=single if chain is nominal else own_predictions.get(id(chain)),
                            transit_time=T, aligned=aligned,
                            modes=modes if chain is nominal else None, circuit=own)
            label = f"{chain.name} N={N} dt={h:.4g}" + (f" run {i + 1} of {len(steps)}" if aligned else "")
            specs.append(RunSpec(text, probes, tstop * ladder.time_unit, backend=request.backend,
                                 timeout=request.timeout, theory=theory, foreign=False, label=label,
                                 engine=request.engine))
    return RequestPlan(request, nominal, tuple(chains), modes, T, tstop, tuple(steps), predicted, reason,
                       accuracy_plan, tuple(specs))


#: Rounds of :func:`_steps_for_samples`: each makes the step finer by the worst sample's predicted error.
SAMPLE_STEP_ROUNDS = 6
#: After its first round, :func:`_steps_for_samples` predicts the samples within this fraction of the worst alone.
SAMPLES_NEAR_WORST = 0.7


def _steps_for_samples(chains: Sequence[Chain], steps: tuple[float, ...], tstop: float, request: Request,
                       accuracy: float) -> tuple[tuple[float, ...], dict[int, float]]:
    """The steps (the nominal chain's, for its accuracy) made finer until every realised chain's own modes predict
    its error within ``SAFETY * accuracy``, as the nominal's plan aims; and each sample's prediction of a single
    run, by ``id`` of its chain (an extrapolation's members have none of their own).  Every sample is predicted
    once (about 16 ms each at N = 100, 3 transits, an extrapolated pair), then those within
    :data:`SAMPLES_NEAR_WORST` of the worst at each finer step.  No cheaper ranking of the samples found the
    worst: neither the leading term of each mode's phase error nor a single run's prediction (the worst sample
    ranked 36th of 50 by the latter)."""
    analysis = request.transient
    runs = len(steps)
    target = SAFETY * accuracy
    own = [normal_modes(chain) for chain in chains]  # the samples' own (the nominal's is none of them)

    def errors(step: float, among: Sequence[Modes]) -> list[float]:
        if runs == 1:
            return [predicted_error(m, step, tstop, method=analysis.method) for m in among]
        return [predicted_extrapolated_error(m, step, runs, tstop, Q=request.Q) for m in among]

    found = errors(steps[0], own)
    worst = max(found)
    # a finer step lowers every sample's error about alike: the next rounds follow those near the worst alone
    near = [m for m, error in zip(own, found, strict=True) if error >= SAMPLES_NEAR_WORST * worst]
    refined = False
    for _ in range(SAMPLE_STEP_ROUNDS):
        if worst <= target * (1 + 1e-9):
            break
        # the error's order in the step: 2 for one trapezoidal run, 2 more for each member of an extrapolation (a
        # guess, aimed a tenth below the target so that one round mostly does: the next round's predictions check)
        steps = member_steps(steps[0] * min(0.98, max(0.3, (0.9 * target / worst) ** (1 / (2 * runs)))), runs)
        worst, refined = max(errors(steps[0], near)), True
    if runs > 1:
        return steps, {}
    final = errors(steps[0], own) if refined else found  # each sample's own prediction, as the nominal's has
    return steps, {id(chain): error for chain, error in zip(chains, final, strict=True)}


def _step_for_circuit(elements: tuple[Element | Pulse, ...], ladder: Ladder, request: Request, step: float,
                      tstop: float, accuracy: float) -> float:
    """``step`` made finer until the circuit's own modes (:func:`lcchain.runs.execute.circuit_predicted_error`, what
    its run is compared with) predict at most ``SAFETY * accuracy``; as given when they predict nothing."""
    drive, method = request.drive, request.transient.method
    exact = circuit_theory(elements)
    names = probe_names(ladder.chain.N, "ends")
    scale = drive.I0 * (ladder.time_unit if drive.kind == "displacement" else 1.0)
    target = SAFETY * accuracy

    def error(h: float) -> float | None:
        return circuit_predicted_error(exact, names, ladder.time_unit, scale, drive.kind, h, tstop, method)

    found = error(step)
    for _ in range(SAMPLE_STEP_ROUNDS):
        if found is None or found <= target * (1 + 1e-9):
            break
        step *= min(0.98, max(0.1, (0.9 * target / found) ** 0.5))  # the trapezoidal error: h^2
        found = error(step)
    return step


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
        field = error.field  # an element's name, or its kind's letter
        named = effect_named(request, ladder, lambda names: field in names or field in {name[0] for name in names})
        if named is None:
            raise
        raise ParameterError(*named, f"a circuit whose exact theory float64 can give ({error.field}: "
                             f"{error.allowed})") from None


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
            bounds = AccuracyOptions(extrapolate=asked, refused=refused, Q=Q, method=analysis.method,
                                     max_points=points)
            plan = plan_for_accuracy(modes, analysis.accuracy, tstop, bounds)
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
