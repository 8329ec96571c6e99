"""The numbers an AC run is judged by: its normal frequencies and end weights against theory (pure arrays).

:class:`SpectrumMetrics` holds, for every theoretical mode n, the circuit's omega_n (NaN where no pole was
seen) and P_n (0 where unseen) beside the theory's, and which modes weigh enough at the ends to be held to the
targets.  From them: the worst relative error of omega, the worst absolute error of P, and the spread of the
spacings delta omega_n = omega_{n+1} - omega_n (the paper's equal spacing: a perfect cradle's spread is 0; real
parts move it).  It is stored as JSON (:meth:`SpectrumMetrics.to_dict`) and read back
(:meth:`SpectrumMetrics.from_dict`).

:func:`sweep_grid` chooses an AC sweep's frequencies (refusing a grid too coarse to separate two poles) and
:func:`compare_spectrum` fits the poles and residues of an AC run
(:func:`lcchain.compare.spectrum.fit_spectrum`) and matches them to the theory's modes: every AC run, whoever
asked for it, is judged by these two.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..core.budget import Estimate, ac_estimate
from ..core.checks import integer
from ..core.errors import ParameterError
from ..core.frozen import FrozenArrays
from ..core.json import JSONDict, LooseJSONObject
from ..core.limits import COUPLED_MAX_N, MAX_AC_POINTS, MIN_AC_POINTS
from ..theory.chain import Chain
from ..theory.modes import Modes
from ..theory.spectrum import ARITHMETICS, admittance_with_bound
from .grid import POINTS_PER_SPACING, Segment, min_points, sweep_segments
from .spectrum import THEORY_MISFIT, SpectrumFit, fit_from_theory, fit_sections, fit_spectrum

__all__ = ["SpectrumMetrics", "SPECTRAL_METRICS", "spacing_spread", "sweep_grid", "compare_spectrum",
           "spectrum_estimate", "nearest_modes", "largest_relative_error", "relative_errors",
           "OMEGA_MARGIN", "OMEGA_WEIGHT_FLOOR", "DEFAULT_OVERSAMPLING", "SPECTRUM_MAX_N", "LOSSY_MAX_N",
           "lossy_range", "check_lossy", "merged_modes", "merged_text", "compare_envelope", "ENVELOPE_MARGIN"]

#: The sweep ends this far above the highest normal frequency (relative).
OMEGA_MARGIN = 0.05
#: A mode's frequency is held to the targets when its weight at the far end is at least this: below, the pole is
#: nearly cancelled in I_N/V_1 and I_1/V_1 and double precision places it to ~1e-16 / |P_n| only (measured on the
#: perfect cradle, N = 100: 1.1e-9 at |P| = 3.9e-8, 2.4e-8 at |P| = 2.0e-10).
OMEGA_WEIGHT_FLOOR = 1e-6
#: Samples per smallest spacing by default: twice what the fit needs at least.
DEFAULT_OVERSAMPLING = 2
#: The largest chain measured (exact modes for the comparison, and the fit's dense least squares).
SPECTRUM_MAX_N = COUPLED_MAX_N

#: The lossy fit (every pole at -1/(2Q) +- j omega_n) tells neighbouring modes apart when Q is at least this over
#: their smallest spacing (measured, ngspice and gnucap, N = 3 to 100: one-, two-mass and uniform chains need 0.07
#: to 0.1), or :data:`LOSSY_GAP_Q_WEAK` where a mode weighs less than :data:`LOSSY_WEAK_RATIO` of its neighbour
#: (the edge modes of a perfect cradle tied to walls: 0.5 to 0.7); and it places the lowest when Q is at least 1
#: over its frequency (near-critical damping: 0.5 missed, 0.7 held).
LOSSY_GAP_Q = 0.15
LOSSY_GAP_Q_WEAK = 0.7
LOSSY_WEAK_RATIO = 0.1
#: ... and places the decay rates (1/Q, against every pole's distance from its neighbours) for Q up to this, and up
#: to LOSSY_QN over N (the rational fits: two-mass N = 100: 2e4 right, 2.2e5 wrong; N = 10: 1e5 right, 4.6e5 wrong;
#: the fit from theory's lossy poles on ngspice, Q_n over the resolved modes: perfect N = 400 and 1000 at Q = 1e4,
#: 8.2e-10 and 4.9e-10; two-mass N = 400 at 1e4, 1.4e-9; N = 100 at 1e5, 3.0e-7).
LOSSY_MAX_Q = 1e5
LOSSY_QN = 1e7
#: The largest lossy ladder measured: the fit from theory's lossy poles
#: (:func:`lcchain.compare.spectrum.fit_from_theory`) places them up to there (benchmarks/spectrum.md, "With
#: losses"); the rational fits alone (:func:`lcchain.compare.spectrum.fit_spectrum`, its fallback) had misses inside
#: every window beyond N = 100 (N = 200 to 700: P_n off by 1e-4 to 1e+91 at some Q between the bounds above).
LOSSY_MAX_N = SPECTRUM_MAX_N

#: The spectral metrics a store's runs hold (``lcchain results --metric``), with their units.
SPECTRAL_METRICS = {"max_rel_error_omega": "relative", "max_abs_error_P": "absolute",
                    "spacing_spread": "(max - min) / mean", "spacing_std": "std / mean", "modes_seen": "modes",
                    "max_rel_error_Y11": "relative"}  # Y_11 over the sweep: with losses that merge modes


def lossy_range(modes: Modes) -> tuple[float, float]:
    """The quality factors Q whose lossy spectrum the fit identifies, for a chain's driven modes (their
    frequencies, units of 1/sqrt(L0 C0), and weights P_n): (lowest, highest); lowest > highest when none does
    (N > :data:`LOSSY_MAX_N`, or modes too close to be told apart below :data:`LOSSY_MAX_Q`).  The lowest is the
    rational fits' range (:data:`LOSSY_GAP_Q`), which says which modes are reported as merged (:func:`merged_modes`);
    the fit from theory's lossy poles holds them where they merge and measures the rest."""
    order = np.argsort(modes.omega)
    omega, weight = np.asarray(modes.omega, dtype=float)[order], np.abs(modes.transfer)[order]
    if omega.size > LOSSY_MAX_N:
        return math.inf, 0.0
    gaps = np.diff(omega)
    ratio = np.minimum(weight[1:], weight[:-1]) / np.maximum(np.maximum(weight[1:], weight[:-1]), 1e-300)
    per_gap = np.where(ratio < LOSSY_WEAK_RATIO, LOSSY_GAP_Q_WEAK, LOSSY_GAP_Q) / np.maximum(gaps, 1e-300)
    moving = omega[omega > 1e-9 * omega[-1]]
    lowest = max(float(np.max(per_gap, initial=0.0)), 1.0 / float(moving[0]) if moving.size else math.inf)
    return lowest, min(LOSSY_MAX_Q, LOSSY_QN / omega.size)


