"""Exact linear response of a chain (or its LC ladder) with losses and pulses.

Every scene is a linear circuit; this module is its theory, in the
dimensionless units of :mod:`lcchain.chain` (masses m_i, springs K, time in
units of tau = sqrt(m/K) = sqrt(L0 C0)).

Equations of motion.  A series resistor R_i = L_i / (Q tau) with every
inductor adds a friction proportional to each mass,

    m_i Q_i'' + (m_i / Q) Q_i' + (K Q)_i = F_i(t),

so in the mass-weighted normal coordinates of Eq. e.BN every mode obeys the
same damped oscillator, with one rate gamma = 1/Q for all modes:

    x_n'' + gamma x_n' + omega_n^2 x_n = f_n(t).

Loop i then moves as

    Q_i(t) = sqrt(m_1/m_i) sum_n U_ni U_n1 h_n(t)                       (1)

(U the eigenvectors of B, Eq. e.BN); without losses and for a kick or a
displacement h_n = cos(omega_n t), and (1) is the transmission amplitude of
Eq. e.utn at i = N and the return amplitude at i = 1.

The mode responses h_n, for the excitations of a scene:

* ``"kick"``: Q_1'(0) = 1 (the current of loop 1, I_1(0) = I0); the output is
  the velocity (loop current / I0), h_n = s_n'(t);
* ``"displacement"``: Q_1(0) = 1 (the charge of loop 1, Q0); the output is the
  position (loop charge / Q0), h_n = c_n(t) = s_n'(t) + gamma s_n(t);
* ``"pulse"``: a force m_1 g(t) on mass 1 (a voltage source L_1 I0 g(t) in
  loop 1), g of unit area; the output is the velocity (current / I0), the
  convolution h_n = (g * s_n')(t).  ``"gaussian"``: g(t) =
  exp(-(t - 4w)^2 / (2 w^2)) / (w sqrt(2 pi)) for t >= 0 and 0 before (the
  gaussian switched on at t = 0, *not* renormalised: its area is
  1 - Phi(-4) = 1 - 3.17e-5, exactly the source the netlist writes);
  ``"rect"``: g(t) = 1/w on [0, w).

Here s_n is the impulse response of the damped oscillator (s(0) = 0,
s'(0) = 1).  With Omega^2 = omega^2 - gamma^2/4 it is

    s(t) = exp(-gamma t/2) sin(Omega t) / Omega          (Omega^2 >= 0)
    s(t) = exp(-gamma t/2) sinh(kappa t) / kappa         (kappa^2 = -Omega^2 > 0)

evaluated without cancellation or overflow in every regime: underdamped,
critical (Omega = 0: s = t exp(-gamma t/2)), overdamped (through
exp(lambda_+ t) and expm1, lambda_+ = -omega^2 / (gamma/2 + kappa)), and the
zero mode of a free chain (s = (1 - exp(-gamma t)) / gamma, or t without
losses).

Pulses.  After the pulse (t >= T, T = 16 w for the gaussian, whose tail
beyond 12 standard deviations weighs exp(-72) ~ 5e-32, and T = w for the
rect) each mode oscillates freely from its state (x_n(T), x_n'(T)), so

    h_n(t) = x_n'(T) s_n'(t - T) - omega_n^2 x_n(T) s_n(t - T).

The state is the integral of g against (s, s') over [0, T], done by
16-point Gauss-Legendre quadrature on panels short enough (<= w and
<= 3 / max|lambda|) that the analytic integrand is integrated to rounding;
the panel states are propagated exactly from panel to panel.  A time inside
the pulse is its panel's state propagated to it plus the quadrature over the
partial panel.  Quadrature rather than the closed forms (complex error
functions for the gaussian, exponentials for the rect) because those are
differences over the two roots lambda_+-, which cancel catastrophically near
critical damping; the quadrature has no such regime.

Cost model (J times, N modes, R output rows: 2 for ``"ends"``, N for
``"all"``).  Free response after the kick, displacement or pulse: N J
exponentials, cosines and sines, plus two (J x N) @ (N x R) products,
evaluated in blocks of about 4 M elements (32 MB); without losses the
``"ends"`` rows use :func:`lcchain.theory.modes.cosine_sum`.  A pulse adds 16 N P
for the P panels and 16 N J_in for the J_in times inside the pulse.
Measured (2 cores, ``"ends"``, J = 20000 on [0, 3N], any effect): N = 100
takes 0.1-0.3 s, N = 1000 about 2 s; ``"all"`` at N = 1000 about 4 s.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ..core.blas import fixed_blas_threads
from ..core.checks import pulse as check_pulse
from ..core.checks import real, time_array
from ..core.errors import ParameterError
from ..core.frozen import FrozenArrays
from ..core.limits import EXACT_MAX_N
from ..core.types import EXCITATION_KINDS, GAUSSIAN_CENTRE, PROBES, PULSE_SHAPES, ExcitationKind, Probes, PulseShape
from .chain import Chain
from .exact import coupled_vectors, diagonalise, exact_modes, modal_weights
from .modes import Modes, cosine_sum

__all__ = [
    "ResponseExcitation",
    "PulseShape",
    "Loops",
    "RESPONSE_EXCITATIONS",
    "PULSE_SHAPES",
    "LOOPS",
    "GAUSSIAN_CENTRE",
    "GAUSSIAN_SPAN",
    "linear_response",
    "prepare_response",
    "Response",
    "loop_weights",
    "pulse_end",
]

#: What sets loop 1 in motion: an initial current or charge, or a voltage pulse.
ResponseExcitation = ExcitationKind
#: Which loops to return: loops 1 and N, or every loop.
Loops = Probes

RESPONSE_EXCITATIONS: tuple[str, ...] = EXCITATION_KINDS
LOOPS: tuple[str, ...] = PROBES

#: Its tail is dropped beyond GAUSSIAN_SPAN standard deviations after the centre (weight exp(-72)).
GAUSSIAN_SPAN = 12.0

_BLOCK = 1 << 22  # elements per temporary block (32 MB of float64)


@functools.cache
def _gauss() -> tuple[np.ndarray, np.ndarray]:
    """The 16 Gauss-Legendre nodes and weights on [-1, 1], made on first use: ``numpy.polynomial`` is 10 ms of
    the start of a command that never integrates a pulse (a batch of foreign netlists)."""
    from numpy.polynomial.legendre import leggauss

    nodes, weights = leggauss(16)
    return nodes, weights


# Panel length times the fastest rate max|lambda|: with 16 nodes the quadrature
# error of an exponential on such a panel is ~ (1.5)^32 / 32! ~ 1e-31.
_PANEL_RATE = 3.0


# ----------------------------------------------------------------- validation
def _check_positive(name: str, value: object, allowed: str) -> float:
    return real(name, value, above=0.0, allowed=allowed)


def pulse_end(shape: PulseShape, width: float) -> float:
    """Time after which the pulse g(t) is over (units of sqrt(L0*C0)).

    ``width`` for the rect; (4 + 12) ``width`` for the gaussian, whose tail
    beyond 12 standard deviations after its centre weighs exp(-72) ~ 5e-32.
    """
    return width if shape == "rect" else (GAUSSIAN_CENTRE + GAUSSIAN_SPAN) * width


def _pulse_shape(shape: str, width: float, t: np.ndarray) -> np.ndarray:
    """g(t) on the quadrature nodes (all inside (0, pulse_end))."""
    if shape == "rect":
        return np.full(t.shape, 1.0 / width)
    z = (t - GAUSSIAN_CENTRE * width) / width
    return np.exp(-0.5 * z * z) / (width * math.sqrt(2.0 * math.pi))


# ------------------------------------------------------------- mode functions
def _basis(omega: np.ndarray, gamma: float, tau: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """X = exp(-gamma tau/2) sin(Omega tau)/Omega and Y = exp(-gamma tau/2) cos(Omega tau).

    Shape (tau.size, omega.size).  For overdamped modes (omega < gamma/2)
    the same functions with Omega = i kappa, sinh and cosh, written as
    exp(lambda_+ tau) times expm1 terms so that nothing overflows or cancels.
    Then s = X, s' = Y - (gamma/2) X and c = Y + (gamma/2) X.
    """
    return _ModeFunctions.of(omega, gamma).basis(np.asarray(tau, dtype=float).ravel())


@dataclass(frozen=True, eq=False)
class _ModeFunctions:
    """What :func:`_basis` needs of omega and gamma, found once: which modes are underdamped (omega >= gamma/2),
    their Omega = sqrt(omega^2 - gamma^2/4) (without cancelling), which of them are critical (Omega = 0), and the
    overdamped ones' kappa and slow rate lambda_+ = -gamma/2 + kappa."""

    half: float
    under: np.ndarray
    big: np.ndarray
    critical: np.ndarray | None
    kappa: np.ndarray
    slow: np.ndarray

    @classmethod
    def of(cls, omega: np.ndarray, gamma: float) -> _ModeFunctions:
        half = 0.5 * gamma
        under = omega >= half
        w = omega[under]
        big = np.sqrt((w - half) * (w + half))  # Omega, without cancelling omega^2 - gamma^2/4
        critical = big == 0.0
        v = omega[~under]
        kappa = np.sqrt((half - v) * (half + v))
        slow = -(v * v) / (half + kappa)  # lambda_+ = -gamma/2 + kappa, without cancellation
        return cls(half, under, big, critical if bool(np.any(critical)) else None, kappa, slow)

    def basis(self, tau: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(X, Y) at the times ``tau`` (a float vector), shape (tau.size, modes)."""
        under, half = self.under, self.half
        sine = cosine = None
        if bool(under.any()):
            phase = np.multiply.outer(tau, self.big)
            decay = np.exp(-half * tau)[:, None]
            cosine = np.cos(phase)
            sine = np.sin(phase)
            with np.errstate(divide="ignore", invalid="ignore"):
                sine /= self.big
            if self.critical is not None:  # sin(Omega t)/Omega -> t
                sine[:, self.critical] = tau[:, None]
            sine *= decay
            cosine *= decay
            if bool(under.all()):  # the usual case: no copies into X and Y
                return sine, cosine
        X = np.empty((tau.size, under.size))
        Y = np.empty((tau.size, under.size))
        if sine is not None and cosine is not None:
            X[:, under] = sine
            Y[:, under] = cosine
        over = ~under
        base = np.exp(np.multiply.outer(tau, self.slow))
        em = np.expm1(np.multiply.outer(tau, -2.0 * self.kappa))  # exp(-2 kappa tau) - 1
        X[:, over] = base * (-em / (2.0 * self.kappa))
        Y[:, over] = base * (1.0 + 0.5 * em)
        return X, Y


def _rows(product: Callable[..., np.ndarray], alone: bool, *operands: np.ndarray) -> np.ndarray:
    """``product(*operands)``, or with ``alone`` the results of ``product`` on each row k of the operands
    (``operand[k : k + 1]``) stacked: a matrix product of one row at a time adds in the order a call with that one
    time does (BLAS's matrix-vector kernel), which the product of several rows need not (its matrix-matrix
    kernel)."""
    if not alone:
        return product(*operands)
    return np.vstack([product(*(operand[k : k + 1] for operand in operands)) for k in range(operands[0].shape[0])])


def _modal_sum(weights: np.ndarray, p: np.ndarray, q: np.ndarray, omega: np.ndarray, gamma: float,
               tau: np.ndarray, alone: bool = False) -> np.ndarray:
    """sum_n weights[n, r] (p_n Y_n(tau) + q_n X_n(tau)), shape (R, tau.size), in blocks; with ``alone`` each
    time's sum as a call with that time alone computes it (:func:`_rows`)."""
    out = np.empty((weights.shape[1], tau.size))
    wp = weights * p[:, None]
    wq = weights * q[:, None]
    use_q = bool(np.any(q != 0.0))
    rows = max(1, _BLOCK // max(omega.size, 1))
    for start in range(0, tau.size, rows):
        block = tau[start : start + rows]
        if use_q:
            X, Y = _basis(omega, gamma, block)
            out[:, start : start + rows] = _rows(lambda y, x: y @ wp + x @ wq, alone, Y, X).T
        else:
            _, Y = _basis(omega, gamma, block)
            out[:, start : start + rows] = _rows(lambda y: y @ wp, alone, Y).T
    return out


# --------------------------------------------------------------------- pulses
def _pulse_states(omega: np.ndarray, gamma: float, shape: str,
                  width: float) -> tuple[np.ndarray, float, np.ndarray, np.ndarray]:
    """Mode states (x, x') at the panel edges b_0 = 0 < ... < b_P = pulse end.

    Returns the edges, the panel length and arrays x, x' of shape (P+1, N).
    """
    half = 0.5 * gamma
    end = pulse_end(shape, width)  # type: ignore[arg-type]
    rate = max(float(np.max(omega)) if omega.size else 0.0, gamma)
    length = width if rate == 0.0 else min(width, _PANEL_RATE / rate)
    panels = max(1, math.ceil(end / length * (1.0 - 1e-12)))
    edges = np.linspace(0.0, end, panels + 1)
    step = end / panels
    # the same propagator and node functions serve every panel
    Xs, Ys = _basis(omega, gamma, np.array([step]))
    Xs, Ys = Xs[0], Ys[0]
    nodes, node_weights = _gauss()
    Xn, Yn = _basis(omega, gamma, 0.5 * step * (1.0 - nodes))  # s, at t_end - t' for each node t'
    Vn = Yn - half * Xn
    x = np.zeros((panels + 1, omega.size))
    v = np.zeros((panels + 1, omega.size))
    w2 = omega * omega
    for k in range(panels):
        gw = 0.5 * step * node_weights * _pulse_shape(shape, width, edges[k] + 0.5 * step * (1.0 + nodes))
        x[k + 1] = (Ys + half * Xs) * x[k] + Xs * v[k] + gw @ Xn
        v[k + 1] = -w2 * Xs * x[k] + (Ys - half * Xs) * v[k] + gw @ Vn
    return edges, step, x, v


def _pulse_inside(weights: np.ndarray, omega: np.ndarray, gamma: float, shape: str, width: float,
                  edges: np.ndarray, step: float, x: np.ndarray, v: np.ndarray, times: np.ndarray,
                  alone: bool = False) -> np.ndarray:
    """Velocity rows at times inside the pulse, shape (R, times.size); ``alone`` as :func:`_modal_sum`'s."""
    half = 0.5 * gamma
    w2 = omega * omega
    nodes, node_weights = _gauss()
    out = np.empty((weights.shape[1], times.size))
    panel = np.clip(np.floor(times / step).astype(int), 0, edges.size - 2)
    rows = max(1, _BLOCK // max(omega.size * (nodes.size + 1), 1))
    for start in range(0, times.size, rows):
        t = times[start : start + rows]
        k = panel[start : start + rows]
        delta = t - edges[k]
        X, Y = _basis(omega, gamma, delta)
        velocity = -w2 * X * x[k] + (Y - half * X) * v[k]
        # quadrature over [b_k, t]: nodes t' = b_k + delta (1 + x_i)/2, lag t - t' = delta (1 - x_i)/2
        lag = np.multiply.outer(delta, 0.5 * (1.0 - nodes))
        source = _pulse_shape(shape, width, edges[k][:, None] + np.multiply.outer(delta, 0.5 * (1.0 + nodes)))
        gw = 0.5 * delta[:, None] * node_weights * source
        Xn, Yn = _basis(omega, gamma, lag)
        Vn = (Yn - half * Xn).reshape(t.size, nodes.size, omega.size)
        velocity += _rows(lambda g, u: np.einsum("jn,jnm->jm", g, u), alone, gw, Vn)
        out[:, start : start + rows] = _rows(lambda u: u @ weights, alone, velocity).T
    return out


# ---------------------------------------------------------------------- modes
@fixed_blas_threads
def loop_weights(chain: Chain, *, force: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """Frequencies omega_n and every loop's weights sqrt(m_1/m_i) U_ni U_n1, shape (N modes, N loops).

    Column i - 1 is loop i's modal weights in Eq. (1) of the module
    docstring (column 0 the mode density, column N - 1 the end-to-end
    transfer).  Needs every eigenvector: N <= EXACT_MAX_N.  With coupled
    neighbours the weights are u_in (M u_n)_1 for a start in loop 1, and
    u_in m_1 u_1n for a force on mass 1 (``force``), u the M-orthonormal modes
    (:mod:`lcchain.theory.exact`); without coupling the two agree.
    """
    if chain.N > EXACT_MAX_N:
        raise ParameterError("N", chain.N, f"N <= {EXACT_MAX_N} for every loop's response (loops='all')")
    if chain.coupled:
        omega, u = coupled_vectors(chain)
        return omega, (u * modal_weights(chain, u, force=force)).T
    omega, U = diagonalise(chain)
    scale = np.sqrt(chain.masses[0] / chain.masses)
    weights = (U * U[0, :]).T * scale[None, :]
    return omega, weights


# ------------------------------------------------------------------ response
@fixed_blas_threads
def linear_response(
    chain: Chain,
    t: ArrayLike,
    *,
    excitation: ResponseExcitation = "kick",
    Q: float | None = None,
    pulse: tuple[PulseShape, float] | None = None,
    loops: Loops = "ends",
    modes: Modes | None = None,
) -> np.ndarray:
    """Exact response of the chain's loops to a kick, displacement or pulse, with losses.

    Eq. (1) of the module docstring: loop i is
    sqrt(m_1/m_i) sum_n U_ni U_n1 h_n(t); without losses and for a kick or
    a displacement this is the transmission amplitude (i = N) and the
    return amplitude (i = 1) of Eq. e.utn.

    Parameters
    ----------
    chain : Chain
        Any chain (walls, free ends, asymmetric, rounded or toleranced
        values), masses and springs in bulk units.
    t : array_like of float, shape (J,)
        Times >= 0 in units of sqrt(m/K) (in the circuit, sqrt(L0*C0)), in
        any order.
    excitation : {"kick", "displacement", "pulse"}
        ``"kick"``: Q_1'(0) = 1, output velocities (loop currents / I0).
        ``"displacement"``: Q_1(0) = 1, output positions (loop charges / Q0).
        ``"pulse"``: a force m_1 g(t) on mass 1 (a voltage L_1 I0 g(t) in
        loop 1), output velocities (currents / I0); needs ``pulse``.
    Q : float, optional
        Quality factor (> 0) of the series resistors R_i = L_i / (Q tau):
        every mode decays at the rate gamma = 1/Q (units of 1/tau).
        None: no losses.
    pulse : (shape, width), optional
        With ``excitation="pulse"`` only: ``"gaussian"`` (g of standard
        deviation ``width``, centred at 4 ``width``, zero before t = 0 and
        not renormalised, area 1 - Phi(-4)) or ``"rect"`` (1/width on
        [0, width)); ``width`` > 0 in units of tau.  As width -> 0 the
        response tends to the kick's (times the area).
    loops : {"ends", "all"}
        ``"ends"``: rows (loop 1, loop N); ``"all"``: every loop 1..N (this
        diagonalises the chain fully, N x N eigenvectors).
    modes : Modes, optional
        Modes of ``chain`` already computed (for ``"ends"``: omega, density
        U_n1^2 and transfer sqrt(m_1/m_N) U_n1 U_nN); default
        :func:`lcchain.theory.exact.exact_modes`.  Ignored for ``"all"``, which
        needs every eigenvector.

    Returns
    -------
    ndarray, shape (2, J) or (N, J)
        Dimensionless responses at the times ``t``.

    Raises
    ------
    ParameterError
        For an unknown excitation, shape or loops, Q <= 0, width <= 0, a
        pulse without ``excitation="pulse"`` (or the reverse), negative or
        non-finite times, or modes of another chain.
    """
    times = time_array("t", t)
    return prepare_response(chain, excitation=excitation, Q=Q, pulse=pulse, loops=loops, modes=modes)(times)


@dataclass(frozen=True, eq=False)
class _FreeSum:
    """sum_n weights[n, r] (p_n Y_n(tau) + q_n X_n(tau)) at tau = t - start, one time a row, as :func:`_modal_sum`
    computes it (``alone``) on the same arrays: the same bits, without its checks and temporaries (one block of
    times), the mode functions' constants found once."""

    start: float
    functions: _ModeFunctions
    wp: np.ndarray
    wq: np.ndarray
    use_q: bool

    def each(self, times: np.ndarray) -> np.ndarray:
        tau = np.asarray(times - self.start if self.start else times, dtype=float).ravel()
        X, Y = self.functions.basis(tau)
        if not self.use_q:
            return np.vstack([Y[k : k + 1] @ self.wp for k in range(tau.size)]).T
        return np.vstack([Y[k : k + 1] @ self.wp + X[k : k + 1] @ self.wq for k in range(tau.size)]).T


@dataclass(frozen=True, eq=False)
class Response(FrozenArrays):
    """:func:`linear_response` of one circuit, prepared once and evaluated at any times.

    Everything that does not depend on the times -- the modes' weights and,
    for a pulse, the mode states at the panel edges -- is computed by
    :func:`prepare_response`; calling the object evaluates the response at
    the times given, exactly as :func:`linear_response` would (the same
    operations on the same arrays: the same bits).  A peak search evaluates
    one circuit at a time some 75 times, where the pulse's states cost ten
    times the evaluation.

    Attributes
    ----------
    omega : ndarray, shape (N,)
        Mode frequencies.
    weights : ndarray, shape (N, R)
        Each returned loop's modal weights.
    gamma : float
        The damping rate 1/Q (0 without losses).
    excitation : {"kick", "displacement", "pulse"}
    pulse : (shape, width) or None
    edges, step, x, v : ndarray, float, ndarray, ndarray, or None
        A pulse's panel edges, panel length and mode states (x, x') at the
        edges (``_pulse_states``).
    cosines : (ndarray, ndarray) or None
        A lossless kick or displacement at the ends: the mode density and
        transfer, summed by :func:`lcchain.theory.modes.cosine_sum`.
    """

    omega: np.ndarray
    weights: np.ndarray
    gamma: float
    excitation: ResponseExcitation
    pulse: tuple[str, float] | None = None
    edges: np.ndarray | None = None
    step: float = 0.0
    x: np.ndarray | None = None
    v: np.ndarray | None = None
    cosines: tuple[np.ndarray, np.ndarray] | None = None

    @fixed_blas_threads
    def __call__(self, t: ArrayLike) -> np.ndarray:
        """The response at times ``t`` (array_like, shape (J,), >= 0): shape (R, J)."""
        return self._evaluate(time_array("t", t), alone=False)

    @fixed_blas_threads
    def each(self, t: ArrayLike) -> np.ndarray:
        """The response at each of the times ``t`` as a call with that time alone computes it, shape (R, J).

        The mode functions of all the times at once, the sums over the modes one time at a time: the values of
        ``self([t_j])`` to the bit, for the cost of about one call (a peak search's searches side by side,
        :func:`lcchain.theory.arrivals.refine_maxima`).
        """
        times = time_array("t", t)
        if self.cosines is not None:
            return np.hstack([self._evaluate(times[k : k + 1], alone=False) for k in range(times.size)])
        free = self._free
        if free is not None and times.size * self.omega.size <= _BLOCK and bool(np.all(times >= free.start)):
            return free.each(times)
        return self._evaluate(times, alone=True)

    @functools.cached_property
    def _free(self) -> _FreeSum | None:
        """The free oscillation's sum made once (after a pulse, or a kick's or a displacement's from t = 0), for
        :meth:`each`: a peak search evaluates it some 40 times, one time a call, where the checks and the
        temporaries of the general path cost more than the sum (bench.toml: 6.8 of a sample's 7.2 ms beyond the
        theory at ngspice's points)."""
        if self.cosines is not None:
            return None
        start, p, q = self._free_state()
        return _FreeSum(start, _ModeFunctions.of(self.omega, self.gamma), self.weights * p[:, None],
                        self.weights * q[:, None], bool(np.any(q != 0.0)))

    def _free_state(self) -> tuple[float, np.ndarray, np.ndarray]:
        """Where the free oscillation starts (0, or the pulse's end) and its p, q: the response there is
        sum_n weights[n] (p_n Y_n(tau) + q_n X_n(tau)).  A kick's velocity s' = Y - (gamma/2) X, a displacement's
        position c = Y + (gamma/2) X; after a pulse, from the mode states at its end."""
        omega, gamma = self.omega, self.gamma
        if self.pulse is None or self.edges is None or self.x is None or self.v is None:
            ones = np.ones(omega.size)
            sign = -1.0 if self.excitation == "kick" else 1.0
            return 0.0, ones, sign * 0.5 * gamma * ones
        xT, vT = self.x[-1], self.v[-1]
        return float(self.edges[-1]), vT, -omega * omega * xT - 0.5 * gamma * vT

    def _evaluate(self, times: np.ndarray, alone: bool) -> np.ndarray:
        omega, weights, gamma = self.omega, self.weights, self.gamma
        if self.cosines is not None:
            # Eq. e.utn exactly as lcchain.modes evaluates it
            density, transfer = self.cosines
            return np.vstack([cosine_sum(density, omega, times), cosine_sum(transfer, omega, times)])
        end, p, q = self._free_state()
        if self.pulse is None or self.edges is None or self.x is None or self.v is None:
            return _modal_sum(weights, p, q, omega, gamma, times, alone)

        shape, width = self.pulse
        edges, step, x, v = self.edges, self.step, self.x, self.v
        out = np.empty((weights.shape[1], times.size))
        after = times >= end
        if np.any(after):  # free oscillation from the state at the end of the pulse
            out[:, after] = _modal_sum(weights, p, q, omega, gamma, times[after] - end, alone)
        if not np.all(after):
            inside = ~after
            out[:, inside] = _pulse_inside(weights, omega, gamma, shape, width, edges, step, x, v, times[inside],
                                           alone)
        return out


@fixed_blas_threads
def prepare_response(
    chain: Chain,
    *,
    excitation: ResponseExcitation = "kick",
    Q: float | None = None,
    pulse: tuple[PulseShape, float] | None = None,
    loops: Loops = "ends",
    modes: Modes | None = None,
) -> Response:
    """:func:`linear_response` of a circuit without its times: a :class:`Response` to call with them.

    Parameters and errors as :func:`linear_response`'s (but for ``t``).
    """
    if not isinstance(chain, Chain):
        raise ParameterError("chain", type(chain).__name__, "a lcchain.Chain")
    spec = check_pulse(excitation, pulse, RESPONSE_EXCITATIONS, PULSE_SHAPES)
    if Q is not None:
        Q = _check_positive("Q", Q, "None (no losses) or a finite quality factor > 0")
    if loops not in LOOPS:
        raise ParameterError("loops", loops, " | ".join(LOOPS))
    if modes is not None and not isinstance(modes, Modes):
        raise ParameterError("modes", type(modes).__name__, "None or the lcchain.modes.Modes of the chain")
    if modes is not None and modes.N != chain.N:
        raise ParameterError("modes", f"modes of N = {modes.N}", f"the modes of this chain (N = {chain.N})")
    gamma = 0.0 if Q is None else 1.0 / Q
    if chain.coupled and Q is not None:
        raise ParameterError("Q", Q, "no losses with coupled coils (coupling != 0): the series resistors' damping "
                             "is then not proportional to the mass matrix, and the modes do not decouple")

    cosines = None
    if loops == "all":
        omega, weights = loop_weights(chain, force=spec is not None)
    elif chain.coupled and spec is not None:
        # a force on mass 1 excites the modes by m_1 u_1n, not by the kick's (M u_n)_1
        omega, every = loop_weights(chain, force=True)
        weights = every[:, [0, chain.N - 1]]
    else:
        if modes is None:
            modes = exact_modes(chain)
        omega = np.asarray(modes.omega, dtype=float)
        weights = np.column_stack((modes.density, modes.transfer))
        if spec is None and gamma == 0.0:
            cosines = (modes.density, modes.transfer)
    if spec is None:
        return Response(omega, weights, gamma, excitation, cosines=cosines)
    shape, width = spec
    edges, step, x, v = _pulse_states(omega, gamma, shape, width)
    return Response(omega, weights, gamma, excitation, spec, edges, step, x, v)
