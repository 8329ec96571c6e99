"""The ladder as a list of elements: the one description its netlist and its exact theory are made from (pure).

An :class:`Element` is one SPICE element (R, L, C or K) with its nodes, its
value in SI units and its initial condition.  :func:`ladder_elements` lists
the ladder's, in the order the netlist writes them: each loop's branch (the
coil L_i and what the effects put in series with it, then across it), the
spring capacitors (with what is in series with and across each), the wall
capacitors, what the effects put from each rail node to ground and between
neighbouring loops, the coupled coils' ``K`` elements.
:func:`lcchain.circuit.netlist.netlist_text` writes each as :meth:`Element.card`
and :mod:`lcchain.circuit.exact` assembles the same elements into the
circuit's equations, so nothing about an element is stated twice.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..core.errors import ParameterError
from ..core.types import GAUSSIAN_CENTRE, PulseShape
from .effects import Effect
from .ladder import Ladder

__all__ = ["Element", "Pulse", "Source", "ladder_elements", "ladder_pulse", "card_number", "GROUND", "RECT_FALL",
           "ELEMENT_HOOKS", "adds_elements"]

#: Every Effect method :func:`ladder_elements` asks for elements: an effect that overrides none of them adds none
#: (the runs' planner relies on it; a new place for elements is added here and in ladder_elements together).
ELEMENT_HOOKS = ("in_series", "across_coil", "capacitor_series", "across_capacitor", "to_ground", "between_coils")


def adds_elements(effect: Effect) -> bool:
    """Whether an effect puts elements of its own in the ladder: it overrides one of :data:`ELEMENT_HOOKS`."""
    return any(getattr(type(effect), hook) is not getattr(Effect, hook) for hook in ELEMENT_HOOKS)

#: The rect pulse's PWL source falls in this fraction of its duration (ngspice needs a finite slope).
RECT_FALL = 1e-9

#: SPICE's ground node.
GROUND = "0"

#: An independent voltage source beside the elements: (name, + node, - node, AC volts).
Source = tuple[str, str, str, float]


def card_number(value: float) -> str:
    """A float as SPICE reads it exactly: ``repr(float(value))``, no suffix."""
    value = float(value)
    if not math.isfinite(value):
        raise ParameterError("value", value, "a finite number in a netlist")
    return repr(value)


@dataclass(frozen=True)
class Element:
    """One linear element of the circuit.

    Parameters
    ----------
    name : str
        Its SPICE name; the first letter is its kind (``R``, ``L``, ``C``, ``K``).
    a, b : str
        Its nodes (a current is counted from ``a`` to ``b`` through it); for a
        ``K`` element, the names of the two coupled inductors.
    value : float
        Ohm, henry, farad, or the coupling coefficient k of a ``K`` element.
    ic : float, optional
        The initial current of an inductor (A, from ``a`` to ``b``) or the
        initial voltage of a capacitor (V, ``v(a) - v(b)``).
    """

    name: str
    a: str
    b: str
    value: float
    ic: float | None = None

    @property
    def kind(self) -> str:
        """``"R"``, ``"L"``, ``"C"`` or ``"K"``."""
        return self.name[0].upper()

    def card(self) -> str:
        """The element's netlist line."""
        ic = "" if self.ic is None else f" IC={card_number(self.ic)}"
        return f"{self.name} {self.a} {self.b} {card_number(self.value)}{ic}"


