"""Exact normal modes: the matrix B of Eq. e.BN diagonalised by LAPACK.

B = M^(-1/2) K M^(-1/2) is built from the physical masses and springs, so it is
right for every N and every chain, symmetric or not (the (x, y, z) matrix of
Eq. e.AN holds for N >= 5 only).

Coupled neighbours (``Chain.coupling`` k != 0, in the circuit mutual
inductance between neighbouring coils) make the mass matrix M tridiagonal,
M_{i,i+1} = k sqrt(m_i m_{i+1}); the modes then solve the generalised problem
K u = omega^2 M u with M-orthonormal u (u^T M u = 1), by LAPACK's dense
symmetric-definite solver (``scipy.linalg.eigh(K, M)``, O(N^3): N is bounded by
:data:`COUPLED_MAX_N`).  An initial current (or charge) e_1 in loop 1 has the
modal amplitudes a_n = (M u_n)_1 and loop i moves as sum_n u_in a_n cos(omega_n t);
a force on mass 1 (a voltage in loop 1) has the amplitudes m_1 u_1n instead.
Without coupling both are m_1 u_1n = sqrt(m_1) U_1n, and the weights are those
of Eq. e.utn.
"""

from __future__ import annotations

import decimal
import math

import numpy as np

from ..core.blas import fixed_blas_threads
from ..core.errors import ParameterError
from ..core.limits import COUPLED_MAX_N, EXACT_MAX_N
from .chain import Chain
from .modes import WEIGHT_PRECISION, Modes
from .reference import certify_frequencies, coupled_reference, lapack_bounds, transfer_weights

__all__ = ["tridiagonal", "diagonalise", "sharp_frequencies", "sharp_frequencies_extended", "exact_modes",
           "driven_modes", "coupled_vectors",
           "modal_weights", "perfect_weights", "is_free_perfect", "perfect_walls", "EXACT_MAX_N", "COUPLED_MAX_N"]


def tridiagonal(chain: Chain) -> tuple[np.ndarray, np.ndarray]:
    """Diagonal and off-diagonal of B (Eq. e.BN) in bulk units."""
    m, K = chain.masses, chain.springs
    diagonal = (K[:-1] + K[1:]) / m
    off = -K[1:-1] / np.sqrt(m[:-1] * m[1:])
    return diagonal, off


@fixed_blas_threads
def diagonalise(chain: Chain) -> tuple[np.ndarray, np.ndarray]:
    """Frequencies omega_n (ascending) and eigenvectors U (columns) of B (Eq. e.BN), LAPACK.

    Every eigenvector: 8 N^2 bytes, callers bound N (:data:`EXACT_MAX_N`).  A chain with coupled
    neighbours has no such B: see :func:`coupled_vectors`.
    """
    if chain.coupled:
        raise ParameterError("coupling", chain.coupling, "0 (coupled chains: theory.exact.coupled_vectors)")
    import scipy.linalg  # on first use: theory.response imports this module for a batch that solves nothing

    diagonal, off = tridiagonal(chain)
    mu, U = scipy.linalg.eigh_tridiagonal(diagonal, off)
    # A free chain has mu_1 = 0 up to rounding (possibly -1e-16): clip, never NaN.
    omega = np.sqrt(np.clip(mu, 0.0, None))
    if chain.is_free:
        # The translation (Goldstone) mode is exactly zero; LAPACK returns
        # mu_1 ~ 1e-16, whose square root (1e-8) would be a spurious frequency.
        omega[0] = 0.0
    return omega, U


def _stiffness(chain: Chain) -> np.ndarray:
    K = chain.springs
    matrix = np.diag(K[:-1] + K[1:])
    off = -K[1:-1]
    return matrix + np.diag(off, 1) + np.diag(off, -1)


