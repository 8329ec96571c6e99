"""The paper's closed form for the modes of a free quasi-uniform chain.

For the free chain with parameters (r, w) (Eq. e.rw; one-mass: r = 1,
w = x^2; uniform free: r = w = 1) the N pseudo wave vectors solve
Eq. e.kn1,

    N k_n + 2 psi(k_n) = pi (n - 1),      n = 1..N,

with the phase shift psi_k = arg u~_k of Eqs. e.tudef and e.psik, and the
mode density is Eq. e.Pk, including the factor 1/2 at k = 0 that
Eqs. e.PkDelta and e.Pk1 omit (without it the density does not sum to 1).
Frequencies are omega = 2 sin(k/2) (Eq. e.omegak).

Numerics
--------
* u~_k is evaluated in the factored form of Eq. e.tukz0,
  e^{3iq} u~_k = A(q) - i B(q) with q = k/2, which has no cancellation as
  k -> 0 even when w is tiny (long optimal chains).
* psi must be continuous in k (atan2 alone jumps by 2 pi where R_k < 0, which
  happens in the two-mass case).  The continuous branch comes from the
  factorisation u~(z) = prod_j (1 - rho_j z), z = e^{-ik}: each factor with
  |rho_j| < 1 has a continuous principal argument.  A root on or outside the
  unit circle means a mode outside the band (a localised end mode) that
  Eq. e.kn1 cannot describe; the closed form then refuses the chain.
* Eq. e.kn1 is solved for all n at once by a safeguarded Newton method
  (bracketed by a monotone interpolation table; a step leaving its bracket
  is replaced by bisection).  The paper's plain fixed-point iteration
  k <- (pi (n-1) - 2 psi(k)) / N diverges wherever 2 |psi'| > N.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from ..core.blas import fixed_blas_threads
from ..core.checks import integer, real
from ..core.errors import ParameterError
from ..core.limits import MAX_DESIGN_N
from .chain import Chain
from .modes import Modes

__all__ = ["closed_form_modes", "closed_form_applies", "phase_shift", "CLOSED_FORM_MIN_N_MODEL"]

#: The closed form is derived for the matrix of Eq. e.AN, valid for N >= 5.
CLOSED_FORM_MIN_N_MODEL = 5

_NEWTON_MAX_ITER = 80


def closed_form_applies(chain: Chain) -> str:
    """Return '' when the closed form covers the chain, else the reason it does not."""
    if chain.N < CLOSED_FORM_MIN_N_MODEL:
        return f"N >= {CLOSED_FORM_MIN_N_MODEL}"
    if chain.coupled:
        return "no coupling between neighbours"
    if not chain.is_free:
        return "free ends (K01 = 0)"
    if not chain.is_quasi_uniform():
        return "a symmetric quasi-uniform chain"
    r, w = chain.rw()
    if _roots_outside(r, w):
        return "no mode outside the band"
    return ""


def _u_roots(r: float, w: float) -> np.ndarray:
    """Roots rho_j with u~(z) = prod_j (1 - rho_j z), Eq. e.tudef."""
    a, b = 1.0 - w, 1.0 - r
    return np.roots([1.0, -a, -a * b, b])


def _roots_outside(r: float, w: float) -> bool:
    return bool(np.any(np.abs(_u_roots(r, w)) >= 1.0 - 1e-12))


def _ab(q: np.ndarray, r: float, w: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """A, B and their q-derivatives with e^{3iq} u~ = A - iB (Eq. e.tukz0)."""
    s, c = np.sin(q), np.cos(q)
    s2, c2 = s * s, c * c
    A = (2 - r) * (w - 4 * s2) * c
    B = r * (2 - w - 4 * c2) * s
    dA = (2 - r) * (-8 * s * c2 - (w - 4 * s2) * s)
    dB = r * (8 * c * s2 + (2 - w - 4 * c2) * c)
    return A, B, dA, dB


def phase_shift(k: ArrayLike, r: float, w: float) -> tuple[np.ndarray, np.ndarray]:
    """Continuous phase shift psi_k (Eq. e.psik) and its derivative psi'_k.

    Parameters
    ----------
    k : array_like
        Pseudo wave vectors in [0, pi].
    r, w : float
        Chain parameters (Eq. e.rw).

    Returns
    -------
    psi, dpsi : ndarray
        psi_k on the branch continuous from psi_0 = 0, and d psi / d k.
    """
    k = np.asarray(k, dtype=float)
    q = 0.5 * k
    A, B, dA, dB = _ab(q, r, w)
    # principal value: psi = -3q + arg(A - iB)
    principal = -3 * q + np.arctan2(-B, A)
    dpsi = -1.5 + 0.5 * (B * dA - A * dB) / (A * A + B * B)
    # continuous branch from the root factorisation (each |rho| < 1)
    rho = _u_roots(r, w)
    z = np.exp(-1j * k)
    continuous = np.zeros_like(k)
    for root in rho:
        continuous += np.angle((1 - root) + root * (1 - z)) - np.angle(1 - root)
    turns = np.round((continuous - principal) / (2 * np.pi))
    return principal + 2 * np.pi * turns, dpsi


def _density(k: np.ndarray, dpsi: np.ndarray, N: int, r: float, w: float) -> np.ndarray:
    """Mode density of Eqs. e.Uk1d / e.Pk with the halving at k = 0."""
    q = 0.5 * k
    A, B, _, _ = _ab(q, r, w)
    density = 2 * (2 - r) * r * w * np.cos(q) ** 2 / ((A * A + B * B) * (N + 2 * dpsi))
    density[k == 0] *= 0.5
    return np.asarray(density)


@fixed_blas_threads
def closed_form_modes(N: int, r: float, w: float) -> Modes:
    """Modes of the free quasi-uniform chain from the paper's closed form.

    Parameters
    ----------
    N : int
        Number of masses, >= 5 (the matrix of Eq. e.AN).
    r, w : float
        Parameters of Eq. e.rw (one-mass chain: r = 1, w = x^2).

    Returns
    -------
    Modes
        With ``k`` set; ``transfer = (-1)^(n-1) P_n`` by mirror symmetry.

    Raises
    ------
    ParameterError
        If the chain has a mode outside the band, or Eq. e.kn1 is not
        monotone in k (then it has no unique solution for every n).
    """
    N = integer("N", N, at_least=CLOSED_FORM_MIN_N_MODEL, at_most=MAX_DESIGN_N,
                allowed=f"an integer from {CLOSED_FORM_MIN_N_MODEL} to {MAX_DESIGN_N} for the closed form (Eq. e.AN)")
    r, w = real("r", r, allowed="a finite real number"), real("w", w, allowed="a finite real number")
    if _roots_outside(r, w):
        raise ParameterError("(r, w)", (r, w), "parameters without a localised mode outside the band (closed form)")

    rho = _u_roots(r, w)

    def phi(k: np.ndarray, turns: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        """Phi(k) = N k + 2 psi_k and its slope; ``turns`` fixes the branch."""
        q = 0.5 * k
        A, B, dA, dB = _ab(q, r, w)
        psi = -3 * q + np.arctan2(-B, A)
        if turns is not None:
            psi = psi + 2 * np.pi * turns
        return N * k + 2 * psi, N + (B * dA - A * dB) / (A * A + B * B) - 3.0

    def branch(k: np.ndarray) -> np.ndarray:
        """Whole turns between atan2's principal value and the continuous psi_k."""
        A, B, _, _ = _ab(0.5 * k, r, w)
        principal = -3 * (0.5 * k) + np.arctan2(-B, A)
        continuous = np.zeros_like(k)
        z = np.exp(-1j * k)
        for root in rho:
            continuous += np.angle((1 - root) + root * (1 - z)) - np.angle(1 - root)
        return np.asarray(np.round((continuous - principal) / (2 * np.pi)))

    # Monotone table of Phi(k) on a grid, for brackets and starting points.
    grid = np.linspace(0.0, math.pi, min(4 * N, 1 << 15) + 1)
    table, slope = phi(grid, branch(grid))
    if np.any(np.diff(table) <= 0) or np.any(slope <= 0):
        raise ParameterError("(r, w)", (r, w), "parameters for which Eq. e.kn1 is monotone in k (closed form)")
    target = math.pi * np.arange(1, N)  # n = 2..N; k_1 = 0 exactly
    j = np.clip(np.searchsorted(table, target) - 1, 0, grid.size - 2)
    lo, hi = grid[j].copy(), grid[j + 1].copy()
    k = np.interp(target, table, grid)
    for _ in range(_NEWTON_MAX_ITER):
        value, derivative = phi(k, branch(k))
        residual = value - target
        below = residual < 0
        lo = np.where(below, k, lo)
        hi = np.where(below, hi, k)
        new = k - residual / derivative
        outside = (new < lo) | (new > hi)
        new = np.where(outside, 0.5 * (lo + hi), new)
        settled = np.all(np.abs(new - k) <= 4 * np.finfo(float).eps * np.maximum(k, 1e-300))
        k = new
        if settled:
            break
    else:  # pragma: no cover - the safeguarded iteration always converges
        raise ParameterError("(r, w)", (r, w), "parameters for which Eq. e.kn1 converges")
    if np.any(np.diff(k) <= 0) or k[0] <= 0 or k[-1] >= math.pi:
        raise ParameterError("(r, w)", (r, w), "parameters with N distinct modes in the band (closed form)")
    k = np.concatenate(([0.0], k))
    _, dpsi = phase_shift(k, r, w)
    density = _density(k, dpsi, N, r, w)
    sign = np.where(np.arange(N) % 2 == 0, 1.0, -1.0)
    omega = 2 * np.sin(0.5 * k)
    return Modes(omega, density, sign * density, "closed-form", k=k)