def merged_modes(modes: Modes, Q: float) -> np.ndarray:
    """Which of a chain's modes losses of quality factor Q merge, bool per mode (ascending omega_n).

    Within the range the fit was measured on (:func:`lossy_range`) none is: the fit separates modes whose
    half-power bands overlap down to :data:`LOSSY_GAP_Q` widths apart.  Below it, a mode is merged when its
    half-power band (width gamma = 1/Q) overlaps a neighbour's, |omega_n - omega_(n+-1)| < 1/Q, or reaches zero
    frequency, 0 < omega_n < 1/Q (a free chain's translation, exactly 0, merges only with a mode within 1/Q of it).
    The rest stay resolved (measured, ngspice, one- and two-mass N = 10 to 60 down to Q = 1: their Q_n to 2e-13,
    where the fit's modes inside a merged cluster were off by up to 40 %).
    """
    omega = np.asarray(modes.omega, dtype=float)
    lowest, _ = lossy_range(modes)
    if Q >= lowest or omega.size == 0:
        return np.zeros(omega.size, dtype=bool)
    gaps = np.diff(omega)
    nearest = np.minimum(np.r_[np.inf, gaps], np.r_[gaps, np.inf])  # the gap on either side, whichever is smaller
    return np.asarray((nearest * Q < 1.0) | ((omega > 0) & (omega * Q < 1.0)))


