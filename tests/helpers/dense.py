"""An independent dense eigen-solution of a chain, for the spectrum tests (not lcchain's own modes)."""

from __future__ import annotations

from fractions import Fraction

import numpy as np
from scipy.linalg import eigh

from lcchain.theory.chain import Chain


def dense_modes(chain: Chain) -> tuple[np.ndarray, np.ndarray]:
    """Frequencies and P_n = m_1 u_1n u_Nn (M-orthonormal u) of K u = omega^2 M u from the full matrices
    (scipy.linalg.eigh; coupled coils put k sqrt(m_i m_i+1) beside M's diagonal)."""
    omega, u = dense_shapes(chain)
    return omega, chain.masses[0] * u[0] * u[-1]


def dense_shapes(chain: Chain) -> tuple[np.ndarray, np.ndarray]:
    """Frequencies and M-orthonormal shapes u (loops x modes) of K u = omega^2 M u, from the full matrices
    (scipy.linalg.eigh), each column's sign free."""
    m, K, k = chain.masses, chain.springs, chain.coupling
    mutual = k * np.sqrt(m[:-1] * m[1:])
    M = np.diag(m) + np.diag(mutual, 1) + np.diag(mutual, -1)
    S = np.diag(K[:-1] + K[1:]) - np.diag(K[1:-1], 1) - np.diag(K[1:-1], -1)
    squares, u = eigh(S, M)
    omega = np.sqrt(np.clip(squares, 0.0, None))
    if chain.is_free:
        omega[0] = 0.0
    return omega, u


def rational_admittance(chain: Chain, omega: float, Q: float) -> complex:
    """Y_11 Z0 = s [(s^2 + s/Q) M + K]^-1_11 at s = j omega in exact rational arithmetic
    (:func:`exact_admittance`), rounded once to complex."""
    real, imag = exact_admittance(chain, omega, Q)
    return complex(float(real), float(imag))


def exact_admittance(chain: Chain, omega: float, Q: float) -> tuple[Fraction, Fraction]:
    """Y_11 Z0 = s [(s^2 + s/Q) M + K]^-1_11 at s = j omega in exact rational arithmetic (fractions.Fraction, complex
    numbers as pairs), eliminating the tridiagonal from the far end: the float inputs taken as the exact rationals
    they are, no rounding at all (real and imaginary parts).  Independent of lcchain's own evaluation (float64, long
    double and double-double)."""

    def mul(a: tuple[Fraction, Fraction], b: tuple[Fraction, Fraction]) -> tuple[Fraction, Fraction]:
        return a[0] * b[0] - a[1] * b[1], a[0] * b[1] + a[1] * b[0]

    def inv(a: tuple[Fraction, Fraction]) -> tuple[Fraction, Fraction]:
        size = a[0] * a[0] + a[1] * a[1]
        return a[0] / size, -a[1] / size

    w, q = Fraction(omega), Fraction(Q)
    lam = (-w * w, w / q)  # s^2 + s/Q at s = j omega
    m = [Fraction(v) for v in chain.masses]
    K = [Fraction(v) for v in chain.springs]
    mutual = [Fraction(v) for v in chain.mass_matrix_bands()[1]]
    N = len(m)

    def diagonal(i: int) -> tuple[Fraction, Fraction]:
        return lam[0] * m[i] + K[i] + K[i + 1], lam[1] * m[i]

    def off(i: int) -> tuple[Fraction, Fraction]:  # entry (i, i + 1)
        return lam[0] * mutual[i] - K[i + 1], lam[1] * mutual[i]

    pivot = diagonal(N - 1)
    for i in range(N - 2, -1, -1):
        term = mul(mul(off(i), off(i)), inv(pivot))
        d = diagonal(i)
        pivot = (d[0] - term[0], d[1] - term[1])
    return mul((Fraction(0), w), inv(pivot))
