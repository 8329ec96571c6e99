"""Exact normal modes: the matrix B of Eq. e.BN diagonalised by LAPACK.

B = M^(-1/2) K M^(-1/2) is built from the physical masses and springs, so it is
right for every N and every chain, symmetric or not (the (x, y, z) matrix of
Eq. e.AN holds for N >= 5 only).
"""

from __future__ import annotations

import numpy as np
from scipy.linalg import eigh_tridiagonal

from ..core.blas import fixed_blas_threads
from ..core.errors import ParameterError
from ..core.limits import EXACT_MAX_N
from .chain import Chain
from .modes import Modes

__all__ = ["tridiagonal", "diagonalise", "exact_modes", "EXACT_MAX_N"]


def tridiagonal(chain: Chain) -> tuple[np.ndarray, np.ndarray]:
    """Diagonal and off-diagonal of B (Eq. e.BN) in bulk units."""
    m, K = chain.masses, chain.springs
    diagonal = (K[:-1] + K[1:]) / m
    off = -K[1:-1] / np.sqrt(m[:-1] * m[1:])
    return diagonal, off


@fixed_blas_threads
def diagonalise(chain: Chain) -> tuple[np.ndarray, np.ndarray]:
    """Frequencies omega_n (ascending) and eigenvectors U (columns) of B (Eq. e.BN), LAPACK.

    Every eigenvector: 8 N^2 bytes, callers bound N (:data:`EXACT_MAX_N`).
    """
    diagonal, off = tridiagonal(chain)
    mu, U = eigh_tridiagonal(diagonal, off)
    # A free chain has mu_1 = 0 up to rounding (possibly -1e-16): clip, never NaN.
    omega = np.sqrt(np.clip(mu, 0.0, None))
    if chain.is_free:
        # The translation (Goldstone) mode is exactly zero; LAPACK returns
        # mu_1 ~ 1e-16, whose square root (1e-8) would be a spurious frequency.
        omega[0] = 0.0
    return omega, U


@fixed_blas_threads
def exact_modes(chain: Chain) -> Modes:
    """Diagonalise B exactly (LAPACK, symmetric tridiagonal).

    Parameters
    ----------
    chain : Chain
        Any chain, symmetric or not, with N <= :data:`EXACT_MAX_N`.
    """
    if chain.N > EXACT_MAX_N:
        raise ParameterError(
            "N", chain.N,
            f"N <= {EXACT_MAX_N} for exact diagonalisation (use the closed form for quasi-uniform free chains)",
        )
    omega, U = diagonalise(chain)
    first, last = U[0, :], U[-1, :]
    density = first * first
    transfer = np.sqrt(chain.masses[0] / chain.masses[-1]) * first * last
    return Modes(omega, density, transfer, "exact")


