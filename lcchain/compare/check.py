"""A simulator's vectors against a linear circuit's exact response, and the step an accuracy needs (arrays only).

:func:`vector_errors` compares each saved vector with the exact reference of
:class:`lcchain.circuit.linear.LinearResponse`, evaluated at the simulator's own time points (or frequencies):
no interpolation error.  The scale of a vector is the largest magnitude of its reference; its relative error is
its error over that scale.

The trapezoidal rule's error is predicted as in :mod:`lcchain.compare.accuracy`: each pole p is mapped by the
same (1 + p h/2) / (1 - p h/2) (:func:`lcchain.compare.accuracy.trapezoidal_poles`, which
:func:`~lcchain.compare.accuracy.predicted_error_damped` uses for a free response), a source's exponential or
sine answered at s' = (2/h) tanh(s h/2), ramps exactly; :func:`predicted_errors` is the largest difference of
that model and the exact response over a fixed-step grid, and :func:`step_for_accuracy` the largest fixed step
whose predicted relative error is at most :data:`lcchain.compare.accuracy.SAFETY` times the accuracy (found by
bisection on log h, the error growing like h^2).  Gear's error is :data:`~lcchain.compare.accuracy.GEAR_ERROR_FACTOR`
times the trapezoidal prediction (measured on ladders only): a rough guide, said so in the result.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from ..circuit.linear import LinearResponse
from .accuracy import GEAR_ERROR_FACTOR, SAFETY, trapezoidal_frequency, trapezoidal_poles

__all__ = ["vector_errors", "predicted_errors", "step_for_accuracy", "prediction_grid", "MAX_PREDICTION_POINTS"]

#: The predicted error is sampled at most at this many points of the fixed-step grid (spread over the run).
MAX_PREDICTION_POINTS = 20000
#: The step search stops when its bracket is this narrow (ratio of its ends).
_STEP_BRACKET = 1.03


def vector_errors(simulated: Sequence[np.ndarray], exact: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(max |simulated - exact|, max |exact|) per vector (rows of ``exact``; complex phasors compare as such)."""
    errors = np.array([float(np.max(np.abs(np.asarray(s) - e))) if e.size else 0.0
                       for s, e in zip(simulated, exact, strict=True)])
    scales = np.array([float(np.max(np.abs(e))) if e.size else 0.0 for e in exact])
    return errors, scales


def prediction_grid(breakpoints: Sequence[float], tstop: float, step: float,
                    limit: int = MAX_PREDICTION_POINTS) -> np.ndarray:
    """A fixed-step run's time points: from each breakpoint in steps of ``step`` (ngspice lands on every
    breakpoint), thinned evenly to at most ``limit`` points."""
    ends = [*breakpoints[1:], tstop]
    counts = [max(int(math.floor((end - start) / step + 1e-9)), 0) + 1 for start, end in
              zip(breakpoints, ends, strict=True)]
    total = sum(counts)
    pieces = []
    for start, count in zip(breakpoints, counts, strict=True):
        keep = max(2, int(math.ceil(count * limit / total))) if total > limit else count
        if keep >= count:
            pieces.append(start + step * np.arange(count))
        else:
            pieces.append(start + step * np.unique(np.linspace(0, count - 1, keep).round()))
    grid = np.unique(np.concatenate([*pieces, [tstop]]))
    return grid[grid <= tstop]


def predicted_errors(response: LinearResponse, outputs: Sequence[object], tstop: float, step: float, *,
                     method: str = "trap") -> np.ndarray:
    """Predicted max |simulation - exact| of each output for a fixed step ``step`` (seconds), in its units."""
    grid = prediction_grid(response.breakpoints(tstop), tstop, step)
    exact, _ = response.transient(outputs, grid, tstop)  # type: ignore[arg-type]
    model, _ = response.transient(outputs, grid, tstop, poles=trapezoidal_poles(response.poles, step),  # type: ignore[arg-type]
                                  warp=lambda s: trapezoidal_frequency(s, step))
    errors = np.max(np.abs(model - exact), axis=1)
    return np.asarray(errors * (GEAR_ERROR_FACTOR if method == "gear" else 1.0))


def step_for_accuracy(response: LinearResponse, outputs: Sequence[object], scales: np.ndarray, tstop: float,
                      accuracy: float, *, method: str = "trap", largest: float | None = None,
                      safety: float = SAFETY) -> float | None:
    """The largest fixed step (seconds, at most ``largest``: by default tstop/50, ngspice's own largest) whose
    predicted relative error (each output over its scale) is at most ``safety * accuracy``; None when no step
    above tstop * 1e-9 reaches it."""
    scales = np.where(np.asarray(scales) > 0, scales, 1.0)
    target = safety * accuracy
    hi = largest if largest is not None else tstop / 50

    def error(h: float) -> float:
        return float(np.max(predicted_errors(response, outputs, tstop, h, method=method) / scales))

    e_hi = error(hi)
    if e_hi <= target:
        return hi
    lo_limit = tstop * 1e-9
    lo, e_lo = None, 0.0
    guess = hi * math.sqrt(target / e_hi)
    while lo is None:
        guess = max(guess, lo_limit)
        e_guess = error(guess)
        if e_guess <= target:
            lo, e_lo = guess, e_guess
        else:
            if guess <= lo_limit:
                return None
            hi, e_hi = guess, e_guess
            guess = guess * min(0.5, math.sqrt(target / e_guess))
    for _ in range(40):
        if hi / lo <= _STEP_BRACKET:
            break
        # the error's power law between the bracket's ends, kept inside it
        slope = math.log(e_hi / e_lo) / math.log(hi / lo) if e_lo > 0 and e_hi > e_lo else 2.0
        middle = lo * (target / e_lo) ** (1 / slope) if e_lo > 0 else math.sqrt(lo * hi)
        middle = min(max(middle, lo * (hi / lo) ** 0.1), lo * (hi / lo) ** 0.9)
        e_middle = error(middle)
        if e_middle <= target:
            lo, e_lo = middle, e_middle
        else:
            hi, e_hi = middle, e_middle
    return lo
