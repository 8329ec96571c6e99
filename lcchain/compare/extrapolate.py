"""Richardson extrapolation of fixed-step trapezoidal runs to the zero-step limit (pure numpy/scipy).

Why it works here
-----------------
The trapezoidal rule is symmetric, so its global error at a fixed time has
an expansion in even powers of the step: on each mode it only warps the
frequency, omega~ = (2/h) atan(omega h / 2) = omega - omega^3 h^2 / 12 +
omega^5 h^4 / 80 - ... (:mod:`.accuracy`).  Runs at h, h/2 and h/4 combined
with the weights of :data:`WEIGHTS` cancel the h^2 term (a pair) or the h^2
and h^4 terms (a triple): the error falls like h^4 or h^6 instead of h^2.
ngspice's start-up and breakpoint steps are backward-Euler steps, whose
phase error is odd (h^3); ngspice takes them tiny (a hundredth of the step,
then doubling), and measured pairs converge as h^4 to 1e-8 (a pair at
dt = 0.04, 0.02 on the N = 100 two-mass chain: predicted 6.78e-7, measured
6.77e-7; at 0.02, 0.01: 4.24e-8 and 4.25e-8).  Uniform losses (every mode
decays at 1/Q) keep the expansion; a pulse with a kink (rect) breaks it
(measured: a pair improves 9x per halving instead of 16x), gear has no such
expansion (it damps), and adaptive steps are not h, h/2, h/4: those are
refused (:func:`refusal`) and the run falls back to one step.

The steps
---------
Richardson needs the members' errors to be the same function of the step.
An ordinary ngspice run restarts its steps after the breakpoint at its print
step t = dt, with a backward-Euler step, and its first steps depend on the
truncation-error test: the grids of runs at dt and dt/2 are not the same up
to scale, and the odd terms of those steps leave 1e-6 spikes at early times.
So the members are *aligned* runs
(:attr:`lcchain.circuit.netlist.SimulationOptions.aligned`): print step =
tstop (no breakpoint inside) and the truncation test off, and ngspice then
takes exactly the steps :data:`ALIGNED_RAMP` times h, then h, whenever
h <= tstop / 1000 (:func:`aligned_grid` gives the rule for larger steps,
whose ramp starts at tstop / 10^4).  Only the two backward-Euler start-up
steps keep an odd h^3 term, which the prediction holds.

The prediction
--------------
:func:`predicted_extrapolated_error` models each member with the
trapezoidal model on its own aligned grid
(:func:`lcchain.compare.accuracy.trap_response`, which reproduces ngspice to
~1e-13), combines the models exactly as the runs will be combined, and
takes the largest difference from the exact modal sum; with losses, times
the decay e^(-t/2Q).  It is computed before any run, so ``--accuracy`` is
met on the first try.

The grid
--------
The combination is made on the coarsest run's own time points; each finer
run is brought onto them by an interpolating spline of degree 7
(:data:`SPLINE_DEGREE`) through its own points: the grids are alike, not
the same points (after its ramp the run at h steps from 1.6 h, the run at
h/2 from 0.8 h: 2.6 h is not among its points).  Its error for a mode of
frequency omega
sampled every h is about (omega h)^8 / 8!: 1e-13 for the bulk band's edge
(omega = 2) at h = 0.05.  The prediction includes it (the models go through
the same splines), and :func:`interpolation_error` reports it alone: the
spline through each finer run's model against the model at the grid.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
import scipy  # its submodules load on first use: commands that need no theory never import them

from ..core.blas import fixed_blas_threads
from ..core.budget import NGSPICE_SECONDS_PER_UNKNOWN_POINT, BudgetError
from ..core.checks import real
from ..core.errors import ParameterError
from ..core.limits import ACCURACY_FLOOR, MAX_ACCURACY_DT
from ..theory.modes import Modes, cosine_sum
from .accuracy import SAFETY, dt_for_accuracy, predicted_error, trap_response, warped_frequencies

__all__ = ["WEIGHTS", "SPLINE_DEGREE", "EXTRAPOLATIONS", "ALIGNED_RAMP", "aligned_grid", "member_steps",
           "refusal", "runs_for_step", "predicted_extrapolated_error", "ExtrapolationPlan", "AccuracyOptions",
           "plan_for_accuracy",
           "combine",
           "interpolation_error", "run_seconds"]

#: Weights of the runs at h, h/2, h/4 (Romberg): 1 run, a pair (h^2 cancelled), a triple (h^2, h^4 cancelled).
WEIGHTS: dict[int, tuple[float, ...]] = {1: (1.0,), 2: (-1.0 / 3.0, 4.0 / 3.0),
                                         3: (1.0 / 45.0, -20.0 / 45.0, 64.0 / 45.0)}
#: ngspice 39's first steps of an aligned run (:attr:`lcchain.circuit.netlist.SimulationOptions.aligned`), in
#: units of its step h when h <= tstop / 1000 (:func:`aligned_grid` has the general rule); the first two are
#: backward-Euler steps, then every step is h.
ALIGNED_RAMP = (0.1, 0.1, 0.2, 0.4, 0.8)
#: Number of runs lcchain may combine.
EXTRAPOLATIONS = (1, 2, 3)
#: Degree of the splines that bring the finer runs onto the coarsest run's time points.
SPLINE_DEGREE = 7
#: Seconds one ngspice run costs beyond its time points (process start, netlist, raw file, theory set-up),
#: measured 0.03 - 0.05 s at N = 20 - 1000 (benchmarks/overhead.md): a run is worth this many points.
RUN_OVERHEAD_S = 0.05
#: Seconds per time point and mode of the comparison with theory (the exact modal sum at every point).
THEORY_SECONDS_PER_MODE_POINT = 2.5e-9
#: The largest omega h of the coarsest run: 2/h atan(omega h/2) has an expansion in h^2 only for omega h < 2,
#: and Richardson's weights need its first terms to dominate ((omega h/2)^2 <= 1/4 here).
EXPANSION_LIMIT = 1.0
#: The most time points (finest run) and points x modes the prediction of an extrapolation is computed on:
#: beyond, the runs would be far beyond any useful accuracy (N = 1000 at 1e-7 needs 5.6e4 points) and the model
#: alone would take minutes and gigabytes (a wall spring of 1e12 on N = 4 asks for 1e9 points).
MODEL_MAX_POINTS = 2e6
MODEL_MAX_MODE_POINTS = 5e8
#: The step search stops when the prediction is within this relative band below the target.
_ERROR_BAND = 0.12


def member_steps(dt: float, runs: int) -> tuple[float, ...]:
    """h, h/2, h/4 for the first ``runs`` members."""
    return tuple(dt / 2**i for i in range(runs))


def refusal(*, method: str = "trap", stepping: str = "fixed", pulse: tuple[str, float] | None = None) -> str:
    """Why runs cannot be extrapolated (one sentence), or "" when they can."""
    if method != "trap":
        return (f"method={method}: gear damps every mode as well as delaying it, so its error has no expansion in "
                "powers of the step to cancel")
    if stepping != "fixed":
        return "adaptive stepping: ngspice chooses its own steps, so the runs are not at h, h/2, h/4"
    if pulse is not None and pulse[0] == "rect":
        return ("a rect pulse: its jumps break the error's expansion (a pair improves 9x per halving instead of "
                "16x, measured)")
    return ""


def runs_for_step(asked: int | None, refused: str) -> tuple[int, str]:
    """Runs at a given step: those asked (default one), one when refused; and the reason when a refusal overrode a
    request for more."""
    runs = 1 if refused or asked is None else asked
    return runs, refused if (asked or 0) > 1 else ""


def _weights_rows(modes: Modes, ends: Sequence[str]) -> list[np.ndarray]:
    return [modes.density if end == "first" else modes.transfer for end in ends]


def aligned_grid(h: float, tstop: float) -> np.ndarray:
    """The time points of an aligned ngspice run at step h, to tstop (:data:`ALIGNED_RAMP`).

    ngspice 39 starts with two steps of min(tstop / 1000, h) / 10, doubles the step until it reaches h, then
    steps h and ends on tstop (measured: the model of each member then matches ngspice to ~1e-13).
    """
    h = real("dt", h, above=0.0)
    first = min(tstop / 1000.0, h) / 10.0
    steps = [first, first]
    while steps[-1] < h:
        steps.append(min(2.0 * steps[-1], h))
    ramp = np.cumsum(steps[:-1])  # the last one is h: the uniform part
    ramp = ramp[ramp < tstop * (1 - 1e-12)]
    start = ramp[-1] if ramp.size else 0.0
    count = int(math.floor((tstop - start) / h * (1 + 1e-12)))
    t = np.concatenate((ramp, start + h * np.arange(1, count + 1)))
    if t.size == 0 or t[-1] < tstop * (1 - 1e-12):
        t = np.append(t, tstop)
    return t


def _envelope(t: np.ndarray, Q: float | None) -> np.ndarray | float:
    return np.exp(-t / (2.0 * Q)) if Q is not None else 1.0


def _rows(modes: Modes, ends: Sequence[str], weights: Sequence[np.ndarray] | None) -> list[np.ndarray]:
    return _weights_rows(modes, ends) if weights is None else [np.asarray(w, dtype=float) for w in weights]


@fixed_blas_threads
def predicted_extrapolated_error(modes: Modes, dt: float, runs: int, tstop: float, *,
                                 ends: Sequence[str] = ("first", "last"), Q: float | None = None,
                                 weights: Sequence[np.ndarray] | None = None) -> float:
    """Predicted max |combination of the aligned runs at dt, dt/2, ... - exact theory|, before any run.

    Each member is modelled by :func:`lcchain.compare.accuracy.trap_response` on its own aligned grid
    (:func:`aligned_grid`: start-up ramp and backward-Euler steps included; ngspice matches it to ~1e-13),
    the models are combined exactly as the runs will be (:func:`combine`: the same splines, the same grid),
    and the result is compared with the exact modal sum.  So the prediction holds the uncancelled odd terms
    of the start-up steps and the interpolation as well as the h^(2 runs) term.  With losses the difference
    is multiplied by e^(-t/2Q) (every mode decays at that rate; the warp of the decay itself is O(h^2/Q^2)).
    """
    if runs not in WEIGHTS:
        raise ParameterError("extrapolate", runs, "1, 2 or 3 runs")
    dt = real("dt", dt, above=0.0)
    rows = _rows(modes, ends, weights)
    times = [aligned_grid(h, tstop) for h in member_steps(dt, runs)]
    models = [np.vstack([trap_response(w, modes.omega, t) for w in rows]) for t in times]
    grid, combined, _ = combine(times, models)
    worst = 0.0
    for w, row in zip(rows, combined, strict=True):
        diff = np.abs(row - np.asarray(cosine_sum(w, modes.omega, grid))) * _envelope(grid, Q)
        worst = max(worst, float(np.max(diff)))
    return worst


def run_seconds(N: int, tstop: float, steps: Sequence[float], *, unknowns: float | None = None) -> float:
    """Estimated wall time of runs at these steps: ngspice's points, the theory at every point, the overheads."""
    unknowns = 2.0 * N if unknowns is None else unknowns
    per_point = NGSPICE_SECONDS_PER_UNKNOWN_POINT * unknowns + THEORY_SECONDS_PER_MODE_POINT * N * 2
    return sum(tstop / h * per_point + RUN_OVERHEAD_S for h in steps)


