"""Refining a ladder's modes against its AC samples, window by window (pure arrays).

A ladder driven in loop 1 (lossless or with losses) has the transfer admittance, at s = j w,

    Y(w) = sum_n c_n j w / D_n(w),       D_n(w) = x_n - w^2 + j gamma_n w,

one second-order section per mode: x_n = omega_n^2, gamma_n its decay rate (0 without losses), c_n its real
residue.  The sum is exact (a proper rational function of degree 2N), so the model has nothing else to fit.

:func:`refine_sections` moves every section's parameters by Gauss-Newton, one window of neighbouring modes at a
time (block Gauss-Seidel; up to :data:`ONE_WINDOW` modes, one window), with the whole model's residual: a window
moves its :data:`WINDOW_MODES` modes on the samples between its outer neighbours, fits a smooth correction
beside them (the other windows' errors, dropped), shortens its step when the whole one overshoots, and the
model is updated on every sample; alternate sweeps shift the windows by half.  Each row is weighted by
min_n |D_n| / w, the inverse of the nearest section's gain, so that every row carries the data's rounding alike
(without losses that is the distance to the nearest pole, as :mod:`lcchain.compare.spectrum` says).
:func:`section_residues` finds the residues of a second admittance at fixed sections the same way (linear, each
window's modes solved beside its neighbours').

Cost per sweep: the least squares of N / K windows of about R rows and 3 K columns, O(N R K) (R ~ 8 K samples
on lcchain's grid: O(N K^2)), and the model's update on every sample, O(points x N).
"""

from __future__ import annotations

import numpy as np

__all__ = ["Sections", "refine_sections", "section_residues", "WINDOW_MODES", "ONE_WINDOW", "WINDOW_SECTIONS"]

#: Modes moved together in one window.
WINDOW_MODES = 64
#: A chain of at most this many modes is one window: plain Gauss-Newton on every mode (with losses, a mode's
#: neighbours within a few decay rates move with it; two-mass N = 100 at Q = 100: 6.5e-9 on Q_n in one window,
#: 2.2e-4 in windows of 64, on exact samples).
ONE_WINDOW = 128
#: Neighbours on each side whose samples a window also fits (their parameters stay).
_HALO = 6
#: ... and the samples within this many decay rates of its modes.
_WIDTHS = 4.0
#: Sections whose columns one window's least squares holds at most beyond :data:`ONE_WINDOW`: its modes and its
#: neighbours on both sides (what the fit's price counts, :func:`lcchain.compare.spectrum.fit_sections`).
WINDOW_SECTIONS = WINDOW_MODES + 2 * _HALO
#: Gauss-Newton sweeps at most; each window's step must lower its misfit.
_SWEEPS = 12
#: Terms of the smooth correction a window fits beside its modes (:func:`_background`).
_BACKGROUND = 4
#: Fractions of a Gauss-Newton step tried in turn until one lowers the window's misfit.
_FRACTIONS = (1.0, 0.5, 0.25, 0.125)
#: A step that lowers its window's misfit by less than this factor counts as no progress.
_GAIN = 0.99
#: Sweeps of the residues' block Gauss-Seidel at most, and the relative change at which it stops.
_RESIDUE_SWEEPS = 6
_RESIDUE_CHANGE = 1e-13
#: Terms of the model formed at once (:func:`_sum`): its (samples x sections) matrices stay near 16 MiB each,
#: where two-mass N = 2000 held three of 26,000 x 2000 complex values (2.5 GB) to update its model.
_BLOCK_VALUES = 2**20
#: Samples closer than this (relative) to a lossless pole are left out: there the circuit's own rounding moves
#: the pole by more than the sample's distance to it (measured: 1.8e-3 relative error at 6e-14 from a pole).
_TOO_CLOSE = 1e-9


