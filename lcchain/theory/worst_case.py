"""The worst first arrival over the whole tolerance box: a search in exact theory, and what it proves.

Every mass m_i (inductor L_i) may lie anywhere in m_i (1 + z_i tol_m) and every spring's compliance 1/K_j
(capacitor C_j) in (1 + z_j tol_K) / K_j, z in the box [-1, 1]^n (n = 2N - 1 parts for a free chain: a free
end has no spring).  The metric f(z) is the first-arrival peak p = max alpha_N near the arrival
(:func:`lcchain.theory.arrivals.first_arrival`) or its energy fraction e = p^2 m_N / m_1; "worst" is its lowest
value, the least transmitted.

Derivatives.  The gradient is exact: :func:`lcchain.theory.sensitivity.peak_sensitivity` (eigen-perturbation
of K u = omega^2 M u at the stationary peak time, O(N^3)), taken to z by the chain rule.  The Hessian is the
central difference of that exact gradient, H e_k = (g(z + h e_k) - g(z - h e_k)) / 2h with h = 1e-3 in z
(a part moved by 1e-3 of its tolerance): truncation ~ h^2 f'''' / 6 and rounding ~ 1e-13 / h are both far
below 1e-6 of H (the asymmetry |H - H^T| of the result, reported, measures them together).

Search.  The quadratic model Q(z) = f(0) + g.z + z.H z / 2 about the nominal is screened cheaply over many
vertices (a flip search from the gradient's signs, the signs of H's most negative eigenvectors and random
corners); its best local minima, the gradient-sign corner, random corners and random interior points start
L-BFGS-B on the exact f in the box, and each result is polished on the vertices of the box (flip the one part
that most improves, exactly, until no single flip does: a local minimum among the vertices).  For a concave f
(an optimal design, whose peak is a maximum at the nominal) the minimum over the box is on a vertex.

Certificate.  ``model_bound`` is proved for the quadratic model Q: a branch and bound over the box
(:func:`quadratic_lower_bound`) whose every box [c - r, c + r] is bounded below by
Q(c) + sum_i min_{|y_i| <= r_i} ((g + H c)_i y_i + d_i y_i^2 / 2), valid whenever H - diag(d) is positive
semidefinite (d = lambda_min(H) for all i, or Gershgorin's rows d_i = H_ii - sum_{j != i} |H_ij|); for the
small chains it closes (Q's minimum over the box proved to 1e-12), for N = 50 it leaves a gap after
:data:`lcchain.core.limits.WORST_CASE_MODEL_NODES` boxes.  The metric itself is bounded by ``bound`` =
model_bound - model_error only under an assumption: that |f - Q| over the box is no larger than
``model_error``, twice the largest |f - Q| seen at every exactly evaluated point (the vertices visited among
them, where the cubic remainder is largest).  That is an
estimate of the remainder, not a bound on the third derivatives over the box: the result is a proof for the
quadratic model and an honest estimate for f, with the gap between the worst found and the bound.
"""

from __future__ import annotations

import heapq
import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from ..core.blas import fixed_blas_threads
from ..core.checks import choice, integer, real
from ..core.errors import ParameterError
from ..core.json import JSONDict
from ..core.limits import WORST_CASE_MODEL_NODES
from ..core.types import ARRIVAL_METRICS, ArrivalMetric
from .arrivals import arrival_window
from .chain import Chain
from .modes import Modes
from .sensitivity import SENSITIVITY_MAX_N, PeakSensitivity, modal_basis, sensitivity_at

__all__ = ["ToleranceBox", "WorstCaseSearch", "worst_case_search", "metric_gradient", "metric_hessian",
           "quadratic_lower_bound", "HESSIAN_STEP", "MODEL_ERROR_MARGIN", "arrival_sensitivity"]

#: The Hessian's difference step in z (a fraction of each part's tolerance): see the module docstring.
HESSIAN_STEP = 1e-3
#: ``model_error`` is this times the largest |f - Q| seen at the exactly evaluated points.
MODEL_ERROR_MARGIN = 2.0


