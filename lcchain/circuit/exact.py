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
coils): :func:`exact_cost` prices them.  Like every theory entry point they run
with one BLAS thread (:mod:`lcchain.core.blas`): the same bits in any process,
and no threads spinning against each other on a busy machine.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np
import scipy  # its submodules load on first use: commands that need no theory never import them

from ..core.blas import fixed_blas_threads
from ..core.errors import ParameterError
from .elements import GROUND, Element, Pulse

__all__ = ["CircuitTheory", "circuit_theory", "exact_cost", "circuit_cost", "circuit_states", "circuit_unknowns",
           "EXACT_FLOPS_PER_SECOND", "MAX_MODAL_ROUNDING"]

_NODES, _WEIGHTS = np.polynomial.legendre.leggauss(16)
_BLOCK = 1 << 18  # modes x times evaluated at once
# A panel of length h with h max|pole| <= 3 integrates exp(pole (t - s)) u(s) to ~1e-31 with 16 nodes.
_PANEL_RATE = 3.0

#: A lossless mode whose squared frequency is below this fraction of the largest is a zero mode (a loop of coils
#: with no capacitor): LAPACK returns a true zero as |w| <= 6e-17 w_max (measured, coupled chains to k -> 1/2 at
#: N = 200 and 2000); the smallest genuine one met is 3.8e-13 w_max (N = 2000, k -> 1/2).  It was 1e-12, which
#: silently froze the lowest modes of the N = 2000 ladder at k > 0.499999 (an error of 5e-9 I0).
_ZERO_MODE = 1e-14
#: A genuine mode within this factor of _ZERO_MODE cannot be told from a zero mode in float64: refused.
_ZERO_MODE_MARGIN = 10.0
#: Largest rounding eps * sum_k |c_k| / |x| of a lossy modal expansion x = sum_k c_k v_k (|v_k| = 1) accepted.
#: Measured against expm of the state matrix (every loop, 161 times over 4 N, ladders of 6 to 12 loops with a
#: mode damped within 1e-16 .. 1e-8 of critical): the error is 0.07 .. 0.98 times this estimate, so accepting up
#: to 5e-10 keeps every accepted response within 1e-9 of its drive's scale (I0 for a kick).
MAX_MODAL_ROUNDING = 5e-10

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


def circuit_states(elements: Sequence[Element | Pulse]) -> int:
    """The states the circuit's theory solves for, counted from its elements without solving: its coils and the
    nodes its capacitors touch (an upper bound: coils tied by Kirchhoff's law count once each)."""
    coils = sum(1 for e in elements if isinstance(e, Element) and e.kind == "L")
    nodes = {node for e in elements if isinstance(e, Element) and e.kind == "C" for node in (e.a, e.b)}
    return coils + len(nodes - {GROUND})


def circuit_unknowns(elements: Sequence[Element | Pulse]) -> int:
    """A simulator's unknowns for the circuit (modified nodal analysis): its nodes, its coils and its sources."""
    nodes = {node for e in elements if not (isinstance(e, Element) and e.kind == "K") for node in (e.a, e.b)}
    branches = sum(1 for e in elements if isinstance(e, Pulse) or e.kind == "L")
    return len(nodes - {GROUND}) + branches


def circuit_cost(elements: Sequence[Element | Pulse], times: int) -> tuple[float, float]:
    """(seconds, bytes) of the circuit's theory of ``elements`` at ``times`` times (:func:`exact_cost`)."""
    lossy = any(isinstance(e, Element) and e.kind == "R" for e in elements)
    return exact_cost(circuit_states(elements), times, lossy)


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
    q0: np.ndarray  # each node's charge at t = 0 (C), from the capacitors' own initial voltages
    i0: np.ndarray
    drive: np.ndarray  # how the pulse u enters each coil's equation (+1, -1 or 0)
    through_g: np.ndarray  # currents the pulse injects into each node: through_g u + through_c u'
    through_c: np.ndarray
    pulse: Pulse | None
    grounded: np.ndarray  # nodes with a capacitor to ground