@dataclass(frozen=True)
class Pulse:
    """A voltage pulse in series with a coil: the source of a pulse drive.

    Parameters
    ----------
    a, b : str
        Its nodes: ``v(a) - v(b)`` is the pulse (``a`` is the node it shares with the coil alone).
    shape : {"gaussian", "rect"}
        A gaussian of standard deviation ``width`` centred at :data:`GAUSSIAN_CENTRE` widths (a ``B`` source),
        or ``1/width`` on [0, width) falling to 0 in :data:`RECT_FALL` of it (a ``PWL`` source).
    width : float
        Seconds.
    area : float
        Volt-seconds.
    """

    a: str
    b: str
    shape: PulseShape
    width: float
    area: float

    @property
    def name(self) -> str:
        return "B1" if self.shape == "gaussian" else "V1"

    def corners(self) -> tuple[float, ...]:
        """Where the waveform is smooth in between, seconds: its end last (a gaussian's tail past 12 widths
        after its centre weighs exp(-72))."""
        if self.shape == "gaussian":
            return (0.0, (GAUSSIAN_CENTRE + 12.0) * self.width)
        return (0.0, self.width, self.width * (1 + RECT_FALL))

    def voltage(self, t: np.ndarray) -> np.ndarray:
        """v(a) - v(b) at the times ``t`` (s) inside the pulse, volts."""
        if self.shape == "gaussian":
            z = (t - GAUSSIAN_CENTRE * self.width) / self.width
            return np.asarray(self.area / (self.width * math.sqrt(2 * math.pi)) * np.exp(-0.5 * z * z))
        level = self.area / self.width
        return np.asarray(np.where(t < self.width, level, level * (1 - (t - self.width) / (RECT_FALL * self.width))))

    def card(self) -> str:
        """The source's netlist line."""
        if self.shape == "gaussian":
            sigma, centre = self.width, GAUSSIAN_CENTRE * self.width
            peak = self.area / (sigma * math.sqrt(2 * math.pi))
            expression = f"{card_number(peak)}*exp(-0.5*((time-{card_number(centre)})/{card_number(sigma)})^2)"
            return f"B1 {self.a} {self.b} V={expression}"
        duration = self.width
        level = self.area / duration
        return (f"V1 {self.a} {self.b} PWL(0 {card_number(level)} {card_number(duration)} {card_number(level)} "
                f"{card_number(duration * (1 + RECT_FALL))} 0)")


def ladder_pulse(ladder: Ladder, shape: PulseShape, width: float, I0: float) -> Pulse:
    """The pulse drive's source in loop 1, between s1 and the rail node n0 (or ground): L_1 I0 g(t), g of unit
    area, ``width`` in units of sqrt(L0 C0)."""
    return Pulse("s1", ladder.node(0), shape, width * ladder.time_unit, ladder.inductances()[0] * I0)


def _names(letters: list[str], stem: str) -> list[str]:
    """Element names letter + stem, a second of a letter ``_2``, a third ``_3``, ..."""
    seen: dict[str, int] = {}
    names = []
    for letter in letters:
        seen[letter] = seen.get(letter, 0) + 1
        names.append(f"{letter}{stem}" + ("" if seen[letter] == 1 else f"_{seen[letter]}"))
    return names


def _inner_nodes(stem: str, count: int) -> list[str]:
    """``count`` nodes inside a series chain: stem, stem_2, stem_3, ..."""
    return [stem if j == 0 else f"{stem}_{j + 1}" for j in range(count)]


def _in_series(parts: list[tuple[str, float]], stem: str, nodes: list[str]) -> list[Element]:
    """``parts`` one after the other along ``nodes`` (one more node than parts), named by :func:`_names`."""
    names = _names([letter for letter, _ in parts], stem)
    return [Element(name, nodes[j], nodes[j + 1], value) for j, (name, (_, value)) in enumerate(zip(names, parts,
                                                                                                    strict=True))]


def _loop_branch(i: int, left: str, right: str, inductance: float, ic: float | None,
                 series: list[tuple[str, float]]) -> list[Element]:
    """Loop i's branch from rail node ``left`` to ``right``: L_i, then each series element (inner nodes m_i...)."""
    nodes = [left, *_inner_nodes(f"m{i}", len(series)), right]
    return [Element(Ladder.inductor(i), nodes[0], nodes[1], inductance, ic), *_in_series(series, str(i), nodes[1:])]


def _beside(parts: list[tuple[str, float]], stem: str, a: str, b: str) -> list[Element]:
    """``parts`` each from node ``a`` to node ``b``, named by :func:`_names`."""
    names = _names([letter for letter, _ in parts], stem)
    return [Element(name, a, b, value) for name, (_, value) in zip(names, parts, strict=True)]


