"""A chain in physical units: the LC ladder's component values (pure).

Mapping (last section of the paper, Fig. LCcircuit): mass m_i -> inductor
L_i = m_i L0, spring K_{i,i+1} -> capacitor C_{i,i+1} = C0 / K_{i,i+1}; a wall
spring is a capacitor to ground and a free end (K = 0) a wire.  Loop charges
are the coordinates, loop currents the velocities, and the time unit is
sqrt(L0 C0).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..core.checks import instance, real
from ..core.errors import ParameterError
from ..core.limits import MAX_IMPEDANCE, MAX_TIME_UNIT, MIN_IMPEDANCE, MIN_TIME_UNIT
from ..core.types import DEFAULT_C0, DEFAULT_L0
from ..theory.chain import Chain

__all__ = ["Ladder"]


@dataclass(frozen=True)
class Ladder:
    """A chain in physical units: the LC ladder's component values.

    Parameters
    ----------
    chain : Chain
        Masses and springs in bulk units.
    L0 : float
        Bulk inductance in henry (the bulk mass), > 0.
    C0 : float
        Bulk capacitance in farad (1 / bulk spring), > 0.
    """

    chain: Chain
    L0: float = DEFAULT_L0
    C0: float = DEFAULT_C0

    def __post_init__(self) -> None:
        instance("chain", self.chain, Chain)
        L0 = real("L0", self.L0, above=0.0, unit="henry")
        C0 = real("C0", self.C0, above=0.0, unit="farad")
        unit, impedance = math.sqrt(L0 * C0), math.sqrt(L0 / C0)
        if not (MIN_TIME_UNIT <= unit <= MAX_TIME_UNIT and MIN_IMPEDANCE <= impedance <= MAX_IMPEDANCE):
            # name the value farther from the usual scale (10 uH, 10 nF): the one the user most likely mistyped
            nearer_C0 = abs(math.log(L0 / DEFAULT_L0)) >= abs(math.log(C0 / DEFAULT_C0))
            field, value = ("L0", L0) if nearer_C0 else ("C0", C0)
            raise ParameterError(field, value, f"L0 and C0 with a time unit sqrt(L0*C0) from {MIN_TIME_UNIT:g} to "
                                 f"{MAX_TIME_UNIT:g} s and an impedance sqrt(L0/C0) from {MIN_IMPEDANCE:g} to "
                                 f"{MAX_IMPEDANCE:g} ohm (here {unit:.3g} s and {impedance:.3g} ohm; ngspice hangs "
                                 "or misbehaves beyond)")
        object.__setattr__(self, "L0", L0)
        object.__setattr__(self, "C0", C0)

    @property
    def time_unit(self) -> float:
        """sqrt(L0 C0) in seconds: the circuit's unit of dimensionless time."""
        return math.sqrt(self.L0 * self.C0)

    @property
    def impedance(self) -> float:
        """sqrt(L0 / C0) in ohm: the bulk characteristic impedance."""
        return math.sqrt(self.L0 / self.C0)

    def inductance(self, loop: int) -> float:
        """L_loop = m_loop L0, henry (loop from 1)."""
        return float(self.chain.masses[loop - 1]) * self.L0

    def inductances(self) -> list[float]:
        """L_i = m_i L0, henry."""
        return [self.inductance(i) for i in range(1, self.chain.N + 1)]

    def capacitances(self) -> list[float | None]:
        """C_{i,i+1} = C0 / K_{i,i+1}, farad (index 0 and N are the walls); None = wire."""
        return [None if k == 0 else self.C0 / float(k) for k in self.chain.springs]

    def parts(self) -> dict[str, list[float | None]]:
        """The part values as a sample's record keeps them: ``{"L": L_i in henry, "C": C_j in farad (None: a
        wire)}``, plain floats."""
        return {"L": [float(v) for v in self.inductances()],
                "C": [None if v is None else float(v) for v in self.capacitances()]}

    @staticmethod
    def inductor(loop: int) -> str:
        """The netlist name of L_loop (loop from 1)."""
        return f"L{loop}"

    @staticmethod
    def capacitor(spring: int) -> str:
        """The netlist name of C_{spring,spring+1} (spring 0..N; 0 and N are the walls)."""
        return f"C{spring}_{spring + 1}"

    def node(self, i: int) -> str:
        """Name of rail node i (0..N); a free end's node is ground."""
        N = self.chain.N
        if (i == 0 and self.chain.springs[0] == 0) or (i == N and self.chain.springs[N] == 0):
            return "0"
        return f"n{i}"
