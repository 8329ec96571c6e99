"""A bill of materials: the ladder's distinct parts, as the netlist writes them, with their counts.

Derived from :func:`lcchain.circuit.elements.ladder_elements` (what the netlist and the exact theory are made
from), so the list cannot miss a part an effect adds: the chain's coils (L_i = m_i L0) and capacitors
(C = C0 / K, none for a free end), rounded to a preferred-number series when one is given
(:func:`lcchain.circuit.effects.rounded`, the ``preferred_values`` effect), and every element the effects add
(a resistor per coil for ``--Q``, a coupling K per pair of neighbouring coils ...).
"""

from __future__ import annotations

from dataclasses import dataclass

from ..theory.chain import Chain
from .effects import Effect, rounded
from .elements import ladder_elements
from .ladder import Ladder

__all__ = ["Part", "bill_of_materials", "PART_KINDS", "PROPERTY_KINDS"]

#: An element's kind (its SPICE letter) as a part, and the unit of its value.
PART_KINDS = {"L": ("inductor", "H"), "C": ("capacitor", "F"), "R": ("resistor", "ohm"), "K": ("coupling", "1")}
#: The kinds that are no part of their own whatever writes them: a coupling is how two coils are wound.
PROPERTY_KINDS = frozenset({"K"})
#: Values equal to this many significant digits are one part (the arithmetic of L0 m_i leaves rounding noise).
_DIGITS = 12


@dataclass(frozen=True)
class Part:
    """One distinct part of the ladder.

    Attributes
    ----------
    kind : str
        ``"inductor"``, ``"capacitor"``, ``"resistor"`` or ``"coupling"``.
    value : float
        Henry, farad, ohm, or the coupling coefficient k.
    unit : str
        ``"H"``, ``"F"``, ``"ohm"`` or ``"1"``.
    names : tuple of str
        The netlist's elements of this value (``L1``, ``L8``).
    bought : bool
        A part to buy (False: a property of the parts bought, which the circuit models as an element of its own:
        a coil's self-capacitance, a capacitor's ESR, the coupling of two coils).
    """

    kind: str
    value: float
    unit: str
    names: tuple[str, ...]
    bought: bool = True

    @property
    def count(self) -> int:
        return len(self.names)


def bill_of_materials(chain: Chain, L0: float, C0: float, *, series: str | None = None,
                      effects: tuple[Effect, ...] = ()) -> tuple[Part, ...]:
    """The ladder's distinct parts: inductors, then capacitors, then what the effects add, each by value.

    Parameters
    ----------
    chain : Chain
        In bulk units (its coupling writes the K elements).
    L0, C0 : float
        Bulk inductance (H) and capacitance (F).
    series : {"E12", "E24", "E96"}, optional
        Round every L and C to this preferred-number series first (free ends stay wires).
    effects : tuple of Effect
        Effects whose elements join the ladder; an effect that changes the chain is applied first.
    """
    for effect in effects:
        chain = effect.realise(chain, L0, C0)
    if series is not None:
        chain = rounded(chain, L0, C0, series)
    ladder = Ladder(chain, L0, C0)
    # the elements the parasitic effects add, found from what each writes (not from its elements' names)
    bought = {element.name for element in ladder_elements(ladder, tuple(e for e in effects if not e.parasitic))}
    grouped: dict[tuple[bool, str, float], list[str]] = {}
    for element in ladder_elements(ladder, effects):
        letter = element.name[0].upper()
        part = element.name in bought and letter not in PROPERTY_KINDS
        grouped.setdefault((part, letter, float(f"{element.value:.{_DIGITS}g}")), []).append(element.name)
    order = list(PART_KINDS)
    parts = [Part(PART_KINDS[letter][0], value, PART_KINDS[letter][1], tuple(names), part)
             for (part, letter, value), names in sorted(grouped.items(), key=lambda item: (
                 not item[0][0], order.index(item[0][1]) if item[0][1] in order else len(order), item[0][2]))
             if letter in PART_KINDS]
    return tuple(parts)