@dataclass(frozen=True)
class ExtrapolationPlan:
    """How ``--accuracy`` will be met: the runs, their steps, the prediction and the estimated cost.

    Attributes
    ----------
    runs : int
        1, 2 or 3.
    dt : float
        The coarsest step (units of sqrt(L0 C0)); the members are dt, dt/2, dt/4.
    predicted_error : float
        The error the combination is predicted to reach (before any run).
    seconds : float
        Estimated wall time of all the runs.
    considered : tuple of (runs, dt, predicted_error, seconds)
        Every option weighed (the cheapest won).
    reason : str
        Why extrapolation was not used ("" when it was, or when one run was simply cheapest).
    """

    runs: int
    dt: float
    predicted_error: float
    seconds: float
    considered: tuple[tuple[int, float, float, float], ...]
    reason: str = ""

    @property
    def steps(self) -> tuple[float, ...]:
        return member_steps(self.dt, self.runs)

    def to_dict(self) -> dict[str, object]:
        return {"runs": self.runs, "dt": list(self.steps), "predicted_error": self.predicted_error,
                "estimated_seconds": self.seconds, "reason": self.reason,
                "considered": [{"runs": r, "dt": d, "predicted_error": e, "estimated_seconds": s}
                               for r, d, e, s in self.considered]}


