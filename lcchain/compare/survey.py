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

With ``exact=True`` (a few columns: the loop-1 fit from theory, :func:`lcchain.compare.spectrum.fit_from_theory`) every
other mode's exact model is subtracted from a window's samples, not only its far neighbours': the banded solve's
residues are refined on the whole residual and the poles move on it, O(samples x N x columns) a sweep, so the
residues reach the samples' rounding.  The sweeps then end when no pole the samples place (standard error at most
:data:`PLACED` of a quarter gap) moved by more than :data:`_SURPRISE` standard errors; the others, too weak to place,
are reported through :attr:`ModeSurvey.placed`.

Cost: the windows' least squares and the far modes' sections, O(samples x (CORE + 2 HALO + 2 FAR)); the loops
enter through the right-hand sides, O(samples x CORE x N) to form them and the banded solve, O(N x (CORE + 2 HALO
+ 2 FAR) x N): O(N^2) on a grid of O(N) frequencies.  Memory: the samples, N x samples complex values, and the
residues, N x N.  Up to :data:`ONE_WINDOW` modes, one window holds every mode (its model exact, no background).
Measured against exact theory in ``benchmarks/spectrum.md``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from ..core.blas import fixed_blas_threads
from ..core.errors import ParameterError
from ..core.frozen import FrozenArrays

if TYPE_CHECKING:
    from scipy.sparse.linalg import SuperLU

    from ..theory.chain import Chain

