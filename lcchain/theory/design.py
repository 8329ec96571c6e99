"""Optimal end designs for any N: Tables I and II of the paper, computed.

* One mass (Sec. IV, Table I): m_1 = m_N = 1/x^2, everything else uniform;
  x* maximises the first-arrival amplitude alpha* = max_s alpha_N(N + s).
* Two masses and their spring (Sec. V, Table II): (r*, w*) maximise it.

The procedure is the paper's (an outer search over the parameters, an inner
maximisation over the delay s), made fast:

* modes come from the closed form (O(N), :mod:`lcchain.closed_form`) for
  N >= 5 and from exact diagonalisation for N = 3, 4;
* the inner maximisation starts from the previous optimum's arrival time
  and only falls back to the full window search of :mod:`lcchain.arrivals`
  when the peak leaves the local bracket;
* the two-mass search first follows the curve w(r) that makes the mode
  density quartic (Eq. e.wr), on which the optimum lies for large N
  (Fig. rw), then relaxes w with a Nelder-Mead search in (r, w);
* the reported arrival is recomputed with the full window search at the
  optimum.

For N = 3 the constrained model forces y = 1 (r = 1): the two-mass case has
the single parameter w and its optimum is the perfect chain, as in Table II.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, replace
from typing import TypeAlias

import numpy as np
import scipy  # its submodules load on first use: commands that need no theory never import them

from ..core.blas import fixed_blas_threads
from ..core.checks import callback, choice, integer
from ..core.errors import ParameterError
from ..core.json import JSONDict
from ..core.limits import MAX_DESIGN_N, MIN_N
from ..core.types import DESIGN_CASES, DesignCase
from .arrivals import arrival_window, first_arrival, refine_peak
from .chain import Chain
from .closed_form import closed_form_modes
from .exact import exact_modes
from .modes import Modes

__all__ = ["Design", "optimal_design", "optimal_one_mass", "optimal_two_mass", "quartic_w", "DESIGN_CHAINS",
           "DESIGN_TABLES", "design_chain"]

#: A design's parameters by name: ``x``, or ``r`` and ``w`` (None: a parameter the other design has).
DesignParams: TypeAlias = Mapping[str, float | None]


def _parameter(params: DesignParams, name: str) -> float:
    value = params[name]
    if value is None:  # the words the chain's own check says for None
        raise ParameterError(name, value, "a finite real number")
    return value


#: Each optimised design's chain from its parameters (the paper's x of Table I; r and w of Table II).
DESIGN_CHAINS: dict[str, Callable[[int, DesignParams], Chain]] = {
    "one-mass": lambda N, params: Chain.one_mass(N, _parameter(params, "x")),
    "two-mass": lambda N, params: Chain.from_rw(N, _parameter(params, "r"), _parameter(params, "w")),
}
#: Each optimised design's table in the paper and what it optimises.
DESIGN_TABLES: dict[str, tuple[str, str]] = {"one-mass": ("Table I", "one optimised mass"),
                                             "two-mass": ("Table II", "two optimised masses and their spring")}
#: The fields of :meth:`Design.to_dict` that only one design has.
_DESIGN_FIELDS: dict[str, tuple[str, ...]] = {"one-mass": ("Delta", "delta_uniform"), "two-mass": ("r", "w")}


def design_chain(case: str, N: int, params: DesignParams) -> Chain:
    """The chain of design ``case`` (``"one-mass"``, ``"two-mass"``) for N masses from its parameters (a mapping
    holding ``x``, or ``r`` and ``w``)."""
    return DESIGN_CHAINS[choice("case", case, DESIGN_CASES)](N, params)


@dataclass(frozen=True)
class Design:
    """An optimised chain and its first arrival (a row of Table I or II).

    Attributes
    ----------
    case : str
        ``"one-mass"`` or ``"two-mass"``.
    N : int
    delta : float
        Transmission loss 1 - alpha* at the first arrival.
    s : float
        Arrival delay s* = t* - N, in units of sqrt(m/K).
    t_arrival : float
        t* = N + s*.
    m1, m2, K12 : float
        End masses and spring, bulk units (Eq. e.m1m2K12-rw).
    x, y, z : float
        The paper's variables (Eq. e.xyz).
    r, w : float or None
        Two-mass parameters (Eq. e.rw).
    Delta : float or None
        One-mass width parameter x^2/(2 - x^2) (Eq. e.xDelta).
    delta_uniform : float or None
        Loss of the uniform free chain of the same N (last column of Table I).
    """

    case: str
    N: int
    delta: float
    s: float
    t_arrival: float
    m1: float
    m2: float
    K12: float
    x: float
    y: float
    z: float
    r: float | None = None
    w: float | None = None
    Delta: float | None = None
    delta_uniform: float | None = None

    @property
    def chain(self) -> Chain:
        """The optimised chain."""
        return design_chain(self.case, self.N, {"x": self.x, "r": self.r, "w": self.w})

    def to_dict(self) -> JSONDict:
        """JSON object: N, case, delta, s, t_arrival, m1, m2, K12, x, y, z and r, w or Delta, delta_uniform."""
        data: dict[str, str | float | None] = {
            "N": self.N, "case": self.case, "delta": self.delta, "s": self.s, "t_arrival": self.t_arrival,
            "m1": self.m1, "m2": self.m2, "K12": self.K12, "x": self.x, "y": self.y, "z": self.z,
        }
        data.update({name: getattr(self, name) for name in _DESIGN_FIELDS[self.case]})
        return {key: (float(v) if isinstance(v, (float, np.floating)) else v) for key, v in data.items()}


def quartic_w(r: float) -> float:
    """w(r) that makes the mode density quartic, Eq. e.wr (0 < r <= 1)."""
    root = math.sqrt(1.0 - r)
    return 2.0 * ((1.0 - root) / (1.0 + root)) ** 2


def amplitude_noise(N: int) -> float:
    """Rounding noise of alpha_N near its peak: the cosine sum's phases reach about 2N rad.

    Each cos(omega_n t) carries an absolute rounding of about eps * omega_n t
    <= 2.2e-16 * 2N, so alpha is known to ~1e-16 * 2N (N = 4000: ~1e-12).  An
    optimiser asked to agree to less than that never stops: Nelder-Mead ran
    its 600 iterations (2300 evaluations, 10 s instead of 0.7 s) at N = 3500
    and 4000 with a fixed 1e-13.
    """
    return max(1e-13, 4e-16 * N)


def _check_design_N(N: object) -> int:
    return integer("N", N, at_least=MIN_N, at_most=MAX_DESIGN_N)


def _modes(N: int, r: float, w: float) -> Modes:
    if N >= 5:
        return closed_form_modes(N, r, w)
    return exact_modes(Chain.from_rw(N, r, w))


#: Amplitude evaluations an optimisation usually takes (for its progress report).
_TYPICAL_EVALUATIONS = {"one-mass": 12, "two-mass": 105}


class _Amplitude:
    """alpha* = max_s alpha_N(N + s) as a function of (r, w), warm-started; counts its evaluations."""

    def __init__(self, N: int, case: str, progress: Callable[[float], None] | None = None):
        self.N = N
        self.t_hint: float | None = None
        self.count = 0
        self.expected = _TYPICAL_EVALUATIONS[case]
        self.progress = callback("progress", progress) if progress is not None else None

    def __call__(self, r: float, w: float) -> float:
        self.count += 1
        if self.progress is not None:
            self.progress(min(self.count / self.expected, 0.99))
        modes = _modes(self.N, r, w)
        if self.t_hint is not None:
            T = modes.transit_time()
            lo, hi = arrival_window(1, T)
            half = 0.3 * max(1.0, T ** (1.0 / 3.0))
            a, b = max(lo, self.t_hint - half), min(hi, self.t_hint + half)
            if a < b:
                t, value = refine_peak(modes.transfer, modes.omega, a, b)
                if a + 1e-3 * half < t < b - 1e-3 * half:
                    self.t_hint = t
                    return value
        arrival = first_arrival(modes)
        self.t_hint = arrival.time
        return arrival.peak


def _finish(case: str, N: int, r: float, w: float, chain: Chain) -> Design:
    """The fields both designs compute alike; each adds its own (:func:`dataclasses.replace`)."""
    arrival = first_arrival(_modes(N, r, w))
    m1, m2, K12 = float(chain.masses[0]), float(chain.masses[1]), float(chain.springs[1])
    x, y, z = chain.xyz()
    return Design(case=case, N=N, delta=1.0 - arrival.peak, s=arrival.time - N, t_arrival=arrival.time,
                  m1=m1, m2=m2, K12=K12, x=x, y=y, z=z)


@fixed_blas_threads
def optimal_one_mass(N: int, progress: Callable[[float], None] | None = None) -> Design:
    """Optimal one-mass chain for N masses (Sec. IV, Table I).

    Parameters
    ----------
    N : int
        3 <= N <= :data:`lcchain.core.limits.MAX_DESIGN_N`.
    progress : callable, optional
        Called with the fraction of the usual work done (0 to 0.99) at each
        evaluation of the amplitude: long designs (minutes at N = 10^7) say
        how far they are.

    Returns
    -------
    Design
        x*, delta*, s*, m1* = 1/x*^2, Delta* = x*^2/(2 - x*^2) and the loss
        delta*(1) of the uniform free chain.
    """
    N = _check_design_N(N)
    amplitude = _Amplitude(N, "one-mass", progress)
    guess = 0.9173 * N ** (-1 / 6) * (1 + 0.1 * N ** (-1 / 3))  # Eq. e.asymp_x with a small-N correction
    lo, hi = 0.8 * guess, min(math.sqrt(2) * 0.999, 1.25 * guess)
    result = scipy.optimize.minimize_scalar(lambda x: -amplitude(1.0, x * x), bounds=(lo, hi), method="bounded",
                             options={"xatol": 1e-10})
    x = float(result.x)
    if not lo + 1e-6 < x < hi - 1e-6:  # pragma: no cover - a guard against a bad guess
        raise RuntimeError(f"one-mass optimum for N={N} hit the search bound at x={x}")
    uniform = first_arrival(_modes(N, 1.0, 1.0))
    chain = Chain.one_mass(N, x)
    return replace(_finish("one-mass", N, 1.0, x * x, chain), Delta=x * x / (2 - x * x),
                   delta_uniform=1.0 - uniform.peak)


@fixed_blas_threads
def optimal_two_mass(N: int, progress: Callable[[float], None] | None = None) -> Design:
    """Optimal two-mass chain for N masses (Sec. V, Table II).

    Parameters
    ----------
    N : int
        3 <= N <= :data:`lcchain.core.limits.MAX_DESIGN_N`.
    progress : callable, optional
        As for :func:`optimal_one_mass`.

    Returns
    -------
    Design
        r*, w*, delta*, s* and m1*, m2*, K12* (Eq. e.m1m2K12-rw).
    """
    N = _check_design_N(N)
    amplitude = _Amplitude(N, "two-mass", progress)
    if N == 3:
        result = scipy.optimize.minimize_scalar(lambda w: -amplitude(1.0, w), bounds=(0.3, 1.2), method="bounded",
                                 options={"xatol": 1e-12})
        r, w = 1.0, float(result.x)
    else:
        # Stage 1: along the quartic curve w(r), Eq. e.wr; a coarse scan in
        # log r brackets the maximum, Brent refines it.
        r_asym = min(1.0, 4.387 * N ** (-1 / 3))
        grid = np.geomspace(0.3 * r_asym, 0.999, 12)
        values = [amplitude(r, quartic_w(r)) for r in grid]
        i = int(np.argmax(values))
        a, b = grid[max(i - 1, 0)], grid[min(i + 1, grid.size - 1)]
        amplitude.t_hint = None
        result = scipy.optimize.minimize_scalar(lambda r: -amplitude(r, quartic_w(r)), bounds=(a, b), method="bounded",
                                 options={"xatol": 1e-7})
        r0 = float(result.x)
        w0 = quartic_w(r0)
        # Stage 2: relax w off the curve (it matters for N < 20).
        # In (log r, log w): both scale as powers of N (Eq. e.rw_N).  alpha
        # is flat along m1 at the optimum (Table II, N = 1000: m1 = 9.146
        # instead of 9.1452 costs 1.6e-9) and noisy at ~1e-14, so the
        # tolerances stop at what the printed digits need.
        start = np.log([r0, w0])
        simplex = np.array([start, start + [0.02, 0.0], start + [0.0, 0.04]])

        def loss(p: np.ndarray) -> float:
            r, w = np.exp(p)
            return -amplitude(r, w) if r < 2 else 1.0

        result = scipy.optimize.minimize(loss, start, method="Nelder-Mead",
                          options={"initial_simplex": simplex, "xatol": 1e-7, "fatol": amplitude_noise(N),
                                   "maxiter": 600})
        result.x = np.exp(result.x)
        r, w = (float(v) for v in result.x)
    chain = Chain.from_rw(N, r, w)
    return replace(_finish("two-mass", N, r, w, chain), r=r, w=w)


@fixed_blas_threads
def optimal_design(case: DesignCase, N: int, progress: Callable[[float], None] | None = None) -> Design:
    """Optimal design of the given case (``"one-mass"`` or ``"two-mass"``) for N masses."""
    choice("case", case, DESIGN_CASES)
    return _OPTIMISERS[case](N, progress)


#: Each design's optimiser.
_OPTIMISERS: dict[str, Callable[[int, Callable[[float], None] | None], Design]] = {
    "one-mass": optimal_one_mass, "two-mass": optimal_two_mass}
