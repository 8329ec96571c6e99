"""A chain's exact modes sharper than an AC run measures them, each with its own error bound.

An AC run places omega_n to about 1e-16 relative and P_n to about 1e-15 absolute (ngspice, one-mass N = 150).
The reference it is held to must be at least ten times sharper, and say by how much:

* **Frequencies.**  omega_n are the singular values of the bidiagonal factor G of B (Eq. e.BN), which its entries
  fix to high relative accuracy; :func:`lcchain.theory.exact.sharp_frequencies` bisects them in extended precision
  (``numpy.longdouble``).  Each is then *certified* here: the Sturm count of G's Golub-Kahan matrix is evaluated in
  double-double arithmetic (about 106 bits) just below and just above it, and the bracket that holds exactly the
  mode's index is its bound (relative, :data:`CERTIFIED_BRACKET` at first, widened until it holds).  The counts'
  own rounding perturbs the entries by about 2^-104 each, which moves a singular value by at most 2N 2^-104
  relative (Demmel and Kahan 1990): added to the bound.  The value is kept as a pair of float64 (``omega`` and
  ``omega_low``), so the comparison is not limited by float64's own rounding of the reference (1.1e-16).
* **End-to-end weights.**  For a Jacobi matrix the residue of its resolvent's corner gives, without eigenvectors,

      P_n = sqrt(m_1/m_N) u_1n u_Nn = (-1)^(n-1) prod_(i<N) K_(i,i+1) / prod_(i>1) m_i / prod_(m!=n) |mu_n - mu_m|

  with mu = omega^2 and mu_n - mu_m = (omega_n - omega_m)(omega_n + omega_m) from the certified frequencies.  Its
  bound, per mode, is first order in the frequencies' bounds plus the extended precision's rounding of every
  factor.  LAPACK's eigenvectors lose eps ||B|| / gap_n (one-mass N = 150: 7e-13 on the lowest modes, fifty times
  what the circuit is measured to).  On a perfect cradle they agree with the weights of its prescribed spectrum
  in closed form (:func:`lcchain.theory.exact.perfect_weights`) to the design's own rounding (N = 30, two walls:
  1.7e-15 absolute; N = 60, one wall: 3.6e-14 relative down to weights of 1.9e-33).

Coupled coils (a generalised problem, LAPACK's dense ``eigh``) keep LAPACK's values with LAPACK's known bounds:
eps ||A|| on the eigenvalues, eps ||A|| / gap on the vectors.
"""

from __future__ import annotations

import numpy as np

from .chain import Chain

__all__ = ["certify_frequencies", "transfer_weights", "lapack_bounds", "CERTIFIED_BRACKET"]

#: The first bracket tried around each extended-precision frequency, relative: 2^-58 (3.5e-18), 16 units of
#: ``longdouble``'s last place; widened 16-fold until the double-double Sturm counts hold it.
CERTIFIED_BRACKET = 2.0**-58
_WIDENINGS = 6
_EPS = float(np.finfo(float).eps)
_EPS_LD = float(np.finfo(np.longdouble).eps)
#: Relative rounding of one double-double operation (Hida, Li and Bailey's double-double: a few units of 2^-104).
_EPS_DD = 4 * 2.0**-104