def merged_text(merged: np.ndarray) -> str:
    """The merged modes as runs, 'n = 2, 30-37 (9 of 37 modes)'."""
    numbers = (np.flatnonzero(merged) + 1).tolist()
    runs: list[str] = []
    for n in numbers:
        if runs and n - 1 in numbers:
            runs[-1] = f"{runs[-1].split('-')[0]}-{n}"
        else:
            runs.append(f"{n}")
    return f"n = {', '.join(runs)} ({len(numbers)} of {merged.size} modes)"


def check_lossy(name: str, Q: float, modes: Modes) -> None:
    """Refuse a losses' Q whose decay rates the fit cannot place on this chain (above the range), or a chain too
    long for the lossy fit, naming ``name``, Q and the range.  Below the range the run goes ahead and says which
    modes merged (:func:`merged_modes`)."""
    _, highest = lossy_range(modes)
    if modes.N > LOSSY_MAX_N:
        raise ParameterError(name, Q, f"no losses on an AC analysis of N = {modes.N} > {LOSSY_MAX_N} masses (the "
                             "lossy fit is measured only up to there; a transient takes any N)")
    if Q > highest:
        raise ParameterError(name, Q, f"Q <= {highest:.4g} on this chain's AC analysis (above, the decay rates are "
                             "beyond the fit; below the modes' own range, those closer than their width 1/Q are "
                             "reported as merged)")


def relative_errors(values: np.ndarray, theory: np.ndarray, low: np.ndarray | None = None) -> np.ndarray:
    """|values - (theory + low)| / |theory| per entry (where |theory| = 0: absolute; NaN where a value is NaN);
    ``low``: the rest of a reference known beyond float64 (:attr:`lcchain.theory.modes.Modes.omega_low`),
    subtracted after the float64 difference, which is exact for values this close (Sterbenz)."""
    scale = np.abs(theory)
    difference = values - theory
    if low is not None:
        difference = difference - low
    return np.asarray(np.abs(difference) / np.where(scale > 0, scale, 1.0))


def largest_relative_error(values: np.ndarray, theory: np.ndarray, where: np.ndarray,
                           low: np.ndarray | None = None) -> float:
    """max |values - theory| / |theory| over ``where`` (:func:`relative_errors`; a NaN value, a mode the circuit
    did not show: infinite); 0 over no mode."""
    error = relative_errors(values, theory, low)
    error = np.where(np.isnan(error), np.inf, error)
    return float(np.max(error[where], initial=0.0))


def spacing_spread(spacings: np.ndarray) -> tuple[float, float]:
    """((max - min) / mean, std / mean) of the finite spacings (NaN, NaN with none)."""
    finite = np.asarray(spacings, dtype=float)
    finite = finite[np.isfinite(finite)]
    if finite.size == 0:
        return float("nan"), float("nan")
    mean = float(finite.mean())
    return float((finite.max() - finite.min()) / mean), float(finite.std() / mean)