@fixed_blas_threads
def coupled_vectors(chain: Chain) -> tuple[np.ndarray, np.ndarray]:
    """Frequencies omega_n (ascending) and M-orthonormal modes u (columns) of K u = omega^2 M u.

    For any chain (coupled or not), N <= :data:`COUPLED_MAX_N` (dense, O(N^3)).
    """
    if chain.N > COUPLED_MAX_N:
        raise ParameterError("N", chain.N, f"N <= {COUPLED_MAX_N} with coupled coils (the generalised eigenproblem "
                             "is solved densely)")
    import scipy.linalg

    diagonal, off = chain.mass_matrix_bands()
    M = np.diag(diagonal) + np.diag(off, 1) + np.diag(off, -1)
    mu, u = scipy.linalg.eigh(_stiffness(chain), M, driver="gvd")
    omega = np.sqrt(np.clip(mu, 0.0, None))
    if chain.is_free:
        omega[0] = 0.0  # the translation mode is exactly zero (see diagonalise)
    return omega, u


def modal_weights(chain: Chain, u: np.ndarray, *, force: bool = False) -> np.ndarray:
    """Each mode's amplitude for a unit start in loop 1: (M u_n)_1, or m_1 u_1n for a force on mass 1 (``force``)."""
    if force:
        return np.asarray(chain.masses[0] * u[0, :])
    diagonal, off = chain.mass_matrix_bands()
    return np.asarray(diagonal[0] * u[0, :] + off[0] * u[1, :])


#: Bisection steps at most in :func:`sharp_frequencies` (each halves every bracket; they start ~1e-8 wide and stop
#: below the extended precision's 2^-63 relative).
_SHARP_STEPS = 80


