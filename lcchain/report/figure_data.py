"""The numbers behind the paper's figures, computed by lcchain (no drawing, no matplotlib).

Each function returns plain data (lists, arrays, dicts) that
:mod:`lcchain.report.paper_figures` draws and the tests check against the
paper (the δ* points are the table values, P_k sums to 1, ...).  Rows of
Tables I and II come from :class:`DesignRows`, which computes each (case, N)
once and may keep it in a cache file.
"""

from __future__ import annotations

import hashlib
import json
import math
import os
from collections.abc import Callable, Iterable, Mapping, Sequence
from pathlib import Path
from typing import NotRequired, TypedDict, cast

import numpy as np
import scipy  # its submodules load on first use: commands that need no theory never import them

from ..circuit.ladder import Ladder
from ..circuit.netlist import NetlistOutput, SimulationOptions, netlist_text
from ..core import __version__
from ..core.arrays import FloatArray
from ..core.blas import fixed_blas_threads
from ..core.errors import ParameterError
from ..core.types import DEFAULT_C0, DEFAULT_L0, DesignCase
from ..studies.designs import design_row
from ..theory.asymptotic import EXPONENTS, asymptotic_amplitude, asymptotic_optimum
from ..theory.cases import chain_for_case
from ..theory.closed_form import closed_form_modes
from ..theory.design import DESIGN_CHAINS, quartic_w
from ..theory.perfect import perfect_design
from ..theory.response import linear_response
from .files import write_text
from .paper import cancelling_pair

__all__ = ["DesignRows", "DesignRow", "QUICK_N", "FULL_N", "cradle4_data", "vk_data", "optimum_data", "int_rw_data",
           "minimiz_data", "pk_data", "circuit_data", "cache_key", "spectrum_points", "Cradle4Data", "VkPanel",
           "VkData", "OptimumData", "IntRwCurve", "IntRwData", "MinimizData", "PkPanel", "PkData", "CircuitElement",
           "CircuitData"]

#: Sizes of the N axes with --quick (a few seconds) and without (every row of the report, up to 1e5).
QUICK_N = [3, 4, 5, 6, 7, 8, 9, 10, 12, 14, 16, 18, 20, 30, 50, 100, 200, 500, 1000]
FULL_N = [*range(3, 11), 12, 14, 16, 18, 20, 25, 30, 35, 40, 45, 50, 60, 70, 80, 90, 100, *range(150, 501, 50), 600,
          700, 800, 900, 1000, 2000, 3000, 4000, 5000, 10000, 20000, 30000, 40000, 50000, 100000]


# ------------------------------------------------------------------ rows of Tables I and II, cached
#: The cache file's own layout: {"format", "key", "rows": {"case:N": {"row": ..., "sha256": ...}}}.  A file of
#: another layout (the flat rows of earlier versions) is recomputed, never read.
CACHE_FORMAT = 2
#: The keys and kinds of a row (``Design.to_dict()`` and its ``seconds``), per case: a row without one of them,
#: or with another kind, is recomputed.
_ROW_KEYS: dict[str, dict[str, type]] = {
    case: {"N": int, "case": str, **dict.fromkeys(("delta", "s", "t_arrival", "m1", "m2", "K12", "x", "y", "z",
                                                  *extra, "seconds"), float)}
    for case, extra in (("one-mass", ("Delta", "delta_uniform")), ("two-mass", ("r", "w")))}
#: How closely a row's derived numbers (its end masses and spring, x, y, z, t*) must follow from its parameters.
_ROW_RTOL = 1e-9


def _code_files() -> list[Path]:
    """The code that makes a row: the theory, and the design task that runs it (:func:`design_row`)."""
    package = Path(__file__).resolve().parent.parent
    return [*sorted((package / "theory").glob("*.py")), package / "studies" / "designs.py"]


def cache_key() -> str:
    """lcchain's version, the cache's layout and a digest of the code that makes a row (the theory and the
    design task): a cached row is reused only by the same code."""
    digest = hashlib.sha256(f"{__version__} {CACHE_FORMAT}".encode())
    for path in _code_files():
        digest.update(path.name.encode())
        digest.update(path.read_bytes())
    return digest.hexdigest()[:16]


