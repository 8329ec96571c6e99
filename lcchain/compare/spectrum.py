"""Normal frequencies, decay rates and mode weights from a ladder's AC response (pure arrays).

A ladder driven by a voltage V in loop 1 has the transfer admittances (dimensionless, times Z0 = sqrt(L0/C0),
at s = j w, w in units of 1/sqrt(L0 C0))

    Y_11 Z0 = sum_n a_n s / (s^2 + gamma_n s + w_n^2),      Y_N1 Z0 = sum_n b_n s / (s^2 + gamma_n s + w_n^2),

with a_n = u_1n^2 > 0 and b_n = u_1n u_Nn for the M-orthonormal modes u (a free chain adds the mode w_0 = 0).
Without losses every gamma_n = 0: g(x) = Im(Y Z0) / w is then a real rational function of x = w^2 with simple
real poles.  Losses proportional to the masses (:class:`lcchain.circuit.effects.Losses`) keep the modes and
give every one the same gamma = 1/Q: its poles move to -gamma/2 +- j sqrt(w_n^2 - gamma^2/4).

An AC run is fitted from its theory's poles first (:func:`fit_from_theory`: the survey's windows, variable
projection and banded solves, :func:`lcchain.compare.survey.fit_survey`, on Y_11 and Y_N1 together; with losses from
theory's lossy poles, every gamma_n = 1/Q, the residues held real), O(samples x N) per sweep and one or two sweeps
(``benchmarks/spectrum.md``).  Where it does not explain the samples (its misfit above :data:`THEORY_MISFIT`: a
circuit that is not its theory), :func:`fit_spectrum` identifies every section from the samples alone.

:func:`fit_spectrum` identifies every section (a_n, gamma_n, w_n) and every b_n from samples on a grid of
frequencies (:mod:`lcchain.compare.grid`):

1. *Every pole, piece by piece.*  The samples are cut into pieces of :data:`_PIECE` samples (a quarter of
   each side overlapping its neighbours); a rational fit of each (AAA, ``scipy.interpolate.AAA``) finds the
   poles in its middle half.  Without losses it fits g_11 against x and keeps its real poles; with losses it
   fits Y_11 Z0 against s and keeps its poles in the left half plane (a pair of real poles is an overdamped
   mode, a lone real one a free chain's zero mode, whose pole is at -gamma).  Poles with a negligible residue
   are the fit's, not modes.  Without losses a pair of neighbouring samples where g_11 decreases brackets a
   pole (every a_n > 0): the rational fits must find at least as many.
2. *Gauss-Newton* on every section together (:func:`lcchain.compare.sections.refine_sections`: windows of
   neighbouring modes, each row weighted by its nearest section's inverse gain), from the rational fits'.
3. The residues of Y_N1 at those sections, by weighted linear least squares.

The work grows like the samples (pieces of fixed size, windows of fixed size) except the model's update,
O(samples x N) per Gauss-Newton sweep.  Measured against exact theory, see ``benchmarks/spectrum.md``.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field, replace

import numpy as np

from ..core.blas import fixed_blas_threads
from ..core.errors import ParameterError
from ..core.frozen import FrozenArrays
from .grid import POINTS_PER_SPACING, min_points
from .sections import ONE_WINDOW, WINDOW_SECTIONS, Sections, refine_sections, section_residues
from .survey import PoleStart, SurveyOptions, fit_survey

__all__ = ["SpectrumFit", "fit_spectrum", "fit_from_theory", "fit_sections", "min_points", "POINTS_PER_SPACING",
           "THEORY_MISFIT"]

#: Samples in one rational fit (beyond 1.5 times this, the samples are cut into overlapping pieces): with losses
#: longer pieces, whose poles are found among more neighbours (two-mass N = 100, Q = 100: a mode missed by pieces
#: of 256 samples).
_PIECE = 256
_PIECE_LOSSY = 512
#: Without losses, one rational fit of every sample while it is cheap (at most this many terms and samples): it
#: finds more of a perfect cradle's weak modes than pieces do (N = 400: 108 modes seen against 85).
_WHOLE_TERMS = 256
_WHOLE_SAMPLES = 6000
#: A pole of the rational fit whose residue is below this (relative to the largest) is the fit's, not a mode.
_WEAKEST = 1e-13
#: AAA's relative tolerance (the samples are ngspice's, good to about 1e-12); with losses relative to the
#: largest sample, a resonance's peak (Q times the others), which ngspice's rounding keeps AAA from reaching.
_AAA_RTOL = 1e-13
_AAA_RTOL_LOSSY = 1e-11
#: Terms of a piece's rational fit beyond two per pole the samples show.
_SPARE_TERMS = 16
#: Samples per spurious section, at most, when the samples are cut into pieces: a piece far finer than the poles
#: around it can leave a pole of its rational fit whose residue is not negligible, and Gauss-Newton carries it
#: as a section (measured: two-mass N = 20 at 20,000 .. 200,000 frequencies, one per 2,900 .. 5,900 samples; N = 100
#: at 50,000, one per 1,800).
_SAMPLES_PER_SPURIOUS = 1024


@dataclass(frozen=True, eq=False)
class SpectrumFit(FrozenArrays):
    """Modes identified from an AC response.

    Attributes
    ----------
    omega : ndarray
        Undamped normal frequencies w_n = |p_n|, ascending (units of 1/sqrt(L0 C0)); a free chain's first is 0.
    first, last : ndarray
        Residues a_n of Y_11 Z0 and b_n of Y_N1 Z0 (multiply by m_1 for the mode weights of alpha_1 and alpha_N).
    sweeps : int
        Gauss-Newton sweeps taken after the rational fits (each lowered some window's misfit).
    residual : float
        Largest misfit of the model to the samples it was fitted on (each times its nearest section's inverse
        gain).
    gamma : ndarray
        Decay rates gamma_n (units of 1/sqrt(L0 C0)); zeros for a lossless fit.
    """

    omega: np.ndarray
    first: np.ndarray
    last: np.ndarray
    sweeps: int
    residual: float
    gamma: np.ndarray = field(default_factory=lambda: np.zeros(0))

    def __post_init__(self) -> None:
        if self.gamma.size != self.omega.size:
            object.__setattr__(self, "gamma", np.zeros(self.omega.size))
        self._freeze_arrays()

    def subset(self, keep: np.ndarray) -> SpectrumFit:
        """The modes ``keep`` (a mask or indices)."""
        return SpectrumFit(self.omega[keep], self.first[keep], self.last[keep], self.sweeps, self.residual,
                           self.gamma[keep])

    def impulse(self, t: np.ndarray, residues: np.ndarray) -> np.ndarray:
        """sum_n residues_n h_n(t): the inverse Laplace transform of sum_n r_n s / (s^2 + gamma_n s + w_n^2)
        at times ``t`` >= 0 (units of sqrt(L0 C0)); with r = m_1 b_n, alpha_N(t) after a kick."""
        half = 0.5 * self.gamma.astype(complex)
        root = np.sqrt(half * half - self.omega.astype(complex) ** 2)
        fast, slow = -half - root, -half + root  # the section's poles; slow = 0 only for an undamped zero mode
        split = np.where(root != 0, root, 1.0)
        t = np.asarray(t, dtype=float)[:, None]
        h = (slow * np.exp(slow * t) - fast * np.exp(fast * t)) / (2.0 * split)
        h = np.where(root != 0, h, (1.0 - half * t) * np.exp(-half * t))  # critically damped
        return np.asarray((h * residues[None, :]).sum(axis=1).real)


def _pieces(size: int, piece: int) -> list[tuple[int, int, int, int]]:
    """(start, stop, core start, core stop) of each overlapping piece; the cores partition 0..size."""
    if size <= 1.5 * piece:
        return [(0, size, 0, size)]
    core = piece // 2
    edges = np.linspace(0, size, max(2, int(round(size / core))) + 1).round().astype(int)
    return [(max(int(a) - core // 2, 0), min(int(b) + core // 2, size), int(a), int(b))
            for a, b in zip(edges[:-1], edges[1:], strict=True)]


def _rational(z: np.ndarray, f: np.ndarray, seen: int, rtol: float = 1e-13) -> tuple[np.ndarray, np.ndarray]:
    """Poles and residues of an AAA fit of f(z) with at most 2 ``seen`` + :data:`_SPARE_TERMS` terms (``seen``:
    the poles the samples show; the others, weak, and the neighbours' beyond the piece take the rest).  AAA's
    own clean-up of spurious poles is left out (it cost seconds): their residues are negligible and dropped."""
    import scipy.interpolate  # here, the one use: reading an AC store's metrics (results) imports no scipy

    with warnings.catch_warnings():  # AAA may stop short of rtol: Gauss-Newton finishes the job
        warnings.simplefilter("ignore", RuntimeWarning)
        fitted = scipy.interpolate.AAA(z, f, rtol=rtol, max_terms=min(z.size // 2, 2 * seen + _SPARE_TERMS),
                                       clean_up=False)
    return np.asarray(fitted.poles()), np.asarray(fitted.residues())


def _lossless_poles(w: np.ndarray, g: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Squared frequencies and residues a_n of g = sum_n a_n / (x_n - x), piece by piece."""
    x = w * w
    poles, residues = [], []
    brackets = int(np.count_nonzero(np.diff(g) < 0))
    whole = 2 * brackets + _SPARE_TERMS <= _WHOLE_TERMS and w.size <= _WHOLE_SAMPLES
    for start, stop, lo, hi in [(0, w.size, 0, w.size)] if whole else _pieces(w.size, _PIECE):
        found, weights = _rational(x[start:stop], g[start:stop], int(np.count_nonzero(np.diff(g[start:stop]) < 0)))
        below = -0.5 * x[0] if lo == 0 else x[lo]
        above = np.inf if hi == w.size else x[hi]
        real = (np.abs(found.imag) <= 1e-9 * x[-1]) & (found.real >= below) & (found.real < above)
        poles.append(found.real[real])
        residues.append(-weights.real[real])
    return np.concatenate(poles), np.concatenate(residues)


def _lossy_sections(w: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Residues, decay rates and squared frequencies of every section of y(s), piece by piece: a complex pole p
    (upper half plane) is the section of x = |p|^2, gamma = -2 Re p; real poles are paired (see the module
    docstring)."""
    c, gamma, x, lone, lone_residue = [], [], [], [], []
    for start, stop, lo, hi in _pieces(w.size, _PIECE_LOSSY):
        found, weights = _rational(1j * w[start:stop], y[start:stop], (stop - start) // 2, _AAA_RTOL_LOSSY)
        below = 0.0 if lo == 0 else w[lo]
        above = np.inf if hi == w.size else w[hi]
        left = found.real < 0
        real = left & (np.abs(found.imag) <= 1e-4 * np.abs(found))  # AAA places a real pole to ~1e-6 of |p|
        where = np.where(real, np.abs(found), found.imag)  # a real pole belongs to the piece of |p|
        keep = left & (where >= below) & (where < above)
        upper = keep & ~real & (found.imag > 0)
        p, r = found[upper], weights[upper]
        c.append((r * 2j * p.imag / p).real)
        gamma.append(-2.0 * p.real)
        x.append(np.abs(p) ** 2)
        lone.append(found.real[keep & real])
        lone_residue.append(weights.real[keep & real])
    pairs = _real_sections(np.concatenate(lone), np.concatenate(lone_residue))
    return (np.concatenate(c + [pairs[0]]), np.concatenate(gamma + [pairs[1]]), np.concatenate(x + [pairs[2]]))


def _real_sections(poles: np.ndarray, residues: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Sections from real poles: with one decay rate for all, each overdamped mode's two poles lie symmetrically
    about -gamma/2 inside (-gamma, 0) and a zero mode's lone pole at -gamma, left of them all: so the leftmost of
    an odd number is the zero mode, and the others pair from outside in."""
    order = np.argsort(poles)
    poles, residues = poles[order], residues[order]
    c, gamma, x = [], [], []
    if poles.size % 2:  # c / (s + gamma)
        c.append(residues[0])
        gamma.append(-poles[0])
        x.append(0.0)
        poles, residues = poles[1:], residues[1:]
    for i in range(poles.size // 2):
        p1, p2, r1 = poles[i], poles[poles.size - 1 - i], residues[i]
        c.append(r1 * (p1 - p2) / p1)
        gamma.append(-(p1 + p2))
        x.append(p1 * p2)
    return np.array(c, dtype=float), np.array(gamma, dtype=float), np.array(x, dtype=float)


def _significant(c: np.ndarray) -> np.ndarray:
    """Sections whose residue is not negligible beside the largest."""
    return np.asarray(np.abs(c) > _WEAKEST * float(np.max(np.abs(c), initial=0.0)))


def fit_sections(points: float, N: int, lossy: bool = False) -> float:
    """The most sections one Gauss-Newton step of :func:`fit_spectrum` moves at once, for its price: its
    matrices are (samples x these).

    Beyond :data:`~lcchain.compare.sections.ONE_WINDOW` modes, a window and its neighbours on both sides.  Below,
    every section at once: the N modes and the spurious poles of pieces much finer than the poles (up to one per
    :data:`_SAMPLES_PER_SPURIOUS` samples: a sweep of 10^6 frequencies for 20 modes fits one window of 128, not
    20), up to one window of :data:`~lcchain.compare.sections.ONE_WINDOW`, the most it ever holds.

    Parameters
    ----------
    points : float
        Samples (frequencies of the sweep).
    N : int
        Modes of the chain.
    lossy : bool
        With losses every piece is fitted apart; without them a sweep of at most :data:`_WHOLE_SAMPLES` samples
        is fitted whole, with no spurious pole.
    """
    if N > ONE_WINDOW:
        return float(WINDOW_SECTIONS)
    whole = not lossy and points <= _WHOLE_SAMPLES and 2 * N + _SPARE_TERMS <= _WHOLE_TERMS
    spurious = 0.0 if whole else points / _SAMPLES_PER_SPURIOUS
    return float(min(N + spurious, ONE_WINDOW))


@fixed_blas_threads
def fit_spectrum(omega: np.ndarray, y11: np.ndarray, yN1: np.ndarray, *, lossy: bool = False) -> SpectrumFit:
    """Identify the modes of a ladder's transfer admittances (see the module docstring).

    Parameters
    ----------
    omega : ndarray
        Angular frequencies of the samples, units of 1/sqrt(L0 C0), ascending, > 0.
    y11, yN1 : ndarray, complex
        Y_11 Z0 and Y_N1 Z0 at those frequencies.
    lossy : bool
        Whether the ladder has losses (then every section's gamma_n is fitted; else every gamma_n = 0).

    Raises
    ------
    ParameterError
        Samples that are not a ladder's (no pole, or not ascending).
    """
    w = np.asarray(omega, dtype=float)
    if w.ndim != 1 or w.size < 8 or not np.all(np.diff(w) > 0) or w[0] <= 0:
        raise ParameterError("omega", f"{w.size} frequencies", "at least 8 ascending frequencies > 0")
    y11, yN1 = np.asarray(y11, dtype=complex), np.asarray(yN1, dtype=complex)
    if lossy:
        c, gamma, x = _lossy_sections(w, y11)
        if x.size == 0:
            raise ParameterError("omega", f"{w[0]:.4g} .. {w[-1]:.4g}", "a frequency range holding a pole")
        keep = _significant(c)
        # a lone real pole is a zero mode, c / (s + gamma): its x is 0 exactly (the pole at 0 cancels)
        sections = Sections(c[keep], gamma[keep], x[keep], lossy=True, fixed_x=x[keep] == 0.0)
    else:
        g11 = y11.imag / w
        brackets = int(np.count_nonzero(np.diff(g11) < 0))
        if brackets == 0:
            raise ParameterError("omega", f"{w[0]:.4g} .. {w[-1]:.4g}", "a frequency range holding a pole")
        x, c = _lossless_poles(w, g11)
        keep = _significant(c)
        x, c = x[keep], c[keep]
        if x.size < brackets:
            raise ParameterError("omega", f"{w.size} frequencies", "more frequencies: the rational fit found fewer "
                                 f"poles ({x.size}) than the samples bracket ({brackets})")
        zero = np.abs(x) < 0.5 * w[0] ** 2  # a free chain's translation mode stays at 0
        sections = Sections(c, np.zeros(x.size), np.where(zero, 0.0, x), lossy=False, fixed_x=zero)
    sweeps, misfit = refine_sections(w, y11, sections)
    last = section_residues(w, yN1, sections)
    return SpectrumFit(np.sqrt(np.clip(sections.x, 0.0, None)), sections.c, last, sweeps, misfit,
                       sections.gamma)


#: The fit from theory's poles (:func:`fit_from_theory`) holds every mode in one window up to this many, and beyond
#: keeps this many per window (measured in-process, two-mass N = 100 and 200: 22 and 48 ms in windows of 32 beyond
#: 16, 35 and 74 ms in one window up to 64; windows of 16 or 96 no faster, on a machine at load 6 to 8).
_THEORY_ONE_WINDOW = 16
_THEORY_CORE = 32
#: With losses the fit starts from theory's residues as well as its poles (:attr:`lcchain.compare.survey.PoleStart.
#: residues`): every other mode's model is then subtracted from a window's samples from the start, and the windows
#: are smaller: 16 modes, 2 neighbours on each side and 6 smooth terms (measured in-process on ngspice's samples,
#: CPU seconds on the loaded machine: two-mass N = 100, 200, 400 at Q = 1000 and perfect N = 400 at 1e4 in 19, 48,
#: 129 and 85 ms, against 36, 90, 236 and 155 ms with windows of 32, 8 and 12; as many modes seen, Q_n, omega_n and
#: P_n as close; with no smooth term 12 of the perfect N = 400's weak modes went unseen, omega_n 8 times further off).
_LOSSY_CORE = 16
#: ... and up to this many modes one window holds them all, as without losses: windows of 16 at two-mass N = 20 and
#: uniform N = 24 left omega_n 7 and 5 times further off (3.4e-14 and 2.2e-15).
_LOSSY_ONE_WINDOW = 32
_LOSSY_HALO = 2
_LOSSY_BACKGROUND = 6
#: The fit from theory's poles stands when its largest misfit (relative to the largest sample of its window) is at
#: most this; above, the samples are not the predicted poles' (a circuit that is not its theory), and the fit from
#: the samples alone (:func:`fit_spectrum`) is made instead.  Measured: 1e-14 .. 1e-11 on ngspice's samples.
THEORY_MISFIT = 1e-8


def fit_from_theory(omega: np.ndarray, y11: np.ndarray, yN1: np.ndarray, predicted: np.ndarray,
                    Q: float | None = None, merged: np.ndarray | None = None,
                    merged_residues: tuple[np.ndarray, np.ndarray] | None = None) -> tuple[SpectrumFit, np.ndarray]:
    """Identify a ladder's modes starting from its predicted poles, at a fraction of the engine's cost.

    Y_11 / (j w) and Y_N1 / (j w) are sum_n (a_n, b_n) / D_n(w), D_n = x_n - w^2 + j gamma_n w (real without
    losses, gamma_n = 0): the two are fitted together as the survey fits its loops
    (:func:`lcchain.compare.survey.fit_survey` with ``exact=True``): windows of neighbouring modes, variable
    projection of the poles from the predicted ones, the residues of every window from one banded solve refined on
    the whole residual.  O(samples x N) per sweep; from theory's poles one sweep moves them by their rounding.
    With losses of quality factor ``Q`` every pole starts at gamma_n = 1/Q (the chain's proportional losses:
    -1/(2Q) +- j sqrt(omega_n^2 - 1/(4Q^2))) and its complex section moves in x_n and gamma_n; given theory's
    residues (``merged_residues``) the fit starts from them too, so that every window fits the whole residual's
    correction in smaller windows (:data:`_LOSSY_CORE`).  A mode is seen
    when the samples place its pole (its standard error at most :data:`lcchain.compare.survey.PLACED` of a quarter
    of its nearest gap): a mode too weak at the ends to be placed, or merged with a neighbour by the losses, stays
    unseen.

    Parameters
    ----------
    omega : ndarray
        Angular frequencies of the samples, units of 1/sqrt(L0 C0), ascending, > 0.
    y11, yN1 : ndarray, complex
        Y_11 Z0 and Y_N1 Z0 at those frequencies.
    predicted : ndarray
        The predicted normal frequencies, ascending (a free chain's first is 0 and stays there).
    Q : float, optional
        The losses' quality factor (every mode's predicted decay rate is 1/Q); None: lossless.
    merged : ndarray of bool, optional
        With losses, the modes they merge (:func:`lcchain.compare.spectral.merged_modes`): the samples cannot tell
        them apart (two-mass N = 1000 at Q = 1000: 205 modes at the top of the band, some 500 spacings to a width),
        so their theory, ``merged_residues``, is subtracted from the samples and the others are fitted; they are
        never seen.  Without ``merged_residues`` their poles are held at theory's and their residues fitted (enough
        where the clusters are small: two-mass N = 400 at Q = 1000; at N = 1000 that left a misfit of 2e2).
    merged_residues : (ndarray, ndarray), optional
        Theory's residues (a_n, b_n) of every mode: the merged ones' are subtracted, the others' are where the
        lossy fit starts.

    Returns
    -------
    fit : SpectrumFit
        The seen modes; ``residual`` the largest misfit relative to its window's largest sample (compare with
        :data:`THEORY_MISFIT`).
    seen : ndarray of int
        The index of each seen mode among ``predicted``.
    """
    w = np.asarray(omega, dtype=float)
    y11, yN1 = np.asarray(y11, dtype=complex), np.asarray(yN1, dtype=complex)
    predicted = np.asarray(predicted, dtype=float)
    if w.ndim != 1 or w.size < 8 or not np.all(np.diff(w) > 0) or w[0] <= 0:
        raise ParameterError("omega", f"{w.size} frequencies", "at least 8 ascending frequencies > 0")
    lossy = Q is not None
    if lossy:  # Y / (j w), complex with losses
        g: np.ndarray = np.column_stack((y11, yN1)) / (1j * w)[:, None]
    else:  # Y / (j w): real without losses
        g = np.column_stack((y11.imag, yN1.imag)) / w[:, None]
    zero = predicted <= 1e-9 * float(np.max(predicted, initial=0.0))
    gamma0 = np.full(predicted.size, 1.0 / float(Q)) if Q is not None else None
    held = np.zeros(predicted.size, dtype=bool) if merged is None or not lossy else np.asarray(merged, dtype=bool)
    fitted = np.arange(predicted.size)
    if held.any() and merged_residues is not None and gamma0 is not None:  # the merged modes' theory, subtracted
        known = np.column_stack(merged_residues)[held].astype(complex)
        x_held = np.where(zero, 0.0, predicted)[held] ** 2
        D = x_held[None, :] - (w * w)[:, None] + 1j * w[:, None] * gamma0[held][None, :]
        g = g - (1.0 / D) @ known
        fitted, held = np.flatnonzero(~held), held[~held]
        if fitted.size == 0:
            empty = np.zeros(0)
            return SpectrumFit(empty, empty, empty, 0, 0.0, empty), fitted
    # with losses from theory's residues too: the windows then fit the whole residual's correction alone
    known_residues = (np.column_stack(merged_residues)[fitted].astype(float)
                      if lossy and merged_residues is not None else None)
    start = PoleStart(np.where(zero, 0.0, predicted)[fitted] ** 2, None if gamma0 is None else gamma0[fitted],
                      zero[fitted] | held, held, known_residues)
    options = SurveyOptions(lossy=lossy, real=True, exact=True, one_window=_THEORY_ONE_WINDOW, core=_THEORY_CORE)
    if known_residues is not None:
        options = replace(options, one_window=_LOSSY_ONE_WINDOW, core=_LOSSY_CORE, halo=_LOSSY_HALO,
                          background=_LOSSY_BACKGROUND)
    survey = fit_survey(w, g, start, options)
    first, last = survey.residues[:, 0].real, survey.residues[:, 1].real
    seen = np.flatnonzero(np.where(zero[fitted], _significant(first), survey.placed) & ~held)
    fit = SpectrumFit(survey.omega[seen], first[seen], last[seen], survey.sweeps, survey.residual,
                      survey.gamma[seen])
    return fit, fitted[seen]