@dataclass(frozen=True)
class ToleranceBox:
    """A nominal chain and the relative tolerances of its masses and spring compliances.

    Parameters
    ----------
    chain : Chain
        The nominal chain (bulk units).
    tol_masses : float
        Relative tolerance of every mass (inductor), 0 <= tol < 1.
    tol_springs : float
        Relative tolerance of every spring's compliance 1/K_j (capacitor C_j = C0 / K_j), 0 <= tol < 1.
    """

    chain: Chain
    tol_masses: float
    tol_springs: float
    slots: np.ndarray = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        if not isinstance(self.chain, Chain):
            raise ParameterError("chain", type(self.chain).__name__, "a lcchain.Chain")
        for name in ("tol_masses", "tol_springs"):
            object.__setattr__(self, name, real(name, getattr(self, name), at_least=0.0, below=1.0,
                                                allowed=f"a number, 0 <= {name} < 1"))
        N = self.chain.N
        slots = [i for i in range(N)] if self.tol_masses else []
        if self.tol_springs:
            slots += [N + j for j in range(N + 1) if self.chain.springs[j] > 0.0]
        if not slots:
            raise ParameterError("tolerance", (self.tol_masses, self.tol_springs), "tol_masses or tol_springs > 0 "
                                 "(a box of one point has no worst case to search)")
        array = np.asarray(slots, dtype=int)
        array.setflags(write=False)
        object.__setattr__(self, "slots", array)

    @property
    def size(self) -> int:
        """n, the parts that vary."""
        return int(self.slots.size)

    def full(self, z: np.ndarray) -> np.ndarray:
        """z in the 2N + 1 slots of a corner (L_1..L_N, then C_0_1..C_N_N+1; 0 where nothing varies)."""
        out = np.zeros(2 * self.chain.N + 1)
        out[self.slots] = z
        return out

    def chain_at(self, z: np.ndarray) -> Chain:
        """The chain at z: m_i (1 + z_i tol_m), K_j / (1 + z_j tol_K)."""
        N = self.chain.N
        zz = self.full(z)
        masses = self.chain.masses * (1.0 + zz[:N] * self.tol_masses)
        springs = self.chain.springs / (1.0 + zz[N:] * self.tol_springs)
        return Chain(masses, springs, name=self.chain.name, coupling=self.chain.coupling)


def arrival_sensitivity(chain: Chain) -> PeakSensitivity:
    """:func:`lcchain.theory.sensitivity.peak_sensitivity` with the peak found by one matrix product.

    The same window and grid as :func:`lcchain.theory.arrivals.first_arrival` (its spacing resolves the pulse),
    evaluated at once, then Newton steps on alpha_N'(t) = 0 from the three best grid maxima within one grid step
    (quadratic convergence from 0.05 of the peak: 1e-13 in time within five steps): the same peak, without the
    Brent search's Python loop, which made 85 % of a search's time.

    Raises
    ------
    ParameterError
        When the largest value is at an edge of the window (no stationary peak: no envelope theorem).
    """
    omega, u, b = modal_basis(chain)
    transfer = u[-1, :] * b
    T = Modes(omega, u[0, :] * b, transfer, "exact").transit_time()
    lo, hi = arrival_window(1, T)
    count = max(64, int(np.ceil((hi - lo) / (0.05 * max(1.0, T ** (1.0 / 3.0))))) + 1)
    grid = np.linspace(lo, hi, count)
    values = np.cos(np.outer(grid, omega)) @ transfer
    h = grid[1] - grid[0]
    inner = np.flatnonzero((values[1:-1] >= values[:-2]) & (values[1:-1] >= values[2:])) + 1
    if values[0] > np.max(values[inner], initial=-np.inf) or values[-1] > np.max(values[inner], initial=-np.inf):
        edge = float(grid[0] if values[0] > values[-1] else grid[-1])
        raise ParameterError("chain", repr(chain), "a chain whose first arrival peaks inside its search window "
                             f"{(lo, hi)} (this one's largest value is at its edge, t = {edge:.6g})")
    best_t, best = 0.0, -np.inf
    for i in inner[np.argsort(values[inner])[::-1][:3]]:
        t = float(grid[i])
        for _ in range(8):
            slope = -np.sum(transfer * omega * np.sin(omega * t))
            curvature = -np.sum(transfer * omega * omega * np.cos(omega * t))
            if curvature >= 0.0:
                break
            step = float(np.clip(-slope / curvature, -h, h))
            t += step
            if abs(step) < 1e-14 * max(1.0, t):
                break
        value = float(np.sum(transfer * np.cos(omega * t)))
        if value > best:
            best_t, best = t, value
    return sensitivity_at(chain, omega, u, b, best_t)