class DesignRow(TypedDict):
    """A row of Table I or II: ``Design.to_dict()`` and the ``seconds`` its design took (:data:`_ROW_KEYS`; the
    report's tables keep the seconds beside the row)."""

    N: int
    case: str
    delta: float
    s: float
    t_arrival: float
    m1: float
    m2: float
    K12: float
    x: float
    y: float
    z: float
    seconds: NotRequired[float]  # every row DesignRows gives has it
    Delta: NotRequired[float]  # one-mass
    delta_uniform: NotRequired[float]  # one-mass
    r: NotRequired[float]  # two-mass
    w: NotRequired[float]  # two-mass


def _row_digest(key: str, name: str, row: Mapping[str, object]) -> str:
    """The fingerprint a row is stored with: the code's key, the row's (case, N) and its numbers."""
    return hashlib.sha256(json.dumps([key, name, row], sort_keys=True).encode()).hexdigest()


#: What else a design's row must satisfy beyond its chain: Table I's Delta follows from its x.
_ROW_CHECKS: dict[str, Callable[[DesignRow], bool]] = {
    "one-mass": lambda row: math.isclose(row["Delta"], row["x"] ** 2 / (2 - row["x"] ** 2), rel_tol=_ROW_RTOL)}


def _consistent(case: str, N: int, row: DesignRow) -> bool:
    """Whether a row's derived numbers follow from its parameters ((r, w) or x), as the design computed them: a
    number edited by hand, or made by other code, is caught even with a fingerprint that matches."""
    try:
        chain = DESIGN_CHAINS[case](N, {"x": row["x"], "r": row.get("r"), "w": row.get("w")})
        check = _ROW_CHECKS.get(case)
        if check is not None and not check(row):
            return False
    except (ValueError, ArithmeticError):  # ParameterError is a ValueError: parameters no chain has
        return False
    derived = (float(chain.masses[0]), float(chain.masses[1]), float(chain.springs[1]), *chain.xyz(), N + row["s"])
    stored = (row["m1"], row["m2"], row["K12"], row["x"], row["y"], row["z"], row["t_arrival"])
    return all(math.isclose(a, b, rel_tol=_ROW_RTOL, abs_tol=1e-300) for a, b in zip(derived, stored, strict=True))


def _row_of(case: str, row: object) -> DesignRow | None:
    """``row`` if it has the keys and kinds of a row of ``case`` (:data:`_ROW_KEYS`), else None."""
    schema = _ROW_KEYS.get(case)
    if schema is None or not isinstance(row, dict) or set(row) != set(schema):
        return None
    for field_name, kind in schema.items():
        value = row[field_name]
        if isinstance(value, bool):
            return None
        if kind is float:
            if not isinstance(value, (int, float)) or not math.isfinite(value):
                return None
        elif not isinstance(value, kind):
            return None
    return cast(DesignRow, row)  # every key and its kind checked just above


def _valid_row(key: str, name: str, entry: object) -> DesignRow | None:
    """The row of a cache entry, or None when the entry is malformed, stale or not what the code makes."""
    if not isinstance(entry, dict) or set(entry) != {"row", "sha256"}:
        return None
    digest = entry["sha256"]
    case, _, size = name.partition(":")
    row = _row_of(case, entry["row"]) if size.isdigit() else None
    if row is None:
        return None
    if row["case"] != case or row["N"] != int(size) or row["seconds"] < 0 or digest != _row_digest(key, name, row):
        return None
    return row if _consistent(case, row["N"], row) else None


def default_cache_dir() -> Path:
    """$XDG_CACHE_HOME/lcchain, else ~/.cache/lcchain."""
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "lcchain"


