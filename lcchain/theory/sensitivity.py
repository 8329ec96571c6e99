"""Sensitivity of the first-arrival peak to every mass and spring, by eigen-perturbation.

The first arrival's peak p = alpha_N(t*) (:func:`lcchain.theory.arrivals.first_arrival`) is a maximum in
time, so to first order moving a mass or a spring moves p only through alpha_N at the fixed time t*
(the envelope theorem: d alpha_N / dt = 0 there):

    dp = d alpha_N(t*).

After a kick of mass 1, Q'(0) = e_1, the velocities are Q'(t) = cos(t sqrt(A)) e_1 with A = M^-1 K, so
alpha_N(t) = e_N^T f(A) e_1, f(lambda) = cos(t sqrt(lambda)).  With the M-orthonormal modes u of
K u = omega^2 M u (A = u Lambda u^T M), the derivative of a matrix function (Daleckii-Krein) gives

    d alpha_N = sum_{k,n} u_Nk F_kn b_n [u^T dK u - (u^T dM u) Lambda]_kn,

b_n = (M u_n)_1, F_kn the divided difference (f(lambda_k) - f(lambda_n)) / (lambda_k - lambda_n), written
without cancellation as -(t^2/2) sinc(t (omega_k + omega_n)/2) sinc(t (omega_k - omega_n)/2) (its diagonal is
f'(lambda_n)).  A spring K_j (between masses j and j+1, walls j = 0 and N) adds d d^T to K, d = e_j - e_{j+1};
a mass m_i adds e_i e_i^T to M (and, with coupled coils, half of each off-diagonal k sqrt(m_i m_{i+1}) over m_i).
With T = u W u^T and S = u (W Lambda) u^T, W_kn = F_kn u_Nk b_n, every derivative is a few entries of the two
N x N matrices: all 2N + 1 of them cost four N x N products, O(N^3), like one eigen-solution.

Scaling every mass (or every spring) by the same factor only rescales time, so the relative sensitivities
m_i dp/dm_i sum to 0, and so do K_j dp/dK_j: a check that needs no finite differences.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..core.blas import fixed_blas_threads
from ..core.errors import ParameterError
from ..core.frozen import FrozenArrays
from ..core.limits import COUPLED_MAX_N
from .arrivals import first_arrival
from .chain import Chain
from .exact import coupled_vectors, diagonalise, modal_weights
from .modes import Modes

__all__ = ["PeakSensitivity", "peak_sensitivity", "energy_fraction", "SENSITIVITY_MAX_N", "modal_basis",
           "sensitivity_at", "stationary_time"]

#: Largest chain whose sensitivities are computed: every eigenvector and four dense N x N products.
SENSITIVITY_MAX_N = COUPLED_MAX_N


def energy_fraction(peak: float, chain: Chain) -> float:
    """The fraction of the kick's energy the last mass holds at the peak: p^2 m_N / m_1."""
    return peak**2 * float(chain.masses[-1] / chain.masses[0])


@dataclass(frozen=True, eq=False)
class PeakSensitivity(FrozenArrays):
    """The first-arrival peak of a kicked chain and its derivatives (bulk units).

    Attributes
    ----------
    chain : Chain
    time : float
        t* of the peak, units of sqrt(m/K).
    peak : float
        p = alpha_N(t*).
    masses : ndarray, shape (N,)
        dp/dm_i, per bulk mass.
    springs : ndarray, shape (N+1,)
        dp/dK_j (j = 0..N, walls first and last), per bulk spring; a free end's entry is the effect of a
        small wall spring added there.
    """

    chain: Chain
    time: float
    peak: float
    masses: np.ndarray
    springs: np.ndarray

    def __post_init__(self) -> None:
        self._freeze_arrays()

    @property
    def relative_masses(self) -> np.ndarray:
        """dp/d ln m_i = m_i dp/dm_i (= dp/d ln L_i)."""
        return np.asarray(self.chain.masses * self.masses)

    @property
    def relative_springs(self) -> np.ndarray:
        """dp/d ln K_j = K_j dp/dK_j (= -dp/d ln C_j); 0 at a free end."""
        return np.asarray(self.chain.springs * self.springs)

    @property
    def energy(self) -> float:
        """The energy fraction the last mass holds at the peak, e = p^2 m_N / m_1."""
        return energy_fraction(self.peak, self.chain)

    @property
    def energy_relative_masses(self) -> np.ndarray:
        """de/d ln m_i = e (2 dp/d ln m_i / p + [i = N] - [i = 1])."""
        ends = np.zeros(self.chain.N)
        ends[-1] += 1.0
        ends[0] -= 1.0
        return np.asarray(self.energy * (2.0 * self.relative_masses / self.peak + ends))

    @property
    def energy_relative_springs(self) -> np.ndarray:
        """de/d ln K_j = 2 e dp/d ln K_j / p."""
        return np.asarray(self.energy * 2.0 * self.relative_springs / self.peak)