def metric_gradient(box: ToleranceBox, z: np.ndarray, metric: ArrivalMetric) -> tuple[float, np.ndarray]:
    """The metric at z and its exact gradient with respect to z (eigen-perturbation, chain rule).

    d f / d z_i = (d f / d ln m_i) tol_m / (1 + z_i tol_m) for a mass; for a spring the compliance moves,
    d ln K_j / d z_j = -tol_K / (1 + z_j tol_K).
    """
    sensitivity = arrival_sensitivity(box.chain_at(z))
    N = box.chain.N
    if metric == "peak":
        value, masses, springs = sensitivity.peak, sensitivity.relative_masses, sensitivity.relative_springs
    else:
        value, masses, springs = (sensitivity.energy, sensitivity.energy_relative_masses,
                                  sensitivity.energy_relative_springs)
    zz = box.full(z)
    relative = np.concatenate((masses * box.tol_masses / (1.0 + zz[:N] * box.tol_masses),
                               -springs * box.tol_springs / (1.0 + zz[N:] * box.tol_springs)))
    return float(value), relative[box.slots]


def metric_hessian(gradient: Callable[[np.ndarray], np.ndarray], z: np.ndarray,
                   step: float = HESSIAN_STEP) -> tuple[np.ndarray, float]:
    """The Hessian by central differences of an exact gradient, symmetrised, and its asymmetry before.

    Returns
    -------
    H : ndarray, shape (n, n)
    asymmetry : float
        max |H_ij - H_ji| of the raw differences: truncation and rounding together.
    """
    n = z.size
    raw = np.empty((n, n))
    for k in range(n):
        e = np.zeros(n)
        e[k] = step
        raw[:, k] = (gradient(np.clip(z + e, -1.0 - step, 1.0 + step)) -
                     gradient(np.clip(z - e, -1.0 - step, 1.0 + step))) / (2.0 * step)
    return 0.5 * (raw + raw.T), float(np.max(np.abs(raw - raw.T))) if n else 0.0