class DesignRows:
    """Rows of Tables I and II (``Design.to_dict()``), each computed once, optionally kept in a JSON file.

    Parameters
    ----------
    cache : path, optional
        A folder for ``designs-<key>.json`` (:func:`cache_key`): rows computed by the same code are read
        back instead of recomputed; None keeps rows in memory only.  Each row is stored with a fingerprint of
        the code and of its numbers; a row whose fingerprint, keys, kinds or derived numbers do not match what
        the code makes is recomputed, never drawn (:func:`_valid_row`).
    progress : callable, optional
        ``progress(case, N, seconds)`` after each row computed (not after a row read from the cache).
    design : callable, optional
        ``design(case, N)`` returns a row not in the cache (default :func:`lcchain.studies.designs.design_row`,
        here); the report's gives the rows a process pool designs (:mod:`lcchain.studies.background`).
        Kept as the attribute ``design``, which may be set once the cache is read (:meth:`missing`).
    """

    def __init__(self, cache: str | os.PathLike[str] | None = None,
                 progress: Callable[[str, int, float], None] | None = None,
                 design: Callable[[DesignCase, int], Mapping[str, object]] | None = None):
        self._key = cache_key()
        self._path = Path(cache) / f"designs-{self._key}.json" if cache is not None else None
        self._rows: dict[str, DesignRow] = {}
        self._progress = progress
        self.design = design or design_row
        self.computed = 0
        #: Rows found in the cache but refused (malformed, stale, or not what the code makes): recomputed.
        self.refused = 0
        if self._path is not None and self._path.is_file():
            self._rows = self._read(self._path)

    def _read(self, path: Path) -> dict[str, DesignRow]:
        try:
            data = json.loads(path.read_text())
        except (OSError, ValueError, RecursionError):
            return {}  # a damaged cache is recomputed, never trusted
        if not isinstance(data, dict) or data.get("format") != CACHE_FORMAT or data.get("key") != self._key \
                or not isinstance(data.get("rows"), dict):
            return {}
        rows = {}
        for name, entry in data["rows"].items():
            row = _valid_row(self._key, name, entry)
            if row is None:
                self.refused += 1
            else:
                rows[name] = row
        return rows

    def row(self, case: str, N: int) -> DesignRow:
        """The design of (case, N) as ``lcchain table --json`` prints it, with its computing time."""
        key = f"{case}:{N}"
        if key not in self._rows:
            designed = self.design(case, N)  # type: ignore[arg-type]
            row = _row_of(case, designed)
            if row is None:
                raise ParameterError("design", f"{case}:{N}", f"a row of {case} with the keys "
                                     f"{', '.join(_ROW_KEYS.get(case, {}))}")
            self._rows[key] = row
            self.computed += 1
            if self._progress is not None:
                self._progress(case, N, self._rows[key]["seconds"])
            self._save()
        return self._rows[key]

    def missing(self, pairs: Iterable[tuple[DesignCase, int]]) -> list[tuple[DesignCase, int]]:
        """The (case, N) of ``pairs`` neither computed nor in the cache, in their order, each once."""
        return list(dict.fromkeys(pair for pair in pairs if f"{pair[0]}:{pair[1]}" not in self._rows))

    def rows(self, case: str, Ns: Iterable[int]) -> list[DesignRow]:
        return [self.row(case, N) for N in Ns]

    def _save(self) -> None:
        if self._path is None:
            return
        entries = {name: {"row": row, "sha256": _row_digest(self._key, name, row)}
                   for name, row in self._rows.items()}
        try:
            self._path.parent.mkdir(parents=True, exist_ok=True)
            write_text(self._path, json.dumps({"format": CACHE_FORMAT, "key": self._key, "rows": entries},
                                              sort_keys=True))
        except (OSError, TypeError, ValueError):
            self._path = None  # an unwritable cache only costs time


# ------------------------------------------------------------------ the figures' data
class Cradle4Data(TypedDict):
    """:func:`cradle4_data`."""

    masses: list[float]
    springs: list[float]
    T: float
    t: FloatArray
    velocities: FloatArray


class VkPanel(TypedDict):
    """One Δ of :func:`vk_data`: the curves on k and the modes' points."""

    Delta: float
    x: float
    v: FloatArray
    P: FloatArray
    k_n: FloatArray
    P_n: FloatArray
    k_mid: FloatArray
    v_n: FloatArray


class VkData(TypedDict):
    """:func:`vk_data`."""

    N: int
    k: FloatArray
    uniform_v: FloatArray
    panels: list[VkPanel]


#: :func:`optimum_data`: both cases' rows against N, their large-N laws (case -> key -> (coefficient, power)) and
#: limits, and w(r*) of each two-mass row.
OptimumData = TypedDict("OptimumData", {"N": list[int], "one-mass": list[DesignRow], "two-mass": list[DesignRow],
                                        "laws": dict[str, dict[str, tuple[float, float]]],
                                        "asymptotes": dict[str, float], "w_of_r": list[float]})