# --------------------------------------------------------- double-double arithmetic (arrays of float64 pairs)
def _two_sum(a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    s = a + b
    v = s - a
    return s, (a - (s - v)) + (b - v)


def _split(a: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    t = 134217729.0 * a  # 2^27 + 1 (Dekker)
    high = t - (t - a)
    return high, a - high


def _two_prod(a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    p = a * b
    ah, al = _split(a)
    bh, bl = _split(b)
    return p, ((ah * bh - p) + ah * bl + al * bh) + al * bl


def _renormalise(s: np.ndarray, e: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    high = s + e
    return high, e - (high - s)


def _dd_add(xh: np.ndarray, xl: np.ndarray, yh: np.ndarray, yl: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    s, e = _two_sum(xh, yh)
    t, f = _two_sum(xl, yl)
    e = e + t
    s, e = _renormalise(s, e)
    return _renormalise(s, e + f)


def _dd_mul(xh: np.ndarray, xl: np.ndarray, yh: np.ndarray, yl: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    p, e = _two_prod(xh, yh)
    return _renormalise(p, e + (xh * yl + xl * yh))


def _dd_div(xh: np.ndarray, xl: np.ndarray, yh: np.ndarray, yl: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    q1 = xh / yh
    ph, pl = _dd_mul(q1, np.zeros_like(q1), yh, yl)
    rh, rl = _dd_add(xh, xl, -ph, -pl)
    q2 = rh / yh
    ph, pl = _dd_mul(q2, np.zeros_like(q2), yh, yl)
    rh, rl = _dd_add(rh, rl, -ph, -pl)
    q3 = rh / yh
    qh, ql = _renormalise(q1, q2)
    return _dd_add(qh, ql, q3, np.zeros_like(q3))


def _ld_to_dd(values: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A longdouble array as float64 pairs, exactly (64 bits of mantissa fit in 2 x 53)."""
    high = values.astype(float)
    return high, (values - high.astype(np.longdouble)).astype(float)


def _edges_squared(chain: Chain) -> tuple[np.ndarray, np.ndarray]:
    """The squares of G's Golub-Kahan off-diagonals, K_(j-1,j)/m_j and K_(j,j+1)/m_j interleaved, double-double."""
    m, K = np.asarray(chain.masses, dtype=float), np.asarray(chain.springs, dtype=float)
    numerator = np.empty(2 * m.size)
    numerator[0::2], numerator[1::2] = K[:-1], K[1:]
    zero = np.zeros(numerator.size)
    return _dd_div(numerator, zero, np.repeat(m, 2), zero)


def _below_dd(squares: tuple[np.ndarray, np.ndarray], sigma: tuple[np.ndarray, np.ndarray]) -> np.ndarray:
    """:func:`lcchain.theory.exact._below` in double-double: singular values of G below each sigma > 0."""
    eh, el = squares
    sh, sl = sigma
    dh, dl = -sh, -sl
    count = np.zeros(sh.size, dtype=np.int64)
    tiny = np.finfo(float).tiny
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        for j in range(eh.size):
            zero = dh == 0
            dh, dl = np.where(zero, -tiny, dh), np.where(zero, 0.0, dl)
            count += dh < 0
            infinite = ~np.isfinite(dh)  # the pivot after it is -sigma (e^2 / inf = 0), as IEEE has it
            safe = np.where(infinite, 1.0, dh)
            qh, ql = _dd_div(np.full(sh.size, eh[j]), np.full(sh.size, el[j]), safe, np.where(infinite, 0.0, dl))
            qh, ql = np.where(infinite, 0.0, qh), np.where(infinite, 0.0, ql)
            overflow = ~np.isfinite(qh)  # e^2 / d beyond float64: the next pivot is -sign(d) inf
            nh, nl = _dd_add(-sh, -sl, -np.where(overflow, 0.0, qh), -np.where(overflow, 0.0, ql))
            dh = np.where(overflow, -np.copysign(np.inf, safe), nh)
            dl = np.where(overflow, 0.0, nl)
    count += dh < 0
    return count - (eh.size // 2 + 1)


def certify_frequencies(chain: Chain, omega: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Certify extended-precision frequencies (``numpy.longdouble``, ascending, a free chain's zero first).

    Returns
    -------
    omega, omega_low : ndarray
        The value as a float64 pair (omega + omega_low is the longdouble value, exactly).
    bound : ndarray
        Each one's relative error bound: the certified bracket's half-width plus the double-double counts' own
        rounding (0 for a free chain's zero mode, exact; infinite where no bracket up to 2^-34 held, which has
        not been seen).
    """
    omega = np.asarray(omega, dtype=np.longdouble)
    high, low = _ld_to_dd(omega)
    bound = np.zeros(omega.size)
    moving = np.flatnonzero(omega > 0)
    if moving.size == 0:
        return high, low, bound
    with np.errstate(all="ignore"):  # a chain beyond float64 is refused by the caller's own checks
        squares = _edges_squared(chain)
    rounding = 2 * squares[0].size * _EPS_DD
    width = np.full(moving.size, CERTIFIED_BRACKET)
    pending = np.ones(moving.size, dtype=bool)
    for _ in range(_WIDENINGS):
        index, value = moving[pending], omega[moving[pending]]
        step = width[pending].astype(np.longdouble)
        with np.errstate(all="ignore"):
            below = _below_dd(squares, _ld_to_dd(value * (1 - step)))
            above = _below_dd(squares, _ld_to_dd(value * (1 + step)))
        held = (below <= index) & (above > index)
        where = np.flatnonzero(pending)
        pending[where[held]] = False
        width[where[~held]] *= 16.0
        if not pending.any():
            break
    bound[moving] = np.where(pending, np.inf, width + rounding)
    return high, low, bound


def _product(factors: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """prod of each row of |factors| (longdouble) as mantissa x 2^exponent, so no product under- or overflows."""
    mantissa = np.ones(factors.shape[0], dtype=np.longdouble)
    exponent = np.zeros(factors.shape[0], dtype=np.int64)
    for start in range(0, factors.shape[1], 64):
        mantissa = mantissa * np.prod(np.abs(factors[:, start : start + 64]), axis=1)
        mantissa, more = np.frexp(mantissa)
        exponent += more
    return mantissa, exponent


def transfer_weights(chain: Chain, omega: np.ndarray, bound: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """:func:`_transfer_weights`; a chain beyond float64 (refused by its caller's own checks) gives inf or NaN
    there, quietly."""
    with np.errstate(all="ignore"):
        return _transfer_weights(chain, omega, bound)


def _transfer_weights(chain: Chain, omega: np.ndarray, bound: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Every P_n = sqrt(m_1/m_N) u_1n u_Nn from the frequencies alone (module docstring), and its absolute bound.

    Parameters
    ----------
    chain : Chain
        Without coupling.
    omega : ndarray
        The frequencies in extended precision (``numpy.longdouble``, ascending).
    bound : ndarray
        Their relative error bounds (:func:`certify_frequencies`).
    """
    N = omega.size
    w = np.asarray(omega, dtype=np.longdouble)
    m, K = np.asarray(chain.masses, dtype=np.longdouble), np.asarray(chain.springs, dtype=np.longdouble)
    top, top_exp = _product(np.concatenate((K[1:-1], 1 / m[1:]))[None, :])
    P = np.empty(N)
    relative = np.empty(N)
    slack = np.asarray(bound, dtype=float) * np.asarray(w, dtype=float)  # absolute bound of each omega
    for start in range(0, N, 256):
        rows = np.arange(start, min(N, start + 256))
        gaps = (w[rows, None] - w[None, :]) * (w[rows, None] + w[None, :])
        gaps[np.arange(rows.size), rows] = 1
        mantissa, exponent = _product(gaps)
        P[rows] = np.ldexp((top[0] / mantissa).astype(float) * 1.0, (top_exp[0] - exponent).astype(np.int64))
        dw = np.abs(np.asarray(w[rows, None] - w[None, :], dtype=float))
        sw = np.asarray(w[rows, None] + w[None, :], dtype=float)
        spread = slack[rows, None] + slack[None, :]
        with np.errstate(divide="ignore", invalid="ignore"):
            terms = spread / dw + np.where(sw > 0, spread / sw, 0.0)
        terms[np.arange(rows.size), rows] = 0.0
        relative[rows] = np.sum(terms, axis=1)
    relative += (6 * N) * _EPS_LD  # the longdouble rounding of every factor, every product
    sign = np.where(np.arange(N) % 2 == 0, 1.0, -1.0)
    P = sign * P
    return P, np.abs(P) * relative + 0.5 * _EPS * np.abs(P)  # and float64's rounding of the result


def lapack_bounds(eigenvalues: np.ndarray, norm: float) -> tuple[np.ndarray, np.ndarray]:
    """LAPACK's known bounds for a symmetric (definite) eigenproblem: eps ||A|| on each eigenvalue mu_n, as a
    relative bound on omega_n = sqrt(mu_n) (eps ||A|| / (2 mu_n), 0 for a zero mode that is exact), and
    eps ||A|| / gap_n on each unit vector (gap_n: the distance to the nearest other eigenvalue)."""
    mu = np.asarray(eigenvalues, dtype=float)
    absolute = _EPS * norm * mu.size
    with np.errstate(divide="ignore"):
        omega = np.where(mu > 0, absolute / (2 * np.maximum(mu, 1e-300)), 0.0)
    gap = np.full(mu.size, np.inf)
    if mu.size > 1:
        spacing = np.diff(mu)
        gap[:-1], gap[1:] = np.minimum(gap[:-1], spacing), np.minimum(gap[1:], spacing)
    return omega, absolute / gap
