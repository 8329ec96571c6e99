"""Normal modes by the best method for the chain, and the end responses built from them.

``normal_modes`` diagonalises exactly (:mod:`lcchain.theory.exact`) or uses
the paper's closed form (:mod:`lcchain.theory.closed_form`) for long free
quasi-uniform chains; the transmission amplitude alpha_N(t) (Eq. e.utn) and
the return amplitude are modal cosine sums (:func:`lcchain.theory.modes.cosine_sum`).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Literal, TypeAlias, TypeVar, get_args, overload

import numpy as np
from numpy.typing import ArrayLike

from ..core.blas import fixed_blas_threads
from ..core.checks import instance
from ..core.errors import ParameterError
from ..core.registry import Registry
from ..core.types import ModeMethod
from .chain import Chain
from .closed_form import closed_form_applies, closed_form_modes
from .exact import exact_modes
from .modes import Modes, cosine_sum

__all__ = ["normal_modes", "modes_of", "MODE_SOLVERS", "transmission_amplitude", "return_amplitude",
           "CLOSED_FORM_MIN_N", "driving_admittance", "admittance_with_bound", "loop_currents",
           "Arithmetic", "ARITHMETICS"]

#: A mode method: the normal modes of a chain.
ModeSolver = Callable[[Chain], Modes]

#: Below this N the "auto" method diagonalises exactly (it is cheap and needs no model).
CLOSED_FORM_MIN_N = 400


@fixed_blas_threads
def normal_modes(chain: Chain, method: ModeMethod | ModeSolver = "auto") -> Modes:
    """Normal modes of a chain by the requested method.

    Parameters
    ----------
    chain : Chain
    method : {"auto", "exact", "closed-form"} or callable
        ``"closed-form"`` uses the paper's Eqs. e.kn1, e.psik and e.Pk and
        needs a free quasi-uniform chain (one-mass, two-mass, uniform free)
        with N >= 5; ``"auto"`` uses it for N >= :data:`CLOSED_FORM_MIN_N`
        when it applies, and exact diagonalisation otherwise.  A function ``Chain -> Modes`` (a mode method
        of one's own, as ``solve_ivp(method=MyOdeSolver)``) is used as given, registered in
        :data:`MODE_SOLVERS` under its ``__name__`` the first time.
    """
    instance("chain", chain, Chain)
    return MODE_SOLVERS.accept("method", method)(chain)


def _closed_form(chain: Chain) -> Modes:
    reason = closed_form_applies(chain)
    if reason:
        raise ParameterError("method", "closed-form", f"a chain the closed form covers ({reason})")
    r, w = chain.rw()
    return closed_form_modes(chain.N, r, w)


def _auto(chain: Chain) -> Modes:
    if chain.N >= CLOSED_FORM_MIN_N and not closed_form_applies(chain):
        r, w = chain.rw()
        return closed_form_modes(chain.N, r, w)
    return exact_modes(chain)


def _admit(name: str, loaded: object) -> ModeSolver:
    """An ``lcchain.mode_methods`` entry point's object (or a mode method given as itself): a function."""
    if not callable(loaded) or isinstance(loaded, type):
        raise TypeError(f"{loaded!r} is not a function Chain -> Modes")
    if not name or name == "<lambda>":
        raise TypeError("it has no name (a def, not a lambda)")
    solver: ModeSolver = loaded
    return solver


_OWN_METHODS: dict[str, ModeSolver] = {"auto": _auto, "exact": exact_modes, "closed-form": _closed_form}

#: Each mode method's solver, the default first, then those of the ``lcchain.mode_methods`` entry points.  To
#: add one: a function Chain -> Modes here, its name in :data:`lcchain.core.types.ModeMethod` (a test checks
#: the two agree).
MODE_SOLVERS: Registry[ModeSolver] = Registry("lcchain.mode_methods", _OWN_METHODS, _admit,
                                              "a function Chain -> Modes, named as the entry point",
                                              name_of=lambda part: str(getattr(part, "__name__", "")))


def modes_of(chain_or_modes: Chain | Modes, method: ModeMethod | ModeSolver = "auto") -> Modes:
    """The modes given, or those of the chain given (ParameterError for anything else)."""
    instance("chain_or_modes", chain_or_modes, (Chain, Modes))
    return chain_or_modes if isinstance(chain_or_modes, Modes) else normal_modes(chain_or_modes, method)


# ------------------------------------------------------------------ responses
def _finite_times(t: ArrayLike) -> ArrayLike:
    """Times as given (a number or an array), or ParameterError naming the first that is not finite; text, a
    boolean or None is no time (``np.asarray("12.2", float)`` would read the text, and None as NaN)."""
    allowed = "times in units of sqrt(m/K): a number or an array of numbers"
    raw = np.asarray(t)
    if raw.dtype.kind in "bUSV" or (raw.dtype.kind == "O" and any(
            v is None or isinstance(v, str | bytes | bool | np.bool_) for v in raw.flat)):
        raise ParameterError("t", t, allowed)
    try:
        times = raw.astype(float)
    except (TypeError, ValueError, OverflowError):
        raise ParameterError("t", t, allowed) from None
    bad = np.flatnonzero(~np.isfinite(np.atleast_1d(times)))
    if bad.size:
        raise ParameterError(f"t[{bad[0]}]", float(np.atleast_1d(times)[bad[0]]), "a finite time")
    return t


@overload
def transmission_amplitude(chain_or_modes: Chain | Modes, t: float, method: ModeMethod = "auto") -> float: ...
@overload
def transmission_amplitude(chain_or_modes: Chain | Modes, t: np.ndarray | Sequence[float],
                           method: ModeMethod = "auto") -> np.ndarray: ...
@fixed_blas_threads
def transmission_amplitude(chain_or_modes: Chain | Modes, t: ArrayLike,
                           method: ModeMethod = "auto") -> np.ndarray | float:
    """Transmission amplitude alpha_N(t), Eq. e.utn.

    The far end's response to a kick (velocity, loop current) or to a
    displacement (position, loop charge) of mass 1, relative to the initial
    value: both are the same function of time.  For an asymmetric chain it
    is the exact modal response sqrt(m_1/m_N) sum U_n1 U_nN cos(omega_n t).

    Parameters
    ----------
    chain_or_modes : Chain or Modes
    t : float or array_like
        Time in units of sqrt(m/K) (in the circuit, sqrt(L0*C0)).
    method : {"auto", "exact", "closed-form"} or callable
        How to compute the modes when a Chain is given.
    """
    modes = modes_of(chain_or_modes, method)
    return cosine_sum(modes.transfer, modes.omega, _finite_times(t))


@overload
def return_amplitude(chain_or_modes: Chain | Modes, t: float, method: ModeMethod = "auto") -> float: ...
@overload
def return_amplitude(chain_or_modes: Chain | Modes, t: np.ndarray | Sequence[float],
                     method: ModeMethod = "auto") -> np.ndarray: ...
@fixed_blas_threads
def return_amplitude(chain_or_modes: Chain | Modes, t: ArrayLike, method: ModeMethod = "auto") -> np.ndarray | float:
    """The first mass's own response, sum_n P_n cos(omega_n t) (1 at t = 0).

    This is what comes back to loop 1 after each round trip.
    """
    modes = modes_of(chain_or_modes, method)
    return cosine_sum(modes.density, modes.omega, _finite_times(t))


#: A complex operation's relative rounding in the running error bound of :func:`admittance_with_bound`, in units of
#: the unit roundoff u (Higham, *Accuracy and Stability of Numerical Algorithms*, 2nd ed., Sec. 3.6: a complex
#: product within sqrt(2) gamma_2, a quotient within sqrt(2) gamma_4 ~ 5.7 u; 8 u bounds either, with the input's
#: own rounding).
_COMPLEX_ROUNDING = 8.0


def _continued_fraction(chain: Chain, omega: np.ndarray, Q: float | None, extended: bool
                        ) -> tuple[np.ndarray, np.ndarray]:
    """The first pivot d_1 of (s^2 + s/Q) M + K at s = j omega, eliminated from the far end, d_i = a_i - o_i^2 /
    d_(i+1), in float64 or (``extended``) long double, and its first-order running error bound |d_1 - exact| /
    |d_1| (Wilkinson's running error analysis: each step's rounding from the computed values themselves).  O(N)
    vector operations on the frequencies, never an (N x frequencies) array."""
    real = np.longdouble if extended else np.float64
    u = float(np.finfo(real).eps) / 2.0
    c = _COMPLEX_ROUNDING * u
    w: np.ndarray = np.asarray(omega, dtype=real)
    s: np.ndarray = w * np.asarray(1j, dtype=np.clongdouble if extended else np.complex128)
    lam = s * s + (0 if Q is None else s / real(Q))
    size = np.abs(lam).astype(float)  # |lambda|: the bound needs no extended precision
    mass, coupling = (np.asarray(band, dtype=float) for band in chain.mass_matrix_bands())
    K = np.asarray(chain.springs, dtype=float)
    springs: np.ndarray = np.asarray(K, dtype=real)  # the sums and squares of the springs in the working precision
    diagonal, square = springs[:-1] + springs[1:], springs[1:-1] * springs[1:-1]
    sizes = K[:-1] + K[1:]
    coupled = bool(np.any(coupling != 0))
    pivot = lam * real(mass[-1]) + diagonal[-1]
    error = c * (size * mass[-1] + sizes[-1])  # |d - exact|, absolute
    modulus = np.abs(pivot) if not extended else np.abs(pivot).astype(float)
    for i in range(chain.N - 2, -1, -1):
        # |o^2 / d| carries d's error relative, o's twice and the products' rounding; d_i = a_i - o^2 / d adds a_i's
        # rounding and the difference's
        if coupled:
            off = lam * real(coupling[i]) - springs[i + 1]
            off_size = np.abs(off).astype(float)
            term = off * off / pivot
            term_size = off_size * off_size / modulus
            term_error = term_size * (error / modulus + c + u) + 2.0 * off_size * c * (
                size * abs(coupling[i]) + K[i + 1]) / modulus
        else:
            term = square[i] / pivot
            term_size = (K[i + 1] * K[i + 1]) / modulus
            term_error = term_size * (error / modulus + (c + u))
        pivot = lam * real(mass[i]) + diagonal[i] - term
        error = term_error + (c + u) * (size * mass[i] + sizes[i])
        modulus = np.abs(pivot) if not extended else np.abs(pivot).astype(float)
    return pivot, error / modulus


# Double-double ("double-word") arithmetic: a real is an unevaluated sum hi + lo of float64s, |lo| <= ulp(hi) / 2.
# Exact transformations (Knuth's two-sum, Dekker's fast two-sum and his two-product by Veltkamp's splitting, no FMA)
# and the double-word blocks analysed by Joldes, Muller & Popescu (ACM TOMS 44(2), 2017): the accurate sum within
# 3u^2 + 13u^3, the quotient within 15u^2 + 56u^3; the product (exact two-product, the cross terms in float64) within
# 2^-102 (CRlibm's Mul22).  u = 2^-53; every array below is one float64 array per frequency, never N x frequencies.

#: The unit of one double-double operation in :func:`_continued_fraction_dd`'s running bound: 16 u^2 = 2^-102 bounds
#: the sum's, the product's and the quotient's relative error above (no underflow: the chain's values are O(1)), so
#: the complex bounds of :data:`_COMPLEX_ROUNDING` hold in this unit as they do in float64's (Higham, Sec. 3.6:
#: each real operation's relative error at most the unit).
_DOUBLE_DOUBLE_UNIT = 2.0 ** -102

_SPLITTER = 2.0 ** 27 + 1.0  # Veltkamp: a float64 into two halves of 26 bits whose products are exact

#: The primitives below take numpy arrays (the frequencies at once) or Python floats (:func:`_admittance_dd_few`).
R = TypeVar("R", np.ndarray, float)
Pair: TypeAlias = tuple[R, R]
DD: TypeAlias = tuple[np.ndarray, np.ndarray]


def _two_sum(a: R, b: R) -> Pair[R]:
    s = a + b
    v = s - a
    return s, (a - (s - v)) + (b - v)


def _fast_two_sum(a: R, b: R) -> Pair[R]:  # |a| >= |b|
    s = a + b
    return s, b - (s - a)


def _split(a: R) -> Pair[R]:
    """Veltkamp's halves of a (26 bits each): their pairwise products are exact."""
    t = _SPLITTER * a
    high = t - (t - a)
    return high, a - high


def _two_prod(a: R, b: R, a_halves: Pair[R] | None = None, b_halves: Pair[R] | None = None) -> Pair[R]:
    """Dekker's exact product; an operand's halves may be given when it is split once and used many times."""
    p = a * b
    ah, al = _split(a) if a_halves is None else a_halves
    bh, bl = _split(b) if b_halves is None else b_halves
    return p, ((ah * bh - p) + ah * bl + al * bh) + al * bl


def _dd_times(x: Pair[R], y: R, x_halves: Pair[R] | None = None, y_halves: Pair[R] | None = None) -> Pair[R]:
    """A double-double times a float64: _dd_mul with y's low part zero, the same values."""
    ch, cl = _two_prod(x[0], y, x_halves, y_halves)
    return _fast_two_sum(ch, cl + x[1] * y)


def _dd_add(x: Pair[R], y: Pair[R]) -> Pair[R]:  # the accurate sum (Joldes et al., Alg. 6)
    sh, sl = _two_sum(x[0], y[0])
    th, tl = _two_sum(x[1], y[1])
    vh, vl = _fast_two_sum(sh, sl + th)
    return _fast_two_sum(vh, tl + vl)


def _dd_neg(x: Pair[R]) -> Pair[R]:
    return -x[0], -x[1]


def _dd_mul(x: Pair[R], y: Pair[R]) -> Pair[R]:  # exact product of the highs, cross terms in float64 (Alg. 10; Mul22)
    ch, cl = _two_prod(x[0], y[0])
    return _fast_two_sum(ch, cl + (x[0] * y[1] + x[1] * y[0]))


def _dd_div(x: Pair[R], y: Pair[R]) -> Pair[R]:  # Alg. 15: one float64 quotient corrected once
    th = x[0] / y[0]
    rh, rl = _dd_times(y, th)
    delta = (x[0] - rh) + (x[1] - rl)
    return _fast_two_sum(th, delta / y[0])


def _dd_of(value: float) -> DD:
    """A float64 as a double-double of shape (1,), broadcast against the frequencies."""
    return np.array([value], dtype=float), np.zeros(1)


# A complex double-double is one double-double of shape (2, frequencies): the real parts in row 0, the imaginary in
# row 1, so that each complex operation is a few double-double operations on both rows at once.
_CONJUGATE, _REAL = np.array([[1.0], [-1.0]]), np.array([[1.0], [0.0]])


def _rows(x: DD, i: int) -> DD:
    return x[0][i], x[1][i]


def _stacked(x: DD, y: DD) -> DD:
    return np.stack((x[0], y[0])), np.stack((x[1], y[1]))


def _c_size(y: DD) -> DD:  # |y|^2
    squares = _dd_mul(y, y)
    return _dd_add(_rows(squares, 0), _rows(squares, 1))


def _c_mul(x: DD, y: DD) -> DD:
    straight, crossed = _dd_mul(x, y), _dd_mul(x, (y[0][::-1], y[1][::-1]))
    return _dd_add(_stacked(_rows(straight, 0), _rows(crossed, 0)),
                   _stacked(_dd_neg(_rows(straight, 1)), _rows(crossed, 1)))


def _c_div(x: DD, y: DD) -> DD:  # the naive quotient (Higham, Sec. 3.6: within sqrt(2) gamma_4 normwise)
    straight, crossed = _dd_mul(x, y), _dd_mul(x, (y[0][::-1], y[1][::-1]))
    numerator = _dd_add(_stacked(_rows(straight, 0), _rows(crossed, 1)),
                        _stacked(_rows(straight, 1), _dd_neg(_rows(crossed, 0))))
    return _dd_div(numerator, _c_size(y))


def _r_div(a: DD, y: DD, a_halves: DD | None = None) -> DD:
    """_c_div with a real numerator: fewer roundings, the same bound.  y's high parts split once for its square and
    the product."""
    halves = _split(y[0])
    ch, cl = _two_prod(y[0], y[0], halves, halves)
    squares = _fast_two_sum(ch, cl + (y[0] * y[1] + y[1] * y[0]))  # _dd_mul(y, y)
    size = _dd_add(_rows(squares, 0), _rows(squares, 1))
    ch, cl = _two_prod(a[0], y[0], a_halves, halves)
    quotient = _dd_div(_fast_two_sum(ch, cl + (a[0] * y[1] + a[1] * y[0])), size)  # _dd_mul(a, y) / |y|^2
    return quotient[0] * _CONJUGATE, quotient[1] * _CONJUGATE


def _c_modulus(x: DD) -> np.ndarray:
    modulus: np.ndarray = np.hypot(x[0][0], x[0][1])
    return modulus


def _continued_fraction_dd(chain: Chain, omega: np.ndarray, Q: float | None) -> tuple[DD, np.ndarray]:
    """:func:`_continued_fraction` in double-double: the pivot d_1 (a complex double-double, real and imaginary
    rows) and its first-order running error bound relative to |d_1|, the same sum in the unit
    :data:`_DOUBLE_DOUBLE_UNIT`."""
    u = _DOUBLE_DOUBLE_UNIT
    c = _COMPLEX_ROUNDING * u
    w = np.asarray(omega, dtype=float)
    zero = np.zeros_like(w)
    imag = (zero, zero) if Q is None else _dd_div((w, zero), _dd_of(float(Q)))
    lam = _stacked(_dd_neg(_two_prod(w, w)), imag)
    size = np.hypot(lam[0][0], lam[0][1])
    mass, coupling = (np.asarray(band, dtype=float) for band in chain.mass_matrix_bands())
    K = np.asarray(chain.springs, dtype=float)
    sizes = K[:-1] + K[1:]
    high, low = _two_sum(K[:-1], K[1:])  # exact; as complex columns (2 x 1) that broadcast
    diagonals = np.zeros((chain.N, 2, 1)), np.zeros((chain.N, 2, 1))
    diagonals[0][:, 0, 0], diagonals[1][:, 0, 0] = high, low
    squares = _two_prod(K, K)
    coupled = bool(np.any(coupling != 0))

    lam_halves, mass_halves, square_halves = _split(lam[0]), _split(mass), _split(squares[0])

    def diagonal(i: int) -> DD:
        scaled = _dd_times(lam, mass[i:i + 1], lam_halves, (mass_halves[0][i:i + 1], mass_halves[1][i:i + 1]))
        return _dd_add(scaled, (diagonals[0][i], diagonals[1][i]))

    pivot = diagonal(chain.N - 1)
    error = c * (size * mass[-1] + sizes[-1])
    modulus = _c_modulus(pivot)
    for i in range(chain.N - 2, -1, -1):
        if coupled:
            off = _dd_add(_dd_mul(lam, _dd_of(float(coupling[i]))), (_REAL * -K[i + 1], np.zeros((2, 1))))
            off_size = _c_modulus(off)
            term = _c_div(_c_mul(off, off), pivot)
            term_size = off_size * off_size / modulus
            term_error = term_size * (error / modulus + c + u) + 2.0 * off_size * c * (
                size * abs(coupling[i]) + K[i + 1]) / modulus
        else:
            term = _r_div((squares[0][i + 1:i + 2], squares[1][i + 1:i + 2]), pivot,
                          (square_halves[0][i + 1:i + 2], square_halves[1][i + 1:i + 2]))
            term_size = (K[i + 1] * K[i + 1]) / modulus
            term_error = term_size * (error / modulus + (c + u))
        pivot = _dd_add(diagonal(i), _dd_neg(term))
        error = term_error + (c + u) * (size * mass[i] + sizes[i])
        modulus = _c_modulus(pivot)
    return pivot, error / modulus


#: At most this many frequencies, an uncoupled chain's double-double pass runs frequency by frequency on Python floats
#: (:func:`_admittance_dd_few`): the same operations and values, without numpy's cost per call, which at a few
#: frequencies is most of each step (two-mass N = 100, 3 frequencies: 2.1 ms against 15 ms; N = 400, 8.2 against
#: 29 ms; at 8 frequencies about half, under load 3.7).
_FEW_FREQUENCIES = 8


def _admittance_dd_few(chain: Chain, omega: np.ndarray, Q: float | None) -> tuple[tuple[DD, DD], np.ndarray]:
    """:func:`_admittance_dd` for a chain without coupled coils, one frequency at a time on Python floats."""
    u = _DOUBLE_DOUBLE_UNIT
    c = _COMPLEX_ROUNDING * u
    mass = [float(v) for v in chain.mass_matrix_bands()[0]]
    K = [float(v) for v in chain.springs]
    sizes = [K[i] + K[i + 1] for i in range(chain.N)]
    diagonals = [_two_sum(K[i], K[i + 1]) for i in range(chain.N)]
    squares = [_two_prod(k, k) for k in K]
    mass_halves, square_halves = [_split(m) for m in mass], [_split(s[0]) for s in squares]
    result = np.zeros((4, omega.size))
    bound = np.zeros(omega.size)

    def quotient(a: Pair[float], a_halves: Pair[float] | None, real: Pair[float], imag: Pair[float]
                 ) -> tuple[Pair[float], Pair[float]]:  # _r_div: a / (real + j imag)
        real_halves, imag_halves = _split(real[0]), _split(imag[0])
        ch, cl = _two_prod(real[0], real[0], real_halves, real_halves)
        real_square = _fast_two_sum(ch, cl + (real[0] * real[1] + real[1] * real[0]))
        ch, cl = _two_prod(imag[0], imag[0], imag_halves, imag_halves)
        imag_square = _fast_two_sum(ch, cl + (imag[0] * imag[1] + imag[1] * imag[0]))
        size = _dd_add(real_square, imag_square)
        ch, cl = _two_prod(a[0], real[0], a_halves, real_halves)
        upper = _dd_div(_fast_two_sum(ch, cl + (a[0] * real[1] + a[1] * real[0])), size)
        ch, cl = _two_prod(a[0], imag[0], a_halves, imag_halves)
        lower = _dd_div(_fast_two_sum(ch, cl + (a[0] * imag[1] + a[1] * imag[0])), size)
        return upper, _dd_neg(lower)

    def diagonal(i: int, lam_real: Pair[float], lam_imag: Pair[float], real_halves: Pair[float],
                 imag_halves: Pair[float]) -> tuple[Pair[float], Pair[float]]:
        return (_dd_add(_dd_times(lam_real, mass[i], real_halves, mass_halves[i]), diagonals[i]),
                _dd_add(_dd_times(lam_imag, mass[i], imag_halves, mass_halves[i]), (0.0, 0.0)))

    for k, w in enumerate(omega.tolist()):
        lam_real = _dd_neg(_two_prod(w, w))
        lam_imag = (0.0, 0.0) if Q is None else _dd_div((w, 0.0), (float(Q), 0.0))
        size = math.hypot(lam_real[0], lam_imag[0])
        lam = (lam_real, lam_imag, _split(lam_real[0]), _split(lam_imag[0]))
        real, imag = diagonal(chain.N - 1, *lam)
        error = c * (size * mass[-1] + sizes[-1])
        modulus = math.hypot(real[0], imag[0])
        for i in range(chain.N - 2, -1, -1):
            upper, lower = quotient(squares[i + 1], square_halves[i + 1], real, imag)
            term_size = (K[i + 1] * K[i + 1]) / modulus
            term_error = term_size * (error / modulus + (c + u))
            a_real, a_imag = diagonal(i, *lam)
            real, imag = _dd_add(a_real, _dd_neg(upper)), _dd_add(a_imag, _dd_neg(lower))
            error = term_error + (c + u) * (size * mass[i] + sizes[i])
            modulus = math.hypot(real[0], imag[0])
        upper, lower = quotient((w, 0.0), None, real, imag)  # omega / d_1; times j exactly
        result[:, k] = (*_dd_neg(lower), *upper)
        bound[k] = error / modulus + c
    return ((result[0], result[1]), (result[2], result[3])), bound


def _admittance_dd(chain: Chain, omega: np.ndarray, Q: float | None) -> tuple[tuple[DD, DD], np.ndarray]:
    """Y_11 Z0 = j omega / d_1 in double-double, unrounded (real and imaginary parts, each hi + lo), and its relative
    bound (the pivot's and the quotient's)."""
    w = np.asarray(omega, dtype=float)
    if w.size <= _FEW_FREQUENCIES and not np.any(chain.mass_matrix_bands()[1] != 0):
        return _admittance_dd_few(chain, w, Q)
    pivot, relative = _continued_fraction_dd(chain, w, Q)
    quotient = _r_div((w, np.zeros_like(w)), pivot)  # omega / d_1; times j exactly
    return (_dd_neg(_rows(quotient, 1)), _rows(quotient, 0)), relative + _COMPLEX_ROUNDING * _DOUBLE_DOUBLE_UNIT


#: The arithmetics of the exact admittance, bluntest (and cheapest) first: :func:`admittance_with_bound` passes a
#: frequency to the next where the bound of one is above what is wanted.
Arithmetic = Literal["float64", "long double", "double-double"]
ARITHMETICS: tuple[Arithmetic, ...] = get_args(Arithmetic)


def _admittance_in(chain: Chain, w: np.ndarray, Q: float | None, arithmetic: Arithmetic
                   ) -> tuple[np.ndarray, np.ndarray]:
    """Y_11 Z0 in one arithmetic, rounded to complex128, and its relative bound (that rounding included)."""
    eps = float(np.finfo(float).eps)
    if arithmetic == "float64":
        pivot, relative = _continued_fraction(chain, w, Q, extended=False)
        return 1j * w / pivot, relative + _COMPLEX_ROUNDING * eps
    if arithmetic == "long double":
        pivot, relative = _continued_fraction(chain, w, Q, extended=True)
        return np.asarray(1j * w.astype(np.longdouble) / pivot, dtype=complex), relative + eps
    (real, imag), relative = _admittance_dd(chain, w, Q)
    return (real[0] + real[1]) + 1j * (imag[0] + imag[1]), relative + eps


def admittance_with_bound(chain: Chain, omega: np.ndarray, Q: float | None = None, rtol: float = 0.0,
                          start: Arithmetic = "float64") -> tuple[np.ndarray, np.ndarray]:
    """The ladder's Y_11 Z0 (:func:`driving_admittance`) and a bound on its relative error at each frequency.

    The continued fraction runs in float64 with a first-order running error bound (Wilkinson; Higham, Sec. 3.3):
    at each pivot d_i = a_i - o_i^2 / d_(i+1) the rounding of a_i, of o_i^2 and of the quotient (each within
    :data:`_COMPLEX_ROUNDING` u of its size) and d_(i+1)'s own error, taken relative to |d_i|.  The bound grows
    where a pivot cancels (near a resonance of Y_11's chain or of a tail's: about u Q omega_n at a lossy peak).
    Where it exceeds ``rtol`` the frequency is computed again in long double (``numpy.clongdouble``, u = 2^-64 on
    x86-64), and where that bound still exceeds ``rtol``, in double-double (:data:`_DOUBLE_DOUBLE_UNIT` = 2^-102),
    each bound the same running sum in that arithmetic's unit (:data:`ARITHMETICS`).  A frequency one arithmetic
    settles keeps that arithmetic's value, bit for bit.  Every result is rounded to complex128 (its bound includes
    that rounding, u = 2^-53: no arithmetic's bound goes below it).

    Parameters
    ----------
    chain : Chain
    omega : ndarray
        Angular frequencies, units of 1/sqrt(L0 C0), > 0.
    Q : float, optional
        The losses' quality factor; None: lossless.
    rtol : float
        The relative bound wanted; 0: every frequency in the sharpest arithmetic (double-double); inf: every
        frequency in ``start``.
    start : {"float64", "long double", "double-double"}
        The first arithmetic tried.

    Returns
    -------
    Y : ndarray, complex
    bound : ndarray
        Each frequency's relative error bound (first order).
    """
    instance("chain", chain, Chain)
    if start not in ARITHMETICS:
        raise ParameterError("start", start, f"one of {', '.join(ARITHMETICS)}")
    w = np.asarray(omega, dtype=float)
    Y, bound = np.empty(w.size, dtype=complex), np.empty(w.size)
    again = np.ones(w.size, dtype=bool)
    tiers = ARITHMETICS[ARITHMETICS.index(start):]
    if rtol <= 0:
        tiers = tiers[-1:]
    for arithmetic in tiers:
        Y[again], bound[again] = _admittance_in(chain, w[again], Q, arithmetic)
        again &= bound > rtol
        if not again.any():
            break
    return Y, bound


def driving_admittance(chain: Chain, omega: np.ndarray, Q: float | None = None, rtol: float = 0.0) -> np.ndarray:
    """The ladder's Y_11 Z0 = I_1/V_1 sqrt(L0/C0) at s = j omega, exactly: the velocity of mass 1 per unit force on
    it, s [(s^2 + s/Q) M + K]^(-1)_11 (Eq. e.Horig with losses proportional to the masses, gamma = 1/Q).

    No modes: the (1, 1) entry of the tridiagonal's inverse by its continued fraction from the far end, so a merged
    spectrum's envelope is compared with the circuit's whatever the modes' overlap; in float64 where its running
    error bound is at most ``rtol``, else in long double, else in double-double (:func:`admittance_with_bound`, which
    also returns the bound; ``rtol`` = 0: every frequency in double-double).

    Parameters
    ----------
    chain : Chain
        Any chain (walls and coupled coils included: M is then tridiagonal).
    omega : ndarray
        Angular frequencies, units of 1/sqrt(L0 C0), > 0.
    Q : float, optional
        The losses' quality factor; None: lossless.
    rtol : float
        The relative error bound wanted at each frequency (0: double-double everywhere).
    """
    return admittance_with_bound(chain, omega, Q, rtol)[0]


#: Complex values (loops x frequencies) of each of :func:`loop_currents`' two elimination arrays at once: a block of
#: 2^20 / N frequencies (16 MB each).
_CURRENTS_BLOCK_VALUES = 2**20


def loop_currents(chain: Chain, omega: np.ndarray, drive: np.ndarray, Q: float | None = None) -> np.ndarray:
    """Every loop's current over j omega when every loop is driven, exactly from the chain: g = I / (j omega) Z0 =
    [K - omega^2 M + j omega M / Q]^(-1) b (the survey's samples, :mod:`lcchain.compare.survey`), no modes.

    The tridiagonal is eliminated from loop 1 (the Thomas algorithm, frequencies side by side, in blocks of
    :data:`_CURRENTS_BLOCK_VALUES` / N), so modes merged by the losses are compared however they overlap; float64,
    O(frequencies x N).  Against long double it is within 2.9e-12, 3.6e-11 and 1.1e-10 (largest over the loops
    relative to the largest, over a survey's sweep) at two-mass N = 100, 400 and 1000, Q = 1000.

    Parameters
    ----------
    chain : Chain
        Any chain (coupled coils: M is then tridiagonal).
    omega : ndarray
        Angular frequencies, units of 1/sqrt(L0 C0), > 0.
    drive : ndarray, complex
        The sources' amplitudes b_k in loops 1..N.
    Q : float, optional
        The losses' quality factor; None: lossless.

    Returns
    -------
    ndarray, complex, (frequencies, loops)
    """
    instance("chain", chain, Chain)
    w = np.asarray(omega, dtype=float)
    b = np.asarray(drive, dtype=complex)
    if b.shape != (chain.N,):
        raise ParameterError("drive", b.shape, f"one amplitude per loop ({chain.N})")
    K = np.asarray(chain.springs, dtype=float)
    m, mutual = chain.mass_matrix_bands()
    coupled = bool(np.any(mutual))
    out = np.empty((w.size, chain.N), dtype=complex)
    block = max(1, _CURRENTS_BLOCK_VALUES // chain.N)
    for start in range(0, w.size, block):
        ws = w[start:start + block]
        lam = -ws * ws + (0j if Q is None else 1j * ws / Q)  # (s^2 + s/Q) at s = j omega, complex either way
        inverse = np.empty((chain.N, ws.size), dtype=complex)  # 1 / pivot
        rhs = np.empty((chain.N, ws.size), dtype=complex)
        for i in range(chain.N):
            diagonal = (K[i] + K[i + 1]) + lam * m[i]
            if not i:
                rhs[i] = b[i]
            elif coupled:
                below = -K[i] + lam * mutual[i - 1]  # A[i, i-1] = A[i-1, i]
                factor = below * inverse[i - 1]
                diagonal -= factor * below
                rhs[i] = b[i] - factor * rhs[i - 1]
            else:  # A[i, i-1] = -K_i: fewer operations on each block (a survey's lossy chain)
                factor = K[i] * inverse[i - 1]
                diagonal -= K[i] * factor
                rhs[i] = b[i] + factor * rhs[i - 1]
            np.divide(1.0, diagonal, out=inverse[i])
        current = rhs[-1] * inverse[-1]
        out[start:start + ws.size, -1] = current
        for i in range(chain.N - 2, -1, -1):
            above = -K[i + 1] + lam * mutual[i] if coupled else -K[i + 1]
            current = (rhs[i] - above * current) * inverse[i]
            out[start:start + ws.size, i] = current
    return out