@dataclass(frozen=True)
class WorstCaseSearch:
    """The worst metric found over the tolerance box and what is known of it.

    Attributes
    ----------
    metric : {"peak", "energy"}
    nominal : float
        The metric of the nominal chain.
    worst : float
        The lowest metric found (exact theory).
    point : tuple of float
        Where: z in the 2N + 1 corner slots (L_1..L_N, C_0_1..C_N_N+1), each in [-1, 1] (0 where nothing varies).
    vertex : bool
        Whether every varied part is at +- its tolerance.
    gradient_corner : float
        The metric at the corner the first-order signs predict (-sign g).
    model_bound : float
        A proved lower bound of the quadratic model over the box.
    model_error : float
        MODEL_ERROR_MARGIN x the largest |f - Q| seen at the evaluated points.
    bound : float
        model_bound - model_error: a lower bound of the metric over the box if |f - Q| <= model_error there.
    starts : int
        Exact local searches run.
    local_optima : tuple of float
        The distinct values the starts ended at, lowest first.
    evaluations : int
        Exact evaluations of the metric and its gradient (Hessian included).
    seconds : float
    hessian_asymmetry : float
        max |H_ij - H_ji| of the differenced Hessian (its accuracy).
    model_vertices : int
        Vertices of the quadratic model visited while screening.
    model_nodes : int
        Boxes of the branch and bound that proved ``model_bound``.
    """

    metric: ArrivalMetric
    nominal: float
    worst: float
    point: tuple[float, ...]
    vertex: bool
    gradient_corner: float
    model_bound: float
    model_error: float
    bound: float
    starts: int
    local_optima: tuple[float, ...]
    evaluations: int
    seconds: float
    hessian_asymmetry: float
    model_vertices: int
    model_nodes: int = 0

    @property
    def gap(self) -> float:
        """worst - bound (>= 0 up to rounding when the bound holds)."""
        return self.worst - self.bound

    @property
    def signs(self) -> tuple[int, ...] | None:
        """The worst point as corner signs, when it is a vertex."""
        return tuple(int(round(v)) for v in self.point) if self.vertex else None

    def to_dict(self) -> JSONDict:
        return {"method": "search", "metric": self.metric, "nominal": self.nominal, "worst": self.worst,
                "point": list(self.point), "vertex": self.vertex, "gradient_corner": self.gradient_corner,
                "model_bound": self.model_bound, "model_error": self.model_error, "bound": self.bound,
                "gap": self.gap, "starts": self.starts, "local_optima": list(self.local_optima),
                "evaluations": self.evaluations, "seconds": self.seconds,
                "hessian_asymmetry": self.hessian_asymmetry, "model_vertices": self.model_vertices,
                "model_nodes": self.model_nodes}


def _shifts(H: np.ndarray) -> list[np.ndarray]:
    """Diagonals d with H - diag(d) positive semidefinite: lambda_min (less its rounding, n eps ||H||, LAPACK's
    bound) for every i, and Gershgorin's rows d_i = H_ii - sum_{j != i} |H_ij| (diagonally dominant rest)."""
    n = H.shape[0]
    lowest = float(np.linalg.eigvalsh(H)[0]) - n * np.finfo(float).eps * float(np.max(np.abs(H)))
    return [np.full(n, lowest), np.diag(H) - (np.sum(np.abs(H), axis=1) - np.abs(np.diag(H)))]


def _node_bound(f0: float, g: np.ndarray, H: np.ndarray, lo: np.ndarray, hi: np.ndarray,
                shifts: list[np.ndarray]) -> tuple[float, float]:
    """A lower bound of Q over the box [lo, hi], and Q at its centre c.

    With z = c + y, |y_i| <= r_i: Q = Q(c) + (g + H c).y + y.H y / 2 >= Q(c) + sum_i min (a_i y_i + d_i y_i^2 / 2)
    for each shift d, the minimum at an end when d_i r_i <= |a_i|, else -a_i^2 / 2 d_i.
    """
    c, r = 0.5 * (lo + hi), 0.5 * (hi - lo)
    a = g + H @ c
    centre = float(f0 + g @ c + 0.5 * c @ H @ c)
    best = -np.inf
    for d in shifts:
        inner = np.where(d * r > np.abs(a), -a * a / (2.0 * np.where(d > 0, d, 1.0)), -np.abs(a) * r + d * r * r / 2.0)
        best = max(best, centre + float(np.sum(inner)))
    return best, centre