@dataclass(frozen=True)
class _Fold:
    """A pulse source's node folded into its other node: v(a) = v(b) + u(t) for every element at node a."""

    pulse: Pulse
    coils: tuple[tuple[str, float], ...]  # (coil, +1 or -1): the coils whose branch voltage gains u
    injected: tuple[tuple[str, str, float], ...]  # (kind "C" or "R", the element's other node, its value)


def _fold_pulse(elements: Sequence[Element | Pulse]) -> tuple[list[Element], _Fold | None]:
    """The elements with the pulse's node ``a`` folded into its node ``b``, and what the pulse then drives."""
    pulses = [e for e in elements if isinstance(e, Pulse)]
    plain = [e for e in elements if isinstance(e, Element)]
    if not pulses:
        return plain, None
    if len(pulses) > 1:
        raise ParameterError("sources", [p.name for p in pulses], "one pulse source")
    pulse = pulses[0]
    if pulse.a == pulse.b or pulse.a == GROUND:
        raise ParameterError(pulse.name, f"{pulse.a} {pulse.b}", "a pulse source between two nodes, its node a "
                             "not ground")
    folded: list[Element] = []
    coils: list[tuple[str, float]] = []
    injected: list[tuple[str, str, float]] = []
    for element in plain:
        if element.kind == "K" or pulse.a not in (element.a, element.b):
            folded.append(element)
            continue
        if element.a == pulse.a and element.b == pulse.a:
            continue
        other = element.b if element.a == pulse.a else element.a
        if element.kind == "L":
            coils.append((element.name.lower(), 1.0 if element.a == pulse.a else -1.0))
        else:
            injected.append((element.kind, other, float(element.value)))
        folded.append(replace(element, a=pulse.b if element.a == pulse.a else element.a,
                              b=pulse.b if element.b == pulse.a else element.b))
    return folded, _Fold(pulse, tuple(coils), tuple(injected))


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


def _assemble(given: Sequence[Element | Pulse]) -> _Network:
    elements, fold = _fold_pulse(given)
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
    q0, i0, own = np.zeros(n), np.zeros(m), np.zeros(m)
    grounded = np.zeros(n, dtype=bool)
    for element in elements:
        value = float(element.value)
        if not np.isfinite(value) or (element.kind != "K" and value <= 0):
            raise ParameterError(element.name, value, "a finite element value > 0")
        a, b = nodes.get(element.a), nodes.get(element.b)
        if element.kind == "R":
            G.two_terminal(a, b, 1.0 / value)
        elif element.kind == "C":
            Cn.two_terminal(a, b, value)
            for index in (a, b):
                if index is not None and (a is None or b is None):
                    grounded[index] = True
            if element.ic is not None:  # its own charge: a capacitor without IC starts at 0 V, as under UIC
                for index, sign in ((a, 1.0), (b, -1.0)):
                    if index is not None:
                        q0[index] += sign * value * element.ic
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
    drive, through_g, through_c = np.zeros(m), np.zeros(n), np.zeros(n)
    if fold is not None:
        for coil, sign in fold.coils:
            drive[inductors[coil]] += sign
        # a capacitor (resistor) from the pulse's node to x carries C (u' ...) (G (u ...)) out of x into b
        b = nodes.get(fold.pulse.b)
        for kind, other, value in fold.injected:
            target, amount = (through_c, value) if kind == "C" else (through_g, 1.0 / value)
            if other in nodes:
                target[nodes[other]] += amount
            if b is not None:
                target[b] -= amount
    return _Network(tuple(nodes), tuple(inductors), Cn.matrix((n, n)), G.matrix((n, n)), A.matrix((n, m)),
                    Lm.matrix((m, m)), q0, i0, drive, through_g, through_c, None if fold is None else fold.pulse,
                    grounded)


