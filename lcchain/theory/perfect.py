"""Perfect cradles for any N: mirror-symmetric chains designed from their spectrum.

A mirror-symmetric chain carries a pulse from mass 1 to mass N perfectly at
time T when every mode satisfies omega_n T = pi (n - 1) (mod 2 pi): then
alpha_N(T) = sum_n P_n cos[pi (n - 1) - omega_n T] = 1 exactly (Eq. e.utn).
The simplest family has equally spaced frequencies, omega_n = (n - 1) dw and
T = pi / dw (a free chain); omega_n = (n - 1 + 2j) dw, j >= 1, gives chains
tied to walls.  A persymmetric Jacobi matrix is determined by its spectrum
alone (Hochstadt; Hald), so each spectrum gives one chain.

The matrix that is inverted
---------------------------
Interleave the springs' and the masses' coordinates: y_0, q_1, y_1, ..., q_N,
y_N with q_i = sqrt(m_i) Q_i (drop y_0 and y_N at free ends).  The chain's
equations of motion are then first order in the zero-diagonal Jacobi matrix
H whose off-diagonals alternate a_(2i-1) = sqrt(K_(i-1,i) / m_i) and
a_(2i) = sqrt(K_(i,i+1) / m_i); H^2 restricted to the masses is B = M^(-1/2)
K M^(-1/2) (Eq. e.BN, up to the signs of its off-diagonals), and H's
eigenvalues are 0 and +-omega_n.  Masses and springs follow from the a_k:
m_(i+1) / m_i = a_(2i)^2 / a_(2i+1)^2 and K_(i,i+1) = a_(2i)^2 m_i, positive
whatever the a_k are.  So every spectrum of distinct frequencies (one zero
for a free chain, none with walls) has a realisation with positive masses and
springs, and a spectrum with a repeated frequency has none (a Jacobi
matrix's eigenvalues are simple).

How it is computed, and why it is stable
-----------------------------------------
The textbook route, the Lanczos (Stieltjes) recursion on B's spectral
measure (nodes mu_n = omega_n^2, weights P_n ~ 1/|prod_(m != n)(mu_n - mu_m)|)
in float64, fails: the weights span hundreds of orders of magnitude already
at N = 200 (about 4^-N; 1e-1200 at N = 2000), and the recursion loses the
small ones and returns a wrong matrix.  Three changes make it exact:

* H instead of B.  H's off-diagonals a_k are the unknowns, and masses and
  springs are products and ratios of the a_k^2: no subtraction anywhere.
  Relative errors in masses and springs scale every frequency (the singular
  values of the chain's incidence matrix) by the same relative amount, so the
  lowest frequencies, omega_max / N, stay as exact as the highest.  H's
  measure has nodes 0 and +-omega_n: the recursion's diagonal is exactly 0,
  and every a_k^2 is a sum of positive terms (relatively accurate).
* Extended exponents.  Each node's Lanczos component is a float64 mantissa
  times its own power of two, renormalised by exact powers of two; the log
  weights are summed from log|omega_n - omega_m| + log(omega_n + omega_m).
  Nothing underflows, nothing rounds when rescaled.
* Half a recursion.  Persymmetry (a_k = a_(L+1-k)) gives the second half of
  H from the first, so the recursion runs only from the end of H to its
  centre.  Along that half each node's component (an eigenvector component
  read from the end inwards) grows or oscillates: the modes that carry the
  tiny weights live in the middle of the chain.  Past the centre they would
  have to decay by hundreds of decades, the unstable direction of a
  three-term recurrence, which is where a full-length recursion goes wrong
  (measured: already at N = 60, weights 1e-36, error 7e-2).

Cost O(N^2) time, O(N) memory, no BLAS.  Every result is checked by
recomputing H's eigenvalues (absolute error about eps sqrt(N) omega_max,
measured on Krawtchouk matrices); a result that misses is polished by
Newton's method on the log a_k (d omega_n / d a_k = 2 u_k u_(k+1) from
orthonormal eigenvectors; the forward problem is well conditioned), and a
spectrum the recursion cannot start is reached by Newton continuation from
the equally spaced closed form.  Equally spaced frequencies need neither: H is
then the Krawtchouk matrix of perfect state transfer (Christandl et al. 2004),
a_k = (dw / 2) sqrt(k (M - k)) for an M-site H, every entry to rounding.

Measured (benchmarks/perfect.md): N = 2000 in 0.3 s (free) and 0.5 s (walls),
its spectrum right to 6e-14 relative by an independent dense SVD; 20000 with
walls right to 9e-13.  The half recursion and its stability argument were
worked out for lcchain in a separate study, checked against exact rational
chains and the Krawtchouk closed form up to N = 32000.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import scipy  # its submodules load on first use: commands that need no theory never import them

from ..core.blas import fixed_blas_threads
from ..core.checks import instance, integer, numbers_list
from ..core.errors import DesignError, ParameterError
from ..core.json import JSONDict
from ..core.limits import MAX_PERFECT_N, MIN_N
from .chain import PERFECT_N, Chain

__all__ = ["PerfectDesign", "perfect_design", "perfect_spectrum", "chain_from_spectrum", "spectrum_of",
           "mode_density_from_spectrum"]



def _tolerance(sites: int) -> float:
    """Newton stops when every frequency is right to this, relative to the largest: what the eigen-solver
    resolves.  Measured on Krawtchouk matrices (exact eigenvalues known): the error of eigvalsh_tridiagonal
    is 1.6 eps omega_max for 11 sites, 31 eps at 1001, 61 eps at 4001, 111 eps at 20001: about sqrt(sites).
    """
    return float(np.finfo(float).eps) * max(32.0, 4.0 * math.sqrt(sites))
#: Newton's iterations per continuation step before the step is halved.
_MAX_CORRECTIONS = 12
#: The half recursion's result is taken as it is when H's recomputed spectrum is right to this, relative to
#: the largest frequency (about eps sqrt(N), what the check itself resolves; the recursion is relatively
#: accurate for every frequency, see the module docstring); else Newton polishes it.
_ACCEPT = 1e-12
#: |log a_k| beyond this is no chain (a ratio of 1e130 between two couplings): a step that gets there failed.
_MAX_LOG = 300.0


def perfect_spectrum(N: int, walls: int = 0) -> np.ndarray:
    """omega_n = (n - 1 + 2 walls) for n = 1..N (frequency spacing dw = 1).

    Parameters
    ----------
    N : int
        Number of masses, >= 3.
    walls : int
        j >= 0: 0 for a free chain, j >= 1 for a chain tied to walls.
    """
    N = integer("N", N, at_least=MIN_N, at_most=MAX_PERFECT_N)
    walls = integer("walls", walls, at_least=0)
    return np.arange(N, dtype=float) + 2.0 * walls


# ------------------------------------------------------------------ H <-> chain
def _krawtchouk(sites: int) -> np.ndarray:
    """Off-diagonals of the Krawtchouk H with eigenvalues -(M-1)/2 ... (M-1)/2 (spacing 1)."""
    k = np.arange(1, sites, dtype=float)
    return 0.5 * np.sqrt(k * (sites - k))


def _chain_of(a: np.ndarray, free: bool) -> tuple[np.ndarray, np.ndarray]:
    """Masses (m_1 = 1) and springs of the chain whose H has off-diagonals a (walls indexing, length 2N)."""
    N = a.size // 2
    odd, even = a[0::2] ** 2, a[1::2] ** 2  # K_(i-1,i)/m_i, K_(i,i+1)/m_i for i = 1..N
    masses = np.ones(N)
    # m_(i+1) = K_(i,i+1)/(K_(i,i+1)/m_(i+1)) = m_i even_i / odd_(i+1), in logs against overflow
    masses[1:] = np.exp(np.cumsum(np.log(even[:-1]) - np.log(odd[1:])))
    springs = np.zeros(N + 1)
    springs[1:-1] = even[:-1] * masses[:-1]
    if not free:
        springs[0] = odd[0] * masses[0]
        springs[-1] = even[-1] * masses[-1]
    # the a_k are exactly persymmetric; the two halves' roundings differ: mirror the first half, exactly
    masses[N - N // 2 :] = masses[: N // 2][::-1]
    springs[N + 1 - (N + 1) // 2 :] = springs[: (N + 1) // 2][::-1]
    return masses, springs


#: The largest |natural log| of a mass or spring, relative to the first mass or to the central ones, that the
#: chain is built with: float64 holds about e^709, and a ratio of the two ends must stay finite too.
_MAX_VALUE_LOG = 700.0


def _log_span(a: np.ndarray) -> float:
    """log10 of the ratio of the largest to the smallest mass or spring of the chain whose H has off-diagonals
    ``a`` (walls indexing, length 2N; a free end's 0 ignored), computed in logs: it overflows nothing."""
    with np.errstate(divide="ignore"):
        log_a2 = 2.0 * np.log(a)
    odd, even = log_a2[0::2], log_a2[1::2]
    masses = np.concatenate(([0.0], np.cumsum(even[:-1] - odd[1:])))
    springs = np.concatenate((odd[:1] + masses[:1], even[:-1] + masses[:-1], even[-1:] + masses[-1:]))
    values = np.concatenate((masses, springs[np.isfinite(springs)]))
    return float(np.max(values) - np.min(values)) / math.log(10.0)


def _representable(a: np.ndarray) -> bool:
    """Whether :func:`_chain_of` and :func:`_bulk` can build the chain of ``a`` in float64 without an overflow or
    a zero: every value within e^:data:`_MAX_VALUE_LOG` of the first mass and of the central ones."""
    if not np.all(np.isfinite(a)) or np.any(a[1:-1] <= 0):
        return False
    return _log_span(a) * math.log(10.0) <= _MAX_VALUE_LOG


def _full(x: np.ndarray, free: bool, N: int) -> np.ndarray:
    """Every off-diagonal (walls indexing, length 2N) from the distinct log a: a_k = a_(L+1-k) (persymmetry).

    H has an even number L of off-diagonals (2N - 2 free, 2N with walls), so they pair up exactly.
    """
    half = np.exp(x)
    inner = np.concatenate((half, half[::-1]))
    return np.concatenate(([0.0], inner, [0.0])) if free else inner


def _distinct(a: np.ndarray, free: bool) -> np.ndarray:
    inner = a[1:-1] if free else a
    return np.asarray(np.log(inner[: inner.size // 2]))


def _frequencies(a: np.ndarray, free: bool) -> np.ndarray:
    """H's positive eigenvalues, ascending (its zero excluded): omega to eps ||H|| absolute."""
    inner = a[1:-1] if free else a
    values = scipy.linalg.eigvalsh_tridiagonal(np.zeros(inner.size + 1), inner)
    N = a.size // 2
    return np.sort(values)[-(N - 1 if free else N):]


def _jacobian(a: np.ndarray, free: bool, omega: np.ndarray) -> np.ndarray:
    """d omega_n / d log(a_k) for the distinct a_k, from B's eigenvectors."""
    N = a.size // 2
    odd, even = a[0::2], a[1::2]
    diagonal = odd**2 + even**2
    off = even[:-1] * odd[1:]
    mu, V = scipy.linalg.eigh_tridiagonal(diagonal, off)
    V = V[:, (1 if free else 0):]  # the modes whose frequencies are solved for (not a free chain's zero mode)
    # a_k d mu / d a_k: 2 a_k^2 v_i^2 plus the cross term 2 a_(2i) a_(2i+1) v_i v_(i+1) shared by both
    squares = V * V
    cross = V[:-1] * V[1:]
    cross *= (2 * off)[:, None]
    d = np.empty((2 * N, V.shape[1]))
    np.multiply((2 * odd**2)[:, None], squares, out=d[0::2])
    np.multiply((2 * even**2)[:, None], squares, out=d[1::2])
    d[2::2] += cross
    d[1:-1:2] += cross
    inner = d[1:-1] if free else d
    D = inner.shape[0] // 2
    folded = inner[:D] + inner[: -D - 1 : -1]  # a_k and its mirror are one unknown
    folded /= 2 * omega[None, :]  # d omega = d mu / (2 omega)
    return folded.T


def _linear_solve(matrix: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    """matrix^-1 rhs; NaN when the matrix is singular (eigenvector entries that underflowed): the caller then
    takes a shorter step."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", scipy.linalg.LinAlgWarning)
        try:
            return np.asarray(scipy.linalg.lu_solve(scipy.linalg.lu_factor(matrix), rhs))
        except (scipy.linalg.LinAlgWarning, ValueError):
            return np.full(rhs.shape, np.nan)


def _residual(x: np.ndarray, target: np.ndarray, free: bool, N: int) -> tuple[np.ndarray, np.ndarray, float]:
    """(a, H's frequencies, max error relative to the largest frequency); an unusable point (overflow) has an
    infinite error."""
    if not np.all(np.isfinite(x)) or np.max(np.abs(x)) > _MAX_LOG:
        return np.empty(0), np.empty(0), math.inf
    a = _full(x, free, N)
    omega = _frequencies(a, free)
    return a, omega, float(np.max(np.abs(omega - target)) / target[-1])


def _newton(x: np.ndarray, target: np.ndarray, free: bool, N: int, tolerance: float) -> tuple[np.ndarray, float]:
    """Newton on the distinct log a_k until H's spectrum is ``target``; returns (x, relative residual).

    A correction that does not reduce the error is refused (the caller then takes a shorter step).
    """
    a, omega, residual = _residual(x, target, free, N)
    for _ in range(_MAX_CORRECTIONS):
        if residual <= tolerance or not math.isfinite(residual):
            break
        step = _linear_solve(_jacobian(a, free, omega), omega - target)
        trial = x - step
        a_new, omega_new, new = _residual(trial, target, free, N)
        if not new < residual:
            break
        x, a, omega, residual = trial, a_new, omega_new, new
    return x, residual


def _log_weights(positive: np.ndarray) -> tuple[float, np.ndarray]:
    """log of the first-component weights of H's nodes 0 and +-omega_n: w ~ 1/prod_(other nodes) |lambda - l'|.

    For +-omega_n the product is omega_n (2 omega_n) prod_(m != n) |omega_n^2 - omega_m^2|, each factor formed
    as |omega_n - omega_m| (omega_n + omega_m) (no cancellation); for the node 0 it is prod_m omega_m^2.
    """
    M = positive.size
    log_weight = np.empty(M)
    rows = max(1, (1 << 20) // M)
    for first in range(0, M, rows):
        last = min(M, first + rows)
        p = positive[first:last, None]
        factors = np.abs(p - positive[None, :]) * (p + positive[None, :])
        index = np.arange(last - first)
        factors[index, first + index] = 1.0  # m == n
        log_weight[first:last] = -(np.log(positive[first:last]) + np.log(2.0 * positive[first:last])
                                   + np.sum(np.log(factors), axis=1))
    return -2.0 * float(np.sum(np.log(positive))), log_weight


def _half_recursion(positive: np.ndarray) -> np.ndarray:
    """a_1^2 .. a_M^2, the first half of H's off-diagonals, by the Stieltjes recursion on H's spectral measure.

    Nodes 0 and +-omega_n (stored once, +- with multiplicity 2: the diagonal is exactly 0), weights from
    :func:`_log_weights`.  Each node's Lanczos component is kept as a float64 mantissa times its own power of
    two, renormalised by exact powers of two, so no weight underflows and no rescaling rounds.  Only the half
    from the end of H to its centre is run; persymmetry gives the rest.
    """
    M = positive.size
    log0, log_rest = _log_weights(positive)
    nodes = np.concatenate(([0.0], positive))
    multiplicity = np.concatenate(([1.0], np.full(M, 2.0)))
    log_all = np.concatenate(([log0], log_rest))
    half_log2 = 0.5 * (log_all - log_all.max()) / math.log(2.0)  # log2 sqrt(w / w_max)
    exponent = np.floor(half_log2).astype(np.int64)
    x = np.exp2(half_log2 - exponent)
    x /= math.sqrt(float(np.sum(multiplicity * np.ldexp(x * x, 2 * exponent))))
    previous = np.zeros_like(x)
    squares = np.empty(M)
    coupling = 0.0
    for k in range(M):
        r = nodes * x - coupling * previous
        squares[k] = float(np.sum(multiplicity * np.ldexp(r * r, 2 * exponent)))
        coupling = math.sqrt(squares[k])
        previous, x = x, r / coupling
        largest = np.maximum(np.abs(x), np.abs(previous))
        scale = np.frexp(largest)[1]
        out = np.flatnonzero((scale > 64) | ((scale < -64) & (largest > 0)))
        if out.size:
            shift = scale[out]
            x[out] = np.ldexp(x[out], -shift)
            previous[out] = np.ldexp(previous[out], -shift)
            exponent[out] += shift
    return squares


def _stieltjes(omega: np.ndarray) -> np.ndarray:
    """H's distinct off-diagonals (the first half) whose positive spectrum is ``omega``, by the half recursion.

    Frequencies are scaled by an exact power of two so that the largest is in [1/2, 1).
    """
    power = math.frexp(float(omega[-1]))[1]
    return np.asarray(np.ldexp(np.sqrt(_half_recursion(np.ldexp(omega, -power))), power))


def _continuation(omega: np.ndarray, free: bool, tolerance: float) -> np.ndarray:
    """The fallback: Newton continuation from the equally spaced closed form to ``omega``."""
    N = omega.size + (1 if free else 0)
    sites = 2 * N - 1 if free else 2 * N + 1
    spacing = (omega[-1] - omega[0]) / max(1, omega.size - 1)
    start = spacing * (np.arange(1, omega.size + 1, dtype=float))
    a = spacing * _krawtchouk(sites)
    x = _distinct(np.concatenate(([0.0], a, [0.0])) if free else a, free)
    s, step = 0.0, 1.0
    while s < 1.0:
        trial = min(1.0, s + step)
        target = (1 - trial) * start + trial * omega
        # Euler predictor along the path, then Newton's corrector
        here = _full(x, free, N)
        tangent = _linear_solve(_jacobian(here, free, _frequencies(here, free)), (trial - s) * (omega - start))
        guess, residual = (_newton(x + tangent, target, free, N, tolerance) if np.all(np.isfinite(tangent))
                           else (x, math.inf))
        if residual <= tolerance:
            x, s = guess, trial
            step = min(1.0, 2 * step)
        else:
            step /= 2
            if step < 1e-6:
                raise DesignError(f"no chain found for this spectrum in float64: the continuation from equally "
                                  f"spaced frequencies stalled at {100 * s:.4g} % of the way (frequencies right to "
                                  f"{residual:.2g} of the largest); its masses or springs may span more than "
                                  f"1e{_MAX_LOG / math.log(10):.0f}")
    return _full(x, free, N)


@fixed_blas_threads
def _solve(omega: np.ndarray, free: bool) -> np.ndarray:
    """The off-diagonals of H (walls indexing) whose positive spectrum is ``omega``.

    Equally spaced from the spacing up: the closed form.  Otherwise the half recursion, checked by
    recomputing H's spectrum (O(N^2)); Newton polishes a result that misses, and the continuation from the
    closed form takes over when the recursion gives no usable start.
    """
    N = omega.size + (1 if free else 0)
    sites = 2 * N - 1 if free else 2 * N + 1
    tolerance = _tolerance(sites)
    spacing = (omega[-1] - omega[0]) / max(1, omega.size - 1)
    if np.allclose(spacing * np.arange(1, omega.size + 1), omega, rtol=0, atol=tolerance * omega[-1]):
        a = spacing * _krawtchouk(sites)
        return np.concatenate(([0.0], a, [0.0])) if free else a
    with np.errstate(all="ignore"):
        half = _stieltjes(omega)
    if np.all(np.isfinite(half)) and np.all(half > 0):
        x, residual = _newton(np.log(half), omega, free, N, max(tolerance, _ACCEPT))
        if residual <= max(tolerance, _ACCEPT):
            return _full(x, free, N)
    return _continuation(omega, free, tolerance)


# ------------------------------------------------------------------ public
def _check_spectrum(omega: object) -> tuple[np.ndarray, bool]:
    given = numbers_list("frequencies", omega, "ascending frequencies omega_1 < ... < omega_N")
    if len(given) < MIN_N:
        raise ParameterError("frequencies", f"{len(given)} values", f"at least {MIN_N} frequencies (one per mass)")
    listed: list[float] = []
    for i, value in enumerate(given):  # the first that is not a finite frequency >= 0, named
        try:
            number = float(value)
        except OverflowError:  # an int past the largest float
            number = math.inf
        if not (math.isfinite(number) and number >= 0):
            raise ParameterError(f"frequencies[{i}]", value, "finite frequencies >= 0")
        listed.append(number)
    values = np.array(listed)
    gaps = np.diff(values)
    if np.any(gaps <= 0):
        i = int(np.flatnonzero(gaps <= 0)[0])
        raise ParameterError(f"frequencies[{i + 1}]", float(values[i + 1]), "frequencies strictly ascending: a chain's "
                             "modes have distinct frequencies (no mirror-symmetric chain has a repeated one)")
    return values, values[0] == 0.0


def _bulk(masses: np.ndarray, springs: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
    """Masses and springs scaled so that the central mass and the central spring are 1; the frequency scale."""
    N = masses.size
    central_mass = masses[N // 2]  # odd N: the middle mass; even N: the two middle ones are equal
    central_spring = springs[(N + 1) // 2]  # even N: the middle spring; odd N: the two middle ones are equal
    scale = math.sqrt(central_mass / central_spring)  # omega_bulk = omega * sqrt(m_c / K_c)
    return masses / central_mass, springs / central_spring, scale


def spectrum_of(chain: Chain) -> np.ndarray:
    """A chain's frequencies from its H (relative accuracy ~eps N for omega >= the bulk spacing).

    H's off-diagonals sqrt(K_(i-1,i)/m_i), sqrt(K_(i,i+1)/m_i) come from the
    masses and springs directly; a free end adds a decoupled zero; the N
    largest eigenvalues are the chain's frequencies (a free chain's first is 0).
    """
    instance("chain", chain, Chain)
    if chain.coupled:
        raise ParameterError("coupling", chain.coupling, "0 (a coupled chain's frequencies: lcchain.theory.exact)")
    m, K = chain.masses, chain.springs
    a = np.empty(2 * chain.N)
    a[0::2], a[1::2] = np.sqrt(K[:-1] / m), np.sqrt(K[1:] / m)
    values = np.sort(scipy.linalg.eigvalsh_tridiagonal(np.zeros(2 * chain.N + 1), a))
    return np.asarray(np.clip(values[-chain.N:], 0.0, None))


def mode_density_from_spectrum(mu: np.ndarray) -> np.ndarray:
    """P_n of a persymmetric chain from its spectrum alone: P_n ~ 1/|prod_(m != n)(mu_n - mu_m)|, mu = omega^2.

    Summed in logs (the products span hundreds of orders of magnitude), normalised to sum 1.
    """
    log_weight = np.empty(mu.size)
    for start in range(0, mu.size, 512):
        block = mu[start : start + 512]
        gaps = np.abs(block[:, None] - mu[None, :])
        gaps[np.arange(block.size), np.arange(start, start + block.size)] = 1.0
        log_weight[start : start + block.size] = -np.sum(np.log(gaps), axis=1)
    weight = np.exp(log_weight - log_weight.max())
    return np.asarray(weight / weight.sum())


def chain_from_spectrum(frequencies: Sequence[float] | np.ndarray, name: str = "from spectrum") -> tuple[Chain, float]:
    """The mirror-symmetric chain with exactly these frequencies.

    Parameters
    ----------
    frequencies : sequence of float
        omega_1 < omega_2 < ... < omega_N (any unit): omega_1 = 0 for a free
        chain, omega_1 > 0 for a chain tied to walls.
    name : str

    Returns
    -------
    chain : Chain
        In bulk units (central mass and central spring 1).
    scale : float
        The factor that turns the given frequencies into the bulk chain's:
        omega_bulk = scale * omega.

    Raises
    ------
    ParameterError
        Fewer than 3 frequencies, a negative or non-finite one, or a repeated
        or descending one: no chain realises such a spectrum.
    """
    omega, free = _check_spectrum(frequencies)
    solved = omega[1:] if free else omega
    with np.errstate(all="ignore"):  # a spectrum beyond float64 is refused below, not warned about
        a = _solve(solved, free)
    if not _representable(a):
        span = _log_span(a) if np.all(np.isfinite(a)) else math.inf
        raise ParameterError("frequencies", f"{omega.size} frequencies up to {float(omega[-1]):.6g}", "a spectrum "
                             f"whose chain float64 holds: its masses and springs would span 10^{span:.0f}, beyond "
                             f"10^{_MAX_VALUE_LOG / math.log(10.0):.0f}")
    masses, springs = _chain_of(a, free)
    masses, springs, scale = _bulk(masses, springs)
    return Chain(masses, springs, name=name), scale


#: The largest N whose largest --walls is searched for when a J is refused (each try is one design, O(N^2):
#: 0.5 s at N = 2000); beyond, the refusal says how far this J spreads the chain instead.
_WALLS_SEARCH_MAX_N = 2000


def _designable(N: int, walls: int) -> bool:
    """Whether the perfect cradle of N masses tied to walls by J = ``walls`` has a chain float64 holds."""
    omega = perfect_spectrum(N, walls)
    try:
        with np.errstate(all="ignore"):
            a = _solve(omega, False)
    except DesignError:
        return False
    return _representable(a)


def _walls_allowed(N: int, walls: int) -> str:
    """The allowed range of ``--walls`` for N masses, once J = ``walls`` was refused: the spread of a walled
    cradle's masses grows with J (about N decades per decade of J beyond N), so the largest J that float64 holds
    is found by halving down from the refused one, then bisection (a dozen designs at most)."""
    if N > _WALLS_SEARCH_MAX_N:
        return (f"an integer J >= 0 for which float64 holds the chain of N = {N} masses (its masses and springs "
                f"spread with J: J = {walls} spreads them beyond 10^{_MAX_VALUE_LOG / math.log(10.0):.0f})")
    good, bad = 0, walls
    probe = walls // 4
    while probe > 0 and not _designable(N, probe):
        bad, probe = probe, probe // 4
    good = probe
    while bad - good > max(1, good // 16):
        middle = (good + bad) // 2
        if _designable(N, middle):
            good = middle
        else:
            bad = middle
    return (f"an integer 0 <= J <= {good} for N = {N} (a larger J spreads the chain's masses and springs beyond "
            f"10^{_MAX_VALUE_LOG / math.log(10.0):.0f}, or narrows its band below what float64 resolves)")


@dataclass(frozen=True)
class PerfectDesign:
    """A perfectly transmitting chain designed from its spectrum.

    Attributes
    ----------
    N, walls : int
    chain : Chain
        Bulk units: the central mass and the central spring are 1.
    t_arrival : float
        T = pi / dw, units of sqrt(m/K) of the bulk.
    delta : float
        1 - alpha_N(T) from the chain's own eigen-decomposition (0 to rounding).
    frequencies : ndarray
        omega_n = (n - 1 + 2 walls) dw in bulk units.
    """

    N: int
    walls: int
    chain: Chain
    t_arrival: float
    delta: float
    frequencies: np.ndarray

    def spread(self) -> dict[str, float | int]:
        """How far the values spread, and how many distinct values a builder needs (to 1e-9 relative)."""
        m, K = self.chain.masses, self.chain.springs
        inner = K[K > 0]

        def distinct(values: np.ndarray) -> int:
            ordered = np.sort(values)
            return int(1 + np.sum(np.diff(ordered) > 1e-9 * ordered[1:]))

        return {"mass_max": float(m.max()), "mass_min": float(m.min()), "spring_max": float(inner.max()),
                "spring_min": float(inner.min()), "distinct_masses": distinct(m), "distinct_springs": distinct(inner)}

    def to_dict(self) -> JSONDict:
        """The JSON of ``lcchain design --case perfect``."""
        return {"N": self.N, "case": "perfect", "walls": self.walls, "masses": [float(v) for v in self.chain.masses],
                "springs": [float(v) for v in self.chain.springs], "t_arrival": self.t_arrival, "delta": self.delta,
                "frequencies": [float(v) for v in self.frequencies], "spread": self.spread()}


@fixed_blas_threads
def perfect_design(N: int, walls: int = 0) -> PerfectDesign:
    """The perfect cradle of N masses: omega_n = (n - 1 + 2 walls) dw, alpha_N(pi/dw) = 1.

    Parameters
    ----------
    N : int
        3 <= N <= :data:`lcchain.core.limits.MAX_PERFECT_N`.
    walls : int
        j = 0: a free chain (closed form, any N); j >= 1: tied to walls.

    Returns
    -------
    PerfectDesign
        N = 3, 4, 5 without walls are the paper's perfect chains (Sec. II.C
        and Appendix A): masses (3/2, 1, 3/2); (5/3, 1, 1, 5/3) with end
        springs 5/6 (Fig. cradle4); (35/18, 10/9, 1, 10/9, 35/18) with end
        springs 7/9.
    """
    omega = perfect_spectrum(N, walls)
    try:
        chain, scale = chain_from_spectrum(omega, name="perfect")
    except (ParameterError, DesignError):
        if walls == 0:  # pragma: no cover - the free cradle is the closed form, exact for every N
            raise
        raise ParameterError("walls", walls, _walls_allowed(N, walls)) from None
    if walls == 0 and N in PERFECT_N:
        # the paper's exact fractions, which the algorithm reproduces to rounding (tests): correct to the last digit
        chain = Chain.perfect(N, bulk=True)
    # marked: its modes' end weights are known from its spectrum in closed form (lcchain.theory.exact.perfect_weights)
    marks = ("perfect",) if walls == 0 else ("perfect", walls)
    chain = Chain(chain.masses, chain.springs, name="perfect", _params=marks)
    T = math.pi / scale  # dw = scale in bulk units
    # the check: the chain's own frequencies, recomputed from its masses and springs, and their mode density
    measured = spectrum_of(chain)
    density = mode_density_from_spectrum(measured**2)
    n = np.arange(N)
    alpha = float(np.sum(density * np.cos(np.pi * n - measured * T)))
    return PerfectDesign(N, walls, chain, T, 1.0 - alpha, omega * scale)