def quadratic_lower_bound(f0: float, g: np.ndarray, H: np.ndarray, *, nodes: int = 0,
                          upper: float = np.inf) -> tuple[float, float, int]:
    """A proved lower bound of Q(z) = f0 + g.z + z.H z / 2 over [-1, 1]^n, by branch and bound.

    Each box's bound is :func:`_node_bound` (proved: H - diag(d) is positive semidefinite); the box with the
    lowest bound is halved along the coordinate that widens it most, until its bound reaches the lowest Q seen
    (the minimum is then proved, to 1e-12) or ``nodes`` boxes were made (0: the whole box's bound alone).

    Returns
    -------
    lower : float
        min over the open boxes of their bounds: Q >= lower on the whole box.
    upper : float
        The lowest Q seen (``upper`` given, or the boxes' centres): min Q <= upper.
    nodes : int
        Boxes made.
    """
    shifts = _shifts(H)
    lo, hi = -np.ones(g.size), np.ones(g.size)
    bound, centre = _node_bound(f0, g, H, lo, hi, shifts)
    upper = min(upper, centre)
    heap: list[tuple[float, int, np.ndarray, np.ndarray]] = [(bound, 0, lo, hi)]
    made = 1
    spread = np.diag(H) ** 2 + np.sum(np.abs(H), axis=1)
    while made < nodes and heap[0][0] < upper - 1e-12:
        bound, _, lo, hi = heapq.heappop(heap)
        c, r = 0.5 * (lo + hi), 0.5 * (hi - lo)
        k = int(np.argmax(r * np.abs(g + H @ c) + r * r * spread))
        for a, b in ((lo[k], c[k]), (c[k], hi[k])):
            low, high = lo.copy(), hi.copy()
            low[k], high[k] = a, b
            child, centre = _node_bound(f0, g, H, low, high, shifts)
            upper = min(upper, centre)
            made += 1
            heapq.heappush(heap, (max(child, bound), made, low, high))
    return heap[0][0], upper, made


def _model_descent(s: np.ndarray, g: np.ndarray, H: np.ndarray) -> np.ndarray:
    """A flip search on the quadratic model's vertices: the best single flip while it lowers Q."""
    s = s.copy()
    slope = g + H @ s
    diagonal = np.diag(H)
    for _ in range(4 * s.size + 10):
        change = -2.0 * s * slope + 2.0 * diagonal
        k = int(np.argmin(change))
        if change[k] >= -1e-15:
            break
        slope -= 2.0 * s[k] * H[:, k]
        s[k] = -s[k]
    return s


def _signs(v: np.ndarray, fallback: np.ndarray) -> np.ndarray:
    """+-1 of v, its zeros taken from ``fallback`` (then +1)."""
    out = np.sign(v)
    out[out == 0] = np.sign(fallback[out == 0])
    out[out == 0] = 1.0
    return np.asarray(out, dtype=float)