@dataclass(frozen=True, eq=False)
class SpectrumMetrics(FrozenArrays):
    """A circuit's spectrum beside its exact theory, mode by mode.

    Attributes
    ----------
    omega_theory, omega : ndarray
        Normal frequencies, units of 1/sqrt(L0 C0): theory's, and the circuit's (NaN where no pole was seen).
    P_theory, P : ndarray
        The modes' coefficients in alpha_N(t) = sum_n P_n cos(omega_n t): theory's, and the circuit's (0 where
        unseen).
    resolved : ndarray of bool
        The modes weighty enough at the ends to be held to the targets.
    fit : SpectrumFit, optional
        The poles and residues found in the circuit, one per seen mode (not stored).
    seen : ndarray of int, optional
        For each fitted pole, the index of its theoretical mode (not stored).
    gamma : ndarray, optional
        With losses: the circuit's decay rate of every mode (NaN where unseen).
    losses : float, optional
        The losses' quality factor Q (every mode's theory decays at 1/Q); None: a lossless ladder.
    gamma_theory : ndarray, optional
        Each mode's own decay rate in theory (a circuit whose losses are not the chain's: its exact poles,
        :func:`lcchain.compare.poles.compare_poles`), instead of 1/Q for every mode.
    omega_low, omega_bound, P_bound : ndarray, optional
        The reference's rest beyond float64 and its own error bounds (relative on omega_n, absolute on P_n:
        :class:`lcchain.theory.modes.Modes`); None where the reference states none.
    merged : ndarray of bool, optional
        The modes losses merge (:func:`merged_modes`): reported as merged, not compared (not errors).
    envelope_error : float, optional
        max |Y_11 - exact Y_11| / |exact Y_11| over the sweep (:func:`lcchain.theory.spectrum.driving_admittance`):
        the response itself, what is measured whatever merged.
    envelope_bound : float, optional
        The exact admittance's own relative error bound, the largest over the sweep (:func:`compare_envelope`).
    """

    omega_theory: np.ndarray
    omega: np.ndarray
    P_theory: np.ndarray
    P: np.ndarray
    resolved: np.ndarray
    fit: SpectrumFit | None = None
    seen: np.ndarray | None = None
    gamma: np.ndarray | None = None
    losses: float | None = None
    gamma_theory: np.ndarray | None = None
    omega_low: np.ndarray | None = None
    omega_bound: np.ndarray | None = None
    P_bound: np.ndarray | None = None
    merged: np.ndarray | None = None
    envelope_error: float | None = None
    envelope_bound: float | None = None

    def __post_init__(self) -> None:
        if (self.gamma is None) != (self.losses is None and self.gamma_theory is None) \
                or (self.losses is not None and self.gamma_theory is not None):
            raise ParameterError("gamma", self.losses, "decay rates with the losses' Q or the theory's own decay "
                                 "rates (one of them), or neither")
        arrays = ("omega_theory", "omega", "P_theory", "P", "resolved") + tuple(
            name for name in ("gamma", "gamma_theory", "omega_low", "omega_bound", "P_bound", "merged")
            if getattr(self, name) is not None)
        sizes = {np.shape(getattr(self, name)) for name in arrays}
        if len(sizes) != 1 or len(next(iter(sizes))) != 1:
            raise ParameterError("metrics", sorted(sizes), "one value per mode in every array")
        self._freeze_arrays()

    @property
    def max_rel_error_omega(self) -> float:
        """Largest |omega - omega_theory| / omega_theory over the resolved modes (a zero mode: absolute); an unseen
        resolved mode is an infinite error; NaN when no mode is resolved (every one merged: no error, not 0)."""
        if not self.resolved.any():
            return float("nan")
        return largest_relative_error(self.omega, self.omega_theory, self.resolved, self.omega_low)

    @property
    def reference_bound_omega(self) -> float | None:
        """The reference's own relative error bound on omega_n, the largest over the resolved modes (None where it
        states none, or no mode is resolved): the measured error is the circuit's where this is well below it."""
        if self.omega_bound is None or not self.resolved.any():
            return None
        return float(np.max(self.omega_bound[self.resolved]))

    @property
    def reference_bound_P(self) -> float | None:
        """The reference's own absolute error bound on P_n, the largest over the modes compared (None where it
        states none, or none is compared)."""
        if self.P_bound is None or not self.compared.any():
            return None
        return float(np.max(self.P_bound[self.compared]))

    @property
    def reference_bound_Q(self) -> float | None:
        """The reference's own relative bound on Q_n = omega_n Q: omega_n's, and the product's rounding."""
        bound = self.reference_bound_omega
        return None if bound is None or self.losses is None else bound + float(np.finfo(float).eps)

    @property
    def compared(self) -> np.ndarray:
        """The modes whose P_n is compared: every mode but the merged ones."""
        return np.ones(self.omega.size, dtype=bool) if self.merged is None else ~self.merged

    @property
    def max_abs_error_P(self) -> float:
        """Largest |P - P_theory| over every mode not merged (an unseen one counts with P = 0); NaN when every mode
        is merged."""
        if not self.compared.any():
            return float("nan")
        return float(np.max(np.abs(self.P - self.P_theory)[self.compared]))

    def spacings(self, theory: bool = False) -> np.ndarray:
        """delta omega_n = omega_{n+1} - omega_n between neighbouring resolved nonzero modes (NaN elsewhere, and
        where the circuit did not see one of the two); ``theory``: the theory's, on the same pairs."""
        omega = self.omega_theory if theory else self.omega
        both = self.resolved[1:] & self.resolved[:-1] & (self.omega_theory[:-1] > 0)
        return np.where(both, np.diff(omega), np.nan)

    @property
    def spacing_spread(self) -> float:
        """(max - min) / mean of the circuit's spacings (0 for equally spaced modes)."""
        return spacing_spread(self.spacings())[0]

    @property
    def spacing_std(self) -> float:
        """std / mean of the circuit's spacings."""
        return spacing_spread(self.spacings())[1]

    @property
    def Q(self) -> np.ndarray:
        """The circuit's quality factor omega_n / gamma_n of every mode (NaN where unseen, and without losses)."""
        if self.gamma is None:
            return np.full(self.omega.size, np.nan)
        return np.asarray(self.omega / self.gamma)

    @property
    def Q_theory(self) -> np.ndarray:
        """omega_n Q: every mode decays at gamma = 1/Q (NaN without losses); with the theory's own decay rates,
        omega_n / gamma_n."""
        if self.gamma_theory is not None:
            with np.errstate(divide="ignore", invalid="ignore"):
                return np.asarray(self.omega_theory / self.gamma_theory)
        return self.omega_theory * (np.nan if self.losses is None else self.losses)

    @property
    def max_rel_error_Q(self) -> float:
        """Largest |Q_n - omega_n Q| / (omega_n Q) over the resolved modes of nonzero frequency (NaN without
        losses, or no such mode: a circuit's zero mode alone, its resistors' other modes merged); an unseen resolved
        mode is an infinite error."""
        ringing = self.resolved & (self.omega_theory > 0)
        if self.gamma is None or not ringing.any():
            return float("nan")
        return largest_relative_error(self.Q, self.Q_theory, ringing)

    @property
    def reference_bounds(self) -> dict[str, float | None]:
        """The reference's own bounds by metric (:attr:`reference_bound_omega`, ``_P``, ``_Q``)."""
        return {"reference_bound_omega": self.reference_bound_omega, "reference_bound_P": self.reference_bound_P,
                "reference_bound_Q": self.reference_bound_Q}

    @property
    def modes_seen(self) -> int:
        return int(np.count_nonzero(np.isfinite(self.omega)))

    def to_dict(self) -> JSONDict:
        """JSON: the metrics, and the modes (``None`` for a frequency the circuit did not show)."""
        return {"analysis": "ac", "modes": int(self.omega.size), "modes_seen": self.modes_seen,
                "max_rel_error_omega": self.max_rel_error_omega, "max_abs_error_P": self.max_abs_error_P,
                "spacing_spread": self.spacing_spread, "spacing_std": self.spacing_std,
                "spacing_spread_theory": spacing_spread(self.spacings(theory=True))[0],
                "omega": [float(w) if np.isfinite(w) else None for w in self.omega],
                "omega_theory": self.omega_theory.tolist(), "P": self.P.tolist(), "P_theory": self.P_theory.tolist(),
                "resolved": self.resolved.tolist()} | self.reference_bounds | {
                    name: getattr(self, name).tolist() for name in ("omega_low", "omega_bound", "P_bound", "merged")
                    if getattr(self, name) is not None} | ({} if self.envelope_error is None else {
                        "max_rel_error_Y11": self.envelope_error,
                        "reference_bound_Y11": self.envelope_bound}) | ({} if self.gamma is None else {
                    "Q": self.losses, "max_rel_error_Q": self.max_rel_error_Q,
                    "gamma": [float(g) if np.isfinite(g) else None for g in self.gamma]}) | (
                    {} if self.gamma_theory is None else {"gamma_theory": self.gamma_theory.tolist()})

    @classmethod
    def from_dict(cls, data: LooseJSONObject) -> SpectrumMetrics:
        """The metrics a store kept (:meth:`to_dict`): JSON read by key, any shape refused as one error."""
        try:
            gamma, gamma_theory = data.get("gamma"), data.get("gamma_theory")
            return cls(np.asarray(data["omega_theory"], dtype=float),
                       np.array([np.nan if w is None else w for w in data["omega"]], dtype=float),
                       np.asarray(data["P_theory"], dtype=float), np.asarray(data["P"], dtype=float),
                       np.asarray(data["resolved"], dtype=bool), gamma=None if gamma is None else
                       np.array([np.nan if g is None else g for g in gamma], dtype=float), losses=data.get("Q"),
                       gamma_theory=None if gamma_theory is None else np.asarray(gamma_theory, dtype=float),
                       omega_low=_optional(data, "omega_low"), omega_bound=_optional(data, "omega_bound"),
                       P_bound=_optional(data, "P_bound"),
                       merged=None if data.get("merged") is None else np.asarray(data["merged"], dtype=bool),
                       envelope_error=data.get("max_rel_error_Y11"), envelope_bound=data.get("reference_bound_Y11"))
        except (KeyError, TypeError, ValueError):
            raise ParameterError("metrics", sorted(data), "an AC run's metrics (omega, P and their theory)") from None


