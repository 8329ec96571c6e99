"""``lcchain bom`` as a function: the ladder's bill of materials (:func:`lcchain.circuit.bom.bill_of_materials`)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from ..circuit.effects import Effect
from ..core.budget import Budget
from ..core.errors import ParameterError
from .inputs import ChainOptions, make_chain

if TYPE_CHECKING:
    from ..circuit.bom import Part
    from ..theory.chain import Chain

__all__ = ["BomRequest", "Bom", "bom"]


@dataclass(frozen=True)
class BomRequest:
    """The chain, its units, a preferred-number ``series`` to round to (None: exact values), its effects."""

    chain: ChainOptions
    L0: float
    C0: float
    series: str | None = None
    effects: tuple[Effect, ...] = ()
    budget: Budget = field(default_factory=Budget)


@dataclass(frozen=True)
class Bom:
    """The chain and its distinct parts (:class:`lcchain.circuit.bom.Part`: kind, value, unit, count, names)."""

    chain: Chain
    parts: tuple[Part, ...]


def bom(request: BomRequest) -> Bom:
    from ..circuit.bom import bill_of_materials

    for option, value in (("--L0", request.L0), ("--C0", request.C0)):
        if not value > 0:
            raise ParameterError(option, value, "a component value > 0")
    chain = make_chain(request.chain, request.budget)
    return Bom(chain, bill_of_materials(chain, request.L0, request.C0, series=request.series,
                                        effects=request.effects))