@fixed_blas_threads
def worst_case_search(box: ToleranceBox, metric: ArrivalMetric = "peak", *, random_starts: int = 4,
                      model_starts: int = 6, seed: int = 0) -> WorstCaseSearch:
    """The lowest first-arrival metric over the tolerance box, in exact theory (module docstring).

    Parameters
    ----------
    box : ToleranceBox
    metric : {"peak", "energy"}
    random_starts : int
        Random corners and as many random interior points started besides the model's (0 .. 1000).
    model_starts : int
        The quadratic model's best local minima started exactly (1 .. 1000).
    seed : int
        Of ``numpy.random.default_rng`` for the random starts and the model's random corners.

    Returns
    -------
    WorstCaseSearch
    """
    choice("metric", metric, ARRIVAL_METRICS)
    random_starts = integer("random_starts", random_starts, at_least=0, at_most=1000)
    model_starts = integer("model_starts", model_starts, at_least=1, at_most=1000)
    seed = integer("seed", seed, at_least=0)
    if not isinstance(box, ToleranceBox):
        raise ParameterError("box", type(box).__name__, "a ToleranceBox")
    if box.chain.N > SENSITIVITY_MAX_N:
        raise ParameterError("N", box.chain.N, f"N <= {SENSITIVITY_MAX_N} for a worst-case search")
    started = time.perf_counter()
    rng = np.random.default_rng(seed)
    n = box.size
    seen: dict[bytes, tuple[float, np.ndarray]] = {}

    def evaluate(z: np.ndarray) -> tuple[float, np.ndarray]:
        z = np.asarray(z, dtype=float)
        key = z.tobytes()
        if key not in seen:
            seen[key] = metric_gradient(box, z, metric)
        return seen[key]

    zero = np.zeros(n)
    f0, g0 = evaluate(zero)
    hessian_points: list[tuple[np.ndarray, float]] = []

    def gradient_only(z: np.ndarray) -> np.ndarray:
        value, gradient = evaluate(z)
        hessian_points.append((z.copy(), value))
        return gradient

    H, asymmetry = metric_hessian(gradient_only, zero)

    def model(z: np.ndarray) -> float:
        return float(f0 + g0 @ z + 0.5 * z @ H @ z)

    # the quadratic model's vertices: from the gradient's signs, H's most negative directions and random corners
    down = _signs(-g0, np.ones(n))
    seeds = [down]
    values, vectors = np.linalg.eigh(H)
    for k in range(min(n, 4)):
        if values[k] < 0:
            v = vectors[:, k]
            seeds += [_signs(v, down), _signs(-v, down)]
    seeds += [rng.choice((-1.0, 1.0), size=n) for _ in range(64)]
    found: dict[bytes, np.ndarray] = {}
    for s in seeds:
        end = _model_descent(s, g0, H)
        found[end.tobytes()] = end
    screened = sorted(found.values(), key=model)[:model_starts]

    starts = [zero, down, *screened]
    starts += [rng.choice((-1.0, 1.0), size=n) for _ in range(random_starts)]
    starts += [rng.uniform(-1.0, 1.0, size=n) for _ in range(random_starts)]
    from scipy.optimize import minimize  # here: a command that only plans a worst case loads no optimiser

    polished: dict[bytes, tuple[float, np.ndarray]] = {}
    ends: list[tuple[float, np.ndarray]] = []
    diagonal = np.diag(H)
    for start in starts:
        result = minimize(evaluate, start, jac=True, method="L-BFGS-B", bounds=[(-1.0, 1.0)] * n,
                          options={"maxiter": 200})
        z = np.clip(np.asarray(result.x, dtype=float), -1.0, 1.0)
        value, gradient = evaluate(z)
        vertex = np.where(np.abs(z) > 1.0 - 1e-9, np.sign(z), _signs(-gradient, z))
        first = vertex.tobytes()
        if first not in polished:
            current, slope = evaluate(vertex)
            while True:  # a flip search on the exact metric, the flips the model thinks best tried first
                for k in np.argsort(-2.0 * vertex * slope + 2.0 * diagonal):
                    trial = vertex.copy()
                    trial[k] = -trial[k]
                    trial_value, trial_slope = evaluate(trial)
                    if trial_value < current:
                        vertex, current, slope = trial, trial_value, trial_slope
                        break
                else:
                    break
            polished[first] = (current, vertex)
        # each start's end: its polished vertex, or the point L-BFGS-B found inside the box if that is lower
        ends.append(min((value, z), polished[first], key=lambda end: end[0]))
    worst_value, worst_point = min(ends, key=lambda end: end[0])
    optima = sorted({round(value, 12) for value, _ in ends})
    model_bound, _, nodes = quadratic_lower_bound(f0, g0, H, nodes=WORST_CASE_MODEL_NODES,
                                                  upper=min(model(z) for z in screened))
    # the quadratic model's error at every exact evaluation (the Hessian's own steps are no test of it)
    steps = {z.tobytes() for z, _ in hessian_points}
    errors = [abs(value - model(np.frombuffer(key))) for key, (value, _) in seen.items() if key not in steps]
    model_error = MODEL_ERROR_MARGIN * max(errors, default=0.0)
    at_vertex = bool(np.all(np.abs(np.abs(worst_point) - 1.0) <= 1e-9))
    point = box.full(np.round(worst_point) if at_vertex else worst_point)
    return WorstCaseSearch(
        metric=metric, nominal=f0, worst=float(worst_value), point=tuple(float(v) + 0.0 for v in point),
        vertex=at_vertex, gradient_corner=float(evaluate(down)[0]), model_bound=model_bound, model_error=model_error,
        bound=model_bound - model_error, starts=len(starts), local_optima=tuple(optima), evaluations=len(seen),
        seconds=time.perf_counter() - started, hessian_asymmetry=asymmetry, model_vertices=len(seeds),
        model_nodes=nodes,
    )
