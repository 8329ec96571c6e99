"""The circuit's own exact theory: its response computed from the elements it is written with (pure).

The chain theory of :mod:`lcchain.theory` follows what a chain can say:
masses, springs, walls, neighbouring coupling, losses proportional to the
masses.  A circuit with any other linear part (a capacitor across a coil, a
winding resistance, a capacitor's ESR or ESL) is no chain any more; its exact
response comes from its elements instead, the very
:class:`~lcchain.circuit.elements.Element` list its netlist is written from.

Equations (modified nodal analysis)
-----------------------------------
Unknowns: the voltage v of every node but ground and the current i of every
inductor (counted from its node ``a`` to its node ``b``)::

    Cn v' = -G v - A i          (Kirchhoff's current law at every node)
    Lm i' = A^T v               (every coil: v(a) - v(b) = L i' + M i'_other)

``Cn`` and ``G`` are the nodal capacitance and conductance matrices, ``A`` the
node-inductor incidence (+1 at ``a``, -1 at ``b``), ``Lm`` the inductance
matrix (``K`` elements put k sqrt(L_1 L_2) off its diagonal).

Nodes that no capacitor touches carry no state:

* a node joined through a resistor (the node between a coil and its winding
  resistance) is algebraic: its voltage follows from the others (a Schur
  complement of ``G``);
* a node joined by coils alone ties their currents (A_p^T i = 0): the
  currents are restricted to that constraint's null space.

What is left is ``M s' = S s`` with ``M`` symmetric positive definite:

* **lossless** (no resistor): the coil currents obey ``j'' = -Lz^-1 K j`` with
  ``K = X^T D^-1 X`` symmetric semi-definite and ``Lz`` positive definite:
  a symmetric-definite generalised eigenproblem (``scipy.linalg.eigh``),
  real frequencies, a zero frequency where a loop of coils has no capacitor;
* **lossy** (any resistors, proportional or not): after a Cholesky factor of
  ``M`` a real standard eigenproblem with complex poles
  (``scipy.linalg.eig``), the response a sum of damped exponentials.

Both are dense, O(n^3) in the number of states n (about twice the number of
coils): :func:`exact_cost` prices them.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import scipy.linalg
import scipy.sparse
import scipy.sparse.linalg

from ..core.errors import ParameterError
from .elements import GROUND, Element

__all__ = ["CircuitTheory", "circuit_theory", "exact_cost", "EXACT_FLOPS_PER_SECOND"]

#: Dense eigen-solvers' throughput on this machine (flop/s), for :func:`exact_cost` (measured: eigh of a
#: 2000 x 2000 pencil in about 2 s, eig of a 1000 x 1000 matrix in about 1.5 s).
EXACT_FLOPS_PER_SECOND = 2e10


def exact_cost(states: int, times: int, lossy: bool) -> tuple[float, float]:
    """(seconds, bytes) of :class:`CircuitTheory` for ``states`` unknowns and a response at ``times`` times.

    The eigen-solution costs about 10 n^3 flops (symmetric) or 25 n^3 (non-symmetric); the response n flops
    per time and probe (complex: 8).  Memory: a few n x n matrices of float64 (complex128 when lossy).
    """
    n = max(int(states), 1)
    flops = (25.0 if lossy else 10.0) * n ** 3 + (8.0 if lossy else 2.0) * n * max(int(times), 1) * 2
    return flops / EXACT_FLOPS_PER_SECOND, (6 if lossy else 4) * 8.0 * n * n * (2 if lossy else 1)


@dataclass(frozen=True)
class _Network:
    """The assembled equations: sparse nodal matrices (nodes numbered as the elements name them, along the
    ladder), the inductance matrix and the initial conditions."""

    nodes: tuple[str, ...]
    inductors: tuple[str, ...]
    Cn: scipy.sparse.csr_array
    G: scipy.sparse.csr_array
    A: scipy.sparse.csr_array
    Lm: scipy.sparse.csr_array
    v0: np.ndarray
    i0: np.ndarray


class _Stamps:
    """Triplets of a sparse matrix being assembled."""

    def __init__(self) -> None:
        self.rows: list[int] = []
        self.cols: list[int] = []
        self.values: list[float] = []

    def add(self, row: int, col: int, value: float) -> None:
        self.rows.append(row)
        self.cols.append(col)
        self.values.append(value)

    def two_terminal(self, a: int | None, b: int | None, value: float) -> None:
        for p, sign_p in ((a, 1.0), (b, -1.0)):
            for q, sign_q in ((a, 1.0), (b, -1.0)):
                if p is not None and q is not None:
                    self.add(p, q, sign_p * sign_q * value)

    def matrix(self, shape: tuple[int, int]) -> scipy.sparse.csr_array:
        return scipy.sparse.csr_array(scipy.sparse.coo_array((self.values, (self.rows, self.cols)), shape=shape))


def _assemble(elements: Sequence[Element]) -> _Network:
    nodes: dict[str, int] = {}
    inductors: dict[str, int] = {}
    for element in elements:
        if element.kind not in "RLCK":
            raise ParameterError("element", element.name, "a linear R, L, C or K element")
        if element.kind == "K":
            continue
        for node in (element.a, element.b):
            if node != GROUND:
                nodes.setdefault(node, len(nodes))
        if element.kind == "L":
            inductors.setdefault(element.name.lower(), len(inductors))
    n, m = len(nodes), len(inductors)
    Cn, G, A, Lm = _Stamps(), _Stamps(), _Stamps(), _Stamps()
    v0, i0, own = np.zeros(n), np.zeros(m), np.zeros(m)
    for element in elements:
        value = float(element.value)
        if not np.isfinite(value) or (element.kind != "K" and value <= 0):
            raise ParameterError(element.name, value, "a finite element value > 0")
        a, b = nodes.get(element.a), nodes.get(element.b)
        if element.kind == "R":
            G.two_terminal(a, b, 1.0 / value)
        elif element.kind == "C":
            Cn.two_terminal(a, b, value)
            if element.ic is not None:
                if b is None and a is not None:
                    v0[a] = element.ic
                elif a is None and b is not None:
                    v0[b] = -element.ic
                else:
                    raise ParameterError(f"{element.name} IC", element.ic, "an initial voltage on a capacitor "
                                         "to ground (the exact theory reads node voltages from them)")
        elif element.kind == "L":
            k = inductors[element.name.lower()]
            own[k] = value
            Lm.add(k, k, value)
            for end, sign in ((a, 1.0), (b, -1.0)):
                if end is not None:
                    A.add(end, k, sign)
            if element.ic is not None:
                i0[k] = element.ic
    for element in elements:
        if element.kind == "K":
            try:
                p, q = inductors[element.a.lower()], inductors[element.b.lower()]
            except KeyError:
                raise ParameterError(element.name, f"{element.a} {element.b}", "a coupling of two inductors of "
                                     "the circuit") from None
            if not -1.0 < element.value < 1.0:
                raise ParameterError(element.name, element.value, "a coupling coefficient -1 < k < 1")
            mutual = element.value * np.sqrt(own[p] * own[q])
            Lm.add(p, q, mutual)
            Lm.add(q, p, mutual)
    return _Network(tuple(nodes), tuple(inductors), Cn.matrix((n, n)), G.matrix((n, n)), A.matrix((n, m)),
                    Lm.matrix((m, m)), v0, i0)


def _cholesky(matrix: np.ndarray, what: str) -> np.ndarray:
    try:
        return np.asarray(scipy.linalg.cholesky(matrix, lower=False))
    except np.linalg.LinAlgError:
        raise ParameterError("circuit", what, "a circuit whose inductance and capacitance matrices are positive "
                             "definite (a coupling at its limit, or capacitors in a loop of their own)") from None


def _symmetric_definite(K: np.ndarray, L: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Eigenvalues (ascending) and L-orthonormal eigenvectors of K u = w L u, K symmetric, L positive definite.

    A ladder's coils numbered along it make K tridiagonal; with L diagonal (no coupling) the problem is scaled to
    a symmetric tridiagonal one and solved in O(n^2) (LAPACK's MRRR); otherwise densely (O(n^3)).
    """
    n = K.shape[0]
    if n > 1 and not np.any(L - np.diag(np.diag(L))) and not np.any(np.triu(K, 2)):
        scale = 1.0 / np.sqrt(np.diag(L))
        diagonal = np.diag(K) * scale * scale
        off = np.diag(K, 1) * scale[:-1] * scale[1:]
        w, V = scipy.linalg.eigh_tridiagonal(diagonal, off)
        return w, V * scale[:, None]
    try:
        w, U = scipy.linalg.eigh(K, L, driver="gvd")
    except np.linalg.LinAlgError:
        raise ParameterError("circuit", "inductance", "a circuit whose inductance matrix is positive definite (a "
                             "coupling at its limit)") from None
    return w, U


