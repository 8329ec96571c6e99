"""Simulation against theory (pure: arrays in, numbers out).

The simulated end-loop signals, made dimensionless (time in sqrt(L0 C0),
currents over I_1(0) for a kick, charges over Q_1(0) for a displacement),
are compared with the exact modal theory of the same chain at ngspice's own
time points: alpha_N(t) at the far end, sum_n P_n cos(omega_n t) at the near
end (:mod:`lcchain.modes`).  For each arrival the peak is searched in the
window of :func:`lcchain.arrivals.arrival_window`, in the theory and in the
samples (refined by a parabola through the best sample and its neighbours).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .arrivals import arrivals as theory_arrivals
from .errors import ParameterError
from .modes import Modes, return_amplitude, transmission_amplitude
from .types import EXCITATIONS, Excitation

__all__ = ["Waveforms", "ArrivalComparison", "Comparison", "normalise", "compare", "sample_peak"]


def _readonly(a) -> np.ndarray:
    a = np.array(a, dtype=float)
    a.flags.writeable = False
    return a


@dataclass(frozen=True, eq=False)
class Waveforms:
    """Dimensionless end-loop signals at the simulator's time points.

    Attributes
    ----------
    t : ndarray
        Time in units of sqrt(L0 C0).
    first, last : ndarray
        Loop 1 and loop N: I/I_1(0) (kick) or Q/Q_1(0) (displacement).
    excitation : str
    """

    t: np.ndarray
    first: np.ndarray
    last: np.ndarray
    excitation: str

    def to_csv(self) -> str:
        """CSV text with columns t, first, last (full precision)."""
        rows = ["t,first,last"]
        rows += [f"{a!r},{b!r},{c!r}" for a, b, c in zip(self.t.tolist(), self.first.tolist(), self.last.tolist())]
        return "\n".join(rows) + "\n"


def _cumulative_trapezoid(t: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Integral of y from t = 0 (where y = 0 for the integrated currents) to each t."""
    tt = np.concatenate(([0.0], t))
    yy = np.concatenate(([0.0], y))
    return np.cumsum(0.5 * np.diff(tt) * (yy[1:] + yy[:-1]))


def normalise(time_s, i_first, i_last, *, time_unit: float, excitation: Excitation, I0: float) -> Waveforms:
    """Turn ngspice's loop currents into the compared dimensionless signals.

    Parameters
    ----------
    time_s : array_like
        Simulator time points, seconds.
    i_first, i_last : array_like
        Currents of L_1 and L_N, ampere.
    time_unit : float
        sqrt(L0 C0), seconds.
    excitation : {"kick", "displacement"}
    I0 : float
        Kick current (A); a displacement's charge is Q0 = I0 * time_unit.

    Notes
    -----
    For a displacement the loop charges are the time integrals of the loop
    currents (trapezoidal rule on the simulator's points: the same rule the
    trapezoidal integrator applies to its capacitor charges), plus Q0 in loop 1.
    With ``uic`` ngspice's first point is after t = 0; the currents there are
    0 for a displacement, which the integral uses.
    """
    if excitation not in EXCITATIONS:
        raise ParameterError("excitation", excitation, " | ".join(EXCITATIONS))
    t = np.asarray(time_s, dtype=float) / time_unit
    first = np.asarray(i_first, dtype=float) / I0
    last = np.asarray(i_last, dtype=float) / I0
    if excitation == "displacement":
        # Q/Q0 = (1/Q0) int I dt = int (I/I0) d(t/time_unit), since Q0 = I0 * time_unit.
        first = 1.0 + _cumulative_trapezoid(t, first)
        last = _cumulative_trapezoid(t, last)
    return Waveforms(_readonly(t), _readonly(first), _readonly(last), excitation)


@dataclass(frozen=True)
class ArrivalComparison:
    """One arrival, in theory and in the simulation."""

    index: int
    end: str
    t_theory: float
    t_sim: float
    peak_theory: float
    peak_sim: float

    def to_dict(self) -> dict:
        return {"index": self.index, "end": self.end, "t_theory": self.t_theory, "t_sim": self.t_sim,
                "peak_theory": self.peak_theory, "peak_sim": self.peak_sim}


@dataclass(frozen=True, eq=False)
class Comparison:
    """Simulation against theory over the whole simulated window.

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

    def to_dict(self) -> dict:
        return {
            "max_abs_error": self.max_abs_error,
            "max_abs_error_first": self.max_abs_error_first,
            "max_abs_error_last": self.max_abs_error_last,
            "arrivals": [a.to_dict() for a in self.arrivals],
        }


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


def compare(waveforms: Waveforms, modes: Modes, transits: int) -> Comparison:
    """Compare simulated end signals with the modal theory of the same chain.

    Parameters
    ----------
    waveforms : Waveforms
        From :func:`normalise`.
    modes : Modes
        Normal modes of the simulated chain.
    transits : int
        Number of arrivals to report (first arrival, then one per bounce).
    """
    t = waveforms.t
    theory_last = transmission_amplitude(modes, t)
    theory_first = return_amplitude(modes, t)
    err_first = float(np.max(np.abs(waveforms.first - theory_first)))
    err_last = float(np.max(np.abs(waveforms.last - theory_last)))
    found = []
    for arrival in theory_arrivals(modes, transits):
        signal = waveforms.last if arrival.end == "last" else waveforms.first
        t_sim, peak_sim = sample_peak(t, signal, *arrival.window)
        found.append(ArrivalComparison(arrival.index, arrival.end, arrival.time, t_sim, arrival.peak, peak_sim))
    return Comparison(max(err_first, err_last), err_first, err_last, tuple(found),
                      _readonly(theory_first), _readonly(theory_last))
