"""What a time step costs in accuracy: the trapezoidal rule's error, predicted (pure numpy).

The trapezoidal rule is exact for the ladder up to a frequency warp
-------------------------------------------------------------------
The ladder is linear, and on each normal mode (q'' = -omega^2 q) one
trapezoidal step of length h is the Cayley map (1 - hA/2)^-1 (1 + hA/2): a
rotation of the mode's phase plane by exactly 2 atan(omega h / 2), with no
change of amplitude.  All modes keep their shapes, so the simulated end
signals are the modal sums of :mod:`lcchain.theory.modes` with the phases

    phi_n(t_k) = sum_{i <= k} 2 atan(omega_n h_i / 2).

On a uniform step dt this is the modal sum with *warped* frequencies

    omega~ = (2/dt) atan(omega dt / 2) = omega - omega^3 dt^2 / 12 + ...,

so the error against the exact alpha_N(t) is a pure phase lag growing like
t omega^3 dt^2 / 12: about (dt^2/12) max_t |t alpha'''(t)|, from the chain's
own modes (:func:`predicted_error`), not from a constant.

ngspice 39 does not take every step with the trapezoidal rule: the first two
steps (t = 0 -> dt/100 -> ...) and the step after its breakpoint at t = dt
(the print step) are backward-Euler steps (order 1), which rotate by
atan(omega h) and shrink the amplitude by 1/sqrt(1 + omega^2 h^2).  With
these steps in :func:`trap_response`, ngspice's waveform equals the model to
about 1e-13 (measured on the N = 20 two-mass chain, dt = 0.1 and 0.01); with
the uniform warp alone, the start-up leaves residuals of ~5e-5 at dt = 0.1
and ~4e-8 at dt = 0.01 (they scale as dt^3).

Error split
-----------
:func:`split_error` divides the total error of a simulation into the
*integration error*, simulation against the trapezoidal model (~1e-13 for a
correct circuit, at any step), and the *physics error*, the model against
the exact theory (the step's predictable phase lag).  A wiring, unit or sign
bug, or a chain that differs from the theory's, cannot hide in the step's
error: it shows in the integration error even at a coarse step.

Gear
----
Gear (BDF2) has no such model: it damps every mode as well as delaying it.
Its error is predicted as :data:`GEAR_ERROR_FACTOR` times the trapezoidal
prediction (measured: 3.9 - 4.1 for optimal two-mass chains over one transit
at dt <= 0.1; benchmarks/accuracy/README.md), and it loses energy on long
runs.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ..core.blas import fixed_blas_threads
from ..core.budget import BudgetError
from ..core.checks import choice, instance, real, strings
from ..core.errors import ParameterError
from ..core.json import JSONDict
from ..core.limits import ACCURACY_FLOOR, MAX_ACCURACY_DT
from ..core.types import METHODS
from ..theory.modes import Modes, cosine_sum
from .waveforms import Waveforms

__all__ = [
    "accuracy_asked",
    "AccuracyWarning",
    "ErrorSplit",
    "GEAR_ERROR_FACTOR",
    "MAX_DT",
    "MEANINGLESS_ERROR",
    "SAFETY",
    "dt_for_accuracy",
    "predicted_error", "predicted_error_damped", "trapezoidal_poles", "trapezoidal_frequency",
    "split_error",
    "trap_response",
    "warn_if_unreliable",
    "warped_frequencies",
    "warped_modes",
]

#: dt_for_accuracy aims at SAFETY * accuracy: the prediction is exact for the
#: trapezoidal model but ngspice's start-up steps and the sampling of the
#: error add a little (a few % of the error at the steps used); 0.8 costs
#: 1/sqrt(0.8) = 1.12 x the run time of the largest admissible step.
SAFETY = 0.8
#: Largest step dt_for_accuracy returns, in units of sqrt(L0 C0): the bulk
#: band reaches omega = 2, whose warp at dt = 0.5 is already 8%.
MAX_DT = MAX_ACCURACY_DT
#: Gear (order 2) over trap error at the same step (measured, see the module docstring).
GEAR_ERROR_FACTOR = 4.0
#: A predicted error above this is reported as meaningless (peaks are O(1)).
MEANINGLESS_ERROR = 0.1
#: dt_for_accuracy stops when the predicted error is within this relative
#: band below the target (error ~ dt^2: 6% in error is 3% in dt).
_ERROR_BAND = 0.06
#: First guess of dt_for_accuracy (error ~ 0.28 dt^2 for optimal chains: 7e-4).
_DT0 = 0.05

_ENDS = ("first", "last")


class AccuracyWarning(UserWarning):
    """A simulation whose settings make its result unreliable (not an error)."""


def _check_dt(dt: object, name: str = "dt") -> float:
    return real(name, dt, above=0.0, allowed="a finite step > 0 in units of sqrt(L0*C0)")


def _check_method(method: str) -> str:
    return choice("method", method, METHODS)


def _end_weights(modes: Modes, ends: Sequence[str]) -> list[np.ndarray]:
    allowed = 'a non-empty subset of ("first", "last")'
    ends = strings("ends", ends, allowed)
    if not ends or any(e not in _ENDS for e in ends):
        raise ParameterError("ends", ends, allowed)
    return [modes.density if end == "first" else modes.transfer for end in ends]


def _check_weights(weights: object, N: int) -> list[np.ndarray]:
    allowed = f"one or more finite arrays of N = {N} modal weights"
    if isinstance(weights, (str, bytes)) or not isinstance(weights, (Sequence, np.ndarray)):
        raise ParameterError("weights", type(weights).__name__, allowed)
    try:
        rows = [np.asarray(w, dtype=float) for w in weights]
    except (TypeError, ValueError):
        raise ParameterError("weights", type(weights).__name__, allowed) from None
    if not rows or any(w.shape != (N,) or not np.all(np.isfinite(w)) for w in rows):
        raise ParameterError("weights", f"{len(rows)} arrays", f"one or more finite arrays of N = {N} modal weights")
    return rows


def warped_frequencies(omega: np.ndarray, dt: float) -> np.ndarray:
    """omega~ = (2/dt) atan(omega dt / 2): the trapezoidal rule's frequencies at a fixed step.

    Parameters
    ----------
    omega : ndarray
        Angular frequencies in units of 1/sqrt(L0 C0).
    dt : float
        Step in units of sqrt(L0 C0).
    """
    dt = _check_dt(dt)
    return (2.0 / dt) * np.arctan(np.asarray(omega, dtype=float) * (0.5 * dt))


def warped_modes(modes: Modes, dt: float) -> Modes:
    """The modes the trapezoidal rule at fixed step dt really simulates.

    Same weights (density, transfer), frequencies warped by
    :func:`warped_frequencies`; the transmission and return amplitudes of
    the result are the simulated end signals at the time points k dt.
    """
    omega = warped_frequencies(modes.omega, dt)
    omega.flags.writeable = False
    return Modes(omega, modes.density, modes.transfer, modes.method, modes.k, modes.precision)


def _grid(dt: float, tstop: float) -> np.ndarray:
    """ngspice's time points after start-up: k dt up to tstop (and tstop itself)."""
    count = int(math.floor(tstop / dt + 1e-9))
    t = dt * np.arange(1, count + 1)
    if t.size == 0 or t[-1] < tstop * (1 - 1e-12):
        t = np.append(t, tstop)
    return t