def _optional(data: LooseJSONObject, name: str) -> np.ndarray | None:
    value = data.get(name)
    return None if value is None else np.asarray(value, dtype=float)


def sweep_grid(omega: np.ndarray, points: int | None = None) -> tuple[list[Segment], int, float]:
    """An AC sweep for a chain's normal frequencies: its even segments (one ``.ac lin`` card each, as fine as the
    poles they hold: :func:`lcchain.compare.grid.sweep_segments`), their frequencies in all, and the last angular
    frequency.

    Parameters
    ----------
    omega : ndarray
        The chain's normal frequencies, ascending, units of 1/sqrt(L0 C0).
    points : int, optional
        Frequencies asked for; default :data:`DEFAULT_OVERSAMPLING` times the fewest that separate every pole
        (:func:`lcchain.compare.grid.min_points`).

    Raises
    ------
    ParameterError
        ``points`` below the fewest that separate every pole (naming that minimum), or a chain whose poles no
        sweep of :data:`lcchain.core.limits.MAX_AC_POINTS` frequencies separates (naming ``chain``).
    """
    omega = np.asarray(omega, dtype=float)
    omega_max = float(omega[-1]) * (1.0 + OMEGA_MARGIN)
    with np.errstate(all="ignore"):  # a count beyond int64 (poles 1e150 apart from 0) wraps: refused below
        needed = min_points(omega, omega_max) if math.isfinite(omega_max) else 0
    if not 0 < needed <= MAX_AC_POINTS:  # named as the chain: its N, its file, its walls
        needs = f"{needed}" if needed > 0 else "more than can be counted"  # a count past int64 wrapped
        raise ParameterError("chain", f"N={omega.size}", f"a chain whose poles a sweep of at most {MAX_AC_POINTS} "
                             f"frequencies separates: this one needs {needs}")
    if points is None:  # never below the engine's least (a chain of a few well-separated poles needs fewer)
        points = min(MAX_AC_POINTS, max(MIN_AC_POINTS, DEFAULT_OVERSAMPLING * needed))
    points = integer("points", points, at_least=needed, at_most=MAX_AC_POINTS,
                     allowed=f"at least {needed} frequencies ({POINTS_PER_SPACING} per spacing of the normal "
                             f"frequencies, up to {omega_max:.4g}) and at most {MAX_AC_POINTS}")
    return sweep_segments(omega, omega_max, POINTS_PER_SPACING, points), points, omega_max