class IntRwCurve(TypedDict):
    """One (τ, σ) of :func:`int_rw_data`."""

    name: str
    tau: float
    sigma: float
    integrand: FloatArray
    alpha: float


class IntRwData(TypedDict):
    """:func:`int_rw_data`."""

    zeta: FloatArray
    weight: FloatArray
    curves: list[IntRwCurve]


class MinimizData(TypedDict):
    """:func:`minimiz_data`."""

    case: str
    sigma: list[float]
    tau_m: list[float]
    delta_m: list[float]
    jumps: list[tuple[float, float]]
    sigma_star: float
    tau_star: float
    delta_star: float


class PkPanel(TypedDict):
    """One N of :func:`pk_data`."""

    N: int
    r: float
    w: float
    k: FloatArray
    P: FloatArray
    spacing: FloatArray


class PkData(TypedDict):
    """:func:`pk_data`."""

    panels: list[PkPanel]
    k: FloatArray
    uniform_v: FloatArray


class CircuitElement(TypedDict):
    """An inductor or capacitor of :func:`circuit_data`, as its netlist card has it."""

    name: str
    kind: str
    nodes: tuple[str, str]
    value: float


class CircuitData(TypedDict):
    """:func:`circuit_data`."""

    case: str
    N: int
    netlist: str
    elements: list[CircuitElement]
    masses: list[float]
    springs: list[float]
    L0: float
    C0: float


# ------------------------------------------------------------------ Fig. cradle4
def cradle4_data(points_per_transit: int = 300, transits: int = 2) -> Cradle4Data:
    """The 4-mass perfect cradle (bulk units: masses 5/3, 1, 1, 5/3, end springs 5/6) and its pulse.

    Returns ``masses``, ``springs``, ``T`` (= sqrt(3) pi), ``t`` (0 .. transits T, T on the grid) and
    ``velocities`` (4 x len(t)): each mass's velocity after a unit kick of mass 1 (the loop currents I_i/I0).
    """
    design = perfect_design(4)
    T = design.t_arrival
    t = np.linspace(0.0, transits * T, transits * points_per_transit + 1)
    velocities = linear_response(design.chain, t, loops="all")
    return {"masses": design.chain.masses.tolist(), "springs": design.chain.springs.tolist(), "T": T, "t": t,
            "velocities": velocities}


# ------------------------------------------------------------------ Fig. vk
def vk_data(N: int = 50, deltas: Sequence[float] = (0.30, 0.1395, 0.05), points: int = 801) -> VkData:
    """Group velocity v_k and mode density P_k of the one-mass chain (Sec. IV.B) for each Δ.

    Δ = x^2 / (2 - x^2), i.e. x^2 = 2Δ/(1 + Δ).  Curves on k in [0, pi): v_k = N/(N + 2 psi'_k) cos(k/2)
    with 2 psi'_k of Eq. e.psiprime, and P_k of Eq. e.PkDelta; points: lcchain's modes of the chain,
    P_n (the n = 1 mode halved, as Eq. e.Pk says) and v = (N/pi)(omega_(n+1) - omega_n) at mid-k.
    """
    k = np.linspace(0.0, math.pi, points, endpoint=False)
    tan2 = np.tan(k / 2) ** 2
    panels: list[VkPanel] = []
    for Delta in deltas:
        x2 = 2 * Delta / (1 + Delta)
        two_psi_prime = (1 - Delta) * (Delta - tan2) / (Delta**2 + tan2)
        v = N / (N + two_psi_prime) * np.cos(k / 2)
        P = Delta * (1 + Delta) / ((N * Delta + 1 - Delta) * Delta + (N - 1 + Delta) * tan2)
        modes = closed_form_modes(N, 1.0, x2)
        assert modes.k is not None  # the closed form always gives its wave vectors
        spacing = np.diff(modes.omega) * N / math.pi
        panels.append({"Delta": Delta, "x": math.sqrt(x2), "v": v, "P": P, "k_n": modes.k,
                       "P_n": modes.density, "k_mid": 0.5 * (modes.k[1:] + modes.k[:-1]), "v_n": spacing})
    return {"N": N, "k": k, "uniform_v": np.cos(k / 2), "panels": panels}


# ------------------------------------------------------------------ Figs. delta, x_xy, m_mmK, rw
def _law(coefficient: float, power: float) -> Callable[[np.ndarray], np.ndarray]:
    return lambda N: coefficient * N**power


