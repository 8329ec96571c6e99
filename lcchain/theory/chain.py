"""The spring-mass chain: N masses and N+1 springs, in bulk units.

A :class:`Chain` stores one canonical representation, the physical masses
``m_i`` (i = 1..N) and spring constants ``K_{i,i+1}`` (i = 0..N, walls
included, 0 = free end), in units of the bulk mass m and bulk spring K
(Eq. e.Horig of the paper).  The paper's parametrisations, (x, y, z) of
Eq. e.mKxyz and (r, w) of Eq. e.rw, are constructors and views.

Every constructor validates its input and raises
:class:`~lcchain.core.errors.ParameterError` naming the field, the value and the
allowed range.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from fractions import Fraction
from typing import TypeAlias

import numpy as np

from ..core.checks import integer, is_number, real
from ..core.errors import ParameterError
from ..core.frozen import FrozenMap, Reduced, readonly
from ..core.json import JSONObject
from ..core.limits import MAX_DESIGN_N, MIN_N

__all__ = ["Chain", "MIN_N", "PERFECT_N", "PERFECT_ARRIVAL", "MAX_COUPLING"]

#: |k| below this keeps the tridiagonal mass matrix positive definite for every N (1 + 2k cos(pi/(N+1)) > 0).
MAX_COUPLING = 0.5

#: Sizes with a perfectly transmitting chain (Sec. II.C and Appendix A).
PERFECT_N = (3, 4, 5)

# Relative tolerance used to recognise the structure of a chain built from
# floats (mirror symmetry, uniform bulk, the constraint A_22 = 0).
_STRUCTURE_RTOL = 1e-12

# Exact rational masses and springs of the perfect chains, Sec. II.C, Eq. e.N5.
_PERFECT = {
    3: ((Fraction(3, 2), Fraction(1), Fraction(3, 2)), (0, 1, 1, 0)),
    4: (
        (Fraction(55, 36), Fraction(11, 12), Fraction(11, 12), Fraction(55, 36)),
        (0, Fraction(5, 6), 1, Fraction(5, 6), 0),
    ),
    5: (
        (Fraction(35, 18), Fraction(10, 9), 1, Fraction(10, 9), Fraction(35, 18)),
        (0, Fraction(7, 9), 1, 1, Fraction(7, 9), 0),
    ),
}
#: Arrival times of the perfect chains: pi / (frequency spacing), Sec. II.C (read-only: one process shares it).
PERFECT_ARRIVAL: FrozenMap[int, float] = FrozenMap({
    3: math.sqrt(1.5) * math.pi,
    4: math.sqrt(11.0) * math.pi / 2.0,
    5: math.sqrt(5.0) * math.pi,
})


def _check_N(N: object, field_name: str = "N") -> int:
    # the documented maximum first: a chain of 10^12 masses would be a 7 TiB array before any other check
    return integer(field_name, N, at_least=MIN_N, at_most=MAX_DESIGN_N)


def _check_real(name: str, value: object) -> float:
    return real(name, value, allowed="a finite real number")


#: What a chain's masses and springs may be (the words of their errors).
_MASSES, _SPRINGS = "a list of N positive numbers", "a list of N+1 non-negative numbers"
#: How a named chain was built, for its views: ("xyz", x, y, z), ("rw", r, w) or ("perfect",); () for others.
ChainParams: TypeAlias = tuple[()] | tuple[str, *tuple[float, ...]]


def _numeric_array(name: str, values: object, allowed: str) -> np.ndarray:
    """Numbers only: a list of int/float (numpy scalars included) or a numeric numpy array."""
    if isinstance(values, np.ndarray):
        if values.dtype.kind not in "iuf":
            raise ParameterError(name, f"an array of dtype {values.dtype}", allowed)
        return np.array(values, dtype=float)
    if isinstance(values, (str, bytes, Mapping)) or not isinstance(values, Sequence):
        # a set or a generator has no order a chain could rely on (a set comes out in hash order)
        raise ParameterError(name, values, f"{allowed} (a list, tuple or numpy array: an ordered sequence)")
    items = list(values)
    if any(isinstance(value, (list, tuple, np.ndarray)) for value in items):
        raise ParameterError(name, values, "a flat list of numbers")
    numbers = []
    for i, value in enumerate(items):
        if not is_number(value):
            raise ParameterError(f"{name}[{i}]", value, "a number")
        try:
            numbers.append(float(value))
        except OverflowError:  # an int past the largest float (10**400)
            raise ParameterError(f"{name}[{i}]", value, "a finite number") from None
    return np.array(numbers, dtype=float)


@dataclass(frozen=True, eq=False)
class Chain:
    """A chain of N masses joined by springs, in units of the bulk m and K.

    Parameters
    ----------
    masses : array_like of float, shape (N,)
        Masses m_1..m_N in units of the bulk mass m; finite and > 0.
    springs : array_like of float, shape (N+1,)
        Spring constants K_01, K_12, ..., K_{N,N+1} in units of the bulk
        spring K; the first and last are the wall springs (0 = free end),
        the inner ones must be > 0 (a zero inner spring would cut the chain).
    name : str, optional
        A label (``"two-mass"``, ``"custom"``), used in reports only.
    coupling : float, optional
        Inertial coupling k of neighbouring masses, -1/2 < k < 1/2: the mass
        matrix is tridiagonal with M_ii = m_i and M_{i,i+1} = k sqrt(m_i m_{i+1})
        (in the LC ladder, a mutual inductance k sqrt(L_i L_{i+1}) between
        neighbouring coils).  0 (the paper's chain): M is diagonal.  |k| < 1/2
        keeps M positive definite for every N.

    Notes
    -----
    The time unit is sqrt(m/K); in the LC ladder it is sqrt(L0*C0).
    """

    masses: np.ndarray
    springs: np.ndarray
    name: str = "custom"
    coupling: float = 0.0
    _params: ChainParams = field(default=(), repr=False, compare=False)

    def __post_init__(self) -> None:
        masses = _numeric_array("masses", self.masses, _MASSES)
        springs = _numeric_array("springs", self.springs, _SPRINGS)
        if masses.ndim != 1:
            raise ParameterError("masses", self.masses, "a flat list of N positive numbers")
        N = masses.size
        if N < MIN_N:
            raise ParameterError("N", N, f"an integer >= {MIN_N} (the number of masses)")
        if springs.ndim != 1 or springs.size != N + 1:
            raise ParameterError(
                "springs", f"{springs.size} values", f"N+1 = {N + 1} values (walls first and last)"
            )
        bad = np.flatnonzero(~(np.isfinite(masses) & (masses > 0)))
        if bad.size:
            raise ParameterError(f"masses[{bad[0]}]", float(masses[bad[0]]), "a finite number > 0")
        inner = np.zeros(N + 1, dtype=bool)
        inner[1:-1] = True
        bad = np.flatnonzero(~np.isfinite(springs) | (springs < 0) | (inner & (springs == 0)))
        if bad.size:
            i = int(bad[0])
            allowed = "a finite number > 0 (an inner spring)" if inner[i] else "a finite number >= 0 (0 = free end)"
            raise ParameterError(f"springs[{i}]", float(springs[i]), allowed)
        object.__setattr__(self, "masses", readonly(masses))
        object.__setattr__(self, "springs", readonly(springs))
        if not isinstance(self.name, str):
            raise ParameterError("name", self.name, "a string")
        coupling = real("coupling", self.coupling, above=-MAX_COUPLING, below=MAX_COUPLING,
                        allowed=f"a coupling coefficient -{MAX_COUPLING:g} < k < {MAX_COUPLING:g} "
                                "(the mass matrix stays positive definite for every N)")
        object.__setattr__(self, "coupling", coupling + 0.0)  # -0.0 is 0.0

    def __reduce__(self) -> Reduced:
        # Rebuilt through __init__: validated again, and the arrays read-only again.
        return (type(self), (self.masses, self.springs, self.name, self.coupling, self._params))

    @property
    def coupled(self) -> bool:
        """Whether neighbouring masses are coupled (a tridiagonal mass matrix)."""
        return self.coupling != 0.0

    def with_coupling(self, coupling: float) -> Chain:
        """The same masses and springs with the inertial coupling k (see ``coupling``)."""
        return type(self)(self.masses, self.springs, name=self.name, coupling=coupling, _params=self._params)

    def mass_matrix_bands(self) -> tuple[np.ndarray, np.ndarray]:
        """Diagonal m_i and off-diagonal k sqrt(m_i m_{i+1}) of the mass matrix (bulk units)."""
        m = self.masses
        return np.array(m), self.coupling * np.sqrt(m[:-1] * m[1:])

    # ------------------------------------------------------------------ basics
    @property
    def N(self) -> int:
        """Number of masses."""
        return int(self.masses.size)

    @property
    def free_ends(self) -> tuple[bool, bool]:
        """Whether the first and the last mass are free (no wall spring)."""
        return bool(self.springs[0] == 0), bool(self.springs[-1] == 0)

    @property
    def is_free(self) -> bool:
        """True when both ends are free: the chain has a zero (Goldstone) mode."""
        return all(self.free_ends)

    @property
    def is_symmetric(self) -> bool:
        """Mirror symmetry i -> N+1-i (Sec. II.A), to a relative 1e-12."""
        return bool(
            np.allclose(self.masses, self.masses[::-1], rtol=_STRUCTURE_RTOL, atol=0)
            and np.allclose(self.springs, self.springs[::-1], rtol=_STRUCTURE_RTOL, atol=0)
        )

    def require_symmetric(self, what: str = "this computation") -> None:
        """Raise :class:`ParameterError` unless the chain is mirror symmetric."""
        if not self.is_symmetric:
            raise ParameterError(
                "chain",
                f"{self.name} chain with masses[0]={float(self.masses[0])!r}, masses[-1]={float(self.masses[-1])!r}",
                f"a mirror-symmetric chain for {what}",
            )

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Chain):
            return NotImplemented
        return bool(np.array_equal(self.masses, other.masses) and np.array_equal(self.springs, other.springs)
                    and self.coupling == other.coupling)

    def __hash__(self) -> int:
        # + 0.0 turns -0.0 into 0.0, which __eq__ already treats as equal
        return hash(((self.masses + 0.0).tobytes(), (self.springs + 0.0).tobytes(), self.coupling))

    def __repr__(self) -> str:
        def short(a: np.ndarray) -> str:
            if a.size <= 8:
                return "[" + ", ".join(f"{v:.6g}" for v in a) + "]"
            head = ", ".join(f"{v:.6g}" for v in a[:3])
            tail = ", ".join(f"{v:.6g}" for v in a[-3:])
            return f"[{head}, ..., {tail}]"

        coupled = f", coupling={self.coupling:.6g}" if self.coupled else ""
        return (f"Chain(name={self.name!r}, N={self.N}, masses={short(self.masses)}, springs={short(self.springs)}"
                f"{coupled})")

    def to_dict(self) -> JSONObject:
        """The chain as the JSON object ``{"masses": [...], "springs": [...]}`` (bulk units; ``coupling`` if not 0)."""
        data: JSONObject = {"masses": [float(m) for m in self.masses], "springs": [float(k) for k in self.springs]}
        if self.coupled:
            data["coupling"] = self.coupling
        return data

    @classmethod
    def from_dict(cls, data: object, where: str | None = None) -> Chain:
        """Build a chain from ``{"masses": [...], "springs": [...]}``.

        Parameters
        ----------
        data : mapping
            The two lists, in bulk units; ``springs`` has N+1 entries, walls
            first and last.  The chain need not be symmetric.
        where : str, optional
            Where the data came from (a file name), for error messages.
        """
        if not isinstance(data, dict):
            raise ParameterError("chain", type(data).__name__, 'an object {"masses": [...], "springs": [...]}', where)
        unknown = sorted(set(data) - {"masses", "springs", "name", "coupling"})
        if unknown:
            raise ParameterError(unknown[0], data[unknown[0]], 'only the keys "masses", "springs" and "coupling"',
                                 where)
        for key in ("masses", "springs"):
            if key not in data:
                raise ParameterError(key, None, f'a list of numbers under "{key}"', where)
            if not isinstance(data[key], list) or not all(
                isinstance(v, (int, float)) and not isinstance(v, bool) for v in data[key]
            ):
                raise ParameterError(key, data[key], "a list of numbers", where)
        try:
            return cls(data["masses"], data["springs"], name=str(data.get("name", "custom")),
                       coupling=data.get("coupling", 0.0))
        except ParameterError as error:
            raise ParameterError(error.field, error.value, error.allowed, where) from None

    # ------------------------------------------------------------ constructors
    @classmethod
    def from_physical(cls, masses: Sequence[float] | np.ndarray, springs: Sequence[float] | np.ndarray,
                      name: str = "custom") -> Chain:
        """The chain with the given masses and springs (bulk units); same as ``Chain(...)``."""
        return cls(_numeric_array("masses", masses, _MASSES), _numeric_array("springs", springs, _SPRINGS), name=name)

    @classmethod
    def _quasi_uniform(cls, N: int, m1: float, m2: float, K01: float, K12: float, name: str,
                       params: ChainParams) -> Chain:
        N = _check_N(N)
        masses = np.ones(N)
        springs = np.ones(N + 1)
        masses[0] = masses[-1] = m1
        springs[0] = springs[-1] = K01
        if N == 3:
            # (m1, m2, m1) joined by K12 twice: m_2 is the middle mass.
            masses[1] = m2
            springs[1] = springs[2] = K12
        else:
            masses[1] = masses[-2] = m2
            springs[1] = springs[-2] = K12
        return cls(masses, springs, name=name, _params=params)

    @classmethod
    def from_xyz(cls, N: int, x: float, y: float, z: float) -> Chain:
        """Quasi-uniform chain from the paper's (x, y, z), Eq. e.mKxyz.

        Parameters
        ----------
        N : int
            Number of masses, >= 3.
        x, y, z : float
            Dimensionless end parameters (Eq. e.xyz): 0 < y < sqrt(2),
            x > 0, z <= z0 = 2 - x^2/(2 - y^2) (z = z0: free ends).  For
            N = 3 the constrained model needs y = 1.

        Returns
        -------
        Chain
            m_2 = 1/y^2, m_1 = (2-y^2)^2/(x^2 y^2), K_12 = (2-y^2)/y^2,
            K_01 = (2-y^2)/(x^2 y^2) [(2-y^2)(2-z) - x^2].
        """
        N = _check_N(N)
        x = _check_real("x", x)
        y = _check_real("y", y)
        z = _check_real("z", z)
        if not 0 < y < math.sqrt(2):
            raise ParameterError("y", y, "0 < y < sqrt(2) (so that m2 and K12 are positive)")
        if not x > 0:
            raise ParameterError("x", x, "x > 0")
        r = 2 - y * y
        z0 = 2 - x * x / r
        if z > z0 * (1 + _STRUCTURE_RTOL) + _STRUCTURE_RTOL:
            raise ParameterError("z", z, f"z <= z0 = 2 - x^2/(2-y^2) = {z0!r} (so that the wall spring K01 >= 0)")
        if N == 3 and abs(y - 1) > _STRUCTURE_RTOL:
            raise ParameterError("y", y, "y = 1 for N = 3 (the constrained model A_22 = 0 fixes m2 = K12)")
        m2 = 1 / (y * y)
        m1 = r * r / (x * x * y * y)
        K12 = r / (y * y)
        K01 = r / (x * x * y * y) * (r * (2 - z) - x * x)
        # z = z0 means a free end; rounding must not leave a 1e-15 wall spring.
        scale = r / (x * x * y * y) * (r * abs(2 - z) + x * x)
        if K01 <= 64 * np.finfo(float).eps * scale:
            K01 = 0.0
        return cls._quasi_uniform(N, m1, m2, K01, K12, "xyz", ("xyz", x, y, z))

    @classmethod
    def from_rw(cls, N: int, r: float, w: float) -> Chain:
        """Free quasi-uniform chain from the paper's (r, w), Eqs. e.rw and e.m1m2K12-rw.

        Parameters
        ----------
        N : int
            Number of masses, >= 3 (for N = 3 the constrained model needs r = 1).
        r, w : float
            r = 2 - y^2 in (0, 2), w = x^2/r > 0.  z = z0 = 2 - w (free ends).

        Returns
        -------
        Chain
            m_1 = r/((2-r) w), m_2 = 1/(2-r), K_12 = r/(2-r), K_01 = 0.
        """
        N = _check_N(N)
        r = _check_real("r", r)
        w = _check_real("w", w)
        if not 0 < r < 2:
            raise ParameterError("r", r, "0 < r < 2 (so that m2 = 1/(2-r) and K12 = r/(2-r) are positive)")
        if not w > 0:
            raise ParameterError("w", w, "w > 0 (so that m1 = r/((2-r) w) is positive and finite)")
        if N == 3 and abs(r - 1) > _STRUCTURE_RTOL:
            raise ParameterError("r", r, "r = 1 for N = 3 (the constrained model A_22 = 0 fixes m2 = K12)")
        return cls._quasi_uniform(N, r / ((2 - r) * w), 1 / (2 - r), 0.0, r / (2 - r), "two-mass", ("rw", r, w))

    @classmethod
    def two_mass(cls, N: int, r: float, w: float) -> Chain:
        """Two-mass chain of Sec. V: free ends, m_1, m_2, K_12 from (r, w). Same as :meth:`from_rw`."""
        return cls.from_rw(N, r, w)

    @classmethod
    def one_mass(cls, N: int, x: float) -> Chain:
        """One-mass chain of Sec. IV: free ends, m_1 = m_N = 1/x^2, everything else uniform (Eq. e.m1x).

        Parameters
        ----------
        x : float
            0 < x < sqrt(2) (x = 1 is the uniform free chain).
        """
        N = _check_N(N)
        x = _check_real("x", x)
        if not 0 < x < math.sqrt(2):
            raise ParameterError("x", x, "0 < x < sqrt(2) (m1 = 1/x^2, Delta = x^2/(2-x^2) > 0)")
        chain = cls._quasi_uniform(N, 1 / (x * x), 1.0, 0.0, 1.0, "one-mass", ("rw", 1.0, x * x))
        return chain

    @classmethod
    def uniform_free(cls, N: int) -> Chain:
        """Uniform chain with free ends, (x, y, z) = (1, 1, 1)."""
        N = _check_N(N)
        springs = np.ones(N + 1)
        springs[0] = springs[-1] = 0.0
        return cls(np.ones(N), springs, name="uniform-free", _params=("rw", 1.0, 1.0))

    @classmethod
    def uniform_bounded(cls, N: int) -> Chain:
        """Uniform chain tied to walls by bulk springs, (x, y, z) = (1, 1, 0)."""
        N = _check_N(N)
        return cls(np.ones(N), np.ones(N + 1), name="uniform-bounded", _params=("xyz", 1.0, 1.0, 0.0))

    @classmethod
    def perfect(cls, N: int, bulk: bool = False) -> Chain:
        """The perfectly transmitting chains N = 3, 4, 5 as the paper prints them (Sec. II.C, Eq. e.N5).

        N = 3: masses (3/2, 1, 3/2); N = 4: (55/36, 11/12, 11/12, 55/36) with
        K_12 = 5/6; N = 5: (35/18, 10/9, 1, 10/9, 35/18) with K_12 = 7/9, which
        lies outside the constrained model (A_22 != 0).  The frequencies are
        equally spaced and alpha_N = 1 at :data:`PERFECT_ARRIVAL`.

        With ``bulk=True`` the masses are divided by the central one (exactly,
        in fractions), the units of :func:`lcchain.perfect_design` for any N:
        N = 4 becomes (5/3, 1, 1, 5/3), Fig. cradle4; N = 3 and 5 are unchanged.
        """
        if isinstance(N, bool) or not isinstance(N, (int, np.integer)) or int(N) not in _PERFECT:
            raise ParameterError("N", N, "3, 4 or 5 (the perfect chains of the paper; any N: perfect_design)")
        masses, springs = _PERFECT[int(N)]
        central = Fraction(masses[len(masses) // 2]) if bulk else Fraction(1)
        return cls(np.array([float(m / central) for m in masses]), np.array([float(k) for k in springs]),
                   name="perfect", _params=("perfect",))

    # ------------------------------------------------------------------- views
    def _end_parameters(self) -> tuple[float, float, float, float] | None:
        """(m1, m2, K01, K12) if the chain is quasi-uniform and symmetric, else None."""
        if not self.is_symmetric:
            return None
        N, m, k = self.N, self.masses, self.springs
        m1, K01 = float(m[0]), float(k[0])
        if N == 3:
            m2, K12 = float(m[1]), float(k[1])
            if not math.isclose(K12, m2, rel_tol=_STRUCTURE_RTOL):
                return None  # A_22 = 2 K12/m2 must be 2
            return m1, m2, K01, K12
        m2, K12 = float(m[1]), float(k[1])
        bulk_m = m[2:-2]
        bulk_k = k[2:-2]
        if not (np.allclose(bulk_m, 1.0, rtol=0, atol=_STRUCTURE_RTOL)
                and np.allclose(bulk_k, 1.0, rtol=0, atol=_STRUCTURE_RTOL)):
            return None
        if not math.isclose((K12 + 1.0) / m2, 2.0, rel_tol=_STRUCTURE_RTOL):
            return None  # the constraint A_22 = 0 of Eq. e.xyz
        return m1, m2, K01, K12

    def is_quasi_uniform(self) -> bool:
        """True when the chain belongs to the paper's constrained model (Eq. e.AN)."""
        return self._end_parameters() is not None

    def xyz(self) -> tuple[float, float, float]:
        """The paper's (x, y, z) of this chain, Eq. e.xyz.

        Raises
        ------
        ParameterError
            If the chain is not symmetric and quasi-uniform (uniform bulk,
            A_22 = 0): the view does not exist.
        """
        if self._params and self._params[0] == "xyz":
            return tuple(float(v) for v in self._params[1:])  # type: ignore[return-value]
        ends = self._end_parameters()
        if ends is None:
            raise ParameterError("chain", self.name,
                                 "a symmetric quasi-uniform chain (uniform bulk, A_22 = 0) for the (x, y, z) view")
        if self._params and self._params[0] == "rw":
            r, w = self._params[1:]
            return math.sqrt(r * w), math.sqrt(2 - r), 2 - w
        m1, m2, K01, K12 = ends
        x = K12 / math.sqrt(m1 * m2)
        y = 1 / math.sqrt(m2)
        z = 2 - (K01 + K12) / m1
        return x, y, z

    def rw(self) -> tuple[float, float]:
        """The paper's (r, w) of this chain, Eq. e.rw (free quasi-uniform chains only)."""
        if self._params and self._params[0] == "rw":
            r, w = self._params[1:]
            return float(r), float(w)
        if not self.is_free:
            raise ParameterError("chain", self.name, "a chain with free ends (K01 = 0) for the (r, w) view")
        x, y, _ = self.xyz()
        r = 2 - y * y
        return r, x * x / r