def _capacitor(ladder: Ladder, effects: tuple[Effect, ...], spring: int, node: str, capacitance: float,
               ic: float | None) -> list[Element]:
    """C_{spring,spring+1} from ``node`` to ground, after what the effects put in series with it (inner nodes
    c{spring}, c{spring}_2, ...), and what they put across it alone (names ``<letter>A{spring}_{spring+1}``)."""
    series = [e for part in effects for e in part.capacitor_series(ladder, spring)]
    nodes = [node, *_inner_nodes(f"c{spring}", len(series))]
    across = [e for part in effects for e in part.across_capacitor(ladder, spring)]
    return [*_in_series(series, f"S{spring}_{spring + 1}", nodes),
            Element(ladder.capacitor(spring), nodes[-1], GROUND, capacitance, ic),
            *_beside(across, f"A{spring}_{spring + 1}", nodes[-1], GROUND)]


def ladder_elements(ladder: Ladder, effects: tuple[Effect, ...] = (), *, source: bool = False,
                    kick: float | None = None, charge: float | None = None, port2: bool = False
                    ) -> tuple[Element, ...]:
    """The ladder's elements, in netlist order.

    Parameters
    ----------
    ladder : Ladder
        The chain in henry and farad (walls, coupling, preferred values and
        tolerances already realised in ``ladder.chain``).
    effects : tuple of Effect
        The elements each adds, in order, through its hooks (:data:`ELEMENT_HOOKS`): in series with every
        coil, across it, in series with and across every capacitor, from every rail node to ground, between
        neighbouring loops (:class:`lcchain.circuit.effects.Effect`).
    source : bool
        Loop 1 opens at node ``s1`` for a drive's source (written by the netlist).
    port2 : bool
        Loop N opens too, at node ``s<N>`` after coil N's branch (what is across the coil spans it), for a
        two-port's second port (its ammeter written by the netlist: :func:`lcchain.circuit.netlist.ac_netlist_text`).
    kick : float, optional
        The initial current of L_1, ampere.
    charge : float, optional
        The initial charge of loop 1, coulomb: the capacitor voltages it implies.
    """
    chain = ladder.chain
    N = chain.N
    L = ladder.inductances()
    C = ladder.capacitances()
    elements: list[Element] = []
    for i in range(1, N + 1):
        left, right = ladder.node(i - 1), ladder.node(i)
        if i == 1 and source:
            left = "s1"  # the source sits between the rail node n0 (or ground) and L1
        if i == N and port2:
            right = f"s{N}"  # the second port sits between coil N's branch and the rail node nN (or ground)
        series = [e for part in effects for e in part.in_series(ladder, i)]
        elements += _loop_branch(i, left, right, L[i - 1], kick if i == 1 else None, series)
        elements += _beside([e for part in effects for e in part.across_coil(ladder, i)], f"P{i}", left, right)
        if i < N:
            capacitance = C[i]
            assert capacitance is not None  # inner springs are > 0 (Chain checks it)
            ic = charge / capacitance if (charge is not None and i == 1) else None
            elements += _capacitor(ladder, effects, i, f"n{i}", capacitance, ic)
    for wall in (0, N):
        wall_capacitance = C[wall]
        if wall_capacitance is not None:
            ic = -charge / wall_capacitance if (charge is not None and wall == 0) else None
            elements += _capacitor(ladder, effects, wall, ladder.node(wall), wall_capacitance, ic)
    for node in range(N + 1):  # beside each rail node's capacitor: names <letter>G{node}
        if ladder.node(node) != GROUND:
            elements += _beside([e for part in effects for e in part.to_ground(ladder, node)], f"G{node}",
                                ladder.node(node), GROUND)
    for i in range(1, N):  # between neighbouring loops: a K of their coils, or an element across both
        between = [e for part in effects for e in part.between_coils(ladder, i)]
        names = _names([letter for letter, _ in between], f"B{i}_{i + 1}")
        elements += [Element(name, Ladder.inductor(i), Ladder.inductor(i + 1), value) if letter == "K"
                     else Element(name, ladder.node(i - 1), ladder.node(i + 1), value)
                     for name, (letter, value) in zip(names, between, strict=True)]
    if chain.coupled:
        # mutual inductance k sqrt(L_i L_i+1) between neighbouring coils: the chain's tridiagonal mass matrix
        elements += [Element(f"K{i}_{i + 1}", Ladder.inductor(i), Ladder.inductor(i + 1), chain.coupling)
                     for i in range(1, N)]
    return tuple(elements)