def _largest_step(error: Callable[[float], float], runs: int, target: float, smallest: float,
                  largest: float = MAX_ACCURACY_DT) -> tuple[float, float] | None:
    """Largest coarse step in [smallest, largest] whose error(dt) is at most target (error ~ dt^(2 runs))."""
    if largest < smallest:
        return None
    order = 2.0 * runs
    dt = max(smallest, min(largest, 0.05))
    e = error(dt)
    best = None
    previous = None
    for _ in range(30):
        if e <= target:
            if best is None or dt > best[0]:
                best = (dt, e)
            if e >= target * (1 - _ERROR_BAND) or dt >= largest:
                return best
        slope = order
        if previous is not None and previous[0] != dt:
            fitted = math.log(previous[1] / e) / math.log(previous[0] / dt)
            if 0.5 * order < fitted < 2.0 * order:
                slope = fitted
        new = min(largest, dt * (target * (1 - 0.5 * _ERROR_BAND) / e) ** (1.0 / slope))
        if new < smallest:
            if dt <= smallest:
                return best
            new = smallest
        previous = (dt, e)
        dt, e = new, max(error(new), 1e-300)
    return best


def _single_run(modes: Modes, accuracy: float, tstop: float, safety: float, max_points: float | None, *,
                exact: bool, method: str = "trap") -> tuple[float, float] | None:
    """(dt, predicted error) of the one run that meets the accuracy, or None beyond the budget.

    Not ``exact``: from the dt^2 law through the prediction at dt = 0.05 (the next term of the warp is
    (omega dt)^2 3/20 smaller: 0.2 % at the band's edge), which costs a fraction of the exact search at the
    small steps one run needs; a single run is only worth its exact step when it wins, and
    :func:`plan_for_accuracy` then asks again with ``exact``.
    """
    probe = min(MAX_ACCURACY_DT, 0.05)
    if not exact and probe * float(np.max(modes.omega)) <= EXPANSION_LIMIT:  # else the dt^2 law does not hold
        dt = probe * math.sqrt(safety * accuracy / max(predicted_error(modes, probe, tstop, method=method), 1e-300))
        dt = min(dt, MAX_ACCURACY_DT)
        if max_points is not None and dt < tstop / max_points:
            return None
        return dt, safety * accuracy
    try:
        dt = dt_for_accuracy(modes, accuracy, tstop, safety=safety, max_points=max_points, method=method)
    except BudgetError:
        return None
    return dt, predicted_error(modes, dt, tstop, method=method)


