"""The first-arrival peak's sensitivities as the ladder's components see them, and the corners they pick (pure).

:func:`lcchain.theory.sensitivity.peak_sensitivity` differentiates the peak with respect to the chain's masses
and springs; here each becomes a component of the netlist, named as :func:`lcchain.circuit.netlist.netlist_text`
names it (``L3``, ``C2_3``; a free end is a wire and has none), with its value in henry or farad, dp/dx in SI and
dp/d ln x, the number a builder sets beside a part's tolerance: a part at (1 + tol) moves the peak by about
tol dp/d ln x.  The metric is the current peak p = max I_N / I_1(0), or the energy fraction e = p^2 L_N / L_1
(``metric="energy"``), which a mismatch of the two end inductors does not move (the peak's largest
sensitivities, +-1/2 for L_1 and L_N of the optimal chains, are that mismatch).

:func:`corners` turns the ranking into the corners of a worst-case study: every combination of the K parts that
move the peak most at their tolerance, and the two corners whose signs the sensitivities predict to be the
extremes with every part at its tolerance.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np

from ..core.checks import choice, integer
from ..core.limits import MAX_CORNER_COMPONENTS
from ..core.types import ARRIVAL_METRICS, ArrivalMetric
from ..theory.sensitivity import PeakSensitivity, peak_sensitivity
from .ladder import Ladder

__all__ = ["Component", "LadderSensitivity", "ladder_sensitivity", "Corner", "corners"]


@dataclass(frozen=True)
class Component:
    """One inductor or capacitor of the ladder and what it does to the first-arrival peak.

    Attributes
    ----------
    name : str
        Its netlist name: ``L<i>`` (loop i = 1..N) or ``C<j>_<j+1>`` (spring j = 0..N, walls 0 and N).
    slot : int
        Its place among the corner signs: i - 1 for L_i, N + j for C_j_j+1.
    value : float
        Henry or farad.
    derivative : float
        dp/dx (or de/dx), per henry or per farad.
    relative : float
        dp/d ln x (or de/d ln x), dimensionless.
    """

    name: str
    slot: int
    value: float
    derivative: float
    relative: float

    @property
    def kind(self) -> str:
        """``"L"`` or ``"C"``."""
        return self.name[0]

    def to_dict(self) -> dict[str, object]:
        return {"name": self.name, "value": self.value, "derivative": self.derivative, "relative": self.relative}


@dataclass(frozen=True)
class LadderSensitivity:
    """The peak of a kicked ladder and every component's sensitivity, most influential first.

    Attributes
    ----------
    ladder : Ladder
    peak : float
        max I_N / I_1(0) at the first arrival.
    time : float
        Its time, units of sqrt(L0 C0).
    components : tuple of Component
        Ranked by the metric's |d/d ln x|, largest first (ties in netlist order).
    metric : {"peak", "energy"}
    value : float
        The metric's value: the peak, or the energy fraction peak^2 L_N / L_1.
    """

    ladder: Ladder
    peak: float
    time: float
    components: tuple[Component, ...]
    metric: ArrivalMetric = "peak"
    value: float = 0.0

    @property
    def time_s(self) -> float:
        """The peak's time in seconds."""
        return self.time * self.ladder.time_unit

    def to_dict(self) -> dict[str, object]:
        return {"N": self.ladder.chain.N, "L0": self.ladder.L0, "C0": self.ladder.C0, "peak": self.peak,
                "metric": self.metric, "value": self.value, "time": self.time, "time_s": self.time_s,
                "components": [c.to_dict() for c in self.components]}


#: Each metric's value and its derivatives by d ln m_i and d ln K_j, from the peak's sensitivities.
METRIC_VIEWS = {
    "peak": lambda s: (s.peak, s.relative_masses, s.relative_springs),
    "energy": lambda s: (s.energy, s.energy_relative_masses, s.energy_relative_springs),
}