def optimum_data(rows: DesignRows, Ns: Sequence[int]) -> OptimumData:
    """The optimal parameters against N for both cases, with the large-N laws (Figs. delta, x_xy, m_mmK, rw).

    ``one-mass`` / ``two-mass``: lists of table rows; ``laws``: for each case a dict of key ->
    (coefficient, power) from :func:`lcchain.theory.asymptotic.asymptotic_optimum`, with ``y`` meaning
    sqrt(2) - c N^p and ``m2`` 1/2 + c N^p; ``asymptotes``: δ*∞ per case; ``w_of_r``: w(r*) of Eq. e.wr for
    each two-mass row.
    """
    sizes = sorted({int(n) for n in Ns})
    one, two = rows.rows("one-mass", sizes), rows.rows("two-mass", sizes)
    laws: dict[str, dict[str, tuple[float, float]]] = {}
    asymptotes: dict[str, float] = {}
    cases: tuple[DesignCase, ...] = ("one-mass", "two-mass")
    for case in cases:
        optimum = asymptotic_optimum(case)
        laws[case] = {key: (value, EXPONENTS[case][key]) for key, value in optimum.coefficients.items()}
        asymptotes[case] = optimum.delta
    return {"N": sizes, "one-mass": one, "two-mass": two, "laws": laws, "asymptotes": asymptotes,
            "w_of_r": [quartic_w(row["r"]) if row["r"] <= 1 else math.nan for row in two]}


# ------------------------------------------------------------------ Figs. int_rw and minimiz
def int_rw_data(points: int = 4001, pairs: Sequence[tuple[str, float, float]] | None = None) -> IntRwData:
    """The integrand of Eq. e.uinftyz on ζ in [0, pi/2] for (τ, σ) pairs, with its weighting function.

    Default pairs (the caption of Fig. int_rw): the one that cancels the linear and cubic terms of θ,
    (τ, σ) = (−2^(3/2)/3, 2^(3/2)) (:func:`lcchain.report.paper.cancelling_pair`; the paper prints τ with
    the other sign, a slip in its findings), and the optimum (τ*, σ*).  Each pair carries α∞ from
    :func:`lcchain.theory.asymptotic.asymptotic_amplitude`: the algebraic area under its curve.

    Note: arctan(tan 2ζ / sqrt 2) is taken on the branch continuous in ζ (atan2 with the sign of
    cos 2ζ handled), which is what 2 atan(sqrt2 ξ / (1 - ξ^2)) means in Eq. e.uinftyxi.
    """
    if pairs is None:
        optimum = asymptotic_optimum("two-mass")
        tau, sigma = cancelling_pair()  # the paper prints tau = +2^(3/2)/3, which leaves the cubic term
        pairs = [("linear and cubic terms cancelled", tau, sigma), ("optimum", optimum.tau, optimum.sigma)]
    zeta = np.linspace(0.0, math.pi / 2, points)
    zeta[-1] = np.nextafter(math.pi / 2, 0.0)  # tan(pi/2) is infinite; the weight there is 0
    tan = np.tan(zeta)
    weight = (2 * math.sqrt(2) / math.pi) * (1 + tan**2) / (1 + tan**4)
    weight[-1] = 0.0
    # 2 atan(sqrt2 xi / (1 - xi^2)) continuous in xi = tan(zeta): atan2 of the same numerator and denominator
    shift = 2 * np.arctan2(math.sqrt(2) * tan, 1 - tan**2)
    curves: list[IntRwCurve] = []
    for name, tau, sigma in pairs:
        theta = tau * tan**3 - sigma * tan + shift
        integrand = weight * np.cos(theta)
        integrand[-1] = 0.0
        curves.append({"name": name, "tau": tau, "sigma": sigma, "integrand": integrand,
                       "alpha": asymptotic_amplitude(tau, sigma, "two-mass")})
    return {"zeta": zeta, "weight": weight, "curves": curves}


#: How closely Fig. minimiz locates a jump of τ_m(σ) (in σ).
JUMP_XTOL = 1e-4