def spectrum_estimate(points: float, N: int, losses: bool = False, circuit: bool = False) -> Estimate:
    """The price of an AC run of a ladder of N masses on ``points`` frequencies and of its comparison
    (:func:`compare_spectrum`): :func:`lcchain.core.budget.ac_estimate` of the fit that runs, from theory's poles
    (:func:`lcchain.compare.spectrum.fit_from_theory`), or for a ``circuit`` whose effects are no chain's the fit
    from its samples (:func:`lcchain.compare.poles.fit_poles`), its memory from the sections that fit moves at once
    (:func:`lcchain.compare.spectrum.fit_sections`, a bound for both).

    The fit from the samples alone (:func:`lcchain.compare.spectrum.fit_spectrum`) is a chain's fallback, made only
    where the fit from theory leaves a misfit above :data:`lcchain.compare.spectrum.THEORY_MISFIT` (samples that are
    not the chain's): never on lcchain's chains measured (benchmarks/spectrum.md, with losses and without), so it is
    not priced."""
    return ac_estimate(points=points, N=N, sections=fit_sections(points, N, losses), losses=losses,
                       from_theory=not circuit)


def _matched(fit: SpectrumFit, theory: Modes) -> SpectrumFit:
    """The fitted modes, one per theoretical mode: where two match the same mode (a spurious pole of the rational
    fit beside a weak mode), the one with the larger residue at loop 1 stays."""
    nearest = nearest_modes(fit.omega, theory.omega)
    keep = np.zeros(nearest.size, dtype=bool)
    for mode in np.unique(nearest):
        candidates = np.flatnonzero(nearest == mode)
        keep[candidates[np.argmax(np.abs(fit.first[candidates]))]] = True
    return fit if keep.all() else fit.subset(keep)


