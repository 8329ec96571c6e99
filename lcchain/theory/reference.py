"""A chain's exact modes sharper than an AC run measures them, each with its own error bound.

An AC run places omega_n to about 1e-16 relative and P_n to about 1e-15 absolute (ngspice, one-mass N = 150).
The reference it is held to must be at least ten times sharper, and say by how much:

* **Frequencies.**  omega_n are the singular values of the bidiagonal factor G of B (Eq. e.BN), which its entries
  fix to high relative accuracy; :func:`lcchain.theory.exact.sharp_frequencies` bisects them in extended precision
  (``numpy.longdouble``).  Each is then *certified* here: the Sturm count of G's Golub-Kahan matrix is evaluated in
  double-double arithmetic (about 106 bits) just below and just above it, and the bracket that holds exactly the
  mode's index is its bound (relative, :data:`CERTIFIED_BRACKET` at first, widened until it holds).  The counts'
  own rounding perturbs the entries by about 2^-104 each, which moves a singular value by at most 2N 2^-104
  relative (Demmel and Kahan 1990): added to the bound, as 2N 2^-90 to be safe.  The value is kept as a pair of
  float64 (``omega`` and ``omega_low``), so the comparison is not limited by float64's own rounding of the
  reference (1.1e-16).
* **End-to-end weights.**  For a Jacobi matrix the residue of its resolvent's corner gives, without eigenvectors,

      P_n = sqrt(m_1/m_N) u_1n u_Nn = (-1)^(n-1) prod_(i<N) K_(i,i+1) / prod_(i>1) m_i / prod_(m!=n) |mu_n - mu_m|

  with mu = omega^2 and mu_n - mu_m = (omega_n - omega_m)(omega_n + omega_m) from the certified frequencies.  Its
  bound, per mode, is first order in the frequencies' bounds plus the extended precision's rounding of every
  factor.  LAPACK's eigenvectors lose eps ||B|| / gap_n (one-mass N = 150: 7e-13 on the lowest modes, fifty times
  what the circuit is measured to).  On a perfect cradle they agree with the weights of its prescribed spectrum
  in closed form (:func:`lcchain.theory.exact.perfect_weights`) to the design's own rounding (N = 30, two walls:
  1.7e-15 absolute; N = 60, one wall: 3.6e-14 relative down to weights of 1.9e-33).

Coupled coils (a generalised problem K u = mu M u, LAPACK's dense ``eigh``): each eigenvector's Rayleigh quotient
in double-double with Temple's bound, the eigenvector's error entering squared, and the weights by the pencil's
residue (:func:`coupled_reference`: two-mass N = 2000, k = 0.2, bounds 1e-17 on omega_n and 2e-17 on P_n, where
LAPACK's known bounds, eps ||A|| and eps ||A|| / gap, were 1e-10).  Where modes are degenerate to rounding Temple
says nothing and LAPACK's values keep LAPACK's bounds (:func:`lapack_bounds`).
"""

from __future__ import annotations

import numpy as np

from .chain import Chain

__all__ = ["certify_frequencies", "transfer_weights", "lapack_bounds", "coupled_reference", "CERTIFIED_BRACKET"]

#: The first bracket tried around each extended-precision frequency, relative: 2^-58 (3.5e-18), 16 units of
#: ``longdouble``'s last place; widened 16-fold until the double-double Sturm counts hold it.
CERTIFIED_BRACKET = 2.0**-58
_WIDENINGS = 6
_EPS = float(np.finfo(float).eps)
_EPS_LD = float(np.finfo(np.longdouble).eps)
#: Relative rounding of one double-double operation (Hida, Li and Bailey's double-double: a few units of 2^-104).
_EPS_DD = 4 * 2.0**-104
#: Relative rounding of a double-double sum of N products, per term, taken conservatively: the coupled Rayleigh
#: quotients landed within 5e-28 relative of a 50-digit decimal evaluation at N = 20 (2^-90 N = 1.6e-26).
_DD_SUMS = 2.0**-90


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
    rounding = squares[0].size * _DD_SUMS  # the counts' own rounding, conservatively (see _DD_SUMS)
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
    with np.errstate(divide="ignore"):  # degenerate to rounding: no bound on the vectors
        return omega, absolute / gap