class Sections:
    """Second-order sections (c_n, gamma_n, x_n), sorted by x_n, as mutable arrays during a fit.

    Parameters
    ----------
    c, gamma, x : ndarray
        Residues, decay rates and squared frequencies (units of 1/sqrt(L0 C0) and its square).
    lossy : bool
        Whether gamma is fitted; without losses it stays 0.
    fixed_x : ndarray of bool, optional
        Frequencies held where they are (a free chain's zero mode without losses).
    """

    def __init__(self, c: np.ndarray, gamma: np.ndarray, x: np.ndarray, *, lossy: bool,
                 fixed_x: np.ndarray | None = None):
        order = np.argsort(x, kind="stable")
        self.c = np.array(c, dtype=float)[order]
        self.gamma = np.array(gamma, dtype=float)[order]
        self.x = np.array(x, dtype=float)[order]
        self.lossy = lossy
        self.fixed_x = (np.zeros(self.x.size, dtype=bool) if fixed_x is None
                        else np.asarray(fixed_x, dtype=bool)[order])

    @property
    def size(self) -> int:
        return int(self.x.size)

    def denominators(self, w: np.ndarray, modes: slice | np.ndarray = slice(None)) -> np.ndarray:
        """D_n(w), shape (w.size, modes)."""
        return np.asarray((self.x[modes][None, :] - (w * w)[:, None]) + 1j * w[:, None] * self.gamma[modes][None, :])

    def value(self, w: np.ndarray, residues: np.ndarray, modes: slice | np.ndarray = slice(None)) -> np.ndarray:
        """sum over ``modes`` of residues_n j w / D_n(w) (infinite on a lossless pole: such samples are not fitted)."""
        return _sum(w, residues[modes], self.x[modes], self.gamma[modes])


