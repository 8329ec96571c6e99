"""Simulation against theory: errors and arrivals, in one shape for every caller (pure).

The simulated loop signals (:class:`~lcchain.compare.waveforms.Signals`) are
compared with the exact theory of the same circuit at ngspice's own time
points.  For each arrival the peak is searched in the window of
:func:`lcchain.theory.arrivals.arrival_window` (shifted by a pulse's centre):
in the samples, refined by a parabola through the best sample and its
neighbours (:func:`sample_peak`), and in the theory, on a fine grid refined
by Brent's method (:func:`lcchain.theory.arrivals.maximum_in_window`).
Odd arrivals are seen at loop N, even ones back at loop 1.
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..core.blas import fixed_blas_threads
from ..core.errors import ParameterError
from ..core.frozen import FrozenArrays
from ..core.json import JSONDict
from ..theory.arrivals import arrival_window, maximum_in_window
from .waveforms import Signals

__all__ = ["ArrivalComparison", "EffectCost", "Metrics", "Comparison", "sample_peak", "compare_signals",
           "residual_difference"]


@dataclass(frozen=True)
class ArrivalComparison:
    """One arrival of the pulse, in theory and in the simulation.

    Attributes
    ----------
    index : int
        1 for the first arrival at loop N, 2 for the return to loop 1, ...
    end : {"first", "last"}
    t_theory, t_sim : float
        Time of the peak, units of sqrt(L0 C0).
    peak_theory, peak_sim : float
        Peak of the dimensionless signal.
    energy_sim : float or None
        After a kick: the fraction of the kick's energy that the end's mass
        (inductor) holds at the simulated peak, peak_sim^2 m_end / m_1.  It
        is at most 1 in a lossless chain, and unlike the current ratio it is
        not moved by a mismatch of the two end inductors.  None for the other
        excitations.
    """

    index: int
    end: str
    t_theory: float
    t_sim: float
    peak_theory: float
    peak_sim: float
    energy_sim: float | None = None

    def to_dict(self) -> JSONDict:
        data: JSONDict = {"index": self.index, "end": self.end, "t_theory": self.t_theory, "t_sim": self.t_sim,
                "peak_theory": self.peak_theory, "peak_sim": self.peak_sim}
        if self.energy_sim is not None:
            data["energy_sim"] = self.energy_sim
        return data


@dataclass(frozen=True)
class EffectCost:
    """What the effects cost the pulse: the first arrival at loop N in the circuit's exact response against the
    ideal chain's alpha_N(t) (both theories, no simulator).

    Attributes
    ----------
    t_circuit, t_ideal : float
        Time of the first arrival's peak, units of sqrt(L0 C0).
    peak_circuit, peak_ideal : float
        Its peak (the dimensionless signal: I_N / I0 after a kick or a pulse, Q_N / Q0 after a displacement).
    energy_circuit, energy_ideal : float or None
        After a kick or a pulse: the fraction of the kick's energy the last coil holds at the peak,
        peak^2 L_N / L_1.  None after a displacement.
    """

    t_circuit: float
    t_ideal: float
    peak_circuit: float
    peak_ideal: float
    energy_circuit: float | None = None
    energy_ideal: float | None = None

    @property
    def energy_loss(self) -> float | None:
        """1 - energy_circuit / energy_ideal: the share of the ideal first arrival's energy the effects take."""
        if self.energy_circuit is None or self.energy_ideal is None:
            return None
        return 1.0 - self.energy_circuit / self.energy_ideal

    @property
    def delay(self) -> float:
        """t_circuit - t_ideal, units of sqrt(L0 C0)."""
        return self.t_circuit - self.t_ideal

    def to_dict(self) -> JSONDict:
        return {"t_circuit": self.t_circuit, "t_ideal": self.t_ideal, "peak_circuit": self.peak_circuit,
                "peak_ideal": self.peak_ideal, "energy_circuit": self.energy_circuit,
                "energy_ideal": self.energy_ideal, "energy_loss": self.energy_loss, "delay": self.delay}


@dataclass(frozen=True)
class Metrics:
    """The numbers a run is judged by.

    Attributes
    ----------
    max_abs_error : float
        max over every saved loop and time point of |simulation - theory|.
    max_abs_error_first, max_abs_error_last : float
        The same for loop 1 and loop N.
    arrivals : tuple of ArrivalComparison
    predicted_error : float or None
        The error model's prediction before the run (fixed-step trap or gear).
    integration_error, physics_error : float or None
        Simulation against the trapezoidal model, and the model against the
        exact theory (:func:`lcchain.compare.accuracy.split_error`); None
        where the model does not apply.
    effects : EffectCost or None
        A circuit whose elements are no chain's (compared with its own exact theory): what its effects cost
        the pulse against the ideal chain.  Separate from the errors above, which are always the simulator
        against the exact theory of the circuit it ran.  None when the chain's theory is the circuit's.
    """

    max_abs_error: float
    max_abs_error_first: float
    max_abs_error_last: float
    arrivals: tuple[ArrivalComparison, ...]
    predicted_error: float | None = None
    integration_error: float | None = None
    physics_error: float | None = None
    effects: EffectCost | None = None

    def to_dict(self) -> JSONDict:
        data: JSONDict = {
            "max_abs_error": self.max_abs_error,
            "max_abs_error_first": self.max_abs_error_first,
            "max_abs_error_last": self.max_abs_error_last,
            "arrivals": [a.to_dict() for a in self.arrivals],
            "predicted_error": self.predicted_error,
            "integration_error": self.integration_error,
            "physics_error": self.physics_error,
        }
        if self.effects is not None:  # only then: the metrics of chain runs are those stored before
            data["effects"] = self.effects.to_dict()
        return data


