"""Every mode of a ladder, with its shape, from an AC analysis that drives every loop (pure arrays).

With an AC source b_k in series with every loop's inductor (zero impedance: the modes are unchanged) the loop
currents are, at s = j w (w in units of 1/sqrt(L0 C0), currents times Z0 = sqrt(L0/C0)),

    I(s) = (s^2 M + s M / Q + K)^-1 s b = sum_n s u_n (u_n . b) / (s^2 + gamma_n s + w_n^2),

for the M-orthonormal modes u_n of the chain (M the masses, K the springs; gamma_n = 1/Q with losses, else 0).
So g(w) = I / (j w) = sum_n r_n / D_n(w), D_n = x_n - w^2 + j gamma_n w, x_n = w_n^2, and each mode's residue is a
vector over the loops, r_n = u_n (u_n . b): r_n . b = (u_n . b)^2, and

    u_n = r_n / sqrt(r_n . b),

the mode's shape, with no knowledge of L or C.  A drive with random complex amplitudes (a seeded generator) makes
|u_n . b| ~ 0 very unlikely: every mode has a strong residue on the loops where it lives, including a perfect
cradle's edge modes, whose weight at the ends (2^-(2N-3)) no fit of a drive in loop 1 can see.

:func:`fit_survey` identifies every (x_n, gamma_n) and every r_n from the samples g (frequencies x loops), starting
from the predicted poles, in windows of :data:`CORE` modes.  A window is fitted on the samples around its modes
and :data:`HALO` neighbours on each side (explicit sections), less the current model of :data:`FAR` further
neighbours on each side, with a smooth correction of :data:`BACKGROUND` Chebyshev terms beside (the modes beyond);
each row is weighted by the nearest section's inverse gain.  At fixed poles a window's residues are linear in its
far neighbours', so every window together is one banded linear system: the residues of every mode on every loop
come from one sparse LU solve with the loops as right-hand sides.  The poles move by Gauss-Newton, window by
window, on :data:`SKETCH` random combinations of the loops (every mode is in each): variable projection with
Kaufman's Jacobian, whose normal equations over all the columns are (parameters x parameters).  Up to
:data:`SWEEPS` steps, until none moves a pole by more than ``_SETTLED`` (from theory's poles: one or two).

Cost: the windows' least squares and the far modes' sections, O(samples x (CORE + 2 HALO + 2 FAR)); the loops
enter through the right-hand sides, O(samples x CORE x N) to form them and the banded solve, O(N x (CORE + 2 HALO
+ 2 FAR) x N): O(N^2) on a grid of O(N) frequencies.  Memory: the samples, N x samples complex values, and the
residues, N x N.  Up to :data:`ONE_WINDOW` modes, one window holds every mode (its model exact, no background).
Measured against exact theory in ``benchmarks/spectrum.md``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..core.blas import fixed_blas_threads
from ..core.errors import ParameterError
from ..core.frozen import FrozenArrays

__all__ = ["ModeSurvey", "fit_survey", "survey_amplitudes", "mode_shapes", "CORE", "HALO", "FAR", "SWEEPS",
           "BACKGROUND", "SURVEY_SEED", "SKETCH", "signed_shapes"]

#: Modes whose parameters one window keeps.
CORE = 8
#: Up to this many modes, one window holds them all (no far modes, no Python loop over windows).
ONE_WINDOW = 128
#: Neighbours on each side fitted beside a window's modes (their values are the neighbouring windows').
HALO = 8
#: Neighbours beyond the halo on each side whose current model is subtracted from a window's samples.
FAR = 32
#: Terms of the smooth correction a window fits beside its sections (the modes beyond the far ones).
BACKGROUND = 12
#: Gauss-Newton steps on the poles at most (each: the residues of every window at once, then each window's step).
SWEEPS = 8
#: A step below this (relative to its window's largest x) ends them: the poles have settled (omega_n moves by half as
#: much, three decades below the target).
_SETTLED = 1e-12
#: Random combinations of the loops the poles are fitted on (the residues are then solved on every loop).
SKETCH = 16
#: The seed of the drive's amplitudes: the same netlist for the same chain, every time.
SURVEY_SEED = 20261127


def survey_amplitudes(N: int, seed: int = SURVEY_SEED) -> np.ndarray:
    """The complex amplitudes b_k of the AC sources in loops 1..N: moduli in [0.5, 1], phases uniform (a fixed
    seeded generator, ``numpy.random.default_rng(seed)``)."""
    rng = np.random.default_rng(seed)
    modulus = rng.uniform(0.5, 1.0, N)
    phase = rng.uniform(0.0, 2.0 * np.pi, N)
    return np.asarray(modulus * np.exp(1j * phase))


@dataclass(frozen=True, eq=False)
class ModeSurvey(FrozenArrays):
    """Every mode found in a survey (:func:`fit_survey`), ascending in omega.

    Attributes
    ----------
    omega : ndarray
        Undamped normal frequencies sqrt(x_n), units of 1/sqrt(L0 C0).
    gamma : ndarray
        Decay rates (0 without losses), units of 1/sqrt(L0 C0).
    residues : ndarray, complex, (modes, loops)
        r_n = u_n (u_n . b) of g = I / (j w).
    sweeps : int
    residual : float
        Largest misfit left on a window's samples (of the loops' random combinations the poles are fitted on),
        relative to the largest sample there.
    """

    omega: np.ndarray
    gamma: np.ndarray
    residues: np.ndarray
    sweeps: int
    residual: float

    def __post_init__(self) -> None:
        self._freeze_arrays()

    def shapes(self, amplitudes: np.ndarray) -> np.ndarray:
        """u_n = r_n / sqrt(r_n . b) (:func:`mode_shapes`), (loops, modes)."""
        return mode_shapes(self.residues, amplitudes)


def mode_shapes(residues: np.ndarray, amplitudes: np.ndarray) -> np.ndarray:
    """The M-orthonormal shapes u_n = r_n / sqrt(r_n . b) as real columns (loops, modes), signed by
    :func:`signed_shapes`.  The imaginary part left (rounding) is dropped."""
    r = np.asarray(residues, dtype=complex)
    u = r / np.sqrt(r @ np.asarray(amplitudes, dtype=complex))[:, None]
    first = _first_large(u.T)
    phase = u[np.arange(u.shape[0]), first]
    u = u * (np.abs(phase) / phase)[:, None]
    return np.asarray(u.real.T)


def _first_large(u: np.ndarray) -> np.ndarray:
    """Per column of ``u`` (loops, modes), the first loop whose |entry| is at least half the largest (a symmetric
    chain's modes have two largest entries of equal size: the first of them would be a coin toss)."""
    size = np.abs(u)
    return np.asarray(np.argmax(size >= 0.5 * np.max(size, axis=0), axis=0))


def signed_shapes(u: np.ndarray) -> np.ndarray:
    """Real shapes (loops, modes), each column's sign chosen so that its first entry of at least half the
    largest size is positive: measured and theoretical shapes signed alike."""
    u = np.asarray(u, dtype=float)
    return np.asarray(u * np.sign(u[_first_large(u), np.arange(u.shape[1])]))


def _chebyshev(x: np.ndarray, terms: int) -> np.ndarray:
    scaled = (2.0 * x - (x[0] + x[-1])) / max(x[-1] - x[0], np.finfo(float).tiny)
    return np.polynomial.chebyshev.chebvander(scaled, terms - 1)


def _edges(x: np.ndarray, w: np.ndarray, lo: int, hi: int) -> np.ndarray:
    """The samples between the middles of the gaps around modes lo..hi-1: every sample below at the bottom, and
    above the top mode as far as its :data:`HALO` neighbours reach below it (further up the far modes' sum is no
    longer smooth on the window's scale where the poles crowd at the top of the band: two-mass N = 1000's top
    modes were placed to 2e-4 with every sample up to 5 % above the top)."""
    root = np.sqrt(np.clip(x, 0.0, None))
    left = -np.inf if lo == 0 else 0.5 * (root[lo - 1] + root[lo])
    top = x.size - 1
    right = (2.0 * root[top] - root[max(top - HALO, 0)] if hi >= x.size else 0.5 * (root[hi - 1] + root[hi]))
    return np.flatnonzero((w > left) & (w <= right))


@fixed_blas_threads
def fit_survey(omega: np.ndarray, g: np.ndarray, x0: np.ndarray, *, lossy: bool = False,
               gamma0: np.ndarray | None = None, fixed_x: np.ndarray | None = None,
               seed: int = SURVEY_SEED) -> ModeSurvey:
    """Identify every mode of g = I / (j w) sampled on every loop (module docstring).

    Parameters
    ----------
    omega : ndarray
        Angular frequencies of the samples, ascending, > 0, units of 1/sqrt(L0 C0).
    g : ndarray, complex, (samples, loops)
        The loop currents over j w (times Z0).
    x0 : ndarray
        The predicted squared frequencies x_n, ascending (one per mode).
    lossy : bool
        Fit each mode's decay rate (from ``gamma0``); else every gamma_n = 0.
    gamma0 : ndarray, optional
        The predicted decay rates.
    fixed_x : ndarray of bool, optional
        Modes whose x_n stays (a free chain's zero mode: x = 0 exactly).
    seed : int
        Of the loops' random combinations the poles are fitted on (:data:`SKETCH` of them).

    Raises
    ------
    ParameterError
        Samples that are not a survey's (not ascending, or a shape that does not match).
    """
    w = np.asarray(omega, dtype=float)
    g = np.asarray(g, dtype=complex)
    if w.ndim != 1 or w.size < 8 or not np.all(np.diff(w) > 0) or w[0] <= 0:
        raise ParameterError("omega", f"{w.size} frequencies", "at least 8 ascending frequencies > 0")
    if g.ndim != 2 or g.shape[0] != w.size:
        raise ParameterError("g", g.shape, f"(frequencies, loops) with {w.size} frequencies")
    x = np.array(x0, dtype=float)
    gamma = np.zeros(x.size) if gamma0 is None else np.array(gamma0, dtype=float)
    fixed = np.zeros(x.size, dtype=bool) if fixed_x is None else np.asarray(fixed_x, dtype=bool)
    if g.shape[1] > SKETCH:  # the poles from a few random combinations of the loops: every mode is in each
        rng = np.random.default_rng(seed)
        mix = rng.standard_normal((g.shape[1], SKETCH)) + 1j * rng.standard_normal((g.shape[1], SKETCH))
        sketch = g @ mix
    else:
        sketch = g
    sweeps = 0
    while sweeps < SWEEPS:
        sweeps += 1
        windows = _plan(w, x, gamma)
        residues = _residues(windows, sketch, x.size)
        step = max(_move_poles(window, w, sketch, x, gamma, fixed, residues, lossy) for window in windows)
        if step <= _SETTLED:  # the windows' sections are the poles' to within rounding: keep them
            break
    else:
        windows = _plan(w, x, gamma)
        residues = _residues(windows, sketch, x.size)
    worst = max(_misfit(window, sketch, residues) for window in windows)  # the sketch's misfit: the loops' mixed
    residues = _residues(windows, g, x.size)
    return ModeSurvey(np.sqrt(np.clip(x, 0.0, None)), gamma, residues, sweeps, worst)


@dataclass
class _Window:
    """One window's least squares at fixed poles: its rows, explicit modes, far modes and projections."""

    lo: int
    hi: int
    rows: np.ndarray
    explicit: np.ndarray
    far: np.ndarray
    weight: np.ndarray
    q: np.ndarray
    solve: np.ndarray  # (explicit + background) x rows: the weighted rows' least squares
    far_columns: np.ndarray  # rows x far: the far modes' sections on the rows


def _sections(ws: np.ndarray, x: np.ndarray, gamma: np.ndarray) -> np.ndarray:
    return np.asarray(1.0 / (x[None, :] - (ws * ws)[:, None] + 1j * ws[:, None] * gamma[None, :]))


def _plan(w: np.ndarray, x: np.ndarray, gamma: np.ndarray) -> list[_Window]:
    import scipy.linalg  # here: importing the survey (every report and app module does) costs no scipy

    n_modes = x.size
    core = n_modes if n_modes <= ONE_WINDOW else CORE
    windows = []
    for lo in range(0, n_modes, core):
        hi = min(lo + core, n_modes)
        a, z = max(lo - HALO, 0), min(hi + HALO, n_modes)
        rows = _edges(x, w, a, z)
        needed = z - a + (BACKGROUND if core < n_modes else 0) + 2
        if rows.size < needed:  # poles crowded closer than the samples (merged lossy modes): the nearest samples
            middle = 0.5 * (np.sqrt(max(x[a], 0.0)) + np.sqrt(max(x[z - 1], 0.0)))
            rows = np.sort(np.argsort(np.abs(w - middle), kind="stable")[:min(needed, w.size)])
        ws = w[rows]
        explicit = np.arange(a, z)
        far = np.r_[max(a - FAR, 0):a, z:min(z + FAR, n_modes)].astype(int)
        A = _sections(ws, x[explicit], gamma[explicit])
        weight = np.min(np.abs(1.0 / A), axis=1)  # the nearest section's inverse gain: rows carry rounding alike
        # the modes beyond the far ones, smooth here; a window of every mode has the exact model and none
        basis = np.hstack((A, _chebyshev(ws * ws, BACKGROUND))) if BACKGROUND and core < n_modes else A
        basis = basis * weight[:, None]
        scale = np.linalg.norm(basis, axis=0)
        q, r = np.linalg.qr(basis / scale)
        solve = scipy.linalg.solve_triangular(r, q.conj().T * weight[None, :]) / scale[:, None]
        windows.append(_Window(lo, hi, rows, explicit, far, weight, q, solve,
                               _sections(ws, x[far], gamma[far])))
    return windows


def _residues(windows: list[_Window], g: np.ndarray, n_modes: int) -> np.ndarray:
    """Every mode's residues on every column of ``g`` at fixed poles: each window's core residues are its least
    squares of (samples - far modes' sections), linear in the far modes' residues, so all windows together are
    one sparse (banded) linear system, solved directly."""
    import scipy.sparse
    import scipy.sparse.linalg

    rhs = np.empty((n_modes, g.shape[1]), dtype=complex)
    rows_i, cols_i, values = [], [], []
    for window in windows:
        core = slice(window.lo - window.explicit[0], window.hi - window.explicit[0])
        solve = window.solve[core]
        rhs[window.lo:window.hi] = solve @ g[window.rows]
        coupling = solve @ window.far_columns  # core x far
        modes = np.arange(window.lo, window.hi)
        rows_i.append(np.repeat(modes, window.far.size))
        cols_i.append(np.tile(window.far, modes.size))
        values.append(coupling.ravel())
    rows_i.append(np.arange(n_modes))
    cols_i.append(np.arange(n_modes))
    values.append(np.ones(n_modes, dtype=complex))
    matrix = scipy.sparse.csc_matrix((np.concatenate(values), (np.concatenate(rows_i), np.concatenate(cols_i))),
                                     shape=(n_modes, n_modes))
    return np.asarray(scipy.sparse.linalg.splu(matrix).solve(rhs))


def _target(window: _Window, g: np.ndarray, residues: np.ndarray) -> np.ndarray:
    return np.asarray(g[window.rows] - window.far_columns @ residues[window.far])


def _misfit(window: _Window, g: np.ndarray, residues: np.ndarray) -> float:
    """The window's largest weighted misfit relative to its largest weighted sample."""
    target = _target(window, g, residues) * window.weight[:, None]
    misfit = target - window.q @ (window.q.conj().T @ target)
    return float(np.max(np.abs(misfit), initial=0.0) / max(float(np.max(np.abs(target), initial=0.0)),
                                                           np.finfo(float).tiny))


def _move_poles(window: _Window, w: np.ndarray, g: np.ndarray, x: np.ndarray, gamma: np.ndarray,
                fixed: np.ndarray, residues: np.ndarray, lossy: bool) -> float:
    """One Gauss-Newton step on the window's core poles, every column at once (variable projection, Kaufman's
    Jacobian J_k[:, i] = P_perp dA_i c_ik: the normal equations are Re((V^H V) * (conj(C) C^T))).  The largest
    step, relative to the largest x of the window (0: nothing moves)."""
    ws = w[window.rows]
    target = _target(window, g, residues)
    coeffs = window.solve @ target
    weighted = target * window.weight[:, None]
    misfit = weighted - window.q @ (window.q.conj().T @ weighted)
    explicit = window.explicit
    slope = -_sections(ws, x[explicit], gamma[explicit]) ** 2 * window.weight[:, None]  # d/dx of each section
    moves_x = np.flatnonzero(~fixed[explicit])
    which = [moves_x] + ([np.arange(explicit.size)] if lossy else [])
    columns = [slope[:, moves_x]] + ([1j * ws[:, None] * slope] if lossy else [])  # d/dgamma = j w d/dx
    if not moves_x.size and not lossy:
        return 0.0
    V = np.hstack(columns)
    V = V - window.q @ (window.q.conj().T @ V)
    c = coeffs[np.concatenate(which)]
    normal = ((V.conj().T @ V) * (c.conj() @ c.T)).real
    rhs = (c.conj() * (V.conj().T @ misfit)).sum(axis=1).real
    delta = np.linalg.lstsq(normal, rhs, rcond=None)[0]
    if not np.all(np.isfinite(delta)):  # a singular window (modes merged beyond telling apart): no step
        return 0.0
    core = (explicit >= window.lo) & (explicit < window.hi)  # a halo mode: its own window places it
    dx = np.zeros(explicit.size)
    dx[moves_x] = delta[:moves_x.size]
    dgamma = delta[moves_x.size:] if lossy else np.zeros(explicit.size)
    # a trust region: no pole moves by more than a quarter of its distance to a neighbour, no decay rate by more
    # than half itself (modes merged beyond telling apart would otherwise wander off)
    gaps = np.diff(x[max(explicit[0] - 1, 0):explicit[-1] + 2])
    room = 0.25 * np.minimum(np.r_[np.inf, gaps], np.r_[gaps, np.inf])
    room = room[1:explicit.size + 1] if explicit[0] > 0 else room[:explicit.size]
    excess = max(float(np.max(np.abs(dx) / np.maximum(room, np.finfo(float).tiny), initial=0.0)),
                 float(np.max(np.abs(dgamma) / np.maximum(0.5 * gamma[explicit], np.finfo(float).tiny),
                              initial=0.0)) if lossy else 0.0)
    if excess > 1.0:
        dx, dgamma = dx / excess, dgamma / excess
    x[explicit[core]] += dx[core]
    gamma[explicit[core]] += dgamma[core]
    largest = float(np.max(np.abs(np.concatenate((dx[core], dgamma[core]))), initial=0.0))
    return largest / max(float(np.max(x[explicit])), np.finfo(float).tiny)