def _floating_common_modes(net: _Network) -> _Network:
    """The network in coordinates where every group of capacitive nodes with no capacitor to ground (a chain of
    coils' self-capacitances between nodes that reach ground through resistors or coils only) has its common
    voltage apart: v = T y, the group's first node carrying the common voltage, the others their difference
    from it.  The capacitors do not see the common voltage (their matrix annihilates it), so it is algebraic or
    inductive like a node no capacitor touches, and what is left of the capacitance matrix is definite."""
    touched = net.Cn.diagonal() > 0
    count, label = scipy.sparse.csgraph.connected_components(abs(net.Cn), directed=False)
    floating = [np.flatnonzero(label == c) for c in range(count)]
    floating = [group for group in floating if touched[group[0]] and not np.any(net.grounded[group])]
    if not floating:
        return net
    n = net.Cn.shape[0]
    T = scipy.sparse.lil_array((n, n))
    T.setdiag(1.0)
    inverse = scipy.sparse.lil_array((n, n))
    inverse.setdiag(1.0)
    for group in floating:
        first = group[0]
        for node in group[1:]:
            T[node, first] = 1.0  # v_node = y_first + y_node
            inverse[node, first] = -1.0  # y_node = v_node - v_first
    T, inverse = scipy.sparse.csr_array(T), scipy.sparse.csr_array(inverse)
    Cn = scipy.sparse.lil_array(T.T @ net.Cn @ T)
    for group in floating:  # exactly what the capacitors see of the common voltage: nothing
        Cn[group[0], :] = 0.0
        Cn[:, group[0]] = 0.0
    # charges go as the currents do (T^T); a floating group's own is nothing (each capacitor's two ends in it)
    q0 = T.T @ net.q0
    for group in floating:
        q0[group[0]] = 0.0
    return replace(net, Cn=scipy.sparse.csr_array(Cn), G=scipy.sparse.csr_array(T.T @ net.G @ T),
                   A=scipy.sparse.csr_array(T.T @ net.A), q0=q0, through_g=T.T @ net.through_g,
                   through_c=T.T @ net.through_c)


def _islands(G: scipy.sparse.csr_array, r: np.ndarray, d: np.ndarray) -> tuple[np.ndarray, list[np.ndarray]]:
    """(resistive nodes, islands): the groups of resistive nodes joined by resistors to each other only, each
    island's first node taken out of the resistive ones (the island's voltage is relative to it).

    A group is an island when raising its voltages together moves no current anywhere: ``G 1_group = 0``, every
    row (a resistor to another node or to ground would show there).  In the coordinates of
    :func:`_floating_common_modes` this also finds a floating capacitor group's common voltage together with the
    resistive nodes that hang from it alone (capacitors' ESR before their ESL)."""
    if r.size == 0:
        return r, []
    inner = G[r, :][:, r]
    count, label = scipy.sparse.csgraph.connected_components(inner, directed=False)
    keep = np.ones(r.size, dtype=bool)
    islands = []
    scale = max(float(abs(G).max()), 1e-300)
    for group in range(count):
        members = np.flatnonzero(label == group)
        moved = np.asarray(G[:, r[members]].sum(axis=1)).ravel()
        if np.any(np.abs(moved) > 1e-12 * scale * members.size):
            continue
        islands.append(r[members])
        keep[members[0]] = False
    return r[keep], islands


def _null_space(law: np.ndarray) -> np.ndarray:
    """An orthonormal basis of the currents that obey ``law`` (rows: Kirchhoff's law at nodes of coils alone),
    from a QR factorisation of its transpose (rank from the pivots): several times cheaper than the SVD of
    ``scipy.linalg.null_space`` (N = 2000 with every capacitor's ESL: 64 s of SVD on a loaded machine)."""
    Q, R, _ = scipy.linalg.qr(law.T, pivoting=True)
    diagonal = np.abs(np.diag(R))
    rank = int(np.sum(diagonal > max(law.shape) * np.finfo(float).eps * (diagonal[0] if diagonal.size else 0.0)))
    return np.asarray(Q[:, rank:])


def _cholesky(matrix: np.ndarray, what: str) -> np.ndarray:
    try:
        return np.asarray(scipy.linalg.cholesky(matrix, lower=False))
    except np.linalg.LinAlgError:
        raise ParameterError("circuit", what, "a circuit whose inductance and capacitance matrices are positive "
                             "definite (a coupling at its limit, capacitors in a loop of their own, or values too "
                             "far apart for float64)") from None


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
                             "coupling at its limit, or inductances too far apart for float64)") from None
    return w, U