# ------------------------------------------------------------------ coupled coils: a symmetric-definite pencil
def _dd_sum(high: np.ndarray, low: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Double-double sums down axis 0, pairwise (log2 of the rows' levels)."""
    while high.shape[0] > 1:
        if high.shape[0] % 2:
            high = np.concatenate((high, np.zeros_like(high[:1])))
            low = np.concatenate((low, np.zeros_like(low[:1])))
        high, low = _dd_add(high[0::2], low[0::2], high[1::2], low[1::2])
    return high[0], low[0]


def _dd_sqrt(high: np.ndarray, low: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """sqrt of a double-double >= 0 by one Newton step from float64's (0 stays 0)."""
    root = np.sqrt(high)
    square_h, square_l = _two_prod(root, root)
    rest_h, _ = _dd_add(high, low, -square_h, -square_l)
    with np.errstate(divide="ignore", invalid="ignore"):
        correction = np.where(root > 0, rest_h / (2 * root), 0.0)
    return _renormalise(root, correction)


def coupled_reference(chain: Chain, u: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray,
                                                               np.ndarray]:
    """Coupled coils' frequencies and end-to-end weights sharper than an AC run measures them, with bounds.

    K u = mu M u with M tridiagonal (mutual inductances k sqrt(m_i m_(i+1))).  Each of LAPACK's M-orthonormal
    vectors ``u`` (columns) gives its Rayleigh quotient rho = u^T K u / u^T M u in double-double arithmetic,
    u^T K u = sum_j K_j (u_j - u_(j-1))^2 (springs' energies: positive terms).  Temple's inequality bounds it:
    |rho - mu_n| <= ||r||^2_(M^-1) / gap_n with r = K u - rho M u (in double-double, M-normalised) and gap_n the
    distance to the other quotients, so the eigenvector's own error (eps ||K|| / gap) enters squared.
    ||x||^2_(M^-1) <= sum x_i^2 / m_i / (1 - 2|k|) (M = D^1/2 (I + C) D^1/2, C's off-diagonals k: |k| < 1/2).
    The weights then follow from the frequencies alone by the pencil's residue,
    m_1 u_1n u_Nn = m_1 (-1)^(N+1) prod_i (K - mu_n M)_(i,i+1) / (det M prod_(m!=n) (mu_m - mu_n)).

    Returns
    -------
    omega, omega_low, omega_bound, transfer, transfer_bound : ndarray
        As :func:`certify_frequencies` and :func:`transfer_weights` give them for a chain without coupling.
    """
    with np.errstate(all="ignore"):  # a chain beyond float64 is refused by the caller's own checks
        return _coupled_reference(chain, np.asarray(u, dtype=float))


def _coupled_reference(chain: Chain, u: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray,
                                                              np.ndarray]:
    N = u.shape[0]
    m = np.asarray(chain.masses, dtype=float)
    K = np.asarray(chain.springs, dtype=float)
    k = float(chain.coupling)
    product_h, product_l = _two_prod(m[:-1], m[1:])
    root_h, root_l = _dd_sqrt(product_h, product_l)
    mo_h, mo_l = _dd_mul(root_h, root_l, np.full(N - 1, k), np.zeros(N - 1))
    padded = np.zeros((N + 2, N))
    padded[1:-1] = u
    # u^T K u: every spring's energy K_j (u_j - u_(j-1))^2, walls included (a free end's K is 0)
    diff_h, diff_l = _two_sum(padded[1:], -padded[:-1])
    square_h, square_l = _dd_mul(diff_h, diff_l, diff_h, diff_l)
    zero = np.zeros_like(square_h)
    springs = np.broadcast_to(K[:, None], square_h.shape)
    num_h, num_l = _dd_sum(*_dd_mul(square_h, square_l, springs, zero))
    # u^T M u = sum m_i u_i^2 + 2 sum M_(i,i+1) u_i u_(i+1)
    diag_h, diag_l = _dd_mul(*_two_prod(u, u), np.broadcast_to(m[:, None], u.shape), np.zeros_like(u))
    cross_h, cross_l = _two_prod(u[:-1], u[1:])
    cross_h, cross_l = _dd_mul(cross_h, cross_l, np.broadcast_to(2 * mo_h[:, None], cross_h.shape),
                               np.broadcast_to(2 * mo_l[:, None], cross_h.shape))
    den_h, den_l = _dd_sum(np.concatenate((diag_h, cross_h)), np.concatenate((diag_l, cross_l)))
    rho_h, rho_l = _dd_div(num_h, num_l, den_h, den_l)
    if chain.is_free:  # the translation is exactly zero
        rho_h[0], rho_l[0] = 0.0, 0.0
    # the residual r = K u - rho M u, in double-double, and Temple's bound
    stiff_h, stiff_l = _dd_add(*_two_prod(np.broadcast_to(K[:-1, None], u.shape), diff_h[:-1]),
                               *_two_prod(np.broadcast_to(-K[1:, None], u.shape), diff_h[1:]))
    # (the differences' low parts: u_j - u_(j-1) is exact in diff_h + diff_l; their K-weighted rest is added here)
    rest_h, rest_l = _dd_add(*_two_prod(np.broadcast_to(K[:-1, None], u.shape), diff_l[:-1]),
                             *_two_prod(np.broadcast_to(-K[1:, None], u.shape), diff_l[1:]))
    stiff_h, stiff_l = _dd_add(stiff_h, stiff_l, rest_h, rest_l)
    mass_h, mass_l = _dd_mul(*_two_prod(u, np.ones_like(u)), np.broadcast_to(m[:, None], u.shape), np.zeros_like(u))
    up_h, up_l = _dd_mul(*_two_prod(u[1:], np.ones_like(u[1:])), np.broadcast_to(mo_h[:, None], u[1:].shape),
                         np.broadcast_to(mo_l[:, None], u[1:].shape))
    down_h, down_l = _dd_mul(*_two_prod(u[:-1], np.ones_like(u[:-1])), np.broadcast_to(mo_h[:, None], u[1:].shape),
                             np.broadcast_to(mo_l[:, None], u[1:].shape))
    mass_h[:-1], mass_l[:-1] = _dd_add(mass_h[:-1], mass_l[:-1], up_h, up_l)
    mass_h[1:], mass_l[1:] = _dd_add(mass_h[1:], mass_l[1:], down_h, down_l)
    scaled_h, scaled_l = _dd_mul(mass_h, mass_l, np.broadcast_to(rho_h, u.shape), np.broadcast_to(rho_l, u.shape))
    residual, _ = _dd_add(stiff_h, stiff_l, -scaled_h, -scaled_l)  # (K u)_i = K_i d_i - K_(i+1) d_(i+1)
    residual = residual.astype(float)
    # r^T M^-1 r <= sum r_i^2 / m_i / (1 - 2|k|): M = D^1/2 (I + C) D^1/2, C's off-diagonals k, so I + C >= 1 - 2|k|
    norm = np.sum(residual * residual / m[:, None], axis=0) / den_h / (1 - 2 * abs(k))
    mu = rho_h.astype(np.longdouble) + rho_l.astype(np.longdouble)
    gap = np.full(N, np.inf)
    if N > 1:
        spacing = np.asarray(np.diff(mu), dtype=float)
        gap[:-1], gap[1:] = np.minimum(gap[:-1], spacing), np.minimum(gap[1:], spacing)
    rounding = N * _DD_SUMS * np.abs(rho_h)
    # Temple with the quotients' own gap, halved: the true eigenvalues' gap is as wide to far below that
    mu_bound = np.where(gap > 0, 2 * norm / gap, np.inf) + rounding
    if chain.is_free:
        mu_bound[0] = 0.0
    omega_h, omega_l = _dd_sqrt(rho_h, rho_l)
    with np.errstate(divide="ignore", invalid="ignore"):
        omega_bound = np.where(rho_h > 0, mu_bound / (2 * rho_h), 0.0) + N * _DD_SUMS
    # the weights from the pencil's residue
    mo = mo_h.astype(np.longdouble) + mo_l.astype(np.longdouble)
    ml = m.astype(np.longdouble)
    pivots = np.empty(N, dtype=np.longdouble)  # det M = prod of the pivots of M's LDL^T (all positive)
    pivots[0] = ml[0]
    for i in range(1, N):
        pivots[i] = ml[i] - mo[i - 1] ** 2 / pivots[i - 1]
    det_m, det_e = _product(pivots[None, :])
    couplings = -(K[1:-1].astype(np.longdouble))[None, :] - mu[:, None] * mo[None, :]  # (K - mu_n M)_(i,i+1)
    top_m, top_e = _product(couplings)
    top_sign = np.prod(np.sign(np.asarray(couplings, dtype=float)), axis=1)
    transfer = np.empty(N)
    relative = np.empty(N)
    slack = np.asarray(mu_bound, dtype=float)
    for start in range(0, N, 256):
        rows = np.arange(start, min(N, start + 256))
        gaps = mu[None, :] - mu[rows, None]
        gaps[np.arange(rows.size), rows] = 1
        gap_m, gap_e = _product(gaps)
        sign = np.prod(np.sign(np.asarray(gaps, dtype=float)), axis=1)
        value = (ml[0] * top_m[rows] / (det_m[0] * gap_m)).astype(float)  # m_1 too: one rounding to float64
        transfer[rows] = (-1.0) ** (N + 1) * top_sign[rows] * sign * np.ldexp(
            value, (top_e[rows] - det_e[0] - gap_e).astype(np.int64))
        spread = slack[rows, None] + slack[None, :]
        absolute_gaps = np.abs(np.asarray(gaps, dtype=float))
        terms = spread / absolute_gaps
        terms[np.arange(rows.size), rows] = 0.0
        coupling_terms = slack[rows, None] * np.abs(np.asarray(mo, dtype=float))[None, :] / np.abs(
            np.asarray(couplings[rows], dtype=float))
        relative[rows] = np.sum(terms, axis=1) + np.sum(coupling_terms, axis=1)
    relative += (8 * N) * _EPS_LD
    transfer_bound = np.abs(transfer) * relative + 0.5 * _EPS * np.abs(transfer)
    return omega_h, omega_l, omega_bound, transfer, transfer_bound