@dataclass(frozen=True)
class AccuracyOptions:
    """What bounds :func:`plan_for_accuracy`'s choice besides the chain, the accuracy and the stop time.

    Parameters
    ----------
    extrapolate : {1, 2, 3}, optional
        Force this many runs; None: the cheapest.
    refused : str
        A reason extrapolation does not apply (:func:`refusal`): one run, and the reason is kept.
    Q : float, optional
        Uniform losses (the prediction decays with them).
    safety : float
        Fraction of the accuracy aimed at.
    max_points : float, optional
        The most time points one run may have (its budget): the finest member's.
    unknowns : float, optional
        ngspice's unknowns per point (default 2 N).
    method : {"trap", "gear"}
        The single run's method (gear is never extrapolated: give its ``refused`` reason too).

    Raises
    ------
    ParameterError
        ``extrapolate`` other than 1, 2, 3 or None.
    """

    extrapolate: int | None = None
    refused: str = ""
    Q: float | None = None
    safety: float = SAFETY
    max_points: float | None = None
    unknowns: float | None = None
    method: str = "trap"

    def __post_init__(self) -> None:
        if self.extrapolate is not None and self.extrapolate not in EXTRAPOLATIONS:
            raise ParameterError("extrapolate", self.extrapolate, "1, 2 or 3 runs (1: no extrapolation)")


