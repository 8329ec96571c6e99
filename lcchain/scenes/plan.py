"""Turning a scene into runs: its chains, its step, its netlists, its run specs (no simulation).

The scene (:mod:`lcchain.scenes.schema`, no physics there) becomes chains
(:mod:`lcchain.circuit.effects`: walls, preferred values, tolerance samples),
netlists (:func:`lcchain.circuit.netlist.netlist_text`: resistors only with
losses, a source only for a pulse, every loop current only for
``probes = "all"``) and one :class:`~lcchain.runs.spec.RunSpec` per realised
circuit, whose theory is the exact linear response of that very circuit.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ..circuit.effects import rounded, tolerance_samples, with_walls
from ..circuit.ladder import Ladder
from ..circuit.netlist import SimulationOptions, netlist_text, probe_names
from ..compare.accuracy import dt_for_accuracy
from ..compare.extrapolate import (
    member_steps,
    plan_for_accuracy,
    predicted_extrapolated_error,
    refusal,
    runs_for_step,
)
from ..core.blas import fixed_blas_threads
from ..core.budget import (
    RUN_START_SECONDS,
    Budget,
    Estimate,
    chain_seconds,
    max_points,
    run_estimate,
    sample_theory_seconds,
)
from ..core.errors import ParameterError
from ..core.limits import EXACT_MAX_N
from ..runs.execute import pulse_centre
from ..runs.spec import RunSpec, Theory
from ..spice.engines import engine_named
from ..theory.arrivals import arrival_window
from ..theory.cases import chain_for_case
from ..theory.chain import Chain
from ..theory.modes import Modes
from ..theory.response import loop_weights
from ..theory.spectrum import normal_modes
from .schema import Scene

__all__ = ["ScenePlan", "base_chain", "scene_chains", "realised", "sample_count", "scene_plan", "scene_netlist",
           "scene_specs", "losses_and_pulse", "ACCURACY_LOOPS"]

#: With probes = "all", the step's error is predicted on at most this many loops, evenly spaced, ends included.
ACCURACY_LOOPS = 64


def base_chain(scene: Scene) -> Chain:
    """The nominal chain of the scene (case or custom), with walls if asked."""
    spec = scene.chain
    if spec.case == "custom":
        assert spec.masses is not None and spec.springs is not None
        chain = Chain(np.array(spec.masses), np.array(spec.springs), name="custom")
    else:
        chain = chain_for_case(spec.case, spec.N)
    if scene.effects.walls is not None:
        chain = with_walls(chain, scene.effects.walls.K0)
    return chain


def realised(scene: Scene) -> bool:
    """Whether the scene simulates chains other than the nominal one (rounded or toleranced)."""
    tol = scene.effects.tolerance
    return scene.effects.preferred_values is not None or (tol is not None and bool(tol.L or tol.C or tol.samples > 1))


def sample_count(scene: Scene) -> int:
    """How many circuits the scene runs."""
    tol = scene.effects.tolerance
    return tol.samples if tol is not None and (tol.L or tol.C or tol.samples > 1) else 1


def scene_chains(scene: Scene, nominal: Chain | None = None) -> tuple[Chain, list[Chain]]:
    """(nominal chain, realised chains): one per tolerance sample, else one."""
    nominal = nominal if nominal is not None else base_chain(scene)
    effects, units = scene.effects, scene.units
    series = effects.preferred_values.series if effects.preferred_values is not None else None
    tol = effects.tolerance
    if tol is not None and (tol.L or tol.C or tol.samples > 1):
        chains = tolerance_samples(nominal, units.L0, units.C0, samples=tol.samples, seed=tol.seed,
                                   tol_L=tol.L, tol_C=tol.C, series=series)
    elif series is not None:
        chain = rounded(nominal, units.L0, units.C0, series)
        chains = [Chain(chain.masses, chain.springs, name=f"{nominal.name} {series}")]
    else:
        chains = [nominal]
    return nominal, chains


def losses_and_pulse(scene: Scene) -> tuple[float | None, tuple[str, float] | None]:
    """The scene's quality factor (None: no losses) and pulse (shape, width) (None: no pulse)."""
    excitation = scene.excitation
    Q = scene.effects.losses.Q if scene.effects.losses is not None else None
    pulse = (excitation.shape, excitation.width) if excitation.kind == "pulse" else None
    return Q, pulse  # type: ignore[return-value]