def _tau_minimum(sigma: float, case: DesignCase, tau_hi: float, points: int) -> tuple[float, float]:
    """(τ_m, δ∞) at σ: the global minimum of δ∞(σ, τ) over τ >= 0, the boundary τ = 0 included.

    δ∞(σ, ·) ripples (its stationary point ξ ~ sqrt(σ / 3τ) runs off as τ -> 0, so the ripples crowd
    towards τ = 0) and for σ below about 2.4 its lowest value is at τ = 0 itself.  A grid even in sqrt(τ)
    (fine near 0) finds the basins; bounded Brent polishes the lowest few, and the boundary's value competes
    with them (Brent never evaluates the ends of its interval: alone it missed the boundary minimum).
    """
    def loss(tau: float) -> float:
        return 1.0 - asymptotic_amplitude(tau, sigma, case)

    while True:
        grid = tau_hi * np.linspace(0.0, 1.0, points) ** 2
        losses = np.array([loss(float(tau)) for tau in grid])
        if int(np.argmin(losses)) < points - 1:
            break
        tau_hi *= 2.0  # the minimum lies beyond the grid
    # the grid's local minima, lowest first: near a jump two basins are almost level, and the grid alone
    # cannot tell which is lower, so the two lowest are polished and compared with the boundary
    inner = [i for i in range(1, points - 1) if losses[i] <= losses[i - 1] and losses[i] <= losses[i + 1]]
    best_tau, best_loss = 0.0, float(losses[0])
    for i in sorted(inner, key=lambda i: losses[i])[:2]:
        result = scipy.optimize.minimize_scalar(loss, bounds=(grid[i - 1], grid[i + 1]), method="bounded",
                                                options={"xatol": 1e-7})
        tau, value = (float(result.x), float(result.fun)) if result.fun < losses[i] else (grid[i], losses[i])
        if value < best_loss:
            best_tau, best_loss = float(tau), float(value)
    return best_tau, best_loss


@fixed_blas_threads
def minimiz_data(sigmas: Sequence[float] | None = None, case: DesignCase = "two-mass", *,
                 quick: bool = False) -> MinimizData:
    """τ_m(σ), the τ >= 0 that minimises δ∞(σ, τ) for each σ, and δ∞ there (Fig. minimiz), with the optimum.

    τ_m jumps where the minimum leaves the boundary τ = 0 for an inner one (near σ = 2.4 for two masses):
    each jump between neighbouring σ's is located by bisection to ``JUMP_XTOL`` and both of its sides are
    added to the curve; ``jumps`` lists (σ below, σ above) for each.  ``quick`` uses fewer σ's and a coarser
    τ grid: the same curve, drawn with fewer points.

    Under the theory's one BLAS thread, set once here: each of the ~23,000 amplitudes would otherwise set and
    restore the limit itself (measured: 8 % of the time with ``quick``; the numbers are the same bits).
    """
    optimum = asymptotic_optimum(case)
    if sigmas is None:
        grid = np.linspace(0.7 * optimum.sigma, 1.5 * optimum.sigma, 31 if quick else 121)
        sigmas = sorted({*grid.tolist(), optimum.sigma})  # σ* on the curve: its minimum is drawn, not cut
    tau_hi, points = 4.0 * optimum.tau + 0.5, 48 if quick else 160  # τ = Δ^3 t / 3 >= 0

    def at(sigma: float) -> tuple[float, float]:
        return _tau_minimum(sigma, case, tau_hi, points)

    curve = {float(sigma): at(float(sigma)) for sigma in sigmas}
    jumps = []
    ordered = sorted(curve)
    for lo, hi in zip(ordered, ordered[1:], strict=False):
        if (curve[lo][0] == 0.0) == (curve[hi][0] == 0.0):
            continue
        lo_side = curve[lo][0] == 0.0
        while hi - lo > JUMP_XTOL:
            mid = 0.5 * (lo + hi)
            curve[mid] = at(mid)
            if (curve[mid][0] == 0.0) == lo_side:
                lo = mid
            else:
                hi = mid
        curve.setdefault(lo, at(lo))
        curve.setdefault(hi, at(hi))
        jumps.append((lo, hi))
    inner = {sigma for pair in jumps for sigma in pair}
    kept = sorted({float(sigma) for sigma in sigmas} | inner)  # the bisection's other points are not drawn
    return {"case": case, "sigma": kept, "tau_m": [curve[s][0] for s in kept], "delta_m": [curve[s][1] for s in kept],
            "jumps": jumps, "sigma_star": optimum.sigma, "tau_star": optimum.tau, "delta_star": optimum.delta}