@fixed_blas_threads
def plan_for_accuracy(modes: Modes, accuracy: float, tstop: float,
                      options: AccuracyOptions | None = None) -> ExtrapolationPlan:
    """The cheapest of one run, a pair and a triple that meets ``accuracy`` (predicted), or the one forced.

    Parameters
    ----------
    modes : Modes
    accuracy : float
        Wanted max |result - theory|, at least :data:`lcchain.core.limits.ACCURACY_FLOOR`.
    tstop : float
        End of the runs, units of sqrt(L0 C0).
    options : AccuracyOptions, optional
        The runs forced or refused, the losses, the safety margin, the budget's points, the method (default
        :class:`AccuracyOptions`: the cheapest of 1, 2, 3 runs, trap, no losses, no budget).

    Raises
    ------
    BudgetError
        No option meets the accuracy within ``max_points``.
    """
    accuracy = real("accuracy", accuracy, above=0.0, below=1.0,
                    allowed="a number with 0 < accuracy < 1 (max |simulation - theory|)")
    if accuracy < ACCURACY_FLOOR:
        raise ParameterError("accuracy", accuracy, f"an accuracy >= {ACCURACY_FLOOR:g}: ngspice's rounding grows "
                             "with its steps, so it does not reliably reach less")
    if options is None:
        options = AccuracyOptions()
    elif not isinstance(options, AccuracyOptions):
        raise ParameterError("options", options, "an AccuracyOptions")
    extrapolate, refused, Q, safety = options.extrapolate, options.refused, options.Q, options.safety
    max_points, unknowns, method = options.max_points, options.unknowns, options.method
    choices = [1] if refused else ([extrapolate] if extrapolate is not None else list(EXTRAPOLATIONS))
    target = safety * accuracy
    considered = []
    for runs in choices:
        if runs == 1:  # an ordinary run, with its breakpoint: the model of lcchain.compare.accuracy
            found: tuple[float, float] | None = _single_run(modes, accuracy, tstop, safety, max_points,
                                                            exact=len(choices) == 1, method=method)
        else:
            # the budget's smallest step, and the model's: its cost grows with the finest run's points
            budget_points = MODEL_MAX_POINTS if max_points is None else min(max_points, MODEL_MAX_POINTS)
            smallest = tstop / min(budget_points, MODEL_MAX_MODE_POINTS / modes.N) * 2 ** (runs - 1)

            def error(dt: float, runs: int = runs) -> float:
                return predicted_extrapolated_error(modes, dt, runs, tstop, Q=Q)

            # The expansion in h^2 converges for omega h / 2 < 1: no coarse step beyond EXPANSION_LIMIT / omega_max.
            largest = min(MAX_ACCURACY_DT, EXPANSION_LIMIT / float(np.max(modes.omega)))
            found = _largest_step(error, runs, target, smallest, largest)
        if found is not None:
            dt, e = found
            considered.append((runs, dt, e, run_seconds(modes.N, tstop, member_steps(dt, runs), unknowns=unknowns)))
    if not considered:  # the single run's own refusal says what it would need
        dt_for_accuracy(modes, accuracy, tstop, safety=safety, max_points=max_points, method=method)
        raise BudgetError("accuracy", accuracy, "an accuracy this machine can afford with one, two or three runs "
                          "(each is limited by --max-memory and --max-time)")
    runs, dt, e, seconds = min(considered, key=lambda option: option[3])
    if runs == 1 and len(choices) > 1:  # the estimate won: now the exact step
        try:
            dt = dt_for_accuracy(modes, accuracy, tstop, safety=safety, max_points=max_points, method=method)
            e = predicted_error(modes, dt, tstop, method=method)
            seconds = run_seconds(modes.N, tstop, (dt,), unknowns=unknowns)
        except BudgetError:  # beyond the budget after all: the next cheapest, or the single run's own refusal
            considered = [option for option in considered if option[0] != 1]
            if not considered:
                raise
            runs, dt, e, seconds = min(considered, key=lambda option: option[3])
    return ExtrapolationPlan(runs, dt, e, seconds, tuple(considered), refused)