def _below(edges: np.ndarray, sigma: np.ndarray) -> np.ndarray:
    """How many singular values of the bidiagonal ``edges`` lie below each sigma > 0 (extended precision): the
    Sturm count of the Golub-Kahan matrix (zero diagonal, off-diagonal ``edges``, order edges.size + 1), whose
    eigenvalues are +- every singular value and one 0, less the edges.size // 2 + 1 at or below 0.  A matrix of
    zero diagonal keeps every pivot relatively accurate (Demmel and Kahan 1990): each singular value, however
    small, to a few units of the working precision, relative."""
    tiny = np.finfo(np.longdouble).tiny
    d = -sigma
    count = np.zeros(sigma.size, dtype=np.int64)
    with np.errstate(over="ignore"):  # a pivot of +-inf is the recurrence's own (IEEE): the next one is -sigma
        for square in edges * edges:
            d = np.where(d == 0, -tiny, d)
            count += d < 0
            d = -sigma - square / d
    count += d < 0
    return count - (edges.size // 2 + 1)


def sharp_frequencies(chain: Chain, omega: np.ndarray) -> np.ndarray:
    """The normal frequencies ``omega`` refined to high relative accuracy (:func:`sharp_frequencies_extended`),
    rounded to float64."""
    return np.asarray(sharp_frequencies_extended(chain, omega), dtype=float)


def sharp_frequencies_extended(chain: Chain, omega: np.ndarray) -> np.ndarray:
    """The normal frequencies ``omega`` (ascending, LAPACK's) refined to high relative accuracy, every one.

    LAPACK places the eigenvalues mu_n = omega_n^2 of B to eps ||B|| absolute: a low mode's relative error is
    then eps ||B|| / mu_n (one-mass N = 613, mode 2: 1e-11), far blunter than an AC run measures it (1e-16).
    B = G^T G with the bidiagonal G = diag(sqrt(K)) D M^(-1/2) (D the springs' differences), so omega_n are the
    singular values of G, which its entries fix to high relative accuracy: each is bisected in extended precision
    (``numpy.longdouble``) on the Sturm count of G's Golub-Kahan matrix (:func:`_below`), from a bracket around
    LAPACK's value.  O(N^2) work (about 0.1 s at N = 600, 1 s at N = 2000), against the AC run's O(N^2)
    least squares.  A free chain's zero mode stays exactly 0.
    """
    m = np.asarray(chain.masses, dtype=np.longdouble)
    K = np.asarray(chain.springs, dtype=np.longdouble)
    edges = np.empty(2 * m.size, dtype=np.longdouble)
    edges[0::2], edges[1::2] = np.sqrt(K[:-1] / m), np.sqrt(K[1:] / m)  # spring j, mass j; spring j+1, mass j
    omega = np.asarray(omega, dtype=float)
    moving = np.flatnonzero(omega > 0)
    if moving.size == 0:
        return omega.astype(np.longdouble)
    index = moving
    mu = omega[moving].astype(np.longdouble) ** 2
    slack = 64 * np.finfo(float).eps * float(np.max(edges * edges)) * 4 + np.finfo(float).tiny
    lo, hi = np.sqrt(np.maximum(mu - slack, 0)), np.sqrt(mu + slack)
    top = np.sqrt(4 * np.max(edges * edges)) * 1.01 + 1
    bad = (_below(edges, np.where(lo > 0, lo, np.finfo(np.longdouble).tiny)) > index) | (_below(edges, hi) <= index)
    lo, hi = np.where(bad, 0, lo), np.where(bad, top, hi)  # LAPACK's bracket missed: the whole range
    width = np.finfo(np.longdouble).eps
    for _ in range(_SHARP_STEPS + (64 if bad.any() else 0)):
        open_ = hi - lo > width * hi
        if not open_.any():
            break
        mid = 0.5 * (lo[open_] + hi[open_])
        above = _below(edges, mid) > index[open_]
        hi[open_] = np.where(above, mid, hi[open_])
        lo[open_] = np.where(above, lo[open_], mid)
    sharp = omega.astype(np.longdouble)
    sharp[moving] = 0.5 * (lo + hi)
    return sharp


@fixed_blas_threads
def driven_modes(chain: Chain) -> Modes:
    """Modes as a voltage in loop 1 drives them (a force on mass 1): density m_1 u_1n^2, transfer m_1 u_1n u_Nn.

    Without coupling these are :func:`exact_modes`' (the kick's); with coupled coils a force excites mode n by
    m_1 u_1n, not by the kick's (M u_n)_1.  They are m_1 times the residues of the transfer admittances
    Y_11 Z0 and Y_N1 Z0 at s^2 = -omega_n^2 (:mod:`lcchain.compare.spectrum`).

    They are the reference an AC run is measured against, each with its own error bound (``omega_bound``,
    ``transfer_bound``): without coupling every omega_n is refined to high relative accuracy
    (:func:`sharp_frequencies_extended`; LAPACK's alone loses eps ||B|| / omega_n^2 on the low modes) and certified,
    kept beyond float64 (``omega_low``), and every P_n follows from the frequencies alone
    (:mod:`lcchain.theory.reference`: about 1e-18 relative on omega_n, 1e-16 absolute on P_n).  Coupled coils
    refine LAPACK's generalised solution by double-double Rayleigh quotients with Temple's bound, and the weights
    by the pencil's residue (:func:`lcchain.theory.reference.coupled_reference`), keeping LAPACK's values and
    known bounds only where modes are degenerate to rounding.
    """
    if not chain.coupled:
        modes = exact_modes(chain)
        extended = sharp_frequencies_extended(chain, modes.omega)
        omega, low, bound = certify_frequencies(chain, extended)
        transfer, transfer_bound = transfer_weights(chain, extended, bound)
        return Modes(omega, modes.density, transfer, modes.method, omega_low=low, omega_bound=bound,
                     transfer_bound=transfer_bound)
    omega, u = coupled_vectors(chain)
    amplitude = modal_weights(chain, u, force=True)
    transfer = u[-1, :] * amplitude
    lapack_omega, vector_bound = lapack_bounds(omega**2, float(np.max(omega, initial=0.0)) ** 2)
    scale = float(chain.masses[0]) / math.sqrt(float(np.min(chain.masses)))  # u is M-orthonormal
    lapack_transfer = scale * vector_bound * (np.abs(u[0, :]) + np.abs(u[-1, :]) + vector_bound)
    sharp, low, omega_bound, weights, transfer_bound = coupled_reference(chain, u)
    # where Temple's bound says nothing (modes degenerate to rounding), LAPACK's values with LAPACK's bounds
    held = np.isfinite(omega_bound) & np.isfinite(sharp)
    weighed = held & np.isfinite(weights) & np.isfinite(transfer_bound)
    # omega stays LAPACK's, the refinement is all in omega_low: the sweep is placed from omega, and a sweep moved by
    # the last bits of its poles changed the fit's result (two-mass N = 100, k = 0.2: its zero mode then unseen)
    correction = (sharp - omega) + low
    return Modes(omega, u[0, :] * amplitude, np.where(weighed, weights, transfer), "exact",
                 precision=WEIGHT_PRECISION, omega_low=np.where(held, correction, 0.0),
                 omega_bound=np.where(held, omega_bound, lapack_omega),
                 transfer_bound=np.where(weighed, transfer_bound, lapack_transfer))


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
    if chain.coupled:
        omega, u = coupled_vectors(chain)
        amplitude = modal_weights(chain, u)  # an initial current (charge) in loop 1
        return Modes(omega, u[0, :] * amplitude, u[-1, :] * amplitude, "exact", precision=WEIGHT_PRECISION)
    omega, U = diagonalise(chain)
    walls = perfect_walls(chain)
    if walls is not None:  # its end weights are known exactly: LAPACK's would be rounding below 1e-16
        density = perfect_weights(chain.N, walls)
        return Modes(omega, density, density * _alternating(chain.N), "exact")
    first, last = U[0, :], U[-1, :]
    density = first * first
    transfer = np.sqrt(chain.masses[0] / chain.masses[-1]) * first * last
    return Modes(omega, density, transfer, "exact", precision=WEIGHT_PRECISION)


def _alternating(N: int) -> np.ndarray:
    return np.where(np.arange(N) % 2 == 0, 1.0, -1.0)


def is_free_perfect(chain: Chain) -> bool:
    """Whether the chain is the free perfect cradle as :func:`lcchain.perfect_design` made it (walls = 0, no
    coupling): a sample drawn from it, or a chain rounded to preferred values, is not."""
    return perfect_walls(chain) == 0 and chain.is_free


def perfect_walls(chain: Chain) -> int | None:
    """The walls j of a perfect cradle as :func:`lcchain.perfect_design` made it (0: free), None for any other
    chain (a sample drawn from one, a chain rounded to preferred values, coupled coils)."""
    if chain._params[:1] != ("perfect",) or chain.coupled:
        return None
    return int(chain._params[1]) if len(chain._params) > 1 else 0


def perfect_weights(N: int, walls: int = 0) -> np.ndarray:
    """A perfect cradle's mode densities from its prescribed spectrum omega_n = n - 1 + 2 walls, in closed form.

    A persymmetric chain's weights are P_n = c / prod_(m != n) |mu_n - mu_m| (mu = omega^2; the Jacobi
    matrix's residue, :mod:`lcchain.theory.reference`), here with mu_n - mu_m = (n - m)(n + m - 2 + 4 walls):
    integers.  Free (walls = 0): P_n = C(2N-2, N-n) / 2^(2N-3), half that for n = 1, in Python integers, rounded
    once (the smallest, P_N = 2^-(2N-3), is 5.0e-60 for N = 100, far below what an eigenvector's 1e-16
    resolves).  With walls, the ratio of neighbours is the exact rational

        P_(n+1) / P_n = (N - n)/n * (n - 1 + 4j)/(n + N - 1 + 4j) * (2n + 4j)/(2n - 2 + 4j),

    multiplied up in 40-digit decimal arithmetic (N roundings of 1e-40: exact in float64).  The transfer weights
    are (-1)^(n-1) P_n (the cradle is mirror symmetric).
    """
    if walls == 0:
        scale = 2 ** (2 * N - 3)
        weights = [math.comb(2 * N - 2, N - n) / scale for n in range(1, N + 1)]
        weights[0] /= 2.0
        return np.array(weights)
    with decimal.localcontext() as context:
        context.prec = 40
        j4 = 4 * walls
        values = [decimal.Decimal(1)]
        for n in range(1, N):
            ratio = decimal.Decimal((N - n) * (n - 1 + j4) * (2 * n + j4)) / decimal.Decimal(
                n * (n + N - 1 + j4) * (2 * n - 2 + j4))
            values.append(values[-1] * ratio)
        total = sum(values)
        return np.array([float(value / total) for value in values])