def modal_basis(chain: Chain) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """omega, the M-orthonormal modes u (columns) and b_n = (M u_n)_1."""
    if chain.coupled:
        omega, u = coupled_vectors(chain)
    else:
        omega, U = diagonalise(chain)
        u = U / np.sqrt(chain.masses)[:, None]  # B = M^-1/2 K M^-1/2: u = M^-1/2 U
    return omega, u, modal_weights(chain, u)


def stationary_time(weights: np.ndarray, omega: np.ndarray, t: float) -> float:
    """The peak time polished by Newton steps on alpha_N'(t) = 0: the envelope theorem needs the derivative
    zero to rounding, where the peak search stops at 1e-10 in time (its residual slope showed as a 3e-8 sum of
    the relative sensitivities, which the scaling identity makes 0)."""
    for _ in range(3):
        slope = -np.sum(weights * omega * np.sin(omega * t))
        curvature = -np.sum(weights * omega * omega * np.cos(omega * t))
        if curvature >= 0.0:  # not a maximum: keep the search's time
            break
        t -= slope / curvature
    return float(t)


@fixed_blas_threads
def peak_sensitivity(chain: Chain) -> PeakSensitivity:
    """The first-arrival peak after a kick and its derivative with respect to every mass and spring.

    Parameters
    ----------
    chain : Chain
        Any chain (walls, free ends, asymmetric, coupled coils), N <= :data:`SENSITIVITY_MAX_N`.

    Returns
    -------
    PeakSensitivity
        dp/dm_i and dp/dK_j from eigen-perturbation at the peak time (module docstring); in the LC ladder
        L_i = m_i L0 and C_j = C0 / K_j, so dp/dL_i = (dp/dm_i) / L0 and dp/dC_j = -(K_j / C_j) dp/dK_j.

    Raises
    ------
    ParameterError
        A chain beyond :data:`SENSITIVITY_MAX_N` masses.
    """
    if not isinstance(chain, Chain):
        raise ParameterError("chain", type(chain).__name__, "a lcchain.Chain")
    if chain.N > SENSITIVITY_MAX_N:
        raise ParameterError("N", chain.N, f"N <= {SENSITIVITY_MAX_N} for sensitivities (every eigenvector and "
                             "dense N x N products, O(N^3))")
    omega, u, b = modal_basis(chain)
    transfer = u[-1, :] * b
    arrival = first_arrival(Modes(omega, u[0, :] * b, transfer, "exact"))
    if min(arrival.time - arrival.window[0], arrival.window[1] - arrival.time) <= 1e-9 * arrival.time:
        # at an edge of its window the peak is no stationary point: the envelope theorem does not hold
        raise ParameterError("chain", repr(chain), "a chain whose first arrival peaks inside its search window "
                             f"{arrival.window} (this one's largest value is at its edge, t = {arrival.time:.6g})")
    return sensitivity_at(chain, omega, u, b, stationary_time(transfer, omega, arrival.time))


def sensitivity_at(chain: Chain, omega: np.ndarray, u: np.ndarray, b: np.ndarray, t: float) -> PeakSensitivity:
    """The derivatives of alpha_N at a stationary peak time t, from the chain's modes (module docstring).

    Parameters
    ----------
    chain : Chain
    omega, u, b : ndarray
        From :func:`modal_basis`: frequencies, M-orthonormal modes (columns) and b_n = (M u_n)_1.
    t : float
        The peak time, where d alpha_N / dt = 0 (to rounding: the envelope theorem needs it).
    """
    transfer = u[-1, :] * b
    # F_kn = (cos(t omega_k) - cos(t omega_n)) / (omega_k^2 - omega_n^2), without cancellation
    total = 0.5 * t * np.add.outer(omega, omega)
    half = 0.5 * t * np.subtract.outer(omega, omega)
    F = -0.5 * t * t * np.sinc(total / np.pi) * np.sinc(half / np.pi)
    W = F * np.outer(u[-1, :], b)
    T = u @ W @ u.T
    S = u @ (W * (omega * omega)[None, :]) @ u.T
    # springs: d = e_j - e_{j+1} between masses j and j+1 (1-based; a wall's d has one entry)
    diag_T = np.diag(T)
    cross = np.diag(T, 1) + np.diag(T, -1)
    springs = np.concatenate(([diag_T[0]], diag_T[:-1] + diag_T[1:] - cross, [diag_T[-1]]))
    # masses: dM = e_i e_i^T, and with coupled coils d M_{i,i+1} / d m_i = M_{i,i+1} / (2 m_i)
    masses = -np.diag(S).copy()
    if chain.coupled:
        _, off = chain.mass_matrix_bands()
        pair = off * (np.diag(S, 1) + np.diag(S, -1)) / 2.0
        masses[:-1] -= pair / chain.masses[:-1]
        masses[1:] -= pair / chain.masses[1:]
    peak = float(np.sum(transfer * np.cos(omega * t)))
    return PeakSensitivity(chain, t, peak, masses, springs)
