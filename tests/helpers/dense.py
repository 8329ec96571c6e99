"""An independent dense eigen-solution of a chain, for the spectrum tests (not lcchain's own modes)."""

from __future__ import annotations

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