def _windows(n: int, shifted: bool = False) -> list[tuple[int, int]]:
    """Consecutive blocks of at most :data:`WINDOW_MODES` modes covering 0..n; ``shifted``: their edges moved by
    half a block (alternate sweeps move the modes at one sweep's edges in the middle of the next's blocks)."""
    count = 1 if n <= ONE_WINDOW else int(np.ceil(n / WINDOW_MODES))
    edges = np.linspace(0, n, count + 1).round().astype(int)
    if shifted and count > 1:
        edges = np.unique(np.concatenate(([0], (edges[:-1] + edges[1:]) // 2, [n])))
    return [(int(a), int(b)) for a, b in zip(edges[:-1], edges[1:], strict=True) if b > a]


def _rows(w: np.ndarray, sections: Sections, lo: int, hi: int) -> tuple[np.ndarray, slice]:
    """The samples a window fits, and the modes near them (those whose gain can be the largest there).

    The samples lie between the window's outer neighbours (:data:`_HALO` modes on each side), widened by
    :data:`_WIDTHS` decay rates of the window's modes (a mode is felt that far); the ends take every sample beyond.
    """
    root = np.sqrt(np.clip(sections.x, 0.0, None))
    width = _WIDTHS * float(np.max(sections.gamma[lo:hi], initial=0.0))
    left = 0.0 if lo - _HALO <= 0 else root[lo - _HALO] - width
    right = np.inf if hi + _HALO >= sections.size else root[hi + _HALO - 1] + width
    rows = np.flatnonzero((w >= left) & (w <= right))
    near = slice(min(int(np.searchsorted(root, left)), max(lo - _HALO, 0)),
                 max(int(np.searchsorted(root, right, side="right")), hi + _HALO))
    if not sections.lossy:  # a sample on top of a pole tells nothing
        gap = np.min(np.abs(sections.denominators(w[rows], near)), axis=1)
        rows = rows[gap > _TOO_CLOSE * w[rows] ** 2]
    return rows, near


def _weights(w: np.ndarray, sections: Sections, near: slice) -> np.ndarray:
    """min_n |D_n| / w over the modes ``near`` the rows: the inverse gain of the nearest section."""
    return np.asarray(np.min(np.abs(sections.denominators(w, near)), axis=1) / w)


def _solve(columns: np.ndarray, target: np.ndarray) -> np.ndarray:
    """Least squares with every column scaled to unit norm first (the columns span many orders of magnitude)."""
    norms = np.linalg.norm(columns, axis=0)
    norms[norms == 0] = 1.0
    solution, *_ = np.linalg.lstsq(columns / norms, target, rcond=None)
    return np.asarray(solution / norms)


def _stack(values: np.ndarray) -> np.ndarray:
    """Complex rows as real rows: real parts, then imaginary parts."""
    return np.concatenate((values.real, values.imag))


def refine_sections(w: np.ndarray, y: np.ndarray, sections: Sections) -> tuple[int, float]:
    """Gauss-Newton on every section's parameters, window by window (see the module docstring), in place.

    Parameters
    ----------
    w : ndarray
        Angular frequencies of the samples, ascending, > 0.
    y : ndarray, complex
        The admittance at those frequencies (Y Z0).
    sections : Sections
        The starting point (a rational fit's); moved in place.

    Returns
    -------
    sweeps, misfit
        Sweeps in which some window's step lowered its misfit by 1 % at least (:data:`_GAIN`), and the largest
        weighted misfit left on the samples fitted.
    """
    model = sections.value(w, sections.c)
    sweeps = 0
    still = 0
    for sweep in range(_SWEEPS):
        moved = False
        for lo, hi in _windows(sections.size, shifted=bool(sweep % 2)):
            moved |= _window_step(w, y, sections, model, lo, hi)
        still = 0 if moved else still + 1
        if still == 2:  # neither the windows nor the shifted ones moved
            break
        sweeps += moved
    return sweeps, _misfit(w, y - model, sections)


def _misfit(w: np.ndarray, residual: np.ndarray, sections: Sections) -> float:
    """Largest weighted misfit, each window's rows weighted by their nearest sections."""
    worst = 0.0
    for lo, hi in _windows(sections.size):
        rows, near = _rows(w, sections, lo, hi)
        worst = max(worst, float(np.max(np.abs(residual[rows]) * _weights(w[rows], sections, near), initial=0.0)))
    return worst


def _window_step(w: np.ndarray, y: np.ndarray, sections: Sections, model: np.ndarray, lo: int, hi: int) -> bool:
    """One Gauss-Newton step on modes lo..hi; taken (and ``model`` updated on every sample) if it lowers the
    window's largest weighted misfit.  Whether it lowered it by :data:`_GAIN` at least (sweeps stop when none
    does: the rounding of the samples is reached)."""
    rows, near = _rows(w, sections, lo, hi)
    if rows.size == 0:
        return False
    ws = w[rows]
    weight = _weights(ws, sections, near)[:, None]
    modes = slice(lo, hi)
    D = sections.denominators(ws, modes)
    c = sections.c[modes][None, :]
    gain = 1j * ws[:, None] / D
    blocks = [gain * weight, -c * gain / D * weight]  # d/dc, d/dx
    if sections.lossy:
        blocks.append(-c * gain * (1j * ws[:, None]) / D * weight)  # d/dgamma
    movable = np.concatenate([np.ones(hi - lo, dtype=bool), ~sections.fixed_x[modes]]
                             + ([np.ones(hi - lo, dtype=bool)] if sections.lossy else []))
    jacobian = _stack(np.hstack(blocks))[:, movable]
    residual = (y[rows] - model[rows]) * weight[:, 0]
    before = float(np.max(np.abs(residual)))
    step = np.zeros(movable.size)
    step[movable] = _solve_beside(jacobian, _background(ws, weight, sections), _stack(residual))
    k = hi - lo
    old = (sections.c[modes].copy(), sections.x[modes].copy(), sections.gamma[modes].copy())
    for fraction in _FRACTIONS:  # the whole step, else shorter ones (overlapping modes: Gauss-Newton overshoots)
        trial_x = old[1] + fraction * step[k:2 * k]
        if not sections.lossy:  # a step that reorders the poles is no step
            bounds = np.concatenate(([sections.x[lo - 1]] if lo > 0 else [], trial_x,
                                     [sections.x[hi]] if hi < sections.size else []))
            if np.any(np.diff(bounds) <= 0):
                continue
        sections.c[modes] = old[0] + fraction * step[:k]
        sections.x[modes] = trial_x
        if sections.lossy:
            sections.gamma[modes] = old[2] + fraction * step[2 * k:]
        change = sections.value(ws, sections.c, modes) - _value(ws, old)
        after = float(np.max(np.abs((y[rows] - model[rows] - change) * _weights(ws, sections, near))))
        if after < before:
            model += sections.value(w, sections.c, modes) - _value(w, old)
            return after < _GAIN * before
        sections.c[modes], sections.x[modes], sections.gamma[modes] = old
    return False


def _background(ws: np.ndarray, weight: np.ndarray, sections: Sections) -> np.ndarray | None:
    """Stacked columns of a smooth correction over a window's rows (None for one window): j w T_k(x) and, with
    losses, w T_k(x), k < :data:`_BACKGROUND`, T_k Chebyshev in x = w^2 scaled to [-1, 1].  The other windows'
    errors are smooth here, so a window's step fits them beside its own modes and drops them, instead of
    moving its modes to make up for them (block Gauss-Seidel then converges in a few sweeps, not dozens)."""
    if sections.size <= ONE_WINDOW:
        return None
    x = ws * ws
    scaled = (2.0 * x - (x[0] + x[-1])) / max(x[-1] - x[0], np.finfo(float).tiny)
    basis = np.polynomial.chebyshev.chebvander(scaled, _BACKGROUND - 1) * (ws * weight[:, 0])[:, None]
    return _stack(np.hstack((1j * basis, basis)) if sections.lossy else 1j * basis)


def _solve_beside(columns: np.ndarray, beside: np.ndarray | None, target: np.ndarray) -> np.ndarray:
    """Least squares for ``columns``' coefficients, with ``beside``'s fitted alongside and dropped."""
    if beside is None:
        return _solve(columns, target)
    return _solve(np.hstack((columns, beside)), target)[:columns.shape[1]]


def _value(w: np.ndarray, params: tuple[np.ndarray, np.ndarray, np.ndarray]) -> np.ndarray:
    """The sum of the sections (c, x, gamma) given apart from ``Sections`` (a window's previous parameters)."""
    c, x, gamma = params
    return _sum(w, c, x, gamma)


def _sum(w: np.ndarray, residues: np.ndarray, x: np.ndarray, gamma: np.ndarray) -> np.ndarray:
    """sum_n residues_n j w / D_n, D_n = x_n - w^2 + j gamma_n w; a sample on a lossless pole (D = 0, within
    rounding of a fitted pole) is infinite and left out of every fit (:func:`_rows`).

    Formed :data:`_BLOCK_VALUES` terms at a time, a block of samples after the other: each sample's sum is the
    same numbers added in the same order, and no (samples x sections) matrix is held whole."""
    out = np.empty(w.size, dtype=complex)
    rows = max(1, _BLOCK_VALUES // max(1, residues.size))
    with np.errstate(divide="ignore", invalid="ignore"):
        for start in range(0, w.size, rows):
            ws = w[start:start + rows]
            D = (x[None, :] - (ws * ws)[:, None]) + 1j * ws[:, None] * gamma[None, :]
            out[start:start + rows] = (1j * ws[:, None] * residues[None, :] / D).sum(axis=1)
    return out


def section_residues(w: np.ndarray, y: np.ndarray, sections: Sections) -> np.ndarray:
    """The residues of another admittance ``y`` at the sections' poles: weighted linear least squares, window by
    window (block Gauss-Seidel on the whole residual) until the residues stop changing."""
    residues = np.zeros(sections.size)
    model = np.zeros(w.size, dtype=complex)
    windows = _windows(sections.size)
    plan = []
    for lo, hi in windows:
        rows, near = _rows(w, sections, lo, hi)
        weight = _weights(w[rows], sections, near)[:, None]
        # the window's modes and its neighbours' (whose steps are dropped: their own windows make them)
        first, stop = max(lo - _HALO, 0), min(hi + _HALO, sections.size)
        columns = _stack(1j * w[rows][:, None] / sections.denominators(w[rows], slice(first, stop)) * weight)
        plan.append((lo, hi, rows, weight, columns, _background(w[rows], weight, sections), slice(lo - first,
                                                                                                   hi - first)))
    for _ in range(_RESIDUE_SWEEPS if len(windows) > 1 else 1):
        largest = 0.0
        for lo, hi, rows, weight, columns, beside, own in plan:
            step = _solve_beside(columns, beside, _stack((y[rows] - model[rows]) * weight[:, 0]))[own]
            residues[lo:hi] += step
            model += _value(w, (step, sections.x[lo:hi], sections.gamma[lo:hi]))
            largest = max(largest, float(np.max(np.abs(step), initial=0.0)))
        if largest <= _RESIDUE_CHANGE * float(np.max(np.abs(residues), initial=1.0)):
            break
    return residues
