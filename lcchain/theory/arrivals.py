"""Arrivals of the pulse at the chain ends: when, and how much of it.

After a kick (or displacement) of mass 1 the pulse reaches mass N at the
first arrival, comes back to mass 1 after the first bounce, reaches mass N
again, and so on.  Arrival j (j = 1, 2, ...) is seen at the far end for odd j
(alpha_N(t), Eq. e.utn) and at the near end for even j (sum P_n cos omega_n t).

Search window
-------------
Arrival j is the largest value of the end's response in the window

    t in [j T - W_j, j T + W_j],  W_j = min(T/2, 4 (j T)^(1/3) + 4),

where T = pi / (omega_2 - omega_1) is the low-frequency transit time
(:meth:`Modes.transit_time`; exact for the perfect chains).  The half width
follows the N^(1/3) growth of the delay s* and of the pulse width (Sec. IV.C)
and never exceeds T/2, so that for small N the window cannot reach the next
passage of the pulse (for N = 3 a window twice as wide finds the maximum at
3 T, a different arrival).  The maximum is located on a grid of spacing
0.05 max(1, T^(1/3)) and refined with a bounded Brent search around the
three best grid points.

The delay of the first arrival is s* = t* - N and its loss
delta* = 1 - alpha_N(N + s*) (Tables I and II).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Generator, Sequence
from dataclasses import dataclass

import numpy as np

from ..core.blas import fixed_blas_threads
from ..core.checks import integer
from ..core.json import JSONDict
from ..core.limits import MAX_TRANSITS
from .chain import Chain
from .modes import Modes, cosine_sum
from .spectrum import modes_of

__all__ = ["Arrival", "arrival_window", "arrivals", "first_arrival", "refine_peak", "refine_maximum", "refine_maxima",
           "maximum_in_window", "stop_time"]


@dataclass(frozen=True)
class Arrival:
    """One arrival of the pulse at an end of the chain.

    Attributes
    ----------
    index : int
        1 for the first arrival at the far end, 2 for the return to mass 1
        after the first bounce, and so on.
    end : str
        ``"last"`` (odd index) or ``"first"`` (even index).
    time : float
        Time of the peak, in units of sqrt(m/K).
    peak : float
        Peak value of the end's response relative to the initial value.
    window : tuple of float
        The searched time window.
    """

    index: int
    end: str
    time: float
    peak: float
    window: tuple[float, float]

    @property
    def loss(self) -> float:
        """1 - peak (delta of the paper for the first arrival)."""
        return 1.0 - self.peak

    def to_dict(self) -> JSONDict:
        return {"index": self.index, "end": self.end, "time": self.time, "peak": self.peak,
                "window": list(self.window)}


def arrival_window(index: int, transit_time: float) -> tuple[float, float]:
    """Time window searched for arrival ``index`` (see the module docstring)."""
    index = integer("index", index, at_least=1)
    centre = index * transit_time
    half = min(transit_time / 2.0, 4.0 * centre ** (1.0 / 3.0) + 4.0)
    return centre - half, centre + half


def stop_time(modes: Modes, transits: int) -> float:
    """End of the last arrival's search window: a run lasts the requested transits and no longer.

    Parameters
    ----------
    modes : Modes
        The chain's modes (their transit time).
    transits : int
        Arrivals to watch, 1 to :data:`lcchain.core.limits.MAX_TRANSITS`.

    Returns
    -------
    float
        Units of sqrt(m/K) (in the circuit, sqrt(L0 C0)).
    """
    transits = integer("transits", transits, at_least=1, at_most=MAX_TRANSITS)
    return arrival_window(transits, modes.transit_time())[1]


def _weights(modes: Modes, index: int) -> np.ndarray:
    return modes.transfer if index % 2 == 1 else modes.density


def refine_maximum(f: Callable[[np.ndarray], np.ndarray], lo: float, hi: float) -> tuple[float, float]:
    """Maximum of a smooth function of time on [lo, hi] by bounded Brent.

    Brent works on the offset from the interval's centre: scipy's bounded
    Brent stops at a tolerance of sqrt(eps) |x| + xatol, which at t ~ 3500 is
    5e-5 in time and, through the peak's curvature, 2.5e-12 in the peak's value;
    on the offset it is xatol.  (That noise stalled the two-mass optimiser at
    N = 3500 and 4000: 2300 evaluations instead of 110.)

    Parameters
    ----------
    f : callable
        Maps an array of times to an array of values.
    lo, hi : float
        The interval, units of sqrt(m/K).

    Returns
    -------
    time, value : float
    """
    return refine_maxima(f, [(lo, hi)])[0]


def refine_maxima(f: Callable[[np.ndarray], np.ndarray], intervals: Sequence[tuple[float, float]],
                  each: Callable[[np.ndarray], np.ndarray] | None = None) -> list[tuple[float, float]]:
    """:func:`refine_maximum` on several intervals, their Brent searches side by side.

    Each search is :func:`_bounded_brent` on its own interval, exactly as
    alone; at every step the searches still running ask for one time each,
    and those times are evaluated in one call of ``each``.  A response with
    a pulse costs about as much for three times as for one, so three
    refinements cost a third of what they did one after the other.

    Parameters
    ----------
    f : callable
        Maps an array of times to an array of values (evaluates the ends of
        each interval, which Brent never does).
    intervals : sequence of (lo, hi)
    each : callable, optional
        Maps an array of times to the values ``f`` gives each time alone,
        ``f(np.array([t]))[0]`` (a matrix product of several rows need not
        add in the order of a single row's: ``each`` must not differ from
        ``f`` in those last bits if the searches are to follow the same
        points).  Default: ``f`` called once per time.

    Returns
    -------
    list of (time, value), one per interval
    """
    if each is None:
        def each(times: np.ndarray) -> np.ndarray:
            return np.array([f(times[k : k + 1])[0] for k in range(times.size)])
    centres = [0.5 * (lo + hi) for lo, hi in intervals]
    searches = [_bounded_brent(lo - centre, hi - centre, 1e-10 * max(1.0, hi - lo))
                for (lo, hi), centre in zip(intervals, centres, strict=True)]
    asked = {k: next(search) for k, search in enumerate(searches)}
    found: dict[int, tuple[float, float]] = {}
    while asked:
        running = list(asked)
        values = each(np.array([centres[k] + asked[k] for k in running]))
        for k, value in zip(running, values, strict=True):
            try:
                asked[k] = searches[k].send(-float(value))
            except StopIteration as stop:
                offset, minimum = stop.value
                found[k] = (centres[k] + offset, float(-minimum))
                del asked[k]
    best = []
    for k, (lo, hi) in enumerate(intervals):
        best_t, best_v = found[k]
        for edge, value in zip((lo, hi), f(np.array([lo, hi])), strict=True):  # Brent never evaluates the ends
            if value > best_v:
                best_t, best_v = float(edge), float(value)
        best.append((best_t, best_v))
    return best


def _bounded_brent(x1: float, x2: float, xatol: float,
                   maxfun: int = 500) -> Generator[float, float, tuple[float, float]]:
    """Minimum on [x1, x2] by scipy's bounded Brent (``minimize_scalar(method="bounded")``, scipy 1.17), as a
    generator: it yields each point to evaluate, is sent the function's value there, and returns (x, f(x)).

    The same operations in the same order as scipy's ``_minimize_scalar_bounded``, so the same points and the
    same result to the bit; as a generator, several searches can run side by side (:func:`refine_maxima`).
    """
    sqrt_eps = math.sqrt(2.2e-16)
    golden_mean = 0.5 * (3.0 - math.sqrt(5.0))
    a, b = x1, x2
    fulc = a + golden_mean * (b - a)
    nfc, xf = fulc, fulc
    rat = e = 0.0
    x = xf
    fx = yield x
    num = 1
    fu = np.inf
    ffulc = fnfc = fx
    xm = 0.5 * (a + b)
    tol1 = sqrt_eps * np.abs(xf) + xatol / 3.0
    tol2 = 2.0 * tol1
    while np.abs(xf - xm) > (tol2 - 0.5 * (b - a)):
        golden = 1
        if np.abs(e) > tol1:  # a parabola through the three best points
            golden = 0
            r = (xf - nfc) * (fx - ffulc)
            q = (xf - fulc) * (fx - fnfc)
            p = (xf - fulc) * q - (xf - nfc) * r
            q = 2.0 * (q - r)
            if q > 0.0:
                p = -p
            q = np.abs(q)
            r = e
            e = rat
            if (np.abs(p) < np.abs(0.5 * q * r)) and (p > q * (a - xf)) and (p < q * (b - xf)):
                rat = (p + 0.0) / q
                x = xf + rat
                if ((x - a) < tol2) or ((b - x) < tol2):
                    si = np.sign(xm - xf) + ((xm - xf) == 0)
                    rat = tol1 * si
            else:
                golden = 1
        if golden:  # a golden-section step
            e = a - xf if xf >= xm else b - xf
            rat = golden_mean * e
        si = np.sign(rat) + (rat == 0)
        x = xf + si * np.maximum(np.abs(rat), tol1)
        fu = yield x
        num += 1
        if fu <= fx:
            if x >= xf:
                a = xf
            else:
                b = xf
            fulc, ffulc = nfc, fnfc
            nfc, fnfc = xf, fx
            xf, fx = x, fu
        else:
            if x < xf:
                a = x
            else:
                b = x
            if (fu <= fnfc) or (nfc == xf):
                fulc, ffulc = nfc, fnfc
                nfc, fnfc = x, fu
            elif (fu <= ffulc) or (fulc == xf) or (fulc == nfc):
                fulc, ffulc = x, fu
        xm = 0.5 * (a + b)
        tol1 = sqrt_eps * np.abs(xf) + xatol / 3.0
        tol2 = 2.0 * tol1
        if num >= maxfun:
            break
    return float(xf), float(fx)


@fixed_blas_threads
def refine_peak(weights: np.ndarray, omega: np.ndarray, lo: float, hi: float) -> tuple[float, float]:
    """Maximum of sum_n weights_n cos(omega_n t) on [lo, hi] by bounded Brent.

    Returns
    -------
    time, value : float
    """
    return refine_maximum(lambda t: np.atleast_1d(cosine_sum(weights, omega, t)), lo, hi)


def maximum_in_window(f: Callable[[np.ndarray], np.ndarray], window: tuple[float, float],
                      transit_time: float,
                      each: Callable[[np.ndarray], np.ndarray] | None = None) -> tuple[float, float]:
    """Largest value of a response in a search window: a grid, then Brent around its three best points.

    The grid spacing 0.05 max(1, T^(1/3)) resolves the pulse, whose width grows
    like T^(1/3) (Sec. IV.C).

    Parameters
    ----------
    f : callable
        Maps an array of times to the response's values.
    window : (float, float)
        From :func:`arrival_window` (possibly shifted by a pulse's centre).
    transit_time : float
        The chain's transit time T.
    each : callable, optional
        ``f`` at each of several times as if alone (:func:`refine_maxima`).

    Returns
    -------
    time, value : float
    """
    lo, hi = window
    step = 0.05 * max(1.0, transit_time ** (1.0 / 3.0))
    count = max(64, int(np.ceil((hi - lo) / step)) + 1)
    grid = np.linspace(lo, hi, count)
    values = f(grid)
    h = grid[1] - grid[0]
    best = (float(grid[np.argmax(values)]), float(np.max(values)))
    intervals = [(max(lo, grid[i] - h), min(hi, grid[i] + h)) for i in np.argsort(values)[::-1][:3]]
    for t, v in refine_maxima(f, intervals, each):
        if v > best[1]:
            best = (t, v)
    return best


def _find_peak(modes: Modes, index: int, window: tuple[float, float]) -> tuple[float, float]:
    weights = _weights(modes, index)
    return maximum_in_window(lambda t: np.atleast_1d(cosine_sum(weights, modes.omega, t)), window,
                             modes.transit_time())


@fixed_blas_threads
def arrivals(chain_or_modes: Chain | Modes, count: int = 1) -> list[Arrival]:
    """The first ``count`` arrivals (first arrival, then one per bounce).

    Parameters
    ----------
    chain_or_modes : Chain or Modes
        For a Chain the modes are computed with ``normal_modes(chain)``.
    count : int
        Number of arrivals (end-to-end transits), 1 to :data:`lcchain.core.limits.MAX_TRANSITS` (as a run's
        transits: each takes a search of its own, milliseconds).
    """
    count = integer("count", count, at_least=1, at_most=MAX_TRANSITS)
    modes = modes_of(chain_or_modes)
    T = modes.transit_time()
    found = []
    for index in range(1, int(count) + 1):
        window = arrival_window(index, T)
        time, peak = _find_peak(modes, index, window)
        found.append(Arrival(index, "last" if index % 2 else "first", float(time), float(peak),
                             (float(window[0]), float(window[1]))))  # Python floats: a repr that reads plainly
    return found


@fixed_blas_threads
def first_arrival(chain_or_modes: Chain | Modes) -> Arrival:
    """The first arrival at the far end: t* = N + s*, peak alpha* = 1 - delta*."""
    return arrivals(chain_or_modes, 1)[0]