def _fitted(theory: Modes, omega: np.ndarray, y11: np.ndarray, yN1: np.ndarray, Q: float | None, mass: float = 1.0
            ) -> tuple[SpectrumFit, np.ndarray]:
    """The modes fitted to the samples and the index of each one's theoretical mode: from theory's poles, lossless or
    lossy (:func:`lcchain.compare.spectrum.fit_from_theory`), while that fit explains the samples, else from the
    samples alone (:func:`lcchain.compare.spectrum.fit_spectrum`'s rational fits).  With losses the modes they merge
    are theory's in the fit (their residues: the density and P_n over ``mass`` = m_1) and are never seen; when every
    mode merged there is nothing to fit (the envelope, compared by :func:`compare_spectrum`, is what is
    measured)."""
    merged = None if Q is None else merged_modes(theory, Q)
    if merged is not None and merged.all():
        empty = np.zeros(0)
        return SpectrumFit(empty, empty, empty, 0, 0.0, empty), np.zeros(0, dtype=int)
    residues = (np.asarray(theory.density, dtype=float) / mass, np.asarray(theory.transfer, dtype=float) / mass)
    fit, seen = fit_from_theory(omega, y11, yN1, np.asarray(theory.omega, dtype=float), Q, merged, residues)
    if fit.residual <= THEORY_MISFIT:
        return fit, seen
    fit = _matched(fit_spectrum(omega, y11, yN1, lossy=Q is not None), theory)
    return fit, nearest_modes(fit.omega, theory.omega)


#: The exact admittance is at least this many times sharper (its own bound) than the envelope error it measures,
#: wherever double-double reaches: everywhere the error is above ten float64 roundings (:func:`compare_envelope`).
ENVELOPE_MARGIN = 10.0