__all__ = ["ModeSurvey", "PoleStart", "SurveyOptions", "fit_survey", "survey_amplitudes", "mode_shapes", "CORE",
           "HALO", "FAR", "SWEEPS", "BACKGROUND", "SURVEY_SEED", "SKETCH", "signed_shapes",
           "remove_modes", "currents_error"]

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
    spread : ndarray
        Each x_n's standard error from the last Gauss-Newton step (the misfit's spread through its normal
        equations; infinite where the samples do not place the pole, and for a pole held fixed).
    """

    omega: np.ndarray
    gamma: np.ndarray
    residues: np.ndarray
    sweeps: int
    residual: float
    spread: np.ndarray = field(default_factory=lambda: np.zeros(0))

    def __post_init__(self) -> None:
        self._freeze_arrays()

    @property
    def placed(self) -> np.ndarray:
        """The modes whose pole the samples place: its standard error at most :data:`PLACED` of a quarter of its
        nearest gap (the others stayed where they started, their step being the samples' noise), bool per mode."""
        return np.asarray(self.spread <= PLACED * _room(self.omega ** 2))

    def shapes(self, amplitudes: np.ndarray) -> np.ndarray:
        """u_n = r_n / sqrt(r_n . b) (:func:`mode_shapes`), (loops, modes)."""
        return mode_shapes(self.residues, amplitudes)


@fixed_blas_threads
def mode_shapes(residues: np.ndarray, amplitudes: np.ndarray) -> np.ndarray:
    """The M-orthonormal shapes u_n = r_n / sqrt(r_n . b) as real columns (loops, modes), signed by
    :func:`signed_shapes`.  The imaginary part left (rounding) is dropped.  Under one BLAS thread, as the fit: a
    second thread woken for this small product cost 10 ms on the loaded machine (the survey's N = 100 fit took
    50 ms)."""
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


@fixed_blas_threads
def remove_modes(omega: np.ndarray, g: np.ndarray, x: np.ndarray, gamma: np.ndarray, shapes: np.ndarray,
                 amplitudes: np.ndarray) -> None:
    """Subtract the given modes' model from the samples, in place: g -= sum_n u_n (u_n . b) / D_n(w), their
    residues r_n = u_n (u_n . b) from the shapes ``shapes`` (loops x these modes, M-orthonormal) and the drive
    ``amplitudes`` b, D_n = x_n - w^2 + j gamma_n w (the modes losses merge, whose theory is subtracted before the
    others are fitted, as the loop-1 fit's :func:`lcchain.compare.spectrum.fit_from_theory` does).  A block of
    :data:`_BLOCK_VALUES` / loops frequencies at a time, two real products (the shapes are real):
    O(frequencies x these modes x loops)."""
    u = np.ascontiguousarray(shapes, dtype=float)
    weight = u.T @ np.asarray(amplitudes, dtype=complex)  # u_n . b
    step = max(1, _BLOCK_VALUES // max(1, g.shape[1]))
    for start in range(0, omega.size, step):
        rows = slice(start, start + step)
        columns = _sections(omega[rows], x, gamma, True) * weight[None, :]
        g[rows] -= _product(u, np.ascontiguousarray(columns.T)).T
    return None


def currents_error(chain: Chain, omega: np.ndarray, g: np.ndarray, amplitudes: np.ndarray, Q: float | None) -> float:
    """max over the samples of max_k |g_k - g_k exact| / max_k |g_k exact|: every loop's current against the chain's
    own (:func:`lcchain.theory.spectrum.loop_currents`, no modes), what modes merged by the losses are measured by.
    A block of 2^20 / loops frequencies at a time (no array of the whole sweep beside the samples)."""
    from ..theory.spectrum import loop_currents

    worst = 0.0
    step = max(1, 2**20 // max(1, g.shape[1]))
    for start in range(0, omega.size, step):
        rows = slice(start, start + step)
        exact = loop_currents(chain, omega[rows], amplitudes, Q)
        error = np.max(np.abs(g[rows] - exact), axis=1) / np.max(np.abs(exact), axis=1)
        worst = max(worst, float(np.max(error, initial=0.0)))
    return worst


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


@dataclass(frozen=True, eq=False)
class PoleStart:
    """Where :func:`fit_survey` starts each mode's pole, and which parts of it stay.

    Attributes
    ----------
    x : ndarray
        The predicted squared frequencies x_n, ascending (one per mode).
    gamma : ndarray, optional
        The predicted decay rates (with losses).
    fixed_x : ndarray of bool, optional
        Modes whose x_n stays (a free chain's zero mode: x = 0 exactly).
    fixed_gamma : ndarray of bool, optional
        With losses, modes whose gamma_n stays (with their x_n in ``fixed_x``: modes the losses merge, whose poles
        the samples cannot tell apart; their residues are still fitted, so that they explain the samples).
    residues : ndarray, optional
        The predicted residues (modes x loops).  With :attr:`SurveyOptions.exact` the fit starts from them: its
        first model is then every mode's, and each window fits only the whole residual's correction, so it needs
        no smooth background (:data:`BACKGROUND`) and no banded solve (the far modes' part of the samples is
        their model, no longer unknown).
    """

    x: np.ndarray
    gamma: np.ndarray | None = None
    fixed_x: np.ndarray | None = None
    fixed_gamma: np.ndarray | None = None
    residues: np.ndarray | None = None


@dataclass(frozen=True)
class SurveyOptions:
    """How :func:`fit_survey` fits.

    Attributes
    ----------
    lossy : bool
        Fit each mode's decay rate (from :attr:`PoleStart.gamma`); else every gamma_n = 0 and the sections are
        real.
    real : bool
        With losses, hold every residue real (proportional losses keep the modes real: the loop-1 fit's a_n and
        b_n); each window's least squares is then on the samples' real and imaginary parts stacked.  A complex
        residue's phase trades with its pole's decay rate: measured on ngspice's perfect cradle N = 20 at Q = 1000,
        the weakest compared mode's gamma_n 1.0e-12 off with complex residues, 2e-13 with real ones.
    seed : int
        Of the loops' random combinations the poles are fitted on (:data:`SKETCH` of them).
    exact : bool
        Subtract every other mode's exact model from a window's samples, not only its :data:`FAR` neighbours':
        the windows' residues are refined on the whole residual (:data:`REFINE` passes of the same banded
        solve) and the poles move on it.  O(samples x modes x loops) per sweep: for a few loops (a drive in loop
        1), whose residues then reach the samples' rounding where the far modes' smooth remainder stopped them
        near 1e-11 (two-mass N = 100 in windows of :data:`CORE`).
    one_window : int
        Up to this many modes, one window holds every mode.
    core : int
        Beyond ``one_window``, the modes whose parameters one window keeps.
    halo : int
        Neighbours on each side fitted beside a window's modes.
    background : int
        Terms of the smooth correction a window fits beside its sections (beyond ``one_window``).
    """

    lossy: bool = False
    real: bool = False
    seed: int = SURVEY_SEED
    exact: bool = False
    one_window: int = ONE_WINDOW
    core: int = CORE
    halo: int = HALO
    background: int = BACKGROUND


@fixed_blas_threads
def fit_survey(omega: np.ndarray, g: np.ndarray, start: PoleStart,
               options: SurveyOptions = SurveyOptions()) -> ModeSurvey:
    """Identify every mode of g = I / (j w) sampled on every loop (module docstring).

    Parameters
    ----------
    omega : ndarray
        Angular frequencies of the samples, ascending, > 0, units of 1/sqrt(L0 C0).
    g : ndarray, complex or real, (samples, loops)
        The loop currents over j w (times Z0); real for a lossless ladder's Im(I) / w, whose model is real.
    start : PoleStart
        The predicted poles, and which of them stay.
    options : SurveyOptions
        Losses, real residues, the seed, the exact subtraction and the windows' sizes.

    Raises
    ------
    ParameterError
        Samples that are not a survey's (not ascending, or a shape that does not match).

    Notes
    -----
    Under one BLAS thread (:func:`lcchain.core.blas.fixed_blas_threads`), as the loop-1 fit: its products are small,
    and a second thread on the loaded 2-core machine made the survey's fit of two-mass N = 200 at Q = 1000 take
    7.2 s instead of 0.1 s (N = 400: 17.8 s).
    """
    lossy, real, seed, exact = options.lossy, options.real, options.seed, options.exact
    one_window, core = options.one_window, options.core
    x0, gamma0, fixed_x, fixed_gamma = start.x, start.gamma, start.fixed_x, start.fixed_gamma
    w = np.asarray(omega, dtype=float)
    g = np.asarray(g)
    g = g.astype(float if np.isrealobj(g) and not lossy else complex, copy=False)
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
    fit = _Fit(w, x, gamma, fixed, lossy, exact, one_window, core, real and lossy)
    fit.halo, fit.background = options.halo, options.background
    if exact and start.residues is not None:
        fit.start = np.asarray(start.residues)
    if fixed_gamma is not None:
        fit.fixed_gamma = np.asarray(fixed_gamma, dtype=bool)
    sweeps, before = 0, np.inf
    last_step = np.inf
    while sweeps < SWEEPS:
        sweeps += 1
        fit.plan()
        fit.solve(sketch)
        planned = (x.copy(), gamma.copy())
        step, misfit, surprise = fit.move(sketch)
        settled = surprise <= _SURPRISE and misfit <= _NOISE**2 * fit.scale(sketch) if exact else step <= _SETTLED
        if settled:  # exact: no placed pole moved by many standard errors, on samples fitted to their noise
            break
        if exact and misfit > _GAIN * before:  # the misfit no longer falls
            break
        if not exact and step > _STALLED * last_step:  # the poles no longer settle (merged modes wandering): the
            x[:], gamma[:] = planned  # step is undone, and the poles stay where the residues were solved
            break
        last_step = step
        before = misfit
    if exact and max(surprise, fit.gamma_surprise) > 1.0:  # the residues at the poles as they now are (within
        fit.update(sketch)  # their standard errors of the plan's, they stand), refined on the whole residual
    elif sweeps == SWEEPS:
        fit.plan()
        fit.solve(sketch)
    worst = max(fit.misfit(window, sketch) for window in fit.windows)  # the sketch's misfit: the loops' mixed
    if sketch is not g:
        fit.solve(g)
    return ModeSurvey(np.sqrt(np.clip(x, 0.0, None)), gamma, fit.residues, sweeps, worst, fit.spread)


#: Passes of the exact residual's refinement (``exact=True``): each shrinks the residues' error by the far modes'
#: smooth remainder (measured on ngspice's two-mass N = 100 in windows of 8: omega_n to 1.0e-11 and P_n to 1.2e-12
#: without it, 2.3e-16 and 8.7e-16 after one pass).
REFINE = 1
#: The samples place a pole when its standard error is at most this fraction of its room (a quarter of its nearest
#: gap): :attr:`ModeSurvey.placed`.
PLACED = 1e-3
#: With ``exact``, the sweeps also end when one lowers the misfit (squared) by less than this factor.
_GAIN = 0.5
#: Without ``exact`` (a survey), the sweeps also end when the largest step is more than this fraction of the last
#: sweep's: from theory's poles Gauss-Newton settles the poles the samples place within one or two sweeps, and a
#: step that does not halve is modes merged beyond telling apart, moving to and fro (lossy two-mass N = 100 at
#: Q = 10: steps of 2e-4 for all 8 sweeps, the fit 7 times ngspice's time; ended at 2 sweeps, 1.7 times).  Measured
#: with it and without: the same modes resolved to the same omega_n, shapes and Q_n on lossy two-mass N = 200 .. 1000
#: and perfect N = 400, and lossless perfect N = 60 .. 1000, two-mass N = 500 and one-mass N = 1000 (the survey ending
#: there after 2 or 3 sweeps where it took 4 and 8 at lossy two-mass N = 400 and 1000).  The step that stalled is
#: undone: the residues were solved at the poles before it (solving them again after it resolved two modes fewer at
#: lossy two-mass N = 1000, 883 against 885).
_STALLED = 0.5
#: ... and when no placed pole moved by more than this many of its standard errors: Gauss-Newton converges
#: quadratically there, the next step is below one (perfect N = 100 on ngspice: 4.9, then 12 as the misfit fell
#: 150-fold, then 0.15; omega_n 1.1e-14 after three sweeps, 8.6e-14 stopping after the first).
_SURPRISE = 16.0
#: ... and the misfit's root mean square is at most this relative to the weighted samples' (ngspice's: 1e-14 ..
#: 1e-12; from poles 1e-3 of a gap off, 8e-4, where the standard errors are the misfit's and say nothing).
_NOISE = 1e-9
#: Samples closer than this (relative) to a lossless pole are left out: there the circuit's own rounding moves the
#: pole by more than the sample's distance to it (:data:`lcchain.compare.sections`' measure).
_TOO_CLOSE = 1e-9
#: A window's least squares of at most this many columns goes through its QR factors, not its formed ``solve``.
_FEW_COLUMNS = 4
#: Values of a block of the exact model formed at once (samples x modes).
_BLOCK_VALUES = 2**20
#: Up to this many values (samples x modes, complex: 64 MiB), the exact model's sections are kept while the poles
#: stay, so that a refinement of the residues costs a product, not the sections again (two-mass N = 400 at
#: Q = 1000: 5402 x 400, 28 ms each of four formed in a fit of 238 ms).
_KEPT_VALUES = 2**22


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
    r: np.ndarray  # the weighted, scaled basis = q r
    scale: np.ndarray  # each basis column's norm before the QR
    columns: np.ndarray  # rows x explicit: the explicit modes' sections on the rows
    far_columns: np.ndarray  # rows x far: the far modes' sections on the rows
    real: bool = False  # real residues: ``q`` and ``solve`` act on the rows' real and imaginary parts stacked
    _solve: np.ndarray | None = None

    @property
    def solve(self) -> np.ndarray:
        """(explicit + background) x rows: the weighted rows' least squares, formed on first use."""
        if self._solve is None:
            import scipy.linalg

            self._solve = scipy.linalg.solve_triangular(self.r, self.q.conj().T * self._rows_weight()[None, :],
                                                        check_finite=False) / self.scale[:, None]
        return self._solve

    def _rows_weight(self) -> np.ndarray:
        return np.concatenate((self.weight, self.weight)) if self.real else self.weight  # the stacked rows'

    def least_squares(self, b: np.ndarray) -> np.ndarray:
        """``solve @ b`` for the stacked rows ``b``: a few columns (the loop-1 fit's two) through the QR factors
        themselves, cols x rows x columns, where forming ``solve`` costs cols^2 x rows; more columns (a survey's
        loops, the banded system's far modes) through ``solve``, formed once."""
        if self._solve is not None or b.shape[1] > _FEW_COLUMNS:
            return _product(self.solve, b)
        import scipy.linalg

        projected = _product(self.q.conj().T, b * self._rows_weight()[:, None])
        return np.asarray(scipy.linalg.solve_triangular(self.r, projected, check_finite=False)
                          / self.scale[:, None])


def _stack(z: np.ndarray, real: bool) -> np.ndarray:
    """``z``'s real parts above its imaginary parts (rows), for a window of real residues; else ``z`` itself."""
    return np.concatenate((z.real, z.imag)) if real else z


def _sections(ws: np.ndarray, x: np.ndarray, gamma: np.ndarray, lossy: bool = True) -> np.ndarray:
    """1 / D_n(w) on the samples ``ws`` (rows) for the modes of ``x`` (columns): real without losses."""
    if not lossy:
        return np.asarray(1.0 / (x[None, :] - (ws * ws)[:, None]))
    # formed in place, its real and imaginary parts written apart: a third of the time of 1 / (D + 1j w gamma) with
    # its temporaries (5402 x 400: 14 ms against 29), the same to the last bit's rounding
    out = np.empty((ws.size, x.size), dtype=complex)
    parts = out.view(float).reshape(ws.size, x.size, 2)
    np.subtract(x[None, :], (ws * ws)[:, None], out=parts[:, :, 0])
    np.multiply(ws[:, None], gamma[None, :], out=parts[:, :, 1])
    return np.reciprocal(out, out=out)


class _Fit:
    """The poles (``x``, ``gamma``, moved in place), their windows' plans and the residues at the poles."""

    def __init__(self, w: np.ndarray, x: np.ndarray, gamma: np.ndarray, fixed: np.ndarray, lossy: bool,
                 exact: bool, one_window: int, core: int, real: bool = False):
        self.w, self.x, self.gamma, self.fixed, self.lossy = w, x, gamma, fixed, lossy
        self.exact, self.one_window, self.core, self.real = exact, one_window, core, real
        self.fixed_gamma = np.zeros(x.size, dtype=bool)
        #: the last :meth:`move`'s largest step of a placed pole's decay rate over its standard error (the sweeps'
        #: stopping rule is on x alone; a decay rate that moved more than its error has the residues solved again)
        self.gamma_surprise = 0.0
        self.windows: list[_Window] = []
        self.residues = np.zeros((x.size, 0))
        self.model: np.ndarray | None = None
        self.spread = np.full(x.size, np.inf)
        self._lu: SuperLU | None = None
        #: the predicted residues to start from (:attr:`PoleStart.residues`), None: solved from the samples
        self.start: np.ndarray | None = None
        self.halo, self.background = HALO, BACKGROUND
        self._kept: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None

    def plan(self) -> None:
        """Each window's rows and least squares at the current poles, and the banded system that couples them (none
        from predicted residues: each window fits the whole residual's correction)."""
        self.windows = _plan(self.w, self.x, self.gamma, self.lossy, self.one_window, self.core, self.real,
                             self.halo, self.background, far_columns=self.start is None)
        self._lu = _band(self.windows, self.x.size) if self.start is None else None

    def solve(self, g: np.ndarray) -> None:
        """Every mode's residues on every column of ``g`` at the planned poles (exact: refined on the whole
        residual, whose model is kept for the poles' steps; from the predicted residues the first time, then from
        the last)."""
        if self.start is not None:
            if self.residues.shape != self.start.shape:
                self.residues = self.start.astype(float if self.real else complex)
            self.update(g)
            return
        self.residues = _solve_band(self._lu, _rhs(self.windows, g, self.x.size))
        self.model = None
        if self.exact:
            self.update(g, REFINE if len(self.windows) > 1 else 0)  # one window's model is every mode's already

    def update(self, g: np.ndarray, passes: int = REFINE) -> None:
        """Refine the residues on the whole residual at the poles as they are (moved since the plan: by so little
        that the plan's least squares still project the residual well, the fixed point is theirs to second order),
        and keep the whole model."""
        model = self.exact_model()
        for _ in range(passes):
            self.residues = self.residues + _solve_band(self._lu, _rhs(self.windows, g - model, self.x.size))
            model = self.exact_model()
        self.model = model

    def exact_model(self) -> np.ndarray:
        """sum_n r_n / D_n(w) on every sample at the current poles and residues; the sections kept while the poles
        stay, up to :data:`_KEPT_VALUES` values."""
        if self.w.size * self.x.size > _KEPT_VALUES:
            return _model(self.w, self.x, self.gamma, self.residues, self.lossy)
        if self._kept is None or not (np.array_equal(self._kept[0], self.x)
                                      and np.array_equal(self._kept[1], self.gamma)):
            with np.errstate(divide="ignore", invalid="ignore"):
                self._kept = (self.x.copy(), self.gamma.copy(), _sections(self.w, self.x, self.gamma, self.lossy))
        return _product(self._kept[2], self.residues)

    def target(self, window: _Window, g: np.ndarray) -> np.ndarray:
        """The window's samples less the modes it does not hold explicitly: exactly (``exact``), or its far
        neighbours' (the rest is the background's)."""
        if self.model is not None:
            own = window.columns @ self.residues[window.explicit]
            return np.asarray(g[window.rows] - self.model[window.rows] + own)
        return np.asarray(g[window.rows] - window.far_columns @ self.residues[window.far])

    def misfit(self, window: _Window, g: np.ndarray) -> float:
        """The window's largest weighted misfit relative to its largest weighted sample (exact: the whole model's,
        relative to the samples themselves, as the target is then only what the window's modes make: noise where
        they are weak)."""
        if self.model is not None:
            weight = window.weight[:, None]
            return float(np.max(np.abs((g[window.rows] - self.model[window.rows]) * weight), initial=0.0)
                         / max(float(np.max(np.abs(g[window.rows] * weight), initial=0.0)), np.finfo(float).tiny))
        target = self.target(window, g) * window.weight[:, None]
        target = _stack(target, window.real)
        misfit = target - window.q @ (window.q.conj().T @ target)
        scale = np.abs(g[window.rows] * window.weight[:, None]) if self.model is not None else np.abs(target)
        return float(np.max(np.abs(misfit), initial=0.0) / max(float(np.max(scale, initial=0.0)),
                                                               np.finfo(float).tiny))

    def scale(self, g: np.ndarray) -> float:
        """The sum over the windows of their weighted samples' squares (what :meth:`move`'s misfit is set against)."""
        return float(sum(np.sum(np.abs(g[window.rows] * window.weight[:, None]) ** 2) for window in self.windows))

    def move(self, g: np.ndarray) -> tuple[float, float, float]:
        """One Gauss-Newton step on every window's core poles (:func:`_move_poles`), their standard errors kept:
        the largest step (relative to its window's largest x), the sum of the windows' squared weighted misfits
        before it, and the largest step of a placed pole over its standard error."""
        largest, total, surprise = 0.0, 0.0, 0.0
        self.gamma_surprise = 0.0
        for window in self.windows:
            step, spread, misfit, own, own_gamma = _move_poles(window, self.w, self.target(window, g), self.x,
                                                               self.gamma, self.fixed, self.lossy, self.fixed_gamma)
            self.spread[window.lo:window.hi] = spread
            largest, total, surprise = max(largest, step), total + misfit, max(surprise, own)
            self.gamma_surprise = max(self.gamma_surprise, own_gamma)
        return largest, total, surprise


def _plan(w: np.ndarray, x: np.ndarray, gamma: np.ndarray, lossy: bool = True,
          one_window: int = ONE_WINDOW, size: int = CORE, real: bool = False, halo: int = HALO,
          background: int = BACKGROUND, far_columns: bool = True) -> list[_Window]:
    import scipy.linalg  # here: importing the survey (every report and app module does) costs no scipy

    n_modes = x.size
    core = n_modes if n_modes <= one_window else size
    windows = []
    for lo in range(0, n_modes, core):
        hi = min(lo + core, n_modes)
        a, z = max(lo - halo, 0), min(hi + halo, n_modes)
        rows = _edges(x, w, a, z)
        smooth_terms = background if core < n_modes else 0
        needed = z - a + smooth_terms + 2
        if rows.size < needed:  # poles crowded closer than the samples (merged lossy modes): the nearest samples
            middle = 0.5 * (np.sqrt(max(x[a], 0.0)) + np.sqrt(max(x[z - 1], 0.0)))
            rows = np.sort(np.argsort(np.abs(w - middle), kind="stable")[:min(needed, w.size)])
        explicit = np.arange(a, z)
        far = np.r_[max(a - FAR, 0):a, z:min(z + FAR, n_modes)].astype(int)
        with np.errstate(divide="ignore"):  # a sample on a lossless pole: left out below
            A = _sections(w[rows], x[explicit], gamma[explicit], lossy)
        weight = 1.0 / np.max(np.abs(A), axis=1)  # the nearest section's inverse gain: rows carry rounding alike
        if not lossy:  # a sample on top of a pole tells nothing
            near = weight > _TOO_CLOSE * w[rows] ** 2
            rows, A, weight = rows[near], A[near], weight[near]
        ws = w[rows]
        # the modes beyond the far ones, smooth here; a window of every mode has the exact model and none
        if smooth_terms:  # real residues: the background's coefficients stay complex
            smooth = _chebyshev(ws * ws, smooth_terms)
            basis = np.hstack((A, smooth, 1j * smooth) if real else (A, smooth))
        else:
            basis = A
        basis = _stack(basis * weight[:, None], real)
        scale = np.linalg.norm(basis, axis=0)
        q, r = scipy.linalg.qr(basis / scale, mode="economic", check_finite=False)  # half numpy's time here
        windows.append(_Window(lo, hi, rows, explicit, far, weight, q, r, scale, A,
                               _sections(ws, x[far], gamma[far], lossy) if far_columns else np.zeros((ws.size, 0)),
                               real))
    return windows


def _band(windows: list[_Window], n_modes: int) -> SuperLU:
    """The LU factors of the banded system of every window's core residues (:func:`_rhs`): each window's core
    residues are its least squares of (samples - far modes' sections), linear in the far modes' residues."""
    import scipy.sparse
    import scipy.sparse.linalg

    rows_i, cols_i, values = [], [], []
    for window in windows:
        core = slice(window.lo - window.explicit[0], window.hi - window.explicit[0])
        coupling = window.solve[core] @ _stack(window.far_columns, window.real)  # core x far
        modes = np.arange(window.lo, window.hi)
        rows_i.append(np.repeat(modes, window.far.size))
        cols_i.append(np.tile(window.far, modes.size))
        values.append(coupling.ravel())
    rows_i.append(np.arange(n_modes))
    cols_i.append(np.arange(n_modes))
    values.append(np.ones(n_modes))
    matrix = scipy.sparse.csc_matrix((np.concatenate(values), (np.concatenate(rows_i), np.concatenate(cols_i))),
                                     shape=(n_modes, n_modes))
    return scipy.sparse.linalg.splu(matrix)


def _rhs(windows: list[_Window], g: np.ndarray, n_modes: int) -> np.ndarray:
    """Each window's least squares of its samples, its core modes' rows of the banded system."""
    real = windows[0].real
    rhs = np.empty((n_modes, g.shape[1]), dtype=float if real else np.result_type(windows[0].q, g))
    for window in windows:
        core = slice(window.lo - window.explicit[0], window.hi - window.explicit[0])
        rhs[window.lo:window.hi] = window.least_squares(_stack(g[window.rows], real))[core]
    return rhs


def _product(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """a @ b; a real matrix times a complex one as one real product of b's real and imaginary parts side by side
    (numpy would make ``a`` complex: twice the work)."""
    if np.iscomplexobj(a) or not np.iscomplexobj(b):
        return np.asarray(a @ b)
    return np.asarray((a @ np.ascontiguousarray(b).view(float)).view(complex))


def _solve_band(lu: SuperLU | None, rhs: np.ndarray) -> np.ndarray:
    """The banded system's solution for ``rhs`` (a real system's real and imaginary parts apart); no system (from
    predicted residues): ``rhs`` itself, each window's correction of its core modes."""
    if lu is None:
        return rhs
    if np.iscomplexobj(rhs) and not np.iscomplexobj(lu.L.data):
        both = np.asarray(lu.solve(np.ascontiguousarray(np.hstack((rhs.real, rhs.imag)))))
        return np.asarray(both[:, :rhs.shape[1]] + 1j * both[:, rhs.shape[1]:])
    return np.asarray(lu.solve(rhs))


def _model(w: np.ndarray, x: np.ndarray, gamma: np.ndarray, residues: np.ndarray, lossy: bool) -> np.ndarray:
    """sum_n r_n / D_n(w) on every sample, :data:`_BLOCK_VALUES` values at a time (a sample on a lossless pole,
    left out of every window, is infinite)."""
    out = np.empty((w.size, residues.shape[1]), dtype=np.result_type(residues, complex if lossy else float))
    step = max(1, _BLOCK_VALUES // max(1, x.size))
    with np.errstate(divide="ignore", invalid="ignore"):
        for start in range(0, w.size, step):
            out[start:start + step] = _product(_sections(w[start:start + step], x, gamma, lossy), residues)
    return out


def _move_poles(window: _Window, w: np.ndarray, target: np.ndarray, x: np.ndarray, gamma: np.ndarray,
                fixed: np.ndarray, lossy: bool, fixed_gamma: np.ndarray | None = None
                ) -> tuple[float, np.ndarray, float, float, float]:
    """One Gauss-Newton step on the window's core poles, every column at once (variable projection, Kaufman's
    Jacobian J_k[:, i] = P_perp dA_i c_ik: the normal equations are Re((V^H V) * (conj(C) C^T))).  The largest
    step, relative to the largest x of the window (0: nothing moves), and each core pole's standard error on x
    (the misfit's spread through the normal equations; infinite where the samples do not place it)."""
    ws = w[window.rows]
    coeffs = window.least_squares(_stack(target, window.real))
    weighted = _stack(target * window.weight[:, None], window.real)
    misfit = weighted - window.q @ (window.q.conj().T @ weighted)
    explicit = window.explicit
    core = (explicit >= window.lo) & (explicit < window.hi)  # a halo mode: its own window places it
    slope = -window.columns ** 2 * window.weight[:, None]  # d/dx of each section
    moves_x = np.flatnonzero(~fixed[explicit])
    moves_gamma = (np.flatnonzero(~fixed_gamma[explicit]) if fixed_gamma is not None else np.arange(explicit.size)
                   ) if lossy else np.zeros(0, dtype=int)
    spread = np.full(window.hi - window.lo, np.inf)
    which = [moves_x] + ([moves_gamma] if lossy else [])
    columns = [slope[:, moves_x]] + ([1j * ws[:, None] * slope[:, moves_gamma]] if lossy else [])  # d/dgamma = j w d/dx
    if not moves_x.size and not moves_gamma.size:
        return 0.0, spread, 0.0, 0.0, 0.0
    V = np.hstack(columns)
    V = _stack(V, window.real)
    V = V - window.q @ (window.q.conj().T @ V)
    c = coeffs[np.concatenate(which)]
    normal = ((V.conj().T @ V) * (c.conj() @ c.T)).real
    rhs = (c.conj() * (V.conj().T @ misfit)).sum(axis=1).real
    room = _room(x)[explicit]
    delta, errors = _step(normal, rhs, misfit)
    spread[np.flatnonzero(~fixed[explicit][core])] = errors[:moves_x.size][core[moves_x]]
    if not np.all(np.isfinite(delta)):  # a singular window (modes merged beyond telling apart): no step
        return 0.0, spread, 0.0, 0.0, 0.0
    dx = np.zeros(explicit.size)
    dx[moves_x] = delta[:moves_x.size]
    dgamma = np.zeros(explicit.size)
    dgamma[moves_gamma] = delta[moves_x.size:]
    # a trust region: no pole moves by more than a quarter of its distance to a neighbour, no decay rate by more
    # than half itself (modes merged beyond telling apart would otherwise wander off)
    excess = max(float(np.max(np.abs(dx) / np.maximum(room, np.finfo(float).tiny), initial=0.0)),
                 float(np.max(np.abs(dgamma) / np.maximum(0.5 * gamma[explicit], np.finfo(float).tiny),
                              initial=0.0)) if lossy else 0.0)
    if excess > 1.0:
        dx, dgamma = dx / excess, dgamma / excess
    x[explicit[core]] += dx[core]
    gamma[explicit[core]] += dgamma[core]
    largest = float(np.max(np.abs(np.concatenate((dx[core], dgamma[core]))), initial=0.0))
    # each placed pole's step against what the samples tell of it (its standard error, or its rounding): <= 1 when
    # none moved by more; a pole the samples do not place wanders by its noise and tells nothing
    own = np.maximum(np.where(np.isfinite(spread), spread, 0.0), 4.0 * np.finfo(float).eps * x[explicit[core]])
    placed = spread <= PLACED * room[core]
    surprise = float(np.max((np.abs(dx[core]) / np.maximum(own, np.finfo(float).tiny))[placed], initial=0.0))
    surprise_gamma = 0.0
    if lossy and moves_gamma.size:  # the same of each placed pole's decay rate
        spread_gamma = np.full(explicit.size, np.inf)
        spread_gamma[moves_gamma] = errors[moves_x.size:]
        own_gamma = np.maximum(np.where(np.isfinite(spread_gamma), spread_gamma, 0.0),
                               4.0 * np.finfo(float).eps * gamma[explicit])[core]
        surprise_gamma = float(np.max((np.abs(dgamma[core]) / np.maximum(own_gamma, np.finfo(float).tiny))[placed],
                                      initial=0.0))
    return (largest / max(float(np.max(x[explicit])), np.finfo(float).tiny), spread,
            float(np.sum(np.abs(misfit) ** 2)), surprise, surprise_gamma)


def _room(x: np.ndarray) -> np.ndarray:
    """A quarter of each pole's distance to its nearest neighbour (in x = omega^2)."""
    gaps = np.diff(x)
    return np.asarray(0.25 * np.minimum(np.r_[np.inf, gaps], np.r_[gaps, np.inf]))


def _step(normal: np.ndarray, rhs: np.ndarray, misfit: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The Gauss-Newton step of the normal equations and each parameter's standard error (the misfit's variance
    per real value through their inverse; infinite where a parameter moves nothing), from one eigen-decomposition
    scaled to a unit diagonal first: the residues span many decades (a perfect cradle's |u_1n|^2 from 1e-2 to
    1e-20), and unscaled the weak modes' steps fell below the solver's cut-off and stayed where they started."""
    values = misfit.size * (2 if np.iscomplexobj(misfit) else 1)
    variance = float(np.sum(np.abs(misfit) ** 2)) / max(values - normal.shape[0], 1)
    diagonal = np.diag(normal).copy()
    scale = np.sqrt(np.where(diagonal > 0, diagonal, 1.0))
    eigenvalues, vectors = np.linalg.eigh(normal / np.outer(scale, scale))
    kept = eigenvalues > normal.shape[0] * np.finfo(float).eps * max(float(eigenvalues[-1]), 0.0)
    inverse = np.where(kept, 1.0 / np.where(kept, eigenvalues, 1.0), 0.0)
    delta = vectors @ (inverse * (vectors.T @ (rhs / scale))) / scale
    with np.errstate(divide="ignore", invalid="ignore"):
        errors = np.sqrt(variance * ((vectors**2) @ inverse)) / scale
    return np.asarray(delta), np.asarray(np.where(diagonal > 0, errors, np.inf))
