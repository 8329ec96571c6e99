"""The exact response of any linear circuit of R, L, C, K and independent sources (pure numpy/scipy).

:mod:`lcchain.circuit.exact` solves lcchain's own circuits (a ladder and one pulse).  This module solves the
circuit a netlist lcchain did not write describes (``lcchain check``): resistors, coils (coupled by K lines),
capacitors, and independent voltage and current sources whose transient function is piecewise linear
(DC, PULSE, PWL), sinusoidal (SIN) or exponential (EXP).

Equations (modified nodal analysis, a descriptor system)
--------------------------------------------------------
Unknowns ``x``: the voltage of every node but ground, the current of every coil (from its node ``a`` to ``b``)
and of every voltage source (from its ``+`` node through the source, ngspice's sign)::

    E x' = A x + B u(t)

``E`` holds the capacitances and inductances, ``A`` the conductances and incidences, ``B`` where each source
enters.  ``E`` is singular: a node without a capacitor, a voltage source's equation are algebraic.  The pencil
``(A, E)`` is solved once (``scipy.linalg.eig`` with left and right eigenvectors): its finite eigenvalues are
the circuit's poles ``p_m``, its infinite ones the algebraic constraints, which never need to be eliminated by
hand: a homogeneous solution lies in the span of the finite right eigenvectors, and the left ones project any
state onto it (``c_m = w_m^H E z / w_m^H E v_m``).  How many poles are finite is the rank of ``E`` less the
constraints that tie differential unknowns alone (two coils in series, a node touched only by coils).

Inputs, exactly
---------------
Between two breakpoints (a PULSE's corners, a PWL's points, a SIN's or EXP's start) every source is
``Re sum_j a_j (t - t_k)^d e^{s_j (t - t_k)}`` with d = 0, or d = 1 and s = 0 (a ramp).  The particular
solution of each term is exact: ``(sE - A)^-1 B`` for an exponential or a sine, ``x = X0 + X1 t`` with
``A X1 = -B``, ``A X0 = E X1`` for a ramp.  The homogeneous part's modal amplitudes carry over each breakpoint
(the state ``E x`` is continuous).  So the response at any time is a modal sum: exact to rounding, not a finer
simulation, and evaluated at the simulator's own time points.

The trapezoidal rule, modelled the same way
-------------------------------------------
At a fixed step h the trapezoidal rule advances each mode by (1 + p h/2) / (1 - p h/2)
(:func:`lcchain.compare.accuracy.trapezoidal_poles`), reproduces ramps exactly, and answers a source term
e^{s t} sampled exactly at its time points with the particular solution at s' = (2/h) tanh(s h/2).
:meth:`LinearResponse.transient` with ``step=h`` evaluates that model; its difference with the exact
response is the step's predicted error (:mod:`lcchain.compare.check`).

Initial state
-------------
ngspice's operating point (the sources at t = 0, every ``E x'`` zero, ``.ic`` nodes held at their values), or
with ``uic`` the capacitors' and coils' ``IC=`` values and the ``.ic`` node voltages (others 0).

What is refused (:class:`~lcchain.core.errors.ParameterError`, naming the elements): a loop of voltage sources,
a cutset of current sources, no DC path for the operating point (a cutset of capacitors, unless ``uic``), a
loop of voltage sources and capacitors or a cutset of current sources and coils with ``uic`` (the initial
state would jump: an impulse), a source term at one of the circuit's poles (resonance: a secular term), and a
modal expansion whose rounding exceeds :data:`MAX_ROUNDING` (nearly defective poles, e.g. critical damping).
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable, Collection, Sequence
from dataclasses import dataclass, field
from typing import Literal

import numpy as np
import scipy  # submodules load on first use

from ..core.blas import fixed_blas_threads
from ..core.errors import ParameterError

__all__ = ["Controlled", "Term", "Waveform", "Branch", "Coupling", "Source", "LinearCircuit", "LinearResponse",
           "linear_response", "pwl_waveform", "PulseSource", "pulse_waveform", "sin_waveform", "exp_waveform",
           "GROUND_NAMES", "MAX_ROUNDING", "circuit_unknowns", "linear_cost"]

#: Node names that are ground.
GROUND_NAMES = frozenset({"0", "gnd"})
#: Largest rounding estimate eps * sum_m |w_m c_m| / scale of a modal sum accepted (as circuit.exact's 5e-10).
MAX_ROUNDING = 5e-10
BranchKind = Literal["R", "L", "C"]
SourceKind = Literal["V", "I"]
ControlledKind = Literal["E", "F", "G", "H"]
#: Time points evaluated at once (a modes x chunk block of complex exponentials).
_CHUNK = 1024
#: What :func:`linear_response` and an evaluation of it cost (measured on this machine, idle, lumped lines of 25
#: to 300 LC sections, 53 to 603 unknowns, 2021 time points, 3 saved vectors; ``lcchain check`` as a whole on 50
#: to 200 sections): the dense pencil's solution about 9e-9 s per unknown cubed (1.95 s at 603), the response
#: 5e-8 s per unknown, time point and vector, and the step's search (the predicted error of each bisected step)
#: 8e-3 s per unknown.  Memory: a few dense n x n complex matrices, and a block of _CHUNK times of the modes.
SOLVE_SECONDS_PER_UNKNOWN_CUBED = 9e-9
EVALUATION_SECONDS = 5e-8
STEP_SEARCH_SECONDS_PER_UNKNOWN = 8e-3
_DENSE_MATRICES = 8


def circuit_unknowns(circuit: LinearCircuit) -> int:
    """The size of the circuit's descriptor system: its nodes but ground, its coils and its voltage sources (what
    :func:`linear_response` solves densely)."""
    ends = [(b.a, b.b) for b in circuit.branches] + [(s.a, s.b) for s in circuit.sources] + [
        (x.a, x.b) for x in circuit.controlled] + [(x.c, x.d) for x in circuit.controlled if x.kind in "EG"]
    nodes = {label for pair in ends for label in pair} - GROUND_NAMES
    return len(nodes) + sum(b.kind == "L" for b in circuit.branches) + sum(s.kind == "V" for s in circuit.sources) \
        + sum(x.kind in "EH" for x in circuit.controlled)


def linear_cost(unknowns: int, points: float, vectors: int) -> tuple[float, float]:
    """(seconds, bytes) of the exact reference of a circuit of ``unknowns`` (:func:`circuit_unknowns`) evaluated at
    ``points`` times or frequencies for ``vectors`` saved vectors, with the suggested step's search."""
    n = max(int(unknowns), 1)
    seconds = (SOLVE_SECONDS_PER_UNKNOWN_CUBED * n ** 3 + EVALUATION_SECONDS * n * float(points) * max(vectors, 1)
               + STEP_SEARCH_SECONDS_PER_UNKNOWN * n)
    return seconds, 16.0 * n * (_DENSE_MATRICES * n + _CHUNK)