# ------------------------------------------------------------------ Fig. Pk20-100
def pk_data(rows: DesignRows, Ns: Sequence[int] = (20, 100)) -> PkData:
    """Mode density P_n and frequency spacing of the optimal two-mass chains (Fig. Pk20-100).

    For each N: ``k`` (k_n), ``P`` (P_n, sums to 1), ``spacing`` ((N/pi)(omega_n - omega_(n-1)) at k_n,
    n >= 2: comparable with the uniform chain's group velocity cos(k/2)).
    """
    panels: list[PkPanel] = []
    for N in Ns:
        row = rows.row("two-mass", N)
        modes = closed_form_modes(N, row["r"], row["w"])
        assert modes.k is not None
        panels.append({"N": N, "r": row["r"], "w": row["w"], "k": modes.k, "P": modes.density,
                       "spacing": np.diff(modes.omega) * N / math.pi})
    k = np.linspace(0.0, math.pi, 400)
    return {"panels": panels, "k": k, "uniform_v": np.cos(k / 2)}


def spectrum_points(modes: Sequence[Mapping[str, object]], N: int) -> dict[str, np.ndarray]:
    """A circuit's measured modes (:class:`lcchain.studies.spectrum_checks.SpectrumCheck`'s ``modes``) as Figs.
    Pk20-100 and vk draw the theory's, from the circuit's numbers alone.

    Returns ``k`` (k_n = 2 arcsin(omega_n / 2), the bulk dispersion omega = 2 sin(k/2) of Eq. e.omegak, by which
    the closed form's omega_n follow from its k_n), ``P`` (|P_n|: for a symmetric chain the weight in alpha_N is
    (-1)^(n-1) times the mode density), ``zero`` (the free chain's zero mode), and for every two neighbouring modes
    both seen ``v`` ((N/pi)(omega_n - omega_(n-1)), as :func:`pk_data` and :func:`vk_data` make the theory's),
    ``k_upper`` (k_n of the upper one: Fig. Pk20-100's abscissa) and ``k_mid`` (their mean: Fig. vk's).  Modes the
    circuit did not see are left out.
    """
    seen = [mode for mode in modes if mode["omega"] is not None]
    omega = np.array([mode["omega"] for mode in seen], dtype=float)
    k = 2.0 * np.arcsin(np.clip(omega / 2.0, 0.0, 1.0))
    n = np.array([mode["n"] for mode in seen], dtype=int)
    neighbours = np.flatnonzero(np.diff(n) == 1)
    return {"k": k, "P": np.abs(np.array([mode["P"] for mode in seen])),
            "zero": np.array([mode["omega_theory"] == 0.0 for mode in seen], dtype=bool),
            "v": (omega[neighbours + 1] - omega[neighbours]) * N / math.pi, "k_upper": k[neighbours + 1],
            "k_mid": 0.5 * (k[neighbours] + k[neighbours + 1])}


# ------------------------------------------------------------------ Fig. LCcircuit
def circuit_data(case: str = "two-mass", N: int = 6, L0: float = DEFAULT_L0, C0: float = DEFAULT_C0) -> CircuitData:
    """The ladder's elements as a generated netlist lists them: name, two nodes, value (H or F).

    Returns ``netlist`` (the text), ``elements`` (list of dicts name/kind/nodes/value, netlist order) and
    the chain's ``masses`` and ``springs``.
    """
    chain = chain_for_case(case, N)
    ladder = Ladder(chain, L0=L0, C0=C0)
    text = netlist_text(ladder, SimulationOptions(dt=0.05, tstop=1.0),
                        output=NetlistOutput(title=f"lcchain {case} N={N}"))
    elements: list[CircuitElement] = []
    for line in text.splitlines():
        fields = line.split()
        if fields and fields[0][0] in "LC" and len(fields) >= 4:
            elements.append({"name": fields[0], "kind": fields[0][0], "nodes": (fields[1], fields[2]),
                             "value": float(fields[3])})
    return {"case": case, "N": N, "netlist": text, "elements": elements, "masses": chain.masses.tolist(),
            "springs": chain.springs.tolist(), "L0": L0, "C0": C0}