# ------------------------------------------------------------------ combining the runs
def _spline(t: np.ndarray, y: np.ndarray, grid: np.ndarray) -> np.ndarray:
    degree = min(SPLINE_DEGREE, t.size - 1)
    return np.asarray(scipy.interpolate.make_interp_spline(t, y, k=degree)(grid))


def combine(times: Sequence[np.ndarray], signals: Sequence[np.ndarray]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The extrapolated signals on the coarsest run's time points.

    Parameters
    ----------
    times : sequence of ndarray
        Each run's time points (coarsest first, then h/2, h/4), same units.
    signals : sequence of ndarray, shape (R, J_m)
        Each run's R signals at its time points.

    Returns
    -------
    grid, combined, keep : ndarray (J,), ndarray (R, J), ndarray of bool (J_0,)
        The coarse grid (the coarsest run's points that every finer run covers), sum_m w_m y_m on it, and
        which of the coarsest run's points the grid kept.
    """
    runs = len(times)
    if runs not in WEIGHTS or len(signals) != runs:
        raise ParameterError("runs", runs, "1, 2 or 3 runs, each with its time points and signals")
    start = max(float(np.asarray(t)[0]) for t in times)
    stop = min(float(np.asarray(t)[-1]) for t in times)
    coarse = np.asarray(times[0], dtype=float)
    keep = (coarse >= start) & (coarse <= stop)
    grid = coarse[keep]
    combined = WEIGHTS[runs][0] * np.asarray(signals[0], dtype=float)[:, keep]
    for weight, t, y in zip(WEIGHTS[runs][1:], times[1:], signals[1:], strict=True):
        rows = np.asarray(y, dtype=float)
        combined = combined + weight * np.vstack([_spline(np.asarray(t, dtype=float), row, grid) for row in rows])
    return grid, combined, keep


@fixed_blas_threads
def interpolation_error(modes: Modes, times: Sequence[np.ndarray], grid: np.ndarray, steps: Sequence[float], *,
                        ends: Sequence[str] = ("first", "last")) -> float:
    """What bringing the finer runs onto ``grid`` costs, measured on their models.

    For each finer run: the spline through its model (the warped modal sum at its own time points) against
    the same model at the grid, weighted as in the combination; the largest over signals and runs.
    """
    worst = 0.0
    runs = len(times)
    for w in _weights_rows(modes, ends):
        for weight, t, h in zip(WEIGHTS[runs][1:], times[1:], steps[1:], strict=True):
            omega = warped_frequencies(modes.omega, h)
            model_points = np.asarray(cosine_sum(w, omega, np.asarray(t, dtype=float)))
            direct = np.asarray(cosine_sum(w, omega, grid))
            worst = max(worst, abs(weight) * float(np.max(np.abs(_spline(np.asarray(t), model_points, grid) - direct))))
    return worst