def _solve_scaled(matrix: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    """``matrix^-1 rhs``; where LAPACK finds the matrix ill-conditioned (values far apart: a coil of 1e6 H beside a
    capacitor of 1e-20 F, driven off their resonance), solved again with its rows and columns equilibrated by
    LAPACK's ``?geequb`` (powers of two: exact).

    Raises
    ------
    scipy.linalg.LinAlgWarning, numpy.linalg.LinAlgError
        Singular (a zero row or column), or ill-conditioned even equilibrated.
    """
    with warnings.catch_warnings():
        warnings.simplefilter("error", scipy.linalg.LinAlgWarning)
        try:
            return np.asarray(scipy.linalg.solve(matrix, rhs))
        except scipy.linalg.LinAlgWarning:
            pass
        equilibrate = scipy.linalg.lapack.zgeequb if np.iscomplexobj(matrix) else scipy.linalg.lapack.dgeequb
        rows, columns, *_, info = equilibrate(matrix)
        if info:
            raise np.linalg.LinAlgError("a zero row or column")
        scaled = scipy.linalg.solve(matrix * rows[:, None] * columns[None, :], (rhs.T * rows).T)
        return np.asarray((np.asarray(scaled).T * columns).T)


@dataclass(frozen=True)
class Term:
    """``coef (t - origin)^degree exp(s (t - origin))`` (its real part counts); degree 1 only with s = 0."""

    coef: complex
    s: complex = 0.0
    degree: int = 0
    origin: float = 0.0

    def shifted(self, start: float) -> list[tuple[complex, complex, int]]:
        """The term as (coef, s, degree) terms of ``t - start``."""
        if self.degree == 1:
            return [(self.coef * (start - self.origin), 0.0, 0), (self.coef, 0.0, 1)]
        return [(self.coef * complex(np.exp(self.s * (start - self.origin))), self.s, 0)]


@dataclass(frozen=True)
class Waveform:
    """A source's value against time: segments (start, terms), the first starting at -inf (a DC value: one).
    ``after``: the times where it jumps and is already its new value (a repeated PWL's jump back, as ngspice 39
    gives it at that very time); at any other breakpoint a time on it is the piece's that ends there."""

    segments: tuple[tuple[float, tuple[Term, ...]], ...]
    after: frozenset[float] = frozenset()

    @staticmethod
    def constant(value: float) -> Waveform:
        return Waveform(((-math.inf, (Term(value),)),))

    def breakpoints(self, tstop: float) -> list[float]:
        return [start for start, _ in self.segments if 0.0 < start < tstop]

    def terms_at(self, start: float) -> list[tuple[complex, complex, int]]:
        """The terms, in ``t - start``, of the segment in force from ``start`` on."""
        index = max(k for k, (begin, _) in enumerate(self.segments) if begin <= start or k == 0)
        return [shifted for term in self.segments[index][1] for shifted in term.shifted(start)]

    def value(self, t: float) -> float:
        return float(sum((c * (0.0 ** d if d else 1.0)).real for c, _, d in self.terms_at(t)))


@dataclass(frozen=True)
class Branch:
    kind: BranchKind
    name: str
    a: str
    b: str
    value: float
    ic: float | None = None


@dataclass(frozen=True)
class Coupling:
    name: str
    first: str
    second: str
    k: float


@dataclass(frozen=True)
class Source:
    kind: SourceKind
    name: str
    a: str
    b: str
    waveform: Waveform
    ac: complex = 0.0


@dataclass(frozen=True)
class Controlled:
    """A linear controlled source from ``a`` to ``b``: ``E`` v(a) - v(b) = gain (v(c) - v(d)); ``G`` a current
    gain (v(c) - v(d)) from a through it to b; ``F`` a current gain i(control) and ``H`` v(a) - v(b) =
    gain i(control), ``control`` a voltage source of the circuit (ngspice's ``i(vname)``)."""

    kind: ControlledKind
    name: str
    a: str
    b: str
    gain: float
    c: str = ""
    d: str = ""
    control: str = ""


@dataclass(frozen=True)
class LinearCircuit:
    """A linear circuit (names lower case).  ``initial``: ``.ic`` node voltages; ``uic``: start from them and the
    elements' ``IC=`` instead of the operating point; ``controlled``: its E, F, G and H sources."""

    branches: tuple[Branch, ...]
    sources: tuple[Source, ...] = ()
    couplings: tuple[Coupling, ...] = ()
    initial: tuple[tuple[str, float], ...] = ()
    uic: bool = False
    controlled: tuple[Controlled, ...] = ()


@dataclass(frozen=True)
class _Output:
    """y = Re(c x + d x' + e u): a saved vector as a functional of the unknowns, their derivatives, the inputs."""

    c: np.ndarray
    d: np.ndarray
    e: np.ndarray


@dataclass
class LinearResponse:
    """The solved circuit: its poles, the projections onto them, and the response at any time or frequency.

    Attributes
    ----------
    poles : ndarray of complex
        The finite poles (1/s).
    states : int
        How many there are (the circuit's order).
    unknowns : int
        The size of the descriptor system (modified nodal analysis).
    """

    circuit: LinearCircuit
    nodes: tuple[str, ...]
    E: np.ndarray
    A: np.ndarray
    B: np.ndarray
    poles: np.ndarray
    right: np.ndarray  # finite right eigenvectors, columns
    project: np.ndarray  # rows w_m^H / (w_m^H E v_m): modal amplitudes of a state z are project @ (E z)
    index: dict[str, int]
    states: int
    unknowns: int
    _solves: dict[complex, np.ndarray] = field(default_factory=dict, repr=False)
    _ramps: dict[tuple[str, int], tuple[np.ndarray, np.ndarray]] = field(default_factory=dict, repr=False)

    # ----------------------------------------------------------------- outputs
    def output(self, name: str) -> _Output | None:
        """A saved vector by its canonical name (``v(n1)``, ``i(v1)``, ``i(l1)``, ``@r1[i]``, ``@c1[i]``,
        ``@l1[i]``, ``v(a,b)``), or None when this circuit cannot say what it is."""
        n, m = self.E.shape[0], len(self.circuit.sources)
        c, d, e = np.zeros(n), np.zeros(n), np.zeros(m)
        name = name.strip().lower()

        def node(label: str) -> np.ndarray:
            row = np.zeros(n)
            if label not in GROUND_NAMES:
                row[self.index[f"v:{label}"]] = 1.0
            return row

        if name.startswith("v(") and name.endswith(")"):
            parts = name[2:-1].split(",")
            if not all(p in GROUND_NAMES or f"v:{p}" in self.index for p in parts) or len(parts) > 2:
                return None
            c = node(parts[0]) - (node(parts[1]) if len(parts) == 2 else 0.0)
            return _Output(c, d, e)
        if name.startswith("i(") and name.endswith(")") and f"i:{name[2:-1]}" in self.index:
            c[self.index[f"i:{name[2:-1]}"]] = 1.0
            return _Output(c, d, e)
        if name.startswith("@") and name.endswith("[i]"):
            label = name[1:-3]
            if f"i:{label}" in self.index:
                c[self.index[f"i:{label}"]] = 1.0
                return _Output(c, d, e)
            for branch in self.circuit.branches:
                if branch.name == label and branch.kind in "RC":
                    across = node(branch.a) - node(branch.b)
                    if branch.kind == "R":
                        return _Output(across / branch.value, d, e)
                    return _Output(c, across * branch.value, e)
            for k, source in enumerate(self.circuit.sources):
                if source.name == label and source.kind == "I":
                    e[k] = 1.0
                    return _Output(c, d, e)
        return None

    # ----------------------------------------------------------------- solves
    def _solve(self, s: complex) -> np.ndarray:
        """(sE - A)^-1 B (cached by s); at s = 0 with a zero pole (a loop of coils, with uic) the least-squares
        solution when the equations have one (the zero mode then carries the rest)."""
        if s not in self._solves:
            kind = complex if complex(s).imag else float
            value = s if kind is complex else complex(s).real
            matrix = (value * self.E - self.A).astype(kind)
            pole = float(np.min(np.abs(self.poles - s))) if self.poles.size else math.inf
            resonant = pole <= 1e-9 * max(abs(s), float(np.max(np.abs(self.poles), initial=1.0)))
            refusal = ParameterError("source", f"a term exp({s:g} t)", "no source term at one of the circuit's "
                                     "poles (resonance grows without bound: no modal solution)")
            if resonant and s != 0:
                raise refusal
            if resonant:
                solved, *_ = scipy.linalg.lstsq(matrix, self.B.astype(kind))
                residual = np.linalg.norm(matrix @ solved - self.B) / max(float(np.linalg.norm(self.B)), 1e-300)
                if residual > 1e-9:
                    raise refusal
            else:  # no pole there: a failure is the rounding of values far apart, not a resonance
                conditioning = ParameterError("source", f"a term exp({s:g} t)", "a circuit whose equations "
                                              "float64 can solve at the source's frequency (element values too far "
                                              "apart: the matrix there is singular to rounding)")
                try:
                    solved = _solve_scaled(matrix, self.B.astype(kind))
                except (ValueError, np.linalg.LinAlgError, scipy.linalg.LinAlgWarning):
                    raise conditioning from None
                if not np.all(np.isfinite(solved)):
                    raise conditioning
            if not np.all(np.isfinite(solved)):
                raise refusal
            self._solves[s] = np.asarray(solved)
        return self._solves[s]

    def _particular(self, terms: list[list[tuple[complex, complex, int]]], tau: np.ndarray,
                    warp: Callable[[complex], complex],
                    rows: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        """(R x_p, R x_p') at the times tau of a piece whose sources have ``terms`` (R: ``rows``, a matrix over the
        unknowns, or the identity; columns: tau)."""
        n = self.E.shape[0]
        R = np.eye(n) if rows is None else rows
        x = np.zeros((R.shape[0], tau.size), dtype=complex)
        dx = np.zeros((R.shape[0], tau.size), dtype=complex)
        for j, source_terms in enumerate(terms):
            for coef, s, degree in source_terms:
                if coef == 0:
                    continue
                if degree == 1:
                    x0, x1 = self._ramp(j)
                    x += coef * ((R @ x0)[:, None] + np.outer(R @ x1, tau))
                    dx += coef * (R @ x1)[:, None]
                else:
                    g = R @ self._solve(warp(s) if s != 0 else 0.0)[:, j]
                    shape = np.exp(s * tau)
                    x += coef * np.outer(g, shape)
                    dx += coef * s * np.outer(g, shape)
        return x, dx

    def _ramp(self, j: int) -> tuple[np.ndarray, np.ndarray]:
        """(X0, X1): x = X0 + X1 t answers a unit ramp of source j (A X1 = -B_j, A X0 = E X1).  With a zero pole
        (a loop of coils, with uic) X1 is only fixed up to the loop's current; the part that makes E X1 a
        right-hand side A can answer is chosen, else the ramp would grow as t^2 in the loop (refused)."""
        key = ("ramp", j)
        if key not in self._ramps:
            x1 = self._solve(0.0)[:, j].real
            null = scipy.linalg.null_space(self.A)
            if null.size:
                left = scipy.linalg.null_space(self.A.T)
                shift, *_ = scipy.linalg.lstsq(left.T @ self.E @ null, -(left.T @ self.E @ x1))
                x1 = x1 + null @ shift
                x0, *_ = scipy.linalg.lstsq(self.A, self.E @ x1)
                if np.linalg.norm(self.A @ x0 - self.E @ x1) > 1e-9 * max(float(np.linalg.norm(self.E @ x1)),
                                                                             1e-300):
                    raise ParameterError("source", "a ramp", "no ramp that drives a loop of coils with nothing "
                                         "across it (its current would grow as t^2: no modal solution)")
            else:
                x0 = scipy.linalg.solve(self.A, self.E @ x1)
            self._ramps[key] = (np.asarray(x0), np.asarray(x1))
        return self._ramps[key]

    # ----------------------------------------------------------------- transient
    def breakpoints(self, tstop: float) -> list[float]:
        found = {b for source in self.circuit.sources for b in source.waveform.breakpoints(tstop)}
        return [0.0, *sorted(found)]

    def _terms(self, start: float) -> list[list[tuple[complex, complex, int]]]:
        return [source.waveform.terms_at(start) for source in self.circuit.sources]

    def initial_charge(self) -> np.ndarray:
        """E x(0): the capacitors' charges and the coils' fluxes the transient starts from."""
        circuit = self.circuit
        n = self.E.shape[0]
        if not circuit.uic:
            return np.asarray(self.E @ self.operating_point())
        volts = dict(circuit.initial)
        z = np.zeros(n)
        for name, value in volts.items():
            if f"v:{name}" in self.index:
                z[self.index[f"v:{name}"]] = value
        charge = np.zeros(n)
        for branch in circuit.branches:
            if branch.kind == "L":
                z[self.index[f"i:{branch.name}"]] = branch.ic or 0.0
        charge += self.E @ z
        for branch in circuit.branches:  # a capacitor's IC= is its voltage, whatever its nodes' .ic
            if branch.kind == "C" and branch.ic is not None:
                rows = [(branch.a, 1.0), (branch.b, -1.0)]
                across = sum(sign * volts.get(node, 0.0) for node, sign in rows if node not in GROUND_NAMES)
                for node, sign in rows:
                    if node not in GROUND_NAMES:
                        charge[self.index[f"v:{node}"]] += sign * branch.value * (branch.ic - across)
        return charge

    def operating_point(self) -> np.ndarray:
        """The DC operating point at t = 0 (``.ic`` nodes held at their values, as ngspice's does)."""
        u0 = np.array([s.waveform.value(0.0) for s in self.circuit.sources])
        matrix, rhs = self.A.copy(), -(self.B @ u0)
        for name, value in self.circuit.initial:
            if f"v:{name}" in self.index:
                k = self.index[f"v:{name}"]
                matrix[k, :] = 0.0
                matrix[k, k] = 1.0
                rhs[k] = value
        return np.asarray(scipy.linalg.solve(matrix, rhs))

    @fixed_blas_threads
    def transient(self, outputs: Sequence[_Output], t: np.ndarray, tstop: float, *, poles: np.ndarray | None = None,
                  warp: Callable[[complex], complex] | None = None) -> tuple[np.ndarray, float]:
        """The outputs at the times ``t`` (ascending, within [0, tstop]): rows per output, and the rounding
        estimate eps * max sum |terms| (same units).

        With ``poles`` (in the order of :attr:`poles`) and ``warp`` (where a source term exp(s t) is answered)
        a model of an integration method instead of the exact response: the trapezoidal rule's at a fixed step
        (:func:`lcchain.compare.check.predicted_errors`)."""
        t = np.asarray(t, dtype=float)
        mapped = self.poles if poles is None else np.asarray(poles, dtype=complex)
        answer: Callable[[complex], complex] = (lambda s: s) if warp is None else warp
        cs = np.array([o.c for o in outputs]).reshape(len(outputs), -1)
        ds = np.array([o.d for o in outputs]).reshape(len(outputs), -1)
        es = np.array([o.e for o in outputs]).reshape(len(outputs), max(len(self.circuit.sources), 0))
        weights = cs @ self.right + (ds @ self.right) * mapped[None, :]
        poles = mapped
        y = np.zeros((len(outputs), t.size))
        rounding = 0.0
        points = self.breakpoints(tstop)
        terms = self._terms(0.0)
        x0, _ = self._particular(terms, np.zeros(1), answer)
        charge = self.initial_charge() - self.E @ x0[:, 0]
        amplitude = self._amplitude(charge)
        # how large each amplitude's rounding may be: the projection's terms, not only its result
        spread = np.abs(self.project) @ np.abs(charge)
        jumps_after = {b for source in self.circuit.sources for b in source.waveform.after}
        for k, start in enumerate(points):
            end = points[k + 1] if k + 1 < len(points) else math.inf
            # a time on a breakpoint belongs to the piece that ends there (the simulator's step arriving at it):
            # what jumps there (a capacitor's current when a ramp turns) is compared as the simulator computes it;
            # but where a source jumps and already is its new value (a repeated PWL's), to the piece it starts
            inside = ((t > start) | (((k == 0) | (start in jumps_after)) & (t >= start))) & (
                (t < end) | ((t == end) & (end not in jumps_after)))
            tau = t[inside] - start
            if tau.size:
                xp, _ = self._particular(terms, tau, answer, cs)
                _, dxp = self._particular(terms, tau, answer, ds)
                part = xp + dxp + es @ _inputs(terms, tau)
                values = part.copy()
                size = np.abs(part)
                for first in range(0, tau.size, _CHUNK):
                    block = slice(first, first + _CHUNK)
                    growth = amplitude[:, None] * np.exp(np.outer(poles, tau[block]))
                    values[:, block] += weights @ growth
                    if poles is self.poles:  # the rounding of the exact response only
                        size[:, block] += np.abs(weights) @ (spread[:, None] * np.abs(growth / np.where(
                            amplitude == 0, 1.0, amplitude)[:, None]))
                y[:, inside] = values.real
                rounding = max(rounding, float(np.max(size)))
            if k + 1 < len(points):
                span = end - start
                before, _ = self._particular(terms, np.array([span]), answer)
                amplitude = amplitude * np.exp(poles * span)
                spread = spread * np.abs(np.exp(poles * span))
                terms = self._terms(end)
                after, _ = self._particular(terms, np.zeros(1), answer)
                jump = self.E @ (before[:, 0] - after[:, 0])
                amplitude = amplitude + self._amplitude(jump)
                spread = spread + np.abs(self.project) @ np.abs(jump)
        if not self.circuit.uic and t.size and t[0] == 0.0:
            # t = 0 is the operating point, as the simulator reports it: what jumps as the sources start to move
            # (a capacitor's current across a voltage source) is its value before
            u0 = np.array([source.waveform.value(0.0) for source in self.circuit.sources])
            y[:, t == 0.0] = (cs @ self.operating_point() + es @ u0)[:, None]
        return y, float(np.finfo(float).eps) * rounding

    def _amplitude(self, charge: np.ndarray) -> np.ndarray:
        """Modal amplitudes of a state given by E z (the projection onto the finite right eigenvectors)."""
        return np.asarray(self.project @ charge)

    def initial_mismatch(self) -> float:
        """|E z0 - E V c0| / |E z0|: how much of the initial state the modes cannot hold (0 for a consistent one)."""
        terms = self._terms(0.0)
        x0, _ = self._particular(terms, np.zeros(1), lambda s: s)
        charge = self.initial_charge() - self.E @ x0[:, 0].real
        back = (self.E @ (self.right @ self._amplitude(charge))).real
        # against the charges a state of the particular solution's size holds too: where both charges are rounding
        # (an algebraic circuit, its capacitor's voltage fixed by a source through a gain of 1000), their ratio is
        # no measure of anything
        scale = max(float(np.linalg.norm(self.initial_charge())), float(np.linalg.norm(self.E @ x0[:, 0].real)),
                    float(np.linalg.norm(self.E)) * float(np.linalg.norm(x0[:, 0].real)), 1e-300)
        return float(np.linalg.norm(back - charge)) / scale

    # ----------------------------------------------------------------- AC
    @fixed_blas_threads
    def ac(self, outputs: Sequence[_Output], frequency: np.ndarray) -> np.ndarray:
        """The outputs' phasors at ``frequency`` (Hz) for the sources' AC magnitudes and phases."""
        u = np.array([s.ac for s in self.circuit.sources], dtype=complex)
        cs = np.array([o.c for o in outputs]).reshape(len(outputs), -1)
        ds = np.array([o.d for o in outputs]).reshape(len(outputs), -1)
        es = np.array([o.e for o in outputs]).reshape(len(outputs), len(u))
        rhs = self.B @ u
        y = np.zeros((len(outputs), np.size(frequency)), dtype=complex)
        for k, f in enumerate(np.asarray(frequency, dtype=float)):
            s = 2j * math.pi * f
            try:  # equilibrated where LAPACK finds the system ill-conditioned (a gain of 1e6 beside 1 pF)
                x = _solve_scaled(s * self.E - self.A, rhs)
            except scipy.linalg.LinAlgWarning:  # still: solved as it is (the check against the engine says how
                with warnings.catch_warnings():  # well), without a warning a frequency on the user's terminal
                    warnings.simplefilter("ignore", scipy.linalg.LinAlgWarning)
                    x = scipy.linalg.solve(s * self.E - self.A, rhs)
            y[:, k] = cs @ x + s * (ds @ x) + es @ u
        return y


def _inputs(terms: list[list[tuple[complex, complex, int]]], tau: np.ndarray) -> np.ndarray:
    """The sources' values (complex; their real parts count) at the times tau of a piece."""
    u = np.zeros((len(terms), tau.size), dtype=complex)
    for j, source_terms in enumerate(terms):
        for coef, s, degree in source_terms:
            u[j] += coef * (tau if degree else 1.0) * np.exp(s * tau)
    return u


# --------------------------------------------------------------------------- waveforms (ngspice 39's functions)


def pwl_waveform(points: Sequence[tuple[float, float]], jumps_after: Collection[float] = ()) -> Waveform:
    """Straight lines between (time s, value) points; the first value before them, the last after; two points at
    one time are a jump, its new value's from that time on at the times of ``jumps_after`` (a repeated PWL's
    repetitions), the value before's at that time elsewhere."""
    segments: list[tuple[float, tuple[Term, ...]]] = [(-math.inf, (Term(points[0][1]),))]
    for (t0, v0), (t1, v1) in zip(points, points[1:], strict=False):
        if t1 > t0:
            segments.append((t0, (Term(v0, 0.0, 0, t0), Term((v1 - v0) / (t1 - t0), 0.0, 1, t0))))
    segments.append((points[-1][0], (Term(points[-1][1]),)))
    merged: list[tuple[float, tuple[Term, ...]]] = []
    for start, terms in segments:  # a later segment at the same time wins (a jump)
        if merged and merged[-1][0] == start:
            merged[-1] = (start, terms)
        else:
            merged.append((start, terms))
    return Waveform(tuple(merged), frozenset(jumps_after))


@dataclass(frozen=True)
class PulseSource:
    """ngspice's PULSE(V1 V2 TD TR TF PW PER NP), its values as the card gives them (SI units).

    Parameters
    ----------
    v1, v2 : float
        The initial and the pulsed value.
    delay, rise, fall, width, period : float
        TD, TR, TF, PW and PER, seconds; a period of 0 makes one pulse, a period shorter than rise + width + fall
        cuts each pulse short (the next one starts from V1), as ngspice does.
    count : int, optional
        NP, the number of pulses (None: as many as fit).

    Notes
    -----
    The values are those a netlist's card gave, read and checked by its reader
    (:func:`lcchain.runs.check.source_function`); only their types are made exact here.
    """

    v1: float
    v2: float
    delay: float
    rise: float
    fall: float
    width: float
    period: float
    count: int | None = None

    def __post_init__(self) -> None:
        for name in ("v1", "v2", "delay", "rise", "fall", "width", "period"):
            object.__setattr__(self, name, float(getattr(self, name)))
        if self.count is not None:
            object.__setattr__(self, "count", int(self.count))


def pulse_waveform(pulse: PulseSource, tstop: float) -> Waveform:
    """ngspice's PULSE up to ``tstop`` (``pulse.count`` pulses, or as many as fit), as a piecewise-linear
    waveform."""
    v1, v2, delay, rise, fall, width, period, count = (pulse.v1, pulse.v2, pulse.delay, pulse.rise, pulse.fall,
                                                      pulse.width, pulse.period, pulse.count)
    points: list[tuple[float, float]] = [(0.0, v1)] if delay > 0 else []
    # its corners summed from the start one after the other, as ngspice 39 places its breakpoints (TD + TR + PW is
    # (TD + TR) + PW: 1u + 0.5u + 2u is 3.5e-6, where 1u + (0.5u + 2u) is one rounding step before it)
    shape = [(0.0, v1), (rise, v2), (rise + width, v2), (rise + width + fall, v1)]
    # a period shorter than the pulse cuts each pulse short (ngspice starts the next one from V1 at once)
    cut = 0.0 < period < rise + width + fall
    if cut:
        (a, va), (b, vb) = next((p, q) for p, q in zip(shape, shape[1:], strict=False) if p[0] <= period <= q[0])
        shape = [point for point in shape if point[0] < period] + [
            (period, va + (vb - va) * (period - a) / (b - a) if b > a else vb)]
    start = delay
    k = 0
    while start <= tstop and (count is None or k < count):
        period_points = [(start + at, value) for at, value in shape] if cut else [
            (start, v1), (start + rise, v2), (start + rise + width, v2), (start + rise + width + fall, v1)]
        if cut and k >= 2:  # ngspice's time k PER is the next pulse's start (floor(time / PER) = k), not the cut
            # pulse's end as at PER (time > PER is strict): the jump comes one rounding step before it
            before = math.nextafter(start, -math.inf)
            points[-1] = (before, points[-1][1])
            period_points[0] = (before, v1)
        points += period_points
        k += 1
        if period <= 0 or not cut and period < rise + width + fall:
            break
        start = delay + k * period  # each period's start as ngspice 39 takes it, not a sum of periods
    return pwl_waveform(points)


def sin_waveform(offset: float, amplitude: float, frequency: float, delay: float, damping: float,
                 phase_degrees: float) -> Waveform:
    """ngspice's SIN: offset + amplitude sin(phase) before ``delay``, then
    offset + amplitude exp(-damping (t - delay)) sin(2 pi frequency (t - delay) + phase)."""
    phase = math.radians(phase_degrees)
    s = complex(-damping, 2 * math.pi * frequency)
    # sin(x) = Re(-1j e^{jx})
    after = (Term(offset), Term(-1j * amplitude * complex(np.exp(1j * phase)), s, 0, delay))
    before = (Term(offset + amplitude * math.sin(phase)),)
    return Waveform(((-math.inf, before), (delay, after)))


def exp_waveform(v1: float, v2: float, delay1: float, tau1: float, delay2: float, tau2: float) -> Waveform:
    """ngspice's EXP: v1, then towards v2 with tau1 from delay1, then back towards v1 with tau2 from delay2."""
    rise = (Term(v2), Term(v1 - v2, -1.0 / tau1, 0, delay1))
    fall = (Term(v1), Term(v1 - v2, -1.0 / tau1, 0, delay1), Term(v2 - v1, -1.0 / tau2, 0, delay2))
    return Waveform(((-math.inf, (Term(v1),)), (delay1, rise), (delay2, fall)))


# --------------------------------------------------------------------------- assembly


def _graph_loop(edges: list[tuple[str, str, str]]) -> list[str] | None:
    """The names of the edges of a loop among ``edges`` (name, a, b), ground names one node; None if a forest."""
    parent: dict[str, str] = {}
    adjacency: dict[str, list[tuple[str, str]]] = {}

    def root(node: str) -> str:
        while parent.setdefault(node, node) != node:
            node = parent[node]
        return node

    for name, a, b in edges:
        a, b = ("0" if a in GROUND_NAMES else a), ("0" if b in GROUND_NAMES else b)
        if root(a) == root(b):
            # the path from a to b in the forest so far, plus this edge
            previous: dict[str, tuple[str, str] | None] = {a: None}
            queue = [a]
            while queue:
                here = queue.pop(0)
                for there, via in adjacency.get(here, []):
                    if there not in previous:
                        previous[there] = (here, via)
                        queue.append(there)
            path, node = [name], b
            while previous.get(node):
                here, via = previous[node]  # type: ignore[misc]
                path.append(via)
                node = here
            return path
        parent[root(a)] = root(b)
        adjacency.setdefault(a, []).append((b, name))
        adjacency.setdefault(b, []).append((a, name))
    return None


def _cutset(edges: list[tuple[str, str, str]], cut: list[tuple[str, str, str]], nodes: set[str]) -> list[str] | None:
    """The names of ``cut`` edges that alone join some part of the circuit to ground (``edges``: all others)."""
    parent: dict[str, str] = {}

    def root(node: str) -> str:
        node = "0" if node in GROUND_NAMES else node
        while parent.setdefault(node, node) != node:
            node = parent[node]
        return node

    for _, a, b in edges:
        parent[root(a)] = root(b)
    ground = root("0")
    for node in sorted(nodes):
        part = root(node)
        if part != ground:
            crossing = [name for name, a, b in cut if (root(a) == part) != (root(b) == part)]
            if crossing:
                return crossing
    return None


def _refuse(field_name: str, names: list[str], allowed: str) -> ParameterError:
    return ParameterError(field_name, " ".join(n.upper() for n in names), allowed)


def _check_topology(circuit: LinearCircuit, nodes: set[str], operating_point: bool = True) -> None:
    # a controlled source fixes a voltage (E, H) or a current (G, F) between its nodes as a source does
    v_edges = [(s.name, s.a, s.b) for s in circuit.sources if s.kind == "V"] + [
        (x.name, x.a, x.b) for x in circuit.controlled if x.kind in "EH"]
    i_edges = [(s.name, s.a, s.b) for s in circuit.sources if s.kind == "I"] + [
        (x.name, x.a, x.b) for x in circuit.controlled if x.kind in "GF"]
    kinds = {kind: [(b.name, b.a, b.b) for b in circuit.branches if b.kind == kind] for kind in "RLC"}
    loop = _graph_loop(v_edges)
    if loop:
        raise _refuse("loop of voltage sources", loop, "no loop of voltage sources alone (their currents are "
                      "undefined; ngspice fails at its operating point)")
    cut = _cutset(kinds["R"] + kinds["L"] + kinds["C"] + v_edges, i_edges, nodes)
    if cut:
        raise _refuse("cutset of current sources", cut, "no cutset of current sources alone (the voltage across "
                      "it is undefined)")
    if not operating_point:  # an AC sweep's phasors need neither an operating point nor a starting state
        return
    if circuit.uic:
        loop = _graph_loop(v_edges + kinds["C"])
        if loop and any(name in {v[0] for v in v_edges} for name in loop):
            raise _refuse("loop of voltage sources and capacitors with uic", loop,
                          "no such loop with uic: the capacitors' initial voltages would have to jump to the "
                          "sources' (an impulse of current); drop uic to start from the operating point")
        cut = _cutset(kinds["R"] + kinds["C"] + v_edges, kinds["L"] + i_edges, nodes)
        if cut and any(name in {i[0] for i in i_edges} for name in cut):
            raise _refuse("cutset of current sources and coils with uic", cut,
                          "no such cutset with uic: the coils' initial currents would have to jump (an impulse "
                          "of voltage); drop uic to start from the operating point")
    else:
        loop = _graph_loop(v_edges + kinds["L"])
        if loop:
            raise _refuse("loop of coils and voltage sources", loop,
                          "no such loop without uic: the operating point's current around it is undefined (coils "
                          "are shorts at DC; ngspice's is arbitrary, found by gmin stepping); uic on the .tran card "
                          "starts from the coils' IC= instead")
        cut = _cutset(kinds["R"] + kinds["L"] + v_edges, kinds["C"] + i_edges, nodes)
        if cut:
            raise _refuse("no DC path to ground through", cut, "a DC path from every node to ground (capacitors "
                          "are open at the operating point: it is undefined, and ngspice's is what its gmin "
                          "stepping finds), or uic on the .tran card")


@fixed_blas_threads
def linear_response(circuit: LinearCircuit, ac: bool = False) -> LinearResponse:
    """Assemble and solve the circuit (module docstring); a :class:`ParameterError` names what is not well posed.
    ``ac``: for an AC sweep alone, which solves the phasors at each frequency: what only a transient needs (an
    operating point, modes that are not defective) is not asked of it."""
    names = [e.name for e in circuit.branches] + [s.name for s in circuit.sources] + [
        x.name for x in circuit.controlled]
    if len(set(names)) != len(names):
        twice = sorted({n for n in names if names.count(n) > 1})
        raise _refuse("element names", twice, "each element named once")
    nodes: list[str] = []
    ends = [(e.a, e.b) for e in circuit.branches] + [(s.a, s.b) for s in circuit.sources] + [
        (x.a, x.b) for x in circuit.controlled] + [(x.c, x.d) for x in circuit.controlled if x.kind in "EG"]
    for pair in ends:
        for label in pair:
            if label not in GROUND_NAMES and label not in nodes:
                nodes.append(label)
    if not nodes:
        raise ParameterError("netlist", "no node but ground", "a circuit with at least one node")
    for element in circuit.branches:
        if not (math.isfinite(element.value) and element.value > 0):
            raise ParameterError(element.name.upper(), element.value, "a finite value > 0 (ohm, henry, farad)")
    _check_topology(circuit, set(nodes), operating_point=not ac)
    coils = [b for b in circuit.branches if b.kind == "L"]
    volts = [s for s in circuit.sources if s.kind == "V"]
    index = {f"v:{node}": k for k, node in enumerate(nodes)}
    voltage_controlled = [x for x in circuit.controlled if x.kind in "EH"]  # each with its branch current
    for k, label in enumerate([*(c.name for c in coils), *(v.name for v in volts),
                               *(x.name for x in voltage_controlled)]):
        index[f"i:{label}"] = len(nodes) + k
    n = len(index)
    E, A = np.zeros((n, n)), np.zeros((n, n))
    B = np.zeros((n, len(circuit.sources)))

    def at(node: str) -> int | None:
        return None if node in GROUND_NAMES else index[f"v:{node}"]

    for branch in circuit.branches:
        a, b = at(branch.a), at(branch.b)
        if branch.kind in "RC":
            target, value = (A, -1.0 / branch.value) if branch.kind == "R" else (E, branch.value)
            for p, q, sign in ((a, a, 1.0), (b, b, 1.0), (a, b, -1.0), (b, a, -1.0)):
                if p is not None and q is not None:
                    target[p, q] += sign * value
        else:
            row = index[f"i:{branch.name}"]
            E[row, row] += branch.value
            for node, sign in ((a, 1.0), (b, -1.0)):
                if node is not None:
                    A[node, row] -= sign
                    A[row, node] += sign
    inductance = {b.name: b.value for b in coils}
    for coupling in circuit.couplings:
        for coil in (coupling.first, coupling.second):
            if coil not in inductance:
                raise ParameterError(coupling.name.upper(), coil.upper(), "a K line coupling two coils of the "
                                     "netlist")
        if not (math.isfinite(coupling.k) and 0 < abs(coupling.k) < 1) or coupling.first == coupling.second:
            raise ParameterError(coupling.name.upper(), coupling.k, "a coupling coefficient 0 < |k| < 1 between "
                                 "two different coils")
        mutual = coupling.k * math.sqrt(inductance[coupling.first] * inductance[coupling.second])
        p, q = index[f"i:{coupling.first}"], index[f"i:{coupling.second}"]
        E[p, q] += mutual
        E[q, p] += mutual
    for j, source in enumerate(circuit.sources):
        a, b = at(source.a), at(source.b)
        if source.kind == "V":
            row = index[f"i:{source.name}"]
            for node, sign in ((a, 1.0), (b, -1.0)):
                if node is not None:
                    A[node, row] -= sign
                    A[row, node] += sign
            B[row, j] = -1.0
        else:
            for node, sign in ((a, -1.0), (b, 1.0)):
                if node is not None:
                    B[node, j] += sign
    _stamp_controlled(circuit, index, {v.name for v in volts}, at, A)
    if circuit.couplings and np.min(np.linalg.eigvalsh(E[len(nodes):len(nodes) + len(coils),
                                                         len(nodes):len(nodes) + len(coils)])) <= 0:
        raise ParameterError("K", "the coupled coils", "an inductance matrix that is positive definite (the "
                             "couplings of three or more coils can make it indefinite)")
    try:
        poles, right, project = _modes(E, A, nodes)
    except ParameterError:
        if not ac:
            raise
        poles, right, project = np.zeros(0, dtype=complex), np.zeros((n, 0), dtype=complex), np.zeros(
            (0, n), dtype=complex)  # a repeated pole with one mode: no modal solution, which phasors do not need
    return LinearResponse(circuit, tuple(nodes), E, A, B, poles, right, project, index, int(poles.size), n)


def _stamp_controlled(circuit: LinearCircuit, index: dict[str, int], volts: set[str],
                      at: Callable[[str], int | None], A: np.ndarray) -> None:
    """The controlled sources' terms of A (their equations have no derivative): a row of each KCL holds minus the
    currents leaving its node; E and H add a row v(a) - v(b) - (their control) = 0 for their branch current."""
    for source in circuit.controlled:
        if not math.isfinite(source.gain):
            raise ParameterError(source.name.upper(), source.gain, "a finite gain")
        a, b = at(source.a), at(source.b)
        if source.kind in "FH":
            if source.control not in volts:
                raise ParameterError(source.name.upper(), source.control.upper(), "the name of a voltage source "
                                     "of the netlist, whose current controls it")
            control = [(index[f"i:{source.control}"], 1.0)]
        else:
            control = [(k, sign) for k, sign in ((at(source.c), 1.0), (at(source.d), -1.0)) if k is not None]
        if source.kind in "GF":  # gain x control flows from a through the source to b
            for node, sign in ((a, 1.0), (b, -1.0)):
                if node is not None:
                    for k, weight in control:
                        A[node, k] -= sign * source.gain * weight
            continue
        row = index[f"i:{source.name}"]
        for node, sign in ((a, 1.0), (b, -1.0)):
            if node is not None:
                A[node, row] -= sign
                A[row, node] += sign
        for k, weight in control:
            A[row, k] -= source.gain * weight


def _modes(E: np.ndarray, A: np.ndarray, nodes: list[str]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The finite poles of the pencil (A, E), their right eigenvectors and the projection onto them."""
    n = E.shape[0]
    # Balanced: each unknown scaled by 1/sqrt of its capacitance or inductance (or conductance), so that the
    # pencil's entries are of one size whatever the units (a line of 250 nH and 100 pF: 1e-9 rounding, not 1e-5),
    # and the rank of E is counted there: a coil of 1 kH beside a capacitor of 1e-15 F (entries 1e18 apart) lost
    # the capacitor's pole to the raw E's rank, and the check refused a consistent initial state.
    diagonal = np.abs(np.diag(E))
    fallback = np.abs(np.diag(A))
    weight = np.where(diagonal > 0, diagonal, np.where(fallback > 0, fallback, 1.0))
    D = 1.0 / np.sqrt(weight)
    Eb, Ab = D[:, None] * E * D[None, :], D[:, None] * A * D[None, :]
    scale_e = max(float(np.abs(Eb).max()), 1e-300)
    scale_a = max(float(np.abs(Ab).max()), 1e-300)
    # then the rows and columns of the two together equilibrated (LAPACK's ?geequb, powers of two): a resistive
    # node between capacitive ones (1 kohm beside 1 pF and 20 uH) left rows 1e4 apart, and the modes 2e-5 off
    rows, columns, *_, info = scipy.linalg.lapack.dgeequb(np.abs(Ab) / scale_a + np.abs(Eb) / scale_e)
    if info == 0:
        Eb, Ab = rows[:, None] * Eb * columns[None, :], rows[:, None] * Ab * columns[None, :]
        scale_e = max(float(np.abs(Eb).max()), 1e-300)
        scale_a = max(float(np.abs(Ab).max()), 1e-300)
        left_scale, right_scale = D * rows, D * columns
    else:  # a zero row or column: the pencil is singular, as eig below finds
        left_scale, right_scale = D, D
    u, sigma, vt = np.linalg.svd(Eb)
    rank = int(np.sum(sigma > sigma[0] * n * 1e-13)) if sigma.size and sigma[0] > 0 else 0
    # constraints that tie differential unknowns alone (coils in series) remove one pole each
    left_null, right_null = u[:, rank:], vt[rank:, :].T
    a22 = left_null.T @ Ab @ right_null
    deficit = 0
    if a22.size:
        singular = np.linalg.svd(a22, compute_uv=False)
        deficit = int(np.sum(singular <= max(float(singular[0]) if singular.size else 0.0, scale_a) * n * 1e-12))
    finite = rank - deficit
    if finite <= 0:
        return np.zeros(0, dtype=complex), np.zeros((n, 0), dtype=complex), np.zeros((0, n), dtype=complex)
    alpha_beta, vl, vr = scipy.linalg.eig(Ab / scale_a, Eb / scale_e, left=True, right=True,
                                          homogeneous_eigvals=True)
    vl, vr = left_scale[:, None] * vl, right_scale[:, None] * vr
    alpha, beta = alpha_beta
    ratio = np.where(np.abs(beta) > 0, np.abs(alpha) / np.maximum(np.abs(beta), 1e-300), np.inf)
    chosen = np.argsort(ratio, kind="stable")[:finite]
    if not np.all(np.isfinite(ratio[chosen])):
        raise ParameterError("circuit", "a singular pencil", "a circuit whose equations have a unique solution "
                             "(a loop of voltage sources or cutset of current sources with what else?)")
    poles = (alpha[chosen] / beta[chosen]) * (scale_a / scale_e)
    right = vr[:, chosen]
    left = vl[:, chosen]
    norms = np.einsum("ij,ij->j", left.conj(), E @ right)
    if np.any(np.abs(norms) <= 1e-13 * np.linalg.norm(left, axis=0) * np.linalg.norm(E @ right, axis=0)):
        raise ParameterError("circuit", "defective poles", "poles with independent modes (a critically damped "
                             "or repeated pole with one mode has no modal solution)")
    unit = right / np.linalg.norm(right, axis=0)
    overlap = np.abs(unit.conj().T @ unit) - np.eye(unit.shape[1])
    close = np.abs(poles[:, None] - poles[None, :]) <= 1e-6 * np.maximum(np.abs(poles[:, None]), 1e-300)
    if np.any(close & (overlap > 1 - 1e-8)):
        k = int(np.argmax(np.any(close & (overlap > 1 - 1e-8), axis=1)))
        raise ParameterError("circuit", f"a double pole at {poles[k]:.6g} /s with one mode",
                             "poles with a mode each (a critically damped pair has none: no modal solution; a "
                             "resistance 1e-6 away from critical damping has)")
    project = left.conj().T / norms[:, None]
    return poles, right, project
