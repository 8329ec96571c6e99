"""Normal modes of a chain and the responses built from them.

The equations of motion of Eq. e.Horig, in mass-weighted coordinates
q_i = sqrt(m_i) Q_i, are q'' = -B q with the symmetric tridiagonal matrix B
of Eq. e.BN, built here from the physical masses and springs (so it is right
for every N; the (x, y, z) matrix of Eq. e.AN holds for N >= 5 only: for
N = 4 its middle element is y^2).

For an initial velocity of mass 1 (a *kick*; in the circuit the current of
loop 1) or an initial displacement of mass 1 (the charge of loop 1), the end
masses move as

    Q_N(t) / Q_1(0) = sqrt(m_1/m_N) * sum_n U_n1 U_nN cos(omega_n t)

(velocities for a kick, positions for a displacement).  For a mirror-symmetric
chain U_nN = (-1)^(n-1) U_n1 and this is the paper's transmission amplitude
alpha_N(t) = sum_n P_n cos(pi (n-1) - omega_n t), Eq. e.utn, with the mode
density P_n = U_n1^2 (Eq. e.Pn).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from ..core.blas import fixed_blas_threads
from ..core.errors import ParameterError
from ..core.extras import optional_module
from ..core.frozen import FrozenArrays, readonly
from ..core.show import Figure, html_table, plot, short_repr

if TYPE_CHECKING:
    import xarray

__all__ = ["Modes", "cosine_sum", "TRANSIT_SPACINGS", "WEIGHT_PRECISION"]

#: Relative precision of mode weights computed in float64 (eigenvectors, closed forms): a |P_n| below this times
#: the largest is rounding noise (P_theory(100) of the perfect cradle came out -2.8e-34 where it is 5.0e-60).
WEIGHT_PRECISION = 1e-15

#: Where a :class:`Modes` comes from: a chain's eigenproblem, its closed form, or a circuit's own poles.
MODE_KINDS = ("exact", "closed-form", "circuit")

#: Number of low-mode spacings whose median gives the transit time.
TRANSIT_SPACINGS = 5


@dataclass(frozen=True, eq=False)
class Modes(FrozenArrays):
    """Normal modes of a chain, as seen from its two ends.

    Attributes
    ----------
    omega : ndarray, shape (N,)
        Angular frequencies omega_n in units of sqrt(K/m), ascending (>= 0).
    density : ndarray, shape (N,)
        Mode density P_n = U_n1^2 (Eq. e.Pn); sums to 1.
    transfer : ndarray, shape (N,)
        End-to-end weights sqrt(m_1/m_N) U_n1 U_nN; for a symmetric chain
        (-1)^(n-1) P_n.
    method : str
        ``"exact"`` or ``"closed-form"`` (a chain's), or ``"circuit"`` (a circuit's own modes, seen from its end
        loops).
    k : ndarray or None
        Pseudo wave vectors k_n of the closed form (Eq. e.kn1), else None.
    precision : float
        Relative precision of the weights: a |weight| below ``precision`` times the largest is rounding noise,
        not a value (:meth:`precise`).  :data:`WEIGHT_PRECISION` for weights computed in float64; 0 for exact
        ones (the free perfect cradle's binomials, :func:`lcchain.theory.exact.perfect_weights`).
    omega_low : ndarray or None
        Where the frequencies are known beyond float64 (an AC run's reference, :mod:`lcchain.theory.reference`):
        the rest of each, the reference being omega_n + omega_low_n, so a comparison is not limited by float64's
        rounding of them (coupled coils: omega_n stays LAPACK's and omega_low holds the whole refinement).
    omega_bound : ndarray or None
        Each frequency's own relative error bound (of omega + omega_low), where it is stated.
    transfer_bound : ndarray or None
        Each end-to-end weight's own absolute error bound, where it is stated: a weight above it is a value
        (:meth:`precise`).
    """

    omega: np.ndarray
    density: np.ndarray
    transfer: np.ndarray
    method: str
    k: np.ndarray | None = None
    precision: float = 0.0
    omega_low: np.ndarray | None = None
    omega_bound: np.ndarray | None = None
    transfer_bound: np.ndarray | None = None

    def precise(self, weights: np.ndarray | None = None) -> np.ndarray:
        """Whether each weight (default: ``transfer``) is above the precision it was computed with, bool per
        mode: False marks rounding noise (printed as "below precision", not drawn on a log axis).  With stated
        bounds (``transfer_bound``): whether the weight is above its own bound."""
        if weights is None and self.transfer_bound is not None:
            return np.asarray(np.abs(self.transfer) > self.transfer_bound)
        values = np.abs(np.asarray(self.transfer if weights is None else weights, dtype=float))
        return np.asarray(values >= self.precision * float(np.max(values, initial=0.0)))

    @property
    def N(self) -> int:
        return int(self.omega.size)

    def transit_time(self) -> float:
        """Estimate of the end-to-end travel time, pi / (median low-mode spacing).

        The median of the first (up to) :data:`TRANSIT_SPACINGS` spacings
        omega_{n+1} - omega_n.  Exact for the perfect chains (equally spaced
        frequencies); for long chains it is the low-frequency group delay, N
        plus the delay of the end masses.  The median, not omega_2 - omega_1
        alone: weak walls lift omega_1 from 0 and shrink the first spacing
        (K0 = 0.01 on the N = 50 two-mass chain: pi / (omega_2 - omega_1) =
        69.7 against a true transit of 55.3).  It centres the arrival search
        windows of :mod:`lcchain.theory.arrivals`.
        """
        spacings = np.diff(self.omega[: TRANSIT_SPACINGS + 1])
        return float(np.pi / np.median(spacings))

    def _rows(self) -> list[tuple[str, object]]:
        rows: list[tuple[str, object]] = [("modes", f"N = {self.N}, {self.method}")]
        if self.N:
            rows.append(("omega_n", f"{float(self.omega[0]):.6g} .. {float(self.omega[-1]):.6g}"))
            if self.N > 1:
                rows.append(("transit time", self.transit_time()))
        return rows

    def __repr__(self) -> str:
        """A few lines (the per-mode arrays: ``omega``, ``density``, ``transfer``; a table: :meth:`to_xarray`)."""
        return short_repr("Modes", self._rows())

    def _repr_html_(self) -> str:
        return html_table("Modes", self._rows())

    def plot(self, ax: object = None) -> Figure:
        """The mode density P_n against omega_n with the spacing on a twin axis (the paper's Fig. Pk).

        Returns
        -------
        matplotlib.figure.Figure
            Never shown.  matplotlib is imported here, not by ``import lcchain``.
        """
        return plot("modes", self, ax=ax)

    def to_xarray(self) -> xarray.Dataset:
        """The modes as an xarray Dataset on ``mode`` (n = 1..N): ``omega`` (units of 1/sqrt(L0 C0)),
        ``density`` and ``transfer`` (dimensionless; NaN where below :attr:`precision`), ``k`` where the closed form
        gives it.  xarray is optional: ``pip install 'lcchain[data]'``."""
        optional_module("xarray", "data", "Modes.to_xarray")  # or the error naming the extra that installs it
        import xarray as xr

        transfer = np.where(self.precise(), self.transfer, np.nan)
        variables: dict[str, tuple[str, np.ndarray, dict[str, str]]] = {
            "omega": ("mode", self.omega, {"units": "1", "long_name": "normal frequency, units of 1/sqrt(L0 C0)"}),
            "density": ("mode", self.density, {"units": "1", "long_name": "mode density at loop 1"}),
            "transfer": ("mode", transfer, {"units": "1", "long_name": "end-to-end weight (NaN: below precision)"})}
        if self.k is not None:
            variables["k"] = ("mode", self.k, {"units": "1", "long_name": "pseudo wave vector of the closed form"})
        return xr.Dataset(variables, coords={"mode": ("mode", np.arange(1, self.N + 1))},
                          attrs={"method": self.method, "precision": self.precision})

    def __post_init__(self) -> None:
        """Its arrays read-only; checked as cheaply as it is made (each Monte Carlo sample makes one): the three
        per-mode arrays flat and of one length, the optional ones of that length, the method one of
        :data:`MODE_KINDS` (a Modes built by hand with arrays that disagree failed later, deep in a matrix product,
        or gave a quietly wrong arrival)."""
        for name in ("omega", "density", "transfer", "k", "omega_low", "omega_bound", "transfer_bound"):
            value = getattr(self, name)
            if value is not None and not isinstance(value, np.ndarray):
                object.__setattr__(self, name, readonly(value))
        shape = self.omega.shape
        if len(shape) != 1:
            raise ParameterError("omega", f"an array of shape {shape}", "a flat array of N frequencies")
        for name in ("density", "transfer", "k", "omega_low", "omega_bound", "transfer_bound"):
            value = getattr(self, name)
            if value is not None and value.shape != shape:
                raise ParameterError(name, f"an array of shape {value.shape}", f"shape {shape}, as omega's (one "
                                     "value a mode)")
        if self.method not in MODE_KINDS:
            raise ParameterError("method", self.method, " | ".join(MODE_KINDS))
        self._freeze_arrays()


# ---------------------------------------------------------------- cosine sums
_BLOCK = 1 << 22  # elements per temporary block (32 MB of float64)
#: Largest phase error omega * (t - grid) a uniform run's times may carry: its second-order remainder,
#: DRIFT_PHASE^2 / 2 = 5e-15 of sum |weights|, is below rounding.
DRIFT_PHASE = 1e-7


@fixed_blas_threads
def cosine_sum(weights: np.ndarray, omega: np.ndarray, t: ArrayLike) -> np.ndarray | float:
    """Evaluate f(t) = sum_n weights_n cos(omega_n t) at the times t.

    On a uniform grid of many times, the grid t_j = t0 + (p Q + q) h is split
    and cos(a_p + b_q) expanded, turning the N x J cosines into
    2 (P + Q) N cosines and two matrix products; otherwise blocks of the
    outer product are summed directly.  Both are exact to rounding.

    Parameters
    ----------
    weights, omega : ndarray, shape (N,)
    t : float or array_like
        Times in units of sqrt(m/K).

    Returns
    -------
    float or ndarray shaped like t
    """
    scalar = np.ndim(t) == 0
    times = np.atleast_1d(np.asarray(t, dtype=float))
    shape = times.shape
    times = times.ravel()
    weights = np.asarray(weights, dtype=float)
    omega = np.asarray(omega, dtype=float)
    J, N = times.size, omega.size
    out = np.empty(J)
    # A simulator's times drift from the exact grid by its accumulated rounding (3.3e-8 after 10^5 steps of
    # ngspice); within DRIFT_PHASE / max(omega) of it, the grid's sum plus its first-order correction
    # d f'(grid) is exact to (DRIFT_PHASE)^2 / 2 of sum |weights|, far below rounding.
    drift = DRIFT_PHASE / max(float(np.max(np.abs(omega))), 1e-300) if N else 0.0
    for start, stop, uniform in _uniform_runs(times, drift):
        part = times[start:stop]
        if uniform and part.size * N > 4_000_000:
            h = (part[-1] - part[0]) / (part.size - 1)
            deviation = part - (part[0] + h * np.arange(part.size))
            if np.any(deviation):
                value, slope = _cosine_sum_split(weights, omega, part[0], h, part.size, slope=True)
                out[start:stop] = value + deviation * slope
            else:
                out[start:stop] = _cosine_sum_split(weights, omega, part[0], h, part.size)[0]
        else:
            out[start:stop] = _cosine_sum_direct(weights, omega, part)
    shaped = out.reshape(shape)
    return float(shaped[0]) if scalar else shaped


def _cosine_sum_direct(weights: np.ndarray, omega: np.ndarray, times: np.ndarray) -> np.ndarray:
    out = np.empty(times.size)
    rows = max(1, _BLOCK // max(omega.size, 1))
    for start in range(0, times.size, rows):
        block = times[start : start + rows]
        out[start : start + rows] = np.cos(np.multiply.outer(block, omega)) @ weights
    return out


def _uniform_runs(times: np.ndarray, drift: float = 0.0, min_run: int = 64) -> list[tuple[int, int, bool]]:
    """Split times into index ranges (start, stop, uniform).

    ``uniform`` marks ranges of at least ``min_run`` equally spaced points,
    each within ``drift`` (or 1e-12 of the largest time, whichever is more)
    of the exact grid between its ends; the others are whatever lies between
    them. A simulator's time points are uniform except for a few start-up
    steps and the last one, so nearly all points fall in one or two long runs
    where :func:`_cosine_sum_split` applies.  A run of equal steps whose
    accumulated rounding strays further than that from its end-to-end grid
    (a long run at a small step) is halved until each part keeps within it
    of its own grid: the times keep the fast path at any length.
    """
    J = times.size
    if J < 2 * min_run:
        return [(0, J, False)]
    steps = np.diff(times)
    scale = 1e-12 * max(1.0, float(np.max(np.abs(times))))
    tolerance = max(scale, drift)
    # boundaries where the step changes
    change = np.flatnonzero(np.abs(np.diff(steps)) > scale) + 1
    edges = np.concatenate(([0], change, [steps.size]))
    runs: list[tuple[int, int, bool]] = []
    pending = 0  # start of points not yet assigned
    for a, b in zip(edges[:-1], edges[1:], strict=True):
        # steps a..b-1 are equal: points a..b form a uniform run, or parts of it do
        for start, stop in _within_grid(times, int(a), int(b) + 1, tolerance, min_run):
            if start > pending:
                runs.append((pending, start, False))
            runs.append((start, stop, True))
            pending = stop
    if pending < J:
        runs.append((pending, J, False))
    return runs


def _within_grid(times: np.ndarray, start: int, stop: int, tolerance: float,
                 min_run: int) -> list[tuple[int, int]]:
    """Ranges of at least ``min_run`` of the equally stepped times[start:stop], each within ``tolerance`` of the
    exact grid between its own ends: the whole range, or its halves' ranges, and so on."""
    if stop - start < min_run:
        return []
    part = times[start:stop]
    grid = part[0] + (part[-1] - part[0]) / (part.size - 1) * np.arange(part.size)
    if np.max(np.abs(grid - part)) <= tolerance:
        return [(start, stop)]
    middle = (start + stop) // 2
    return _within_grid(times, start, middle, tolerance, min_run) + _within_grid(times, middle, stop, tolerance,
                                                                               min_run)


def _cosine_sum_split(weights: np.ndarray, omega: np.ndarray, t0: float, h: float, J: int,
                      slope: bool = False) -> tuple[np.ndarray, np.ndarray | None]:
    """sum_n w_n cos(omega_n t_j) on the grid t_j = t0 + j h, and with ``slope`` its derivative
    -sum_n w_n omega_n sin(omega_n t_j), by cos(a + b) and sin(a + b) expanded."""
    Q = int(np.ceil(np.sqrt(J)))
    P = -(-J // Q)
    a = t0 + (Q * h) * np.arange(P)
    b = h * np.arange(Q)
    out = np.zeros((P, Q))
    der = np.zeros((P, Q)) if slope else None
    cols = max(1, _BLOCK // (P + Q))
    for start in range(0, omega.size, cols):
        om = omega[start : start + cols]
        wt = weights[start : start + cols]
        phase_a = np.multiply.outer(a, om)
        phase_b = np.multiply.outer(b, om)
        cos_a, sin_a, cos_b, sin_b = np.cos(phase_a), np.sin(phase_a), np.cos(phase_b), np.sin(phase_b)
        out += (cos_a * wt) @ cos_b.T
        out -= (sin_a * wt) @ sin_b.T
        if der is not None:  # -w omega sin(a + b) = -w omega (sin a cos b + cos a sin b)
            der -= (sin_a * (wt * om)) @ cos_b.T
            der -= (cos_a * (wt * om)) @ sin_b.T
    return out.ravel()[:J], None if der is None else der.ravel()[:J]