@dataclass(frozen=True, eq=False)
class ScenePlan:
    """What a scene will run, decided before ngspice starts.

    Attributes
    ----------
    nominal : Chain
        The chain of the scene's case (with walls if asked), before rounding
        and tolerances.
    chains : tuple of Chain
        The realised chains, one per tolerance sample (else the nominal, or
        its preferred-value rounding).
    modes : Modes
        Normal modes of the nominal chain (transit time, step choice).
    transit_time, tstop, dt : float
        Units of sqrt(L0 C0): the end-to-end travel time, the end of the
        analysis (the window of the last requested transit, shifted by the
        pulse's centre) and the maximum step (``analysis.dt``, or the largest
        step whose predicted error meets ``analysis.accuracy``, at most
        width/8 for a pulse); with extrapolation, dt is the coarsest run's.
    steps : tuple of float
        Each sample's runs: (dt,), or (dt, dt/2[, dt/4]) extrapolated
        (:mod:`lcchain.compare.extrapolate`).
    predicted_error : float, optional
        The extrapolation's predicted error (None for one run).
    reason : str
        Why extrapolation was not used where it was asked or considered.
    """

    nominal: Chain
    chains: tuple[Chain, ...]
    modes: Modes
    transit_time: float
    tstop: float
    dt: float
    steps: tuple[float, ...] = ()
    predicted_error: float | None = None
    reason: str = ""

    @property
    def runs(self) -> int:
        """Runs per sample."""
        return max(1, len(self.steps))


def _cost(scene: Scene, N: int, realised: bool) -> dict[str, int]:
    """The numbers a scene's run costs by (:func:`lcchain.core.budget.run_estimate`)."""
    saved = N if scene.output.probes == "all" else 2
    losses = scene.effects.losses is not None
    return {"saved": saved, "compared": saved, "unknowns": (3 if losses else 2) * N,
            "exact_N": N if (realised or scene.output.probes == "all") else 0}


def _accuracy_weights(scene: Scene, nominal: Chain) -> list[np.ndarray] | None:
    if scene.output.probes != "all":
        return None
    # Interior loops can have 4x the ends' error: predict it on up to ACCURACY_LOOPS of them.
    _, every = loop_weights(nominal)
    loops = np.unique(np.linspace(0, every.shape[1] - 1, min(ACCURACY_LOOPS, every.shape[1])).round().astype(int))
    return [every[:, i] for i in loops]


def _choose_steps(scene: Scene, nominal: Chain, modes: Modes, tstop: float,
                  points: float) -> tuple[tuple[float, ...], float | None, str]:
    """The runs of each sample (their steps), the extrapolation's predicted error, and why not extrapolated."""
    analysis = scene.analysis
    Q, pulse = losses_and_pulse(scene)
    engine = engine_named(analysis.engine, "analysis.engine")
    refused = refusal(method=analysis.method, pulse=pulse) or (
        "" if engine.extrapolates else f"engine {engine.name}: {engine.no_extrapolation}")
    asked = analysis.extrapolate
    if analysis.dt is not None:
        runs, reason = runs_for_step(asked, refused)
        steps = member_steps(float(analysis.dt), runs)
    else:
        assert analysis.accuracy is not None
        weights = _accuracy_weights(scene, nominal)
        if refused or asked == 1 or weights is not None:
            # one run: the single-run model knows interior loops and gear
            dt = dt_for_accuracy(modes, analysis.accuracy, tstop, method=analysis.method, weights=weights,
                                 max_points=points)
            steps = (dt,)
            reason = refused if (asked or 0) > 1 or (asked is None and refused) else ""
            if weights is not None and (asked or 0) > 1:
                reason = "probes = \"all\": the extrapolation's prediction covers the end loops only"
        else:
            plan = plan_for_accuracy(modes, analysis.accuracy, tstop, extrapolate=asked, Q=Q, max_points=points)
            steps, reason = plan.steps, plan.reason
    if scene.excitation.kind == "pulse":
        # the accuracy model is for free oscillation; resolve the pulse too
        assert scene.excitation.width is not None
        if steps[0] > scene.excitation.width / 8:
            steps = member_steps(scene.excitation.width / 8, len(steps))
    predicted = None
    if len(steps) > 1:
        predicted = predicted_extrapolated_error(modes, steps[0], len(steps), tstop, Q=Q)
    return steps, predicted, reason


#: Internal names of what a scene sets, and the scene keys the user wrote.
_SCENE_KEYS = {"L0": "units.L0", "C0": "units.C0", "K0": "effects.walls.K0", "dt": "analysis.dt",
               "accuracy": "analysis.accuracy", "N": "chain.N", "engine": "analysis.engine"}


@fixed_blas_threads
def scene_plan(scene: Scene, budget: Budget | None = None) -> ScenePlan:
    """Chains, stop time and step of a scene (no simulation), within a budget.

    Raises
    ------
    ParameterError
        Named by the scene's key and file, for a scene that cannot run: a
        component scale ngspice cannot take, or exact theory beyond
        :data:`lcchain.core.limits.EXACT_MAX_N`.
    BudgetError
        The scene's estimated cost (per run, and its samples together) is beyond ``budget``.
    """
    try:
        return _plan(scene, budget if budget is not None else Budget())
    except ParameterError as error:
        named = error.renamed(_SCENE_KEYS[error.field]) if error.field in _SCENE_KEYS else error
        raise named.located(scene.source) from None


