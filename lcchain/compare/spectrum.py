"""Normal frequencies and mode weights from a ladder's AC response (pure arrays).

A lossless ladder driven by a voltage V in loop 1 has the transfer admittances (dimensionless, times
Z0 = sqrt(L0/C0), at the angular frequency w in units of 1/sqrt(L0 C0))

    Y_11 Z0 = j w sum_n a_n / (w_n^2 - w^2),      Y_N1 Z0 = j w sum_n b_n / (w_n^2 - w^2),

with a_n = u_1n^2 > 0 and b_n = u_1n u_Nn for the M-orthonormal modes u (a free chain adds the pole
w_0 = 0).  So g(x) = Im(Y Z0) / w is a real rational function of x = w^2 with simple real poles x_n and
residues -a_n (-b_n).

:func:`fit_spectrum` identifies them from samples on a grid of frequencies:

1. *Brackets.*  Every a_n > 0, so g_11 increases strictly between its poles: a pair of neighbouring samples
   where it decreases brackets a pole (the grid must separate the poles: :func:`min_points`).  A pole too weak
   to show between two samples has no bracket; the rational fit still finds it.
2. *All poles at once.*  A rational fit of g_11 (AAA, ``scipy.interpolate.AAA``) on the samples (beyond
   :data:`_ALL_ROWS` of them, those around the bracketed poles and an even spread); its real poles in the
   range are the modes, those with a negligible residue dropped.  A free chain's pole at 0 is its
   translation mode.
3. *Gauss-Newton* on every pole and residue together, each sample weighted by its distance to the nearest
   pole (so that every row carries the data's rounding alike); samples within 1e-9 of a pole are left out,
   because there the circuit's own rounding moves the pole by more than the sample's distance to it.
4. The residues of Y_N1 at those poles, by weighted linear least squares.

Measured against exact theory, see ``benchmarks/spectrum.md``.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np
from scipy.interpolate import AAA

from ..core.errors import ParameterError
from ..core.frozen import FrozenArrays

__all__ = ["SpectrumFit", "fit_spectrum", "min_points", "POINTS_PER_SPACING"]

#: Samples per smallest spacing of the poles that the fit needs (at least): each pole's window then holds a few
#: samples on each side.  :func:`min_points` uses it to refuse a grid too coarse before anything runs.
POINTS_PER_SPACING = 4
#: Gauss-Newton steps at most (each must lower the misfit).
_SWEEPS = 6
#: Rows of the rational fit and of the residues' least squares: this many around each pole, and an even spread.
_ROWS_PER_POLE = 8
_SPREAD = 200
#: Up to this many samples, the rational fit takes them all; beyond, those near the poles and a spread.
_ALL_ROWS = 6000
#: A pole of the rational fit whose residue is below this (relative to the largest) is the fit's, not a mode.
_WEAKEST = 1e-13
#: Samples closer than this (relative) to a pole are left out of the fits.
_TOO_CLOSE = 1e-9
#: AAA's relative tolerance (the samples are ngspice's, good to about 1e-12).
_AAA_RTOL = 1e-13


@dataclass(frozen=True, eq=False)
class SpectrumFit(FrozenArrays):
    """Poles and residues identified from an AC response.

    Attributes
    ----------
    omega : ndarray
        Normal frequencies w_n, ascending (units of 1/sqrt(L0 C0)); a free chain's first is 0.
    first, last : ndarray
        Residues a_n of Y_11 Z0 and b_n of Y_N1 Z0 (multiply by m_1 for the mode weights of alpha_1 and alpha_N).
    sweeps : int
        Gauss-Newton steps taken after the rational fit (each one lowered the misfit).
    residual : float
        Largest misfit of the model to the samples it was fitted on (each times its distance to the nearest pole).
    """

    omega: np.ndarray
    first: np.ndarray
    last: np.ndarray
    sweeps: int
    residual: float

    def __post_init__(self) -> None:
        self._freeze_arrays()


def min_points(omega: np.ndarray, omega_max: float) -> int:
    """The fewest evenly spaced frequencies on (0, omega_max] that separate every pole of ``omega`` (ascending)."""
    positive = np.asarray(omega, dtype=float)
    positive = positive[positive > 0]
    if positive.size < 2:
        return 16
    spacing = float(np.min(np.diff(positive)))
    return int(np.ceil(POINTS_PER_SPACING * omega_max / spacing)) + 1


def _poles_between(g: np.ndarray) -> np.ndarray:
    """Indices k with a pole of the increasing g between samples k and k + 1."""
    return np.flatnonzero(np.diff(g) < 0)


def _solve(columns: np.ndarray, target: np.ndarray) -> np.ndarray:
    """Least squares with every column scaled to unit norm first (the columns span many orders of magnitude)."""
    norms = np.linalg.norm(columns, axis=0)
    norms[norms == 0] = 1.0
    solution, *_ = np.linalg.lstsq(columns / norms, target, rcond=None)
    return np.asarray(solution / norms)


def _rows_near(x: np.ndarray, poles: np.ndarray, per: int) -> np.ndarray:
    """Sample indices around each pole (``per`` of them), and a sparse even spread over the whole range."""
    at = np.searchsorted(x, poles)
    near = (at[:, None] + np.arange(-per // 2, per // 2)[None, :]).ravel()
    spread = np.linspace(0, x.size - 1, min(x.size, _SPREAD)).round().astype(int)
    return np.unique(np.clip(np.concatenate((near, spread)), 0, x.size - 1))


def _residues(x: np.ndarray, g: np.ndarray, poles: np.ndarray, rows: np.ndarray) -> np.ndarray:
    """Residues of g = sum_n r_n / (x_n - x) at fixed poles, by least squares on the rows given, each row
    weighted by its distance to the nearest pole (so that every row carries the data's rounding alike)."""
    xs = x[rows]
    distance = poles[None, :] - xs[:, None]
    weight = np.min(np.abs(distance), axis=1)
    return _solve(weight[:, None] / distance, g[rows] * weight)


def _misfit(x: np.ndarray, g: np.ndarray, poles: np.ndarray, residues: np.ndarray) -> float:
    """Largest misfit of the model on the samples, relative to the sample's distance-weighted size."""
    distance = poles[None, :] - x[:, None]
    weight = np.min(np.abs(distance), axis=1)
    return float(np.max(np.abs(((residues[None, :] / distance).sum(axis=1) - g) * weight)))


def fit_spectrum(omega: np.ndarray, y11: np.ndarray, yN1: np.ndarray) -> SpectrumFit:
    """Identify the poles and residues of a lossless ladder's transfer admittances (see the module docstring).

    Parameters
    ----------
    omega : ndarray
        Angular frequencies of the samples, units of 1/sqrt(L0 C0), ascending, > 0.
    y11, yN1 : ndarray, complex
        Y_11 Z0 and Y_N1 Z0 at those frequencies.

    Raises
    ------
    ParameterError
        Samples that are not a lossless ladder's (no pole, or not ascending).
    """
    w = np.asarray(omega, dtype=float)
    if w.ndim != 1 or w.size < 8 or not np.all(np.diff(w) > 0) or w[0] <= 0:
        raise ParameterError("omega", f"{w.size} frequencies", "at least 8 ascending frequencies > 0")
    x = w * w
    g11 = np.asarray(y11).imag / w
    gN1 = np.asarray(yN1).imag / w
    brackets = _poles_between(g11)
    if brackets.size == 0:
        raise ParameterError("omega", f"{w[0]:.4g} .. {w[-1]:.4g}", "a frequency range holding a pole")
    left, right = g11[brackets], g11[brackets + 1]
    guess = (left * x[brackets] - right * x[brackets + 1]) / (left - right)
    rows = np.arange(x.size) if x.size <= _ALL_ROWS else _rows_near(x, guess, _ROWS_PER_POLE)
    # 1. every pole at once: a rational fit of g_11 on the rows (AAA); its real poles in the range are the modes,
    # weak ones included (a pole whose weight hides it between two samples has no bracket)
    with warnings.catch_warnings():  # AAA may stop short of rtol: Gauss-Newton below finishes the job
        warnings.simplefilter("ignore", RuntimeWarning)
        fitted = AAA(x[rows], g11[rows], rtol=_AAA_RTOL, max_terms=min(rows.size // 2, 2 * brackets.size + 16))
    found, weights = np.asarray(fitted.poles()), np.asarray(fitted.residues())
    real = (np.abs(found.imag) <= 1e-9 * x[-1]) & (found.real < x[-1]) & (found.real > -0.5 * x[0])
    real &= np.abs(weights.real) > _WEAKEST * float(np.max(np.abs(weights.real[real]), initial=0.0))
    columns = np.sort(found.real[real])
    zero = bool(columns.size and abs(columns[0]) < 0.5 * x[0])  # a free chain's translation mode
    if zero:
        columns[0] = 0.0
    if columns.size < brackets.size:
        raise ParameterError("omega", f"{w.size} frequencies", "more frequencies: the rational fit found fewer "
                             f"poles ({columns.size}) than the samples bracket ({brackets.size})")
    # A sample within a few ulps of a pole tells nothing: there the circuit's own rounding moves the pole by more
    # than the sample's distance to it (measured: 1.8e-3 relative error at 6e-14 from a pole).
    clear = np.min(np.abs(columns[None, :] - x[rows][:, None]), axis=1) > _TOO_CLOSE * x[rows]
    rows = rows[clear]
    # 2. Gauss-Newton on every pole and residue at once, from the rational fit's, on the same rows (each weighted
    # by its distance to the nearest pole); a free chain's zero pole stays at 0
    movable = np.arange(columns.size) >= (1 if zero else 0)
    residues = _residues(x, g11, columns, rows)
    xs, gs = x[rows], g11[rows]
    best = (_misfit(xs, gs, columns, residues), columns.copy(), residues.copy())
    sweeps = 0
    for _ in range(_SWEEPS):
        distance = columns[None, :] - xs[:, None]
        weight = np.min(np.abs(distance), axis=1)[:, None]
        value = (residues[None, :] / distance).sum(axis=1)
        jacobian = np.hstack((weight / distance, (-weight * residues[None, :] / distance**2)[:, movable]))
        step = _solve(jacobian, (gs - value) * weight[:, 0])
        trial_residues = residues + step[:columns.size]
        trial = columns.copy()
        trial[movable] += step[columns.size:]
        if np.any(np.diff(trial) <= 0):  # a step that reorders the poles is no step
            break
        misfit = _misfit(xs, gs, trial, trial_residues)
        if misfit >= best[0]:
            break
        columns, residues = trial, trial_residues
        best = (misfit, columns.copy(), residues.copy())
        sweeps += 1
    columns, first = best[1], best[2]
    last = _residues(x, gN1, columns, rows)
    misfit = max(_misfit(x[rows], g11[rows], columns, first), _misfit(x[rows], gN1[rows], columns, last))
    return SpectrumFit(np.sqrt(np.clip(columns, 0.0, None)), first, last, sweeps, misfit)