def trapezoidal_poles(poles: np.ndarray, dt: float) -> np.ndarray:
    """The poles the trapezoidal rule at fixed step dt really simulates: log((1 + p dt/2) / (1 - p dt/2)) / dt,
    one step of a mode exp(p t) being the Cayley map (1 + p dt/2) / (1 - p dt/2) (units: those of 1/dt)."""
    p = np.asarray(poles, dtype=complex)
    step = (1 + 0.5 * p * dt) / (1 - 0.5 * p * dt)
    # a real pole at exactly -2/dt: one step takes the mode to 0 (log 0); a smallest factor instead, gone as well
    step = np.where(step == 0, np.finfo(float).tiny, step)
    return np.asarray(np.log(step) / dt)


def trapezoidal_frequency(s: complex, dt: float) -> complex:
    """Where the trapezoidal rule answers a source exp(s t) sampled exactly at its fixed steps dt: at
    s' = (2/dt) tanh(s dt/2) (its particular solution is the exact one at s'; s' = s for s = 0)."""
    return complex((2.0 / dt) * np.tanh(s * dt / 2.0))


@fixed_blas_threads
def predicted_error_damped(poles: np.ndarray, weights: Sequence[np.ndarray], dt: float, tstop: float, *,
                           method: str = "trap") -> float:
    """Predicted max |simulation - exact theory| of a fixed-step run of a lossy circuit's free response.

    The trapezoidal rule advances each mode exp(p t) of a linear circuit by (1 + p dt/2) / (1 - p dt/2) a step
    (the same map as :func:`warped_frequencies` without losses); the prediction is the largest difference of the
    two modal sums at ngspice's time points.

    Parameters
    ----------
    poles : ndarray of complex, shape (M,)
        The modes' poles, units of 1/sqrt(L0 C0) (real parts < 0).
    weights : sequence of ndarray of complex, shape (M,)
        Each compared signal's modal weights: the signal is the real part of sum_m weights_m exp(poles_m t).
    dt, tstop : float
        Fixed step and end of the run, units of sqrt(L0 C0).
    method : {"trap", "gear"}
        Gear is :data:`GEAR_ERROR_FACTOR` times the trapezoidal prediction.
    """
    dt = _check_dt(dt)
    tstop = _check_dt(tstop, "tstop")
    _check_method(method)
    t = _grid(dt, tstop)
    p = np.asarray(poles, dtype=complex)
    step = trapezoidal_poles(p, dt)
    rows = max(1, (1 << 18) // max(p.size, 1))
    worst = 0.0
    for w in weights:
        w = np.asarray(w, dtype=complex)
        for k in range(0, t.size, rows):
            block = t[k : k + rows]
            diff = (w @ (np.exp(np.outer(step, block)) - np.exp(np.outer(p, block)))).real
            worst = max(worst, float(np.max(np.abs(diff))))
    return worst * (GEAR_ERROR_FACTOR if method == "gear" else 1.0)


def predicted_error(modes: Modes, dt: float, tstop: float, *, ends: Sequence[str] = _ENDS,
                    method: str = "trap", weights: Sequence[np.ndarray] | None = None) -> float:
    """Predicted max |simulation - exact theory| of a fixed-step run.

    Parameters
    ----------
    modes : Modes
        Normal modes of the simulated chain.
    dt : float
        Fixed (maximum) step, units of sqrt(L0 C0).
    tstop : float
        End of the run, units of sqrt(L0 C0).
    ends : sequence of {"first", "last"}
        End signals compared (the return amplitude at loop 1, alpha_N at loop N).
    method : {"trap", "gear"}
        Gear is :data:`GEAR_ERROR_FACTOR` times the trapezoidal prediction.
    weights : sequence of ndarray, optional
        Modal weights of the compared signals, one array of N per signal
        (e.g. sqrt(m_1/m_i) U_n1 U_ni for interior loops i, whose error can be
        4 times the ends'); replaces ``ends``.

    Returns
    -------
    float
        max over the signals and the time points k dt <= tstop of
        |warped theory - exact theory| (dimensionless, relative to the kick).
    """
    instance("modes", modes, Modes)
    dt = _check_dt(dt)
    tstop = _check_dt(tstop, "tstop")
    _check_method(method)
    t = _grid(dt, tstop)
    omega_w = warped_frequencies(modes.omega, dt)
    signals = _end_weights(modes, ends) if weights is None else _check_weights(weights, modes.N)
    worst = 0.0
    for w in signals:
        diff = cosine_sum(w, omega_w, t) - cosine_sum(w, modes.omega, t)
        worst = max(worst, float(np.max(np.abs(diff))))
    return worst * (GEAR_ERROR_FACTOR if method == "gear" else 1.0)


#: An accuracy is refused without predicting the error at the budget's smallest step when the dt^2 law from a
#: larger step foresees it this many times above the target.
_FORESEEN_MARGIN = 4.0


@fixed_blas_threads
def accuracy_asked(accuracy: object) -> float:
    """An accuracy a run may ask for (max |simulation - theory|), as a float: 0 < accuracy < 1 and not below
    :data:`~lcchain.core.limits.ACCURACY_FLOOR`, or a ParameterError saying why."""
    value = real("accuracy", accuracy, above=0.0, below=1.0,
                 allowed="a number with 0 < accuracy < 1 (max |simulation - theory|)")
    if value < ACCURACY_FLOOR:
        raise ParameterError("accuracy", value, f"an accuracy >= {ACCURACY_FLOOR:g}: ngspice's rounding grows "
                             "with its steps, so asked for 1e-11 it reaches 7e-11 to 6e-10 (measured); even "
                             f"{ACCURACY_FLOOR:g} is sometimes missed, and a run that misses its accuracy fails")
    return value


def dt_for_accuracy(modes: Modes, accuracy: float, tstop: float, *, method: str = "trap",
                    safety: float = SAFETY, ends: Sequence[str] = _ENDS,
                    weights: Sequence[np.ndarray] | None = None, max_points: float | None = None) -> float:
    """Largest fixed step whose predicted error is at most ``safety * accuracy``.

    The error grows like dt^2, so the search starts at dt = 0.05, rescales
    by sqrt(target / error) and refines with secant steps on (log dt, log
    error) until the prediction lies within 6% below the target (3% in dt);
    the step is capped at :data:`MAX_DT`.

    Parameters
    ----------
    modes : Modes
    accuracy : float
        Wanted max |simulation - theory| (dimensionless), 0 < accuracy < 1.
    tstop : float
        End of the run, units of sqrt(L0 C0).
    method : {"trap", "gear"}
    safety : float
        Fraction of ``accuracy`` aimed at, 0 < safety <= 1 (see :data:`SAFETY`).
    ends, weights
        The compared signals, as for :func:`predicted_error`.
    max_points : float, optional
        The most time points the run may have (its budget): no step below
        tstop / max_points is tried, and an accuracy that needs one is refused.

    Returns
    -------
    float
        dt in units of sqrt(L0 C0).

    Raises
    ------
    ParameterError
        ``accuracy`` below :data:`lcchain.core.limits.ACCURACY_FLOOR`, which
        ngspice's double precision does not reliably reach.
    BudgetError
        The accuracy needs more than ``max_points`` time points.
    """
    instance("modes", modes, Modes)
    tstop = _check_dt(tstop, "tstop")
    if max_points is not None:
        max_points = real("max_points", max_points, at_least=1.0)
    accuracy = accuracy_asked(accuracy)
    safety = real("safety", safety, above=0.0, at_most=1.0)
    target = accuracy * safety
    smallest = 0.0 if max_points is None else tstop / max_points

    def error(dt: float) -> float:
        return max(predicted_error(modes, dt, tstop, ends=ends, method=method, weights=weights), 1e-300)

    def refuse(reached: float, law: bool = False) -> BudgetError:
        assert max_points is not None
        how = "about " if law else ""
        why = " by the dt^2 law" if law else ""
        return BudgetError("accuracy", accuracy, f"an accuracy this machine can afford: it needs a step below "
                           f"{smallest:.3g}, more than {max_points:.3g} time points (the predicted error at that "
                           f"step is {how}{reached:.3g}{why}); raise --max-memory and --max-time, or ask for less")

    e_max = error(MAX_DT)
    if e_max <= target:
        return MAX_DT
    best = None  # largest dt known to meet the target
    start = max(_DT0, smallest)
    dt, e = start, error(start)
    previous = None
    for _ in range(30):
        if e <= target:
            if best is None or dt > best[0]:
                best = (dt, e)
            if e >= target * (1 - _ERROR_BAND):
                return dt
        # Secant on log error against log dt (slope 2 for a pure dt^2 law).
        slope = 2.0
        if previous is not None and previous[0] != dt:
            fitted = math.log(previous[1] / e) / math.log(previous[0] / dt)
            if 0.5 < fitted < 4.0:
                slope = fitted
        aim = target * (1 - 0.5 * _ERROR_BAND)
        new = min(MAX_DT, dt * (aim / e) ** (1.0 / slope))
        if new < smallest:  # the budget's smallest step: it must do, or nothing will
            if dt <= smallest:
                raise refuse(e)
            # Predicting at the smallest step costs its tstop / smallest points (seconds, for a stiff chain); the
            # dt^2 law from here foresees it, and only under-foresees (an error saturated at a large step grows
            # less than the law when the step shrinks).  Far beyond the target, that is the answer.
            foreseen = e * (smallest / dt) ** 2
            if foreseen > _FORESEEN_MARGIN * target:
                raise refuse(foreseen, law=True)
            new = smallest
        previous = (dt, e)
        dt, e = new, error(new)
    if best is None:  # pragma: no cover - the dt^2 law makes the search converge
        raise ParameterError("accuracy", accuracy, "an accuracy reachable with dt > 0")
    return best[0]


# ------------------------------------------------------------ the discrete trapezoidal solution
def _order_one_steps(steps: np.ndarray, t: np.ndarray, tstep: float | None) -> np.ndarray:
    """Which steps ngspice 39 takes with backward Euler (see the module docstring)."""
    order_one = np.zeros(steps.size, dtype=bool)
    order_one[:2] = True
    if tstep is not None:
        # The step that starts at the breakpoint t = tstep.
        at = np.flatnonzero(np.abs(t[:-1] - tstep) <= 1e-9 * tstep)
        order_one[at + 1] = True
    return order_one


def _runs(steps: np.ndarray, order_one: np.ndarray, min_run: int = 64) -> list[tuple[int, int]]:
    """Index ranges [a, b) of equal steps and order (long uniform runs) or single steps."""
    J = steps.size
    same = np.abs(np.diff(steps)) <= 1e-9 * steps[1:]
    same &= ~order_one[1:] & ~order_one[:-1]
    runs = []
    a = 0
    while a < J:
        b = a + 1
        while b < J and same[b - 1]:
            b += 1
        if b - a >= min_run:
            runs.append((a, b))
        else:
            runs.extend((i, i + 1) for i in range(a, b))
        a = b
    return runs


@fixed_blas_threads
def trap_response(weights: np.ndarray, omega: np.ndarray, t: ArrayLike, *, tstep: float | None = None) -> np.ndarray:
    """The trapezoidal rule's own solution at a simulator's time points.

    f(t_k) = sum_n weights_n A_n(k) cos(phi_n(k)) with phi_n(k) the sum over
    the steps h_i = t_i - t_{i-1} (t_{-1} = 0) of 2 atan(omega_n h_i / 2);
    ngspice's backward-Euler steps (the first two and the one after the
    breakpoint at ``tstep``) rotate by atan(omega_n h_i) and scale A_n by
    1/sqrt(1 + (omega_n h_i)^2).

    Parameters
    ----------
    weights, omega : ndarray, shape (N,)
        Mode weights (density or transfer) and exact frequencies (1/sqrt(L0 C0)).
    t : array_like, shape (J,)
        Simulator time points, increasing, > 0, units of sqrt(L0 C0).
    tstep : float, optional
        The print step of ``.tran`` (lcchain writes dt), units of sqrt(L0 C0).

    Returns
    -------
    ndarray, shape (J,)
    """
    t = np.asarray(t, dtype=float)
    weights = np.asarray(weights, dtype=float)
    omega = np.asarray(omega, dtype=float)
    steps = np.diff(np.concatenate(([0.0], t)))
    order_one = _order_one_steps(steps, t, tstep)
    out = np.empty(t.size)
    phase = np.zeros(omega.size)
    log_amp = np.zeros(omega.size)
    for a, b in _runs(steps, order_one):
        L = b - a
        h = (t[b - 1] - (t[a - 1] if a else 0.0)) / L  # mean step of the run (rounding of t)
        x = omega * h
        if order_one[a]:
            theta, shrink = np.arctan(x), -0.5 * np.log1p(x * x)
        else:
            theta, shrink = 2.0 * np.arctan(0.5 * x), np.zeros_like(x)
        if L == 1:
            phase += theta
            log_amp += shrink
            out[a] = np.dot(weights * np.exp(log_amp), np.cos(phase))
            continue
        # shrink is 0 here (runs of backward-Euler steps are single steps)
        coeff = weights * np.exp(log_amp) * np.exp(1j * (phase + theta))  # value at the run's first point
        out[a:b] = _geometric_sum(coeff, theta, L)
        phase += L * theta
        log_amp += L * shrink
    return out


def _geometric_sum(coeff: np.ndarray, theta: np.ndarray, L: int) -> np.ndarray:
    """Re sum_n coeff_n exp(i theta_n m) for m = 0..L-1, split as m = p Q + q (two matrix products)."""
    Q = int(math.ceil(math.sqrt(L)))
    P = -(-L // Q)
    out = np.zeros((P, Q))
    block = max(1, (1 << 21) // (P + Q))
    p = np.arange(P) * float(Q)
    q = np.arange(Q, dtype=float)
    for s in range(0, theta.size, block):
        th = theta[s : s + block]
        left = np.exp(1j * np.multiply.outer(p, th)) * coeff[s : s + block]
        right = np.exp(1j * np.multiply.outer(q, th))
        out += (left @ right.T).real
    return out.ravel()[:L]


@dataclass(frozen=True)
class ErrorSplit:
    """Total error of a simulation against theory, split in two.

    Attributes
    ----------
    integration_error : float or None
        max |simulation - trapezoidal model| (:func:`trap_response`) over
        both ends: ~1e-13 for a correct circuit at any step.  None for gear
        (no model).
    physics_error : float or None
        max |trapezoidal model - exact theory|: the step's predictable error.
        None for gear.
    total_error : float
        max |simulation - exact theory|.
    """

    integration_error: float | None
    physics_error: float | None
    total_error: float

    def to_dict(self) -> JSONDict:
        return {"integration_error": self.integration_error, "physics_error": self.physics_error,
                "total_error": self.total_error}


@fixed_blas_threads
def split_error(waveforms: Waveforms, modes: Modes, dt: float, *, method: str = "trap",
                exact: tuple[np.ndarray, np.ndarray] | None = None, breakpoint: bool = True) -> ErrorSplit:
    """Split the error of a simulation into integration and physics error.

    Parameters
    ----------
    waveforms : lcchain.compare.waveforms.Waveforms
        Simulated end signals (``t``, ``first``, ``last``) of a kick; for a
        displacement the charges are integrals of the currents and the model
        holds to the start-up steps' accuracy only.
    modes : Modes
        Modes of the chain the theory describes (exact frequencies).
    dt : float
        The run's print and maximum step (the breakpoint at t = dt).
    method : {"trap", "gear"}
        For gear only the total error is available.
    exact : (ndarray, ndarray), optional
        The exact theory of the first and last loop at ``waveforms.t``, when
        already computed (e.g. ``Comparison.theory_first``, ``theory_last``).
    breakpoint : bool
        ngspice restarts its steps at t = dt (the print step); False for
        aligned runs, whose print step is the stop time.
    """
    dt = _check_dt(dt)
    _check_method(method)
    t = np.asarray(waveforms.t, dtype=float)
    if exact is None:
        exact = (np.asarray(cosine_sum(modes.density, modes.omega, t)),
                 np.asarray(cosine_sum(modes.transfer, modes.omega, t)))
    total = integration = physics = 0.0
    for weights, signal, theory in ((modes.density, waveforms.first, exact[0]),
                                    (modes.transfer, waveforms.last, exact[1])):
        total = max(total, float(np.max(np.abs(signal - theory))))
        if method == "trap":
            model = trap_response(weights, modes.omega, t, tstep=dt if breakpoint else None)
            integration = max(integration, float(np.max(np.abs(signal - model))))
            physics = max(physics, float(np.max(np.abs(model - theory))))
    if method == "gear":
        return ErrorSplit(None, None, total)
    return ErrorSplit(integration, physics, total)


def warn_if_unreliable(*, method: str, transits: int, predicted: float) -> list[str]:
    """Warn (:class:`AccuracyWarning`) about settings that make a run unreliable.

    Gear over more than one transit (it damps the pulse: energy is lost),
    and a step whose predicted error exceeds :data:`MEANINGLESS_ERROR`.

    Returns
    -------
    list of str
        The messages warned.
    """
    messages = []
    if method == "gear" and transits > 1:
        messages.append(f"method=gear over {transits} transits: gear loses energy (it damps every mode); "
                        "use method=trap for multi-transit runs")
    if predicted > MEANINGLESS_ERROR:
        messages.append(f"predicted error {predicted:.3g} > {MEANINGLESS_ERROR}: dt so coarse the result is "
                        "meaningless; use a smaller dt or --accuracy")
    for message in messages:
        warnings.warn(message, AccuracyWarning, stacklevel=3)
    return messages