class CircuitTheory:
    """The exact response of a linear R, L, C, K circuit, from its elements.

    Parameters
    ----------
    elements : sequence of Element
        The circuit (its initial conditions are the drive: ``IC`` on coils
        and on capacitors, each capacitor's own voltage; one without ``IC`` starts at 0 V, as under SPICE's UIC,
        and the charges at a node are shared at once among its capacitors).

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

    @fixed_blas_threads
    def __init__(self, elements: Sequence[Element | Pulse]):
        net = _floating_common_modes(_assemble(elements))
        plain = [e for e in elements if isinstance(e, Element)]
        self._couplings = tuple((e.name, float(e.value)) for e in plain if e.kind == "K")
        self._pulse = net.pulse
        self._states: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None  # a pulse's panels (_edge_states)
        self.inductors = net.inductors
        touched = net.Cn.diagonal() > 0
        resistive = ~touched & (abs(net.G).sum(axis=1) > 0)
        inductive = ~touched & ~resistive
        d, r, p = (np.flatnonzero(mask) for mask in (touched, resistive, inductive))
        # Kirchhoff's law on the currents alone: at every node of coils alone, and summed over every island of
        # resistive nodes with no resistor out of it (a winding resistance between two such nodes): each island's
        # common voltage is free like a coil node's, the rest of it is algebraic.
        laws = [net.A[p, :].toarray()]
        r, islands = _islands(net.G, r, d)
        laws += [np.asarray(net.A[island, :].sum(axis=0)).reshape(1, -1) for island in islands]
        law = np.vstack(laws)
        Z = None if law.shape[0] == 0 else _null_space(law)
        self._Z = Z
        Lm = net.Lm.toarray()
        Lz = Lm if Z is None else Z.T @ Lm @ Z
        # Initial currents that break Kirchhoff's law at a node of coils alone (a kick of L1 where a capacitor's
        # ESL meets it) redistribute at once, conserving each loop's flux: the Lm-nearest lawful currents.
        j0 = net.i0 if Z is None else np.linalg.solve(Lz, Z.T @ (Lm @ net.i0))
        D = net.Cn[d, :][:, d]
        Bd = net.A[d, :] if Z is None else scipy.sparse.csr_array(np.asarray(net.A[d, :] @ Z))
        Br = net.A[r, :] if Z is None else scipy.sparse.csr_array(np.asarray(net.A[r, :] @ Z))
        G_dd, G_dr, G_rr = net.G[d, :][:, d], net.G[d, :][:, r], net.G[r, :][:, r]
        nj = Lz.shape[0]
        if not nj:
            raise ParameterError("elements", "no coil current", "a circuit in which a coil can carry current (here "
                                 "Kirchhoff's law holds every coil's at 0: a coil in series with a capacitor to a "
                                 "node nothing else reaches?)")
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
        # the capacitive nodes' voltages at t = 0+: their charges shared among every capacitor at them (the
        # capacitors' own voltages, as SPICE's UIC starts them, need not agree; a coil's self-capacitance beside a
        # spring's capacitor at a displaced mass takes its share at once, as in the simulator)
        y0 = (np.atleast_1d(scipy.sparse.linalg.spsolve(scipy.sparse.csc_array(D), net.q0[d]))
              if np.any(net.q0[d]) else np.zeros(d.size))
        if np.any(net.through_c[~touched]):
            raise ParameterError("sources", "pulse", "a pulse source whose capacitors reach capacitive nodes")
        # M s' = S s + e_u u + e_du u': the pulse through the coils and the resistors (u), the capacitors (u')
        bz = net.drive if Z is None else Z.T @ net.drive
        e_du = np.concatenate((net.through_c[d], np.zeros(nj)))
        if r.size:
            Wg = factor.solve(net.through_g[r])
            e_u = np.concatenate((net.through_g[d] - G_dr @ Wg, bz + Br.T @ Wg))
        else:
            e_u = np.concatenate((net.through_g[d], bz))
        if self.lossless:
            self._lossless(D, scipy.sparse.csr_array(X), Lz, y0, j0)
            # a'' + omega^2 a = (U^T bz + U^T X^T D^-1 c) u' for the modal currents a = U^T Lz j
            injected = e_du[: d.size]
            via_c = (X.T @ scipy.sparse.linalg.spsolve(scipy.sparse.csc_array(D), injected) if np.any(injected)
                     else np.zeros(nj))
            self._gain = self._shape * (self._U.T @ (bz + via_c))
            self._gain_now = np.zeros_like(self._gain)
        else:
            self._lossy(D.toarray(), Gs, X.toarray() if scipy.sparse.issparse(X) else X, Rz, Lz, y0, j0)
            modal_u, modal_du = (self._modal(scipy.linalg.solve_triangular(self._R, e, trans="T"), what)
                                 for e, what in ((e_u, "the pulse"), (e_du, "the pulse")))
            # c' = lam c + g u + h u': c = (g + lam h) w + h u(t), w the convolution of u with exp(lam t)
            self._gain = self._shape * (modal_u + self._lam * modal_du)
            self._gain_now = self._shape * modal_du
        self._refuse_non_finite()

    def _refuse_non_finite(self) -> None:
        """Refuse a circuit whose modes float64 could not give: a pole, a mode's shape or its gain that overflowed
        or became NaN (values far apart: the response would be NaN, and its comparison with it)."""
        arrays = [self.poles, self._shape, self._gain, self._gain_now,
                  *((self._cos, self._sin) if self.lossless else (self._coefficients,))]
        if all(bool(np.all(np.isfinite(values))) for values in arrays):
            return
        raise ParameterError("circuit", "modes not finite", "a circuit whose exact theory float64 can give (element "
                             "values too far apart: its modes overflowed)")

    # -------------------------------------------------------------- lossless
    def _lossless(self, D: scipy.sparse.csr_array, X: scipy.sparse.csr_array, Lz: np.ndarray, y0: np.ndarray,
                  j0: np.ndarray) -> None:
        Z = self._Z
        diagonal = D.diagonal()
        if D.shape[0] == 0:
            K = np.zeros_like(Lz)
        elif (D - scipy.sparse.diags_array(diagonal)).count_nonzero() == 0:
            if Z is None:  # every capacitor to ground: K = X^T D^-1 X keeps the ladder's band
                K = (X.T @ scipy.sparse.diags_array(1.0 / diagonal) @ X).toarray()
            else:  # currents restricted to Kirchhoff's law: X is dense, and sparse products of it are slow
                dense = X.toarray()
                K = dense.T @ (dense / diagonal[:, None])
        else:
            dense = X.toarray()
            K = dense.T @ scipy.linalg.cho_solve(scipy.linalg.cho_factor(D.toarray()), dense)
        K = 0.5 * (K + K.T)
        w, U = _symmetric_definite(K, Lz)  # U^T Lz U = 1
        scale = max(float(np.max(np.abs(w))), 1e-300)
        doubtful = (w >= _ZERO_MODE * scale) & (w < _ZERO_MODE * _ZERO_MODE_MARGIN * scale)
        if np.any(doubtful):
            # the lowest frequency is lost in the rounding of the highest: its phase, or whether it moves at all
            ratio = float(np.min(w[doubtful]) / scale)
            field, value = self._couplings[0] if self._couplings else ("circuit", ratio)
            hint = ": a coupling further from 1/2" if self._couplings else ""
            raise ParameterError(field, value, f"a circuit whose lowest mode's omega^2 is not within rounding of zero "
                                 f"(here {ratio:.1e} of the highest; float64 tells a mode from a zero mode above "
                                 f"{_ZERO_MODE * _ZERO_MODE_MARGIN:g}{hint})")
        w = np.where(w < _ZERO_MODE * scale, 0.0, w)
        self._omega = np.sqrt(w)
        self._cos = U.T @ (Lz @ j0)  # what each mode starts with: current, then current's slope
        self._sin = U.T @ (X.T @ y0)
        self._shape = U if self._Z is None else self._Z @ U  # each mode's coil currents
        self._U = U
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
        self._lam = lam
        self._V, self._R = V, R
        self._lu = scipy.linalg.lu_factor(V)
        coefficients = self._modal(R @ np.concatenate((y0, j0)), "the initial conditions")
        back = scipy.linalg.solve_triangular(R, V)  # R^-1 V: each mode's states
        self._coefficients = coefficients
        self._shape = back[nd:, :] if self._Z is None else self._Z @ back[nd:, :]
        self.poles = lam

    def _modal(self, state: np.ndarray, what: str) -> np.ndarray:
        """The coefficients c of ``state`` = V c (a state in the Cholesky frame), refused where rounding spoils them.

        Where two modes' eigenvectors are nearly parallel (a pair of poles near critical damping, an eigenvector
        matrix near defective), the expansion cancels large coefficients: the rounding of the response is about
        eps sum_k |c_k| (|v_k| = 1), whatever the time (the modes decay).  Measured, the error stays below it (see
        :data:`MAX_MODAL_ROUNDING`); above :data:`MAX_MODAL_ROUNDING` of |state| it is refused.
        """
        coefficients = np.asarray(scipy.linalg.lu_solve(self._lu, state.astype(complex)))
        size = float(np.linalg.norm(state))
        if size == 0.0:
            return coefficients
        rounding = float(np.finfo(float).eps * np.sum(np.abs(coefficients)) / size)
        if rounding > MAX_MODAL_ROUNDING:
            worst = int(np.argmax(np.abs(coefficients)))
            pole = complex(self._lam[worst])
            damping = -pole.real / max(abs(pole), 1e-300)
            raise ParameterError("R", round(damping, 12), f"resistors that damp no mode within rounding of critical "
                                 f"(damping ratio 1): two modes near pole {pole:.4g}/s have nearly parallel "
                                 f"eigenvectors, so float64 loses {rounding:.1e} of the response to {what}, over "
                                 f"{MAX_MODAL_ROUNDING:g} allowed")
        return coefficients

    # -------------------------------------------------------------- outputs
    def _rows(self, probes: Sequence[str]) -> list[int]:
        rows = []
        for name in probes:
            key = name.lower().removeprefix("i(").removesuffix(")")
            if key not in self.inductors:
                raise ParameterError("probes", name, f"a coil of the circuit ({', '.join(self.inductors[:3])}, ...)")
            rows.append(self.inductors.index(key))
        return rows

    def _blocks(self, times: np.ndarray) -> list[np.ndarray]:
        """The times in blocks whose mode x time arrays (a few MB) stay in cache: all at once, N = 2000 at 10^4
        times held 480 MB of phases, cosines and sines."""
        rows = max(1, _BLOCK // max(self._shape.shape[1], 1))
        return [times[k : k + rows] for k in range(0, times.size, rows)] or [times]

    @fixed_blas_threads
    def currents(self, t: np.ndarray, probes: Sequence[str]) -> np.ndarray:
        """The coils' currents (A) at the times ``t`` (s): shape (len(probes), len(t)).

        Raises
        ------
        ParameterError
            A response float64 could not give: modes that rounding left growing (a passive circuit's decay or
            hold), with element values far apart, overflowed at these times.
        """
        times = np.atleast_1d(np.asarray(t, dtype=float)).ravel()
        with np.errstate(over="ignore", invalid="ignore"):  # refused below, in words, not as numpy's warnings
            currents = np.hstack([self._currents(block, probes) for block in self._blocks(times)])
        if not np.all(np.isfinite(currents)):
            growing = float(np.max(self.poles.real))
            raise ParameterError("circuit", "response not finite", "a circuit whose exact response float64 can give "
                                 f"(element values too far apart: rounding left a mode growing at {growing:.3g}/s, "
                                 "which overflowed)")
        return currents

    def _currents(self, times: np.ndarray, probes: Sequence[str]) -> np.ndarray:
        free = self._free_currents(times, probes)
        if self._pulse is None:
            return free
        rows = self._rows(probes)
        forced = self._gain[rows, :] @ self._convolution(times)
        if np.any(self._gain_now):
            forced = forced + np.outer(self._gain_now[rows, :].sum(axis=1), self._during(times))
        return np.asarray(free + forced.real)

    def _during(self, times: np.ndarray) -> np.ndarray:
        """u(t): the pulse's voltage at the times (0 past its end)."""
        assert self._pulse is not None
        end = self._pulse.corners()[-1]
        inside = (times >= 0) & (times < end)
        out = np.zeros(times.size)
        out[inside] = self._pulse.voltage(times[inside])
        return out

    def _convolution(self, times: np.ndarray) -> np.ndarray:
        """w_k(t) = integral from 0 to t of exp(p_k (t - s)) u(s) ds for each mode's pole p_k (lossless: +1j omega,
        whose real part is the cosine's convolution), shape (modes, times): Gauss-Legendre panels no longer than
        3 / max|p| (16 nodes: exact to rounding), joined by the exact propagator.  The states at the panels' edges
        are computed once (:meth:`_edge_states`): a peak search evaluates the response some 75 times."""
        poles, edge, state = self._edge_states()
        out = np.empty((poles.size, times.size), dtype=complex)
        end = edge[-1]
        after = times >= end
        out[:, after] = np.exp(np.outer(poles, times[after] - end)) * state[-1][:, None]
        inside = np.flatnonzero(~after)
        if inside.size:
            panel = np.clip(np.searchsorted(edge, times[inside], side="right") - 1, 0, edge.size - 2)
            for j, k in zip(inside, panel, strict=True):
                out[:, j] = np.exp(poles * (times[j] - edge[k])) * state[k] + self._panel(poles, edge[k], times[j])
        return out

    def _edge_states(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(poles, panel edges, the convolution's state at each edge), computed on first use and kept."""
        if self._states is not None:
            return self._states
        pulse = self._pulse
        assert pulse is not None
        poles = 1j * self._omega if self.lossless else self._lam
        rate = max(float(np.max(np.abs(poles))) if poles.size else 0.0, 1e-300)
        corners = pulse.corners()
        edges = [corners[0]]
        for lo, hi in zip(corners[:-1], corners[1:], strict=False):
            count = max(1, int(np.ceil((hi - lo) * rate / _PANEL_RATE)),
                        int(np.ceil((hi - lo) / pulse.width)) if pulse.shape == "gaussian" else 1)
            edges += list(np.linspace(lo, hi, count + 1)[1:])
        edge = np.asarray(edges)
        state = np.zeros((edge.size, poles.size), dtype=complex)
        for k in range(edge.size - 1):
            state[k + 1] = np.exp(poles * (edge[k + 1] - edge[k])) * state[k] + self._panel(poles, edge[k],
                                                                                               edge[k + 1])
        self._states = (poles, edge, state)
        return self._states

    def _panel(self, poles: np.ndarray, lo: float, hi: float) -> np.ndarray:
        """integral from lo to hi of exp(p (hi - s)) u(s) ds, by Gauss-Legendre."""
        assert self._pulse is not None
        if hi <= lo:
            return np.zeros(poles.size, dtype=complex)
        s = lo + 0.5 * (hi - lo) * (1.0 + _NODES)
        weights = 0.5 * (hi - lo) * _WEIGHTS * self._pulse.voltage(s)
        return np.asarray(np.exp(np.outer(poles, hi - s)) @ weights)

    def _free_currents(self, times: np.ndarray, probes: Sequence[str]) -> np.ndarray:
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

    @fixed_blas_threads
    def charges(self, t: np.ndarray, probes: Sequence[str], q0: Sequence[float]) -> np.ndarray:
        """The charges (C) that have flowed through the coils since t = 0, plus ``q0``: the loop charges."""
        times = np.atleast_1d(np.asarray(t, dtype=float)).ravel()
        return np.hstack([self._charges(block, probes, q0) for block in self._blocks(times)])

    def _charges(self, times: np.ndarray, probes: Sequence[str], q0: Sequence[float]) -> np.ndarray:
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

    def admittances(self, probes: Sequence[str]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The transfer admittances I_k(s) / V(s) of the coils ``probes`` from the circuit's source (its pulse, whose
        shape does not matter here: per volt of it, wherever it drives), as poles and residues::

            I_k(s) / V(s) = direct_k + sum_n residues[k, n] / (s - poles[n])

        the Laplace transform of the very response :meth:`currents` convolves the pulse with (the same modal gains),
        so an AC analysis and a transient of the circuit follow one theory.

        Returns
        -------
        poles : ndarray of complex, shape (modes,)
            rad/s: lossless ``+-1j omega_n`` (a mode of zero frequency once, at 0), lossy the circuit's ``lam``.
        residues : ndarray of complex, shape (len(probes), modes)
            Siemens x rad/s; a conjugate pole's residue is the conjugate (the admittance is real on the real axis).
        direct : ndarray, shape (len(probes),)
            Siemens: what a coil carries at once when the source reaches capacitive nodes (0 to rounding: a coil
            carries no current at infinite frequency).

        Raises
        ------
        ParameterError
            A circuit with no source (no pulse among its elements).
        """
        if self._pulse is None:
            raise ParameterError("elements", "no source", "a circuit with a source (a pulse) for its admittances")
        rows = self._rows(probes)
        gain = self._gain[rows, :]
        if self.lossless:
            # gain s / (s^2 + omega^2) = (gain / 2) / (s - j omega) + (gain / 2) / (s + j omega); 1 / s at omega = 0
            moving = self._omega > 0
            omega = self._omega[moving]
            poles = np.concatenate((1j * omega, -1j * omega, np.zeros(np.count_nonzero(~moving))))
            residues = np.hstack((0.5 * gain[:, moving], 0.5 * gain[:, moving], gain[:, ~moving])).astype(complex)
            return poles, residues, np.zeros(len(rows))
        # c' = lam c + g u + h u': C(s) = (g + s h) / (s - lam) U(s) = (h + (g + lam h) / (s - lam)) U(s)
        direct = self._gain_now[rows, :].sum(axis=1).real
        return self._lam.astype(complex), gain.astype(complex), np.asarray(direct, dtype=float)

    def cosine_weights(self, probes: Sequence[str], *, charges: bool = False) -> tuple[np.ndarray, np.ndarray] | None:
        """The free response of the coils ``probes`` as a pure sum of cosines: (omega in rad/s, weights of shape
        (len(probes), modes)), of their currents, or with ``charges`` of the charges through them (less their
        constant part); None when it is not one (losses, a pulse, a start with both currents and voltages, or a
        charge that drifts at zero frequency).  The accuracy model predicts a fixed-step run's error from it
        (:func:`lcchain.compare.accuracy.predicted_error`)."""
        if not self.lossless or self._pulse is not None:
            return None
        shape = self._shape[self._rows(probes), :]
        omega = self._omega
        if not charges:
            return (omega, shape * self._cos) if not np.any(self._sin) else None
        if np.any(self._cos) or np.any(self._sin[omega == 0]):
            return None
        return omega, -shape * self._sin / np.where(omega > 0, omega, 1.0) ** 2

    def damped_weights(self, probes: Sequence[str], *, charges: bool = False) -> tuple[np.ndarray, np.ndarray] | None:
        """The free response of the coils ``probes`` of a lossy circuit as a sum of damped exponentials: (poles in
        1/s, complex weights of shape (len(probes), modes)) whose real part is the currents, or with ``charges``
        the charges through them less their constant part; None for a lossless circuit or with a pulse
        (:meth:`cosine_weights`)."""
        if self.lossless or self._pulse is not None:
            return None
        weights = self._shape[self._rows(probes), :] * self._coefficients
        if charges:
            if np.any(self._lam == 0):
                return None
            weights = weights / self._lam
        return self._lam, weights


#: The last circuit's theory, by its elements: a run planned and executed in one process (``lcchain simulate``,
#: a serial study) solves its circuit once, the planner's check and the comparison alike.
_LAST: list[tuple[tuple[Element | Pulse, ...], CircuitTheory]] = []


def circuit_theory(elements: Sequence[Element | Pulse]) -> CircuitTheory:
    """:class:`CircuitTheory` of ``elements``, the last one kept: the same elements again cost nothing."""
    key = tuple(elements)
    last = _LAST[:1]
    if last and last[0][0] == key:
        return last[0][1]
    theory = CircuitTheory(key)
    _LAST[:] = [(key, theory)]
    return theory