@dataclass(frozen=True, eq=False)
class Comparison(FrozenArrays):
    """Simulation against theory over the whole simulated window, with the theory's end signals.

    Attributes
    ----------
    max_abs_error : float
        max over both ends and all time points of |simulation - theory|.
    max_abs_error_first, max_abs_error_last : float
        The same for each end.
    arrivals : tuple of ArrivalComparison
    theory_first, theory_last : ndarray
        Theory at the simulator's time points.
    """

    max_abs_error: float
    max_abs_error_first: float
    max_abs_error_last: float
    arrivals: tuple[ArrivalComparison, ...]
    theory_first: np.ndarray
    theory_last: np.ndarray

    def to_dict(self) -> JSONDict:
        return {
            "max_abs_error": self.max_abs_error,
            "max_abs_error_first": self.max_abs_error_first,
            "max_abs_error_last": self.max_abs_error_last,
            "arrivals": [a.to_dict() for a in self.arrivals],
        }

    @classmethod
    def of(cls, metrics: Metrics, signals: Signals) -> Comparison:
        """The comparison of a run from its metrics and signals."""
        return cls(metrics.max_abs_error, metrics.max_abs_error_first, metrics.max_abs_error_last,
                   metrics.arrivals, signals.theory[0], signals.theory[-1])


def sample_peak(t: np.ndarray, y: np.ndarray, lo: float, hi: float) -> tuple[float, float]:
    """Peak of samples (t, y) inside [lo, hi], refined by a parabola through 3 points."""
    inside = np.flatnonzero((t >= lo) & (t <= hi))
    if inside.size == 0:
        raise ParameterError("window", (lo, hi), "a window containing simulated points")
    i = int(inside[np.argmax(y[inside])])
    if 0 < i < t.size - 1:
        x0, x1, x2 = t[i - 1 : i + 2]
        y0, y1, y2 = y[i - 1 : i + 2]
        # Parabola through three (possibly unevenly spaced) points.
        d01, d12, d02 = x1 - x0, x2 - x1, x2 - x0
        a = (y2 - y1) / (d12 * d02) - (y1 - y0) / (d01 * d02)
        b = (y1 - y0) / d01 - a * (x0 + x1)
        if a < 0:
            tp = -b / (2 * a)
            if x0 <= tp <= x2:
                yp = y1 + (tp - x1) * ((y1 - y0) / d01 + a * (tp - x0))
                return float(tp), float(yp)
    return float(t[i]), float(y[i])


@fixed_blas_threads
def compare_signals(signals: Signals, *, transit_time: float, transits: int, shift: float = 0.0,
                    theory_end: Callable[[int, np.ndarray], np.ndarray],
                    theory_each: Callable[[int, np.ndarray], np.ndarray] | None = None) -> Metrics:
    """Errors and arrivals of a run.

    Parameters
    ----------
    signals : Signals
        Simulated and theoretical loop signals at the simulator's times.
    transit_time : float
        The chain's transit time T (units of sqrt(L0 C0)): it centres the windows.
    transits : int
        Arrivals to report.
    shift : float
        Delay of every arrival (a pulse's centre), units of sqrt(L0 C0).
    theory_end : callable
        ``theory_end(row, t)``: the theory of loop 1 (row 0) or loop N (row -1)
        at any times, for the theory's own peak search.
    theory_each : callable, optional
        ``theory_each(row, t)``: the same at each of the times t as if called
        with that time alone, so that the peak search refines its three best
        grid points side by side (:func:`lcchain.theory.arrivals.refine_maxima`).

    Returns
    -------
    Metrics
        Without the error model's numbers (the caller adds them).
    """
    t, sim, theory = signals.t, signals.sim, signals.theory
    error = np.abs(sim - theory)
    found = []
    for index in range(1, transits + 1):
        lo, hi = arrival_window(index, transit_time)
        window = (lo + shift, min(hi + shift, float(t[-1])))
        row = -1 if index % 2 else 0
        t_sim, peak_sim = sample_peak(t, sim[row], *window)
        each = None if theory_each is None else functools.partial(theory_each, row)
        t_theory, peak_theory = maximum_in_window(functools.partial(theory_end, row), window, transit_time, each)
        found.append(ArrivalComparison(index, "last" if index % 2 else "first", t_theory, t_sim, peak_theory,
                                       peak_sim))
    return Metrics(float(np.max(error)), float(np.max(error[0])), float(np.max(error[-1])), tuple(found))


def residual_difference(t_a: np.ndarray, residual_a: np.ndarray, t_b: np.ndarray, residual_b: np.ndarray) -> float:
    """max |a - b| of two runs of the same circuit on their own time grids, through their residuals.

    A run's residual (simulation - exact theory) varies on the modes' time scale, not the step's, so run b's
    residual is brought onto run a's times by linear interpolation; there a - b = residual_a - residual_b
    (the theory is the same at the same time).  Times of a outside b's span are left out.
    """
    inside = (t_a >= t_b[0]) & (t_a <= t_b[-1])
    if not np.any(inside):
        raise ValueError("the two runs share no time span")
    return float(np.max(np.abs(residual_a[inside] - np.interp(t_a[inside], t_b, residual_b))))