def compare_envelope(chain: Chain, omega: np.ndarray, y11: np.ndarray, Q: float) -> tuple[float, float]:
    """max |Y_11 - exact Y_11| / |exact Y_11| over the sweep, and the exact admittance's own bound there.

    The exact admittance (:func:`lcchain.theory.spectrum.admittance_with_bound`) is taken in float64 first, with
    its running error bound; the frequencies where that bound is above 1 / :data:`ENVELOPE_MARGIN` of the largest
    error measured are computed again in the next arithmetic (long double, then double-double:
    :data:`lcchain.theory.spectrum.ARITHMETICS`), until none is or every such frequency is in double-double (the
    first errors are measured against float64 itself; the bound of each includes the final rounding to float64,
    u = 1.1e-16, so an error below ten of those cannot have its margin).  Float64 holds away from the peaks
    (two-mass N = 1000 at Q = 1000: long double at 112, then 1,623 more, of 13,174 frequencies; 0.70 s against
    1.82 s in long double everywhere, and 0.29 s in float64 alone, under load; O(N x frequencies) either way).

    Returns
    -------
    error : float
        The largest relative error of ``y11`` over the sweep.
    bound : float
        The largest relative error bound of the exact admittance (first order) over the sweep.
    """
    y11, omega = np.asarray(y11, dtype=complex), np.asarray(omega, dtype=float)
    exact, bound = admittance_with_bound(chain, omega, Q, rtol=np.inf, start=ARITHMETICS[0])
    measured = np.abs(y11 - exact) / np.abs(exact)
    tier = np.zeros(omega.size, dtype=int)  # each frequency's arithmetic, an index in ARITHMETICS
    while True:  # the largest error is float64's until its peaks are sharper: the threshold falls, then stays
        again = (tier < len(ARITHMETICS) - 1) & (bound > float(np.max(measured, initial=0.0)) / ENVELOPE_MARGIN)
        if not again.any():
            break
        for current in np.unique(tier[again]):
            now = again & (tier == current)
            exact[now], bound[now] = admittance_with_bound(chain, omega[now], Q, rtol=np.inf,
                                                           start=ARITHMETICS[int(current) + 1])
        measured[again] = np.abs(y11[again] - exact[again]) / np.abs(exact[again])
        tier[again] += 1
    return float(np.max(measured, initial=0.0)), float(np.max(bound, initial=0.0))


def nearest_modes(omega: np.ndarray, theory: np.ndarray) -> np.ndarray:
    """The index of the theoretical frequency (ascending) nearest each of ``omega``."""
    right = np.clip(np.searchsorted(theory, omega), 1, max(theory.size - 1, 1))
    left = right - 1
    return np.where(np.abs(theory[right] - omega) < np.abs(omega - theory[left]), right, left).astype(int)


def compare_spectrum(theory: Modes, omega: np.ndarray, y11: np.ndarray, yN1: np.ndarray,
                     mass: float, Q: float | None = None, chain: Chain | None = None) -> SpectrumMetrics:
    """An AC run's poles and residues against the driven modes of the same chain.

    Parameters
    ----------
    theory : Modes
        The chain's driven modes (:func:`lcchain.theory.exact.driven_modes`): omega_n and P_n in ``transfer``.
    omega : ndarray
        The sweep's angular frequencies, units of 1/sqrt(L0 C0).
    y11, yN1 : ndarray, complex
        I_1/V_1 and I_N/V_1 times sqrt(L0/C0).
    mass : float
        m_1 (P_n = m_1 times the residue of Y_N1).
    Q : float, optional
        The losses' quality factor (every mode decays at gamma = 1/Q): the fit then finds each mode's decay rate,
        and the modes the losses merge (:func:`merged_modes`) are said, not compared.
    chain : Chain, optional
        The chain itself: with losses, Y_11 is then compared over the whole sweep with its exact admittance
        (``envelope_error``), what is measured however the modes merge.
    """
    fit, seen = _fitted(theory, omega, y11, yN1, Q, mass)
    circuit, gamma = np.full(theory.N, np.nan), np.full(theory.N, np.nan)
    circuit[seen], gamma[seen] = fit.omega, fit.gamma
    P = np.zeros(theory.N)
    P[seen] = mass * fit.last
    merged = None if Q is None else merged_modes(theory, Q)
    if merged is not None:  # a merged mode's pole is the fit's guess inside the cluster: not the circuit's
        circuit[merged], gamma[merged], P[merged] = np.nan, np.nan, 0.0
    envelope = bound = None
    if chain is not None and Q is not None:
        envelope, bound = compare_envelope(chain, omega, y11, Q)
    resolved = np.abs(theory.transfer) >= OMEGA_WEIGHT_FLOOR
    return SpectrumMetrics(np.asarray(theory.omega, dtype=float), circuit, np.asarray(theory.transfer, dtype=float),
                           P, resolved if merged is None else resolved & ~merged, fit, seen,
                           gamma if Q is not None else None, Q, omega_low=theory.omega_low,
                           omega_bound=theory.omega_bound, P_bound=theory.transfer_bound, merged=merged,
                           envelope_error=envelope, envelope_bound=bound)