def ladder_sensitivity(ladder: Ladder, sensitivity: PeakSensitivity | None = None, *,
                       metric: ArrivalMetric = "peak") -> LadderSensitivity:
    """Every component's d/dx and d/d ln x of the metric (L_i = m_i L0; C_j = C0 / K_j, so
    d/d ln C_j = -d/d ln K_j); d/dx = (d/d ln x) / x.

    Parameters
    ----------
    ladder : Ladder
    sensitivity : PeakSensitivity, optional
        Of ``ladder.chain``, when already computed.
    metric : {"peak", "energy"}
        The current peak p, or the energy fraction p^2 L_N / L_1.
    """
    choice("--metric", metric, ARRIVAL_METRICS)
    chain = ladder.chain
    sensitivity = sensitivity if sensitivity is not None else peak_sensitivity(chain)
    value, masses, springs = METRIC_VIEWS[metric](sensitivity)
    N = chain.N
    parts = []
    for i, inductance in enumerate(ladder.inductances()):
        parts.append(Component(ladder.inductor(i + 1), i, inductance, float(masses[i]) / inductance, float(masses[i])))
    for j, capacitance in enumerate(ladder.capacitances()):
        if capacitance is None:
            continue  # a free end is a wire
        relative = -float(springs[j])
        parts.append(Component(ladder.capacitor(j), N + j, capacitance, relative / capacitance, relative))
    order = sorted(range(len(parts)), key=lambda k: -abs(parts[k].relative))
    return LadderSensitivity(ladder, sensitivity.peak, sensitivity.time, tuple(parts[k] for k in order), metric,
                             float(value))


@dataclass(frozen=True)
class Corner:
    """One corner of a worst-case study.

    Attributes
    ----------
    label : str
        ``"nominal"``, the moved parts (``"L1+ C1_2-"``), or ``"predicted max"`` / ``"predicted min"``.
    signs : tuple of int or float
        2N + 1 signs (L_1..L_N, then C_0_1..C_N_N+1): what :class:`lcchain.circuit.effects.Tolerance` takes
        (a worst-case search's point may lie inside the box: positions in [-1, 1]).
    predicted : float
        The peak's change to first order, sum of s_x tol_x dp/d ln x.
    """

    label: str
    signs: tuple[float, ...]
    predicted: float


def corners(sensitivity: LadderSensitivity, *, components: int, tol_L: float, tol_C: float) -> list[Corner]:
    """The nominal, the 2^K corners of the K parts that move the peak most at their tolerance, and the two
    corners of every part at its tolerance whose signs the sensitivities predict to be the extremes.

    Parameters
    ----------
    sensitivity : LadderSensitivity
    components : int
        K, 1 .. :data:`lcchain.core.limits.MAX_CORNER_COMPONENTS` and at most the ladder's parts.
    tol_L, tol_C : float
        The relative tolerances of the inductors and the capacitors: parts are ranked by |dp/d ln x| tol_x,
        the peak's move at the tolerance.
    """
    parts = sensitivity.components
    components = integer("--components", components, at_least=1,
                         at_most=min(MAX_CORNER_COMPONENTS, len(parts)))
    tolerance = {"L": tol_L, "C": tol_C}
    ranked = sorted(parts, key=lambda c: -abs(c.relative) * tolerance[c.kind])[:components]
    size = 2 * sensitivity.ladder.chain.N + 1

    def corner(label: str, moved: dict[int, int]) -> Corner:
        signs = np.zeros(size, dtype=int)
        predicted = 0.0
        for part in parts:
            sign = moved.get(part.slot, 0)
            signs[part.slot] = sign
            predicted += sign * tolerance[part.kind] * part.relative
        return Corner(label, tuple(int(s) for s in signs), predicted)

    found = [corner("nominal", {})]
    for picked in itertools.product((1, -1), repeat=components):
        moved = {part.slot: sign for part, sign in zip(ranked, picked, strict=True)}
        found.append(corner(" ".join(f"{p.name}{'+' if s > 0 else '-'}" for p, s in zip(ranked, picked,
                                                                                       strict=True)), moved))
    for label, direction in (("predicted max", 1), ("predicted min", -1)):
        found.append(corner(label, {part.slot: direction * int(np.sign(part.relative)) for part in parts}))
    return found