def _plan(scene: Scene, budget: Budget) -> ScenePlan:
    nominal = base_chain(scene)
    Ladder(nominal, scene.units.L0, scene.units.C0)  # a scale ngspice cannot take stops here, before any theory
    N, samples = nominal.N, sample_count(scene)
    if N > EXACT_MAX_N and (realised(scene) or scene.output.probes == "all"):
        why = "every loop's response" if scene.output.probes == "all" else "tolerances or preferred values"
        raise ParameterError("chain.N", N, f"N <= {EXACT_MAX_N} with {why} (the theory needs the exact modes "
                             "of each realised chain)")
    modes = normal_modes(nominal)  # raises for a chain beyond both exact and closed-form modes
    T = modes.transit_time()
    Q, pulse = losses_and_pulse(scene)
    tstop = arrival_window(scene.analysis.transits, T)[1] + pulse_centre(scene.excitation.kind, pulse)
    cost = _cost(scene, N, realised(scene))
    points = max_points(budget, saved=cost["saved"], compared=cost["compared"], unknowns=cost["unknowns"])
    steps, predicted, reason = _choose_steps(scene, nominal, modes, tstop, points)
    dt = steps[0]
    one = run_estimate(points=tstop / steps[-1], **cost)
    one = replace(one, seconds=one.seconds * engine_named(scene.analysis.engine, "analysis.engine").relative_cost)
    field, value = ("dt", dt) if scene.analysis.dt is not None else ("accuracy", scene.analysis.accuracy)
    one.check(budget, field, value, "a larger step, a coarser accuracy or fewer transits")
    per_sample = sum(steps[-1] / h for h in steps)  # the members' costs relative to the finest
    theory = sample_theory_seconds(N)  # each realised chain's own modes (or the nominal's) and its comparison
    every = Estimate(f"{samples * len(steps)} runs of up to {one.what}", one.memory,
                     chain_seconds(scene.chain.case, N) + samples * (one.seconds * per_sample
                                                                     + RUN_START_SECONDS * len(steps) + theory))
    every.check(budget, "effects.tolerance.samples" if samples > 1 else field, samples if samples > 1 else value,
                "fewer samples")
    # What the engine cannot run (gnucap: a gaussian pulse's B-source) is refused now, before any sample is drawn.
    engine_named(scene.analysis.engine, "analysis.engine").dialect(
        scene_netlist(scene, nominal, dt, tstop, aligned=len(steps) > 1), probe_names(N, scene.output.probes))
    _, chains = scene_chains(scene, nominal)  # the samples are drawn once the scene is known to fit
    return ScenePlan(nominal, tuple(chains), modes, T, tstop, dt, steps, predicted, reason)


def scene_netlist(scene: Scene, chain: Chain, dt: float, tstop: float, *, aligned: bool = False) -> str:
    """The netlist of one realised chain of the scene: only the elements its effects need.

    Parameters
    ----------
    scene : Scene
    chain : Chain
        The nominal chain or one of its realisations (:func:`scene_chains`).
    dt, tstop : float
        Maximum step and stop time in units of sqrt(L0 C0) (:func:`scene_plan`).
    aligned : bool
        An extrapolation's member (:attr:`lcchain.circuit.netlist.SimulationOptions.aligned`).
    """
    Q, pulse = losses_and_pulse(scene)
    excitation = scene.excitation
    ladder = Ladder(chain, scene.units.L0, scene.units.C0)
    options = SimulationOptions(dt=dt, tstop=tstop, method=scene.analysis.method, aligned=aligned)
    return netlist_text(ladder, options, excitation=excitation.kind, I0=excitation.I0, probes=scene.output.probes,
                        title=scene.title, Q=Q, pulse=pulse)  # type: ignore[arg-type]


def scene_specs(scene: Scene, plan: ScenePlan) -> list[RunSpec]:
    """The run specs of the scene's realised circuits, each with its own exact theory.

    One per sample, or with extrapolation :attr:`ScenePlan.runs` per sample, coarsest first
    (:func:`lcchain.scenes.run.scene_result` combines them).
    """
    Q, pulse = losses_and_pulse(scene)
    units, excitation, analysis = scene.units, scene.excitation, scene.analysis
    time_unit = Ladder(plan.nominal, units.L0, units.C0).time_unit
    steps = plan.steps or (plan.dt,)
    aligned = len(steps) > 1
    specs = []
    for chain in plan.chains:
        for i, h in enumerate(steps):
            theory = Theory(chain, time_unit, I0=excitation.I0, excitation=excitation.kind, Q=Q, pulse=pulse,  # type: ignore[arg-type]
                            probes=scene.output.probes, transits=analysis.transits, dt=h, method=analysis.method,
                            transit_time=plan.transit_time, aligned=aligned,
                            modes=plan.modes if chain is plan.nominal else None)
            label = chain.name + (f" run {i + 1} of {len(steps)}" if aligned else "")
            specs.append(RunSpec(scene_netlist(scene, chain, h, plan.tstop, aligned=aligned),
                                 tuple(probe_names(chain.N, scene.output.probes)), plan.tstop * time_unit,
                                 backend=analysis.backend, theory=theory, foreign=False, label=label,
                                 engine=analysis.engine))
    return specs