class CircuitTheory:
    """The exact response of a linear R, L, C, K circuit, from its elements.

    Parameters
    ----------
    elements : sequence of Element
        The circuit (its initial conditions are the drive: ``IC`` on coils
        and on capacitors to ground).

    Attributes
    ----------
    lossless : bool
        No resistor: real frequencies from a symmetric-definite eigenproblem.
    poles : ndarray of complex
        The modes' poles, rad/s: ``±1j omega`` (lossless) or ``-gamma ± 1j omega``.
    states : int
        The number of state variables the circuit reduces to.

    Raises
    ------
    ParameterError
        An element that is not linear R, L, C or K, a value that is not finite
        and positive, a coupling outside (-1, 1), or a circuit the float64
        problem cannot represent (an indefinite inductance matrix, a group of
        resistive nodes with no path to the rest), named in one line.
    """

    def __init__(self, elements: Sequence[Element]):
        net = _assemble(elements)
        self.inductors = net.inductors
        touched = net.Cn.diagonal() > 0
        resistive = ~touched & (abs(net.G).sum(axis=1) > 0)
        inductive = ~touched & ~resistive
        d, r, p = (np.flatnonzero(mask) for mask in (touched, resistive, inductive))
        # Currents: the null space of Kirchhoff's law at the nodes joined by coils alone (none: every current).
        Z = None if p.size == 0 else np.asarray(scipy.linalg.null_space(net.A[p, :].toarray()))
        self._Z = Z
        j0 = net.i0 if Z is None else Z.T @ net.i0
        if Z is not None and np.linalg.norm(Z @ j0 - net.i0) > 1e-12 * max(float(np.linalg.norm(net.i0)), 1e-300):
            raise ParameterError("IC", net.i0.tolist(), "initial coil currents that obey Kirchhoff's law at the "
                                 "nodes joined by coils alone")
        if np.any(net.v0[~touched]):
            raise ParameterError("IC", net.v0.tolist(), "initial voltages on capacitive nodes only")
        Lm = net.Lm.toarray()
        Lz = Lm if Z is None else Z.T @ Lm @ Z
        D = net.Cn[d, :][:, d]
        Bd = net.A[d, :] if Z is None else scipy.sparse.csr_array(net.A[d, :] @ Z)
        Br = net.A[r, :] if Z is None else scipy.sparse.csr_array(net.A[r, :] @ Z)
        G_dd, G_dr, G_rr = net.G[d, :][:, d], net.G[d, :][:, r], net.G[r, :][:, r]
        nj = Lz.shape[0]
        if r.size:
            try:
                factor = scipy.sparse.linalg.splu(scipy.sparse.csc_array(G_rr))
            except RuntimeError:
                raise ParameterError("circuit", "resistors", "resistive nodes joined to the rest of the circuit "
                                     "(a group of resistors with no path out)") from None
            WG = factor.solve(G_dr.T.toarray())  # G_rr^-1 G_rd
            WB = factor.solve(Br.toarray())  # G_rr^-1 Br
            Gs = G_dd.toarray() - G_dr @ WG
            X = Bd.toarray() - G_dr @ WB
            Rz = np.asarray(Br.T @ WB)
        else:
            Gs, X, Rz = G_dd.toarray(), Bd, np.zeros((nj, nj))
        self.lossless = net.G.nnz == 0 or not np.any(net.G.data)
        self.states = d.size + nj
        y0 = net.v0[d]
        if self.lossless:
            self._lossless(D, scipy.sparse.csr_array(X), Lz, y0, j0)
        else:
            self._lossy(D.toarray(), Gs, X.toarray() if scipy.sparse.issparse(X) else X, Rz, Lz, y0, j0)

    # -------------------------------------------------------------- lossless
    def _lossless(self, D: scipy.sparse.csr_array, X: scipy.sparse.csr_array, Lz: np.ndarray, y0: np.ndarray,
                  j0: np.ndarray) -> None:
        diagonal = D.diagonal()
        if D.shape[0] == 0:
            K = np.zeros_like(Lz)
        elif (D - scipy.sparse.diags_array(diagonal)).count_nonzero() == 0:
            # every capacitor to ground: K = X^T D^-1 X keeps the ladder's band
            K = (X.T @ scipy.sparse.diags_array(1.0 / diagonal) @ X).toarray()
        else:
            dense = X.toarray()
            K = dense.T @ scipy.linalg.cho_solve(scipy.linalg.cho_factor(D.toarray()), dense)
        K = 0.5 * (K + K.T)
        w, U = _symmetric_definite(K, Lz)  # U^T Lz U = 1
        scale = max(float(np.max(np.abs(w))), 1e-300)
        w = np.where(w < 1e-12 * scale, 0.0, w)
        self._omega = np.sqrt(w)
        self._cos = U.T @ (Lz @ j0)  # what each mode starts with: current, then current's slope
        self._sin = U.T @ (X.T @ y0)
        self._shape = U if self._Z is None else self._Z @ U  # each mode's coil currents
        self.poles = 1j * self._omega

    # -------------------------------------------------------------- lossy
    def _lossy(self, D: np.ndarray, Gs: np.ndarray, X: np.ndarray, Rz: np.ndarray, Lz: np.ndarray,
               y0: np.ndarray, j0: np.ndarray) -> None:
        nd, nj = D.shape[0], Lz.shape[0]
        M = np.zeros((nd + nj, nd + nj))
        M[:nd, :nd], M[nd:, nd:] = D, Lz
        S = np.zeros_like(M)
        S[:nd, :nd], S[:nd, nd:], S[nd:, :nd], S[nd:, nd:] = -Gs, -X, X.T, -Rz
        R = _cholesky(M, "capacitance and inductance")
        # R^-T S R^-1: a real matrix, skew-symmetric but for its dissipation
        H = scipy.linalg.solve_triangular(R, scipy.linalg.solve_triangular(R, S.T, trans="T").T, trans="T")
        lam, V = scipy.linalg.eig(H)
        coefficients = np.linalg.solve(V, R @ np.concatenate((y0, j0)))
        back = scipy.linalg.solve_triangular(R, V)  # R^-1 V: each mode's states
        self._lam = lam
        self._coefficients = coefficients
        self._shape = back[nd:, :] if self._Z is None else self._Z @ back[nd:, :]
        self.poles = lam

    # -------------------------------------------------------------- outputs
    def _rows(self, probes: Sequence[str]) -> list[int]:
        rows = []
        for name in probes:
            key = name.lower().removeprefix("i(").removesuffix(")")
            if key not in self.inductors:
                raise ParameterError("probes", name, f"a coil of the circuit ({', '.join(self.inductors[:3])}, ...)")
            rows.append(self.inductors.index(key))
        return rows

    def currents(self, t: np.ndarray, probes: Sequence[str]) -> np.ndarray:
        """The coils' currents (A) at the times ``t`` (s): shape (len(probes), len(t))."""
        times = np.asarray(t, dtype=float)
        shape = self._shape[self._rows(probes), :]
        if self.lossless:
            omega = self._omega
            moving = omega > 0
            phase = np.outer(omega, times)
            # sin(omega t) / omega, and t for a mode of zero frequency
            weights = np.where(moving, self._sin / np.where(moving, omega, 1.0), 0.0)
            out = (shape * self._cos) @ np.cos(phase) + (shape * weights) @ np.sin(phase)
            if not np.all(moving):
                out += np.outer(shape[:, ~moving] @ self._sin[~moving], times)
            return np.asarray(out)
        growth = np.exp(np.outer(self._lam, times))
        return np.asarray(((shape * self._coefficients) @ growth).real)

    def charges(self, t: np.ndarray, probes: Sequence[str], q0: Sequence[float]) -> np.ndarray:
        """The charges (C) that have flowed through the coils since t = 0, plus ``q0``: the loop charges."""
        times = np.asarray(t, dtype=float)
        shape = self._shape[self._rows(probes), :]
        start = np.asarray(q0, dtype=float)[:, None]
        if self.lossless:
            omega = self._omega
            phase = np.outer(omega, times)
            safe = np.where(omega > 0, omega, 1.0)[:, None]
            first = np.where(omega[:, None] > 0, np.sin(phase) / safe, times[None, :])
            second = np.where(omega[:, None] > 0, (1 - np.cos(phase)) / safe ** 2, 0.5 * times[None, :] ** 2)
            return np.asarray(start + (shape * self._cos) @ first + (shape * self._sin) @ second)
        lam = self._lam
        small = np.abs(lam) == 0
        integral = np.where(small[:, None], times[None, :],
                            np.expm1(np.outer(lam, times)) / np.where(small, 1.0, lam)[:, None])
        return np.asarray(start + ((shape * self._coefficients) @ integral).real)


def circuit_theory(elements: Sequence[Element]) -> CircuitTheory:
    """:class:`CircuitTheory` of ``elements`` (the same list :func:`lcchain.circuit.netlist.netlist_text`
    writes)."""
    return CircuitTheory(elements)
