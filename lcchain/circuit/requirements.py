"""How good must the parts be: the first arrival's energy against each real part's parameter (pure).

For a chain built from real coils and capacitors, each parasitic of :data:`PARTS` (a coil's self-capacitance, its
winding resistance, a capacitor's ESR and ESL, the coupling between neighbouring coils) is swept alone over
decades, and the first arrival at the far end is computed exactly, from the circuit's own theory
(:mod:`lcchain.circuit.exact`) of the elements the netlist would be written from.  The loss a part costs is
``1 - e / e_ideal``: the first arrival's energy fraction ``e = p^2 L_N / L_1`` (``p`` the largest
``I_N / I_0`` in the first arrival's window, the kick's current ``I_0`` in loop 1) relative to the ideal
ladder's.  The requirement is the largest parameter below which that loss stays under a target (1 %, 0.1 %):
the first crossing of the curve, sampled on a logarithmic grid and refined by Brent's method, so a loss that
would dip again beyond it is not counted.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
import scipy  # its submodules load on first use: commands that need no theory never import them

from ..core.errors import ParameterError
from ..core.frozen import Reduced
from ..core.json import JSONDict
from ..core.physical import band_top
from ..theory.arrivals import arrival_window, maximum_in_window
from ..theory.chain import MAX_COUPLING, Chain
from ..theory.spectrum import normal_modes
from .effects import CapacitorESL, CapacitorESR, CoilCapacitance, CoilResistance, Effect
from .elements import ladder_elements
from .exact import CircuitTheory, exact_cost
from .ladder import Ladder

__all__ = ["Part", "PARTS", "part_named", "si", "Requirement", "Arrival", "first_arrival_energy", "requirement",
           "requirements_cost", "LOSS_TARGETS"]

#: The losses each requirement is given for: 1 % and 0.1 % of the first arrival's energy.
LOSS_TARGETS = (1e-2, 1e-3)
#: Points of each curve (log-spaced over the part's range) before the crossings are refined.
GRID_POINTS = 13


def _hertz(omega: float, ladder: Ladder) -> str:
    return si(omega / (2 * math.pi * ladder.time_unit), "Hz")


def si(value: float, unit: str) -> str:
    """A value with an SI prefix, 3 significant digits: ``2.31 MHz``."""
    if value == 0 or not math.isfinite(value):
        return f"{value:g} {unit}"
    exponent = min(max(int(math.floor(math.log10(abs(value)) / 3)), -5), 4)
    prefix = {-5: "f", -4: "p", -3: "n", -2: "µ", -1: "m", 0: "", 1: "k", 2: "M", 3: "G", 4: "T"}[exponent]
    return f"{value / 10.0 ** (3 * exponent):.3g} {prefix}{unit}"


@dataclass(frozen=True)
class Part:
    """One parasitic, swept alone: its parameter x (bulk units, worse as it grows) and what x means.

    ``build(chain, x)`` gives the chain and the effects of a ladder with that parasitic; ``physical(x, ladder)`` says
    the requirement ``x`` in the units an experimenter buys parts in.
    """

    key: str
    symbol: str
    what: str
    low: float
    high: float
    build: Callable[[Chain, float], tuple[Chain, tuple[Effect, ...]]]
    physical: Callable[[float, Ladder], str]
    room: Callable[[Chain], float] | None = None

    def span(self, chain: Chain) -> tuple[float, float]:
        """The range swept on ``chain``: ``low`` to ``high``, or to what ``room(chain)`` leaves when it is less
        (a stray coupling on a coupled design: up to the largest coupling a chain may have).

        Raises
        ------
        ParameterError
            No room at all (the design's coupling already at the limit).
        """
        high = self.high if self.room is None else min(self.high, self.room(chain))
        if not high > self.low:
            raise ParameterError("coupling", chain.coupling, f"|k| < {0.98 * MAX_COUPLING - self.low:.6g}, to "
                                 f"leave room for a stray {self.symbol} beside it (or leave {self.key} out of the "
                                 "parts)")
        return self.low, high

    def __reduce__(self) -> Reduced:
        # a part of PARTS travels by its key (its callables are lambdas, which do not pickle): a requirement
        # computed in the report's pool comes back holding the same part
        if any(part is self for part in PARTS):
            return (part_named, (self.key,))
        return (Part, (self.key, self.symbol, self.what, self.low, self.high, self.build, self.physical, self.room))


def _effect(make: Callable[[float], Effect]) -> Callable[[Chain, float], tuple[Chain, tuple[Effect, ...]]]:
    return lambda chain, x: (chain, (make(x),))


PARTS: tuple[Part, ...] = (
    Part("coil_capacitance", "r", "a capacitor r C0 across every coil (its self-resonance)", 1e-5, 1.0,
         _effect(CoilCapacitance),
         lambda x, ladder: (f"coil self-resonance above {_hertz(1 / math.sqrt(x), ladder)} "
                            f"(self-capacitance below {si(x * ladder.C0, 'F')}; the band top is "
                            f"{_hertz(band_top(ladder.chain.coupling), ladder)})")),
    Part("coil_resistance", "R", "a winding resistance R sqrt(L0/C0) in series with every coil", 1e-6, 1.0,
         _effect(CoilResistance),
         lambda x, ladder: (f"coil Q above {1 / x:.3g} at {_hertz(1.0, ladder)} (winding resistance below "
                            f"{si(x * ladder.impedance, 'Ω')})")),
    Part("capacitor_esr", "R", "an ESR R sqrt(L0/C0) in series with every capacitor", 1e-6, 1.0,
         _effect(CapacitorESR),
         lambda x, ladder: (f"capacitor ESR below {si(x * ladder.impedance, 'Ω')} (dissipation factor below "
                            f"{x:.3g} at {_hertz(1.0, ladder)})")),
    Part("capacitor_esl", "L", "an ESL L L0 in series with every capacitor", 1e-6, 1.0, _effect(CapacitorESL),
         lambda x, ladder: (f"capacitor ESL below {si(x * ladder.L0, 'H')} (capacitor self-resonance above "
                            f"{_hertz(1 / math.sqrt(x), ladder)})")),
    Part("coupling", "k", "a mutual inductance k sqrt(L_i L_i+1) between neighbouring coils, beside a coupled "
         "design's own and of its sign", 1e-6, 0.98 * MAX_COUPLING,
         lambda chain, x: (chain.with_coupling(_stray(chain.coupling, x)), ()), lambda x, ladder: (
             f"coupling between neighbouring coils below k = {x:.3g}" if not ladder.chain.coupling else
             f"stray coupling between neighbouring coils below k = {x:.3g} (k = "
             f"{_stray(ladder.chain.coupling, x):.3g} in all, beside the design's {ladder.chain.coupling:g})"),
         lambda chain: 0.98 * MAX_COUPLING - abs(chain.coupling)),
)


def _stray(coupling: float, k: float) -> float:
    """A design's coupling with a stray ``k`` beside it, of its sign (positive beside none)."""
    return coupling + math.copysign(k, coupling)


def part_named(key: str) -> Part:
    """The part of :data:`PARTS` whose key is ``key``."""
    for part in PARTS:
        if part.key == key:
            return part
    raise ParameterError("part", key, " | ".join(part.key for part in PARTS))


@dataclass(frozen=True)
class Arrival:
    """The first arrival at the far end: time (units of sqrt(L0 C0)), peak p = max I_N / I_0, energy fraction e."""

    time: float
    peak: float
    energy: float


def first_arrival_energy(ladder: Ladder, effects: tuple[Effect, ...] = (), transit_time: float | None = None
                         ) -> Arrival:
    """The kicked ladder's first arrival, from the circuit's own exact theory.

    ``transit_time`` places the search window (default: the ladder's chain's own).
    """
    chain = ladder.chain
    theory = CircuitTheory(ladder_elements(ladder, effects, kick=1.0))
    unit = ladder.time_unit
    last = f"L{chain.N}"
    transit = transit_time if transit_time is not None else normal_modes(chain).transit_time()
    time, peak = maximum_in_window(lambda t: theory.currents(np.asarray(t) * unit, [last])[0],
                                   arrival_window(1, transit), transit)
    return Arrival(time, peak, peak * peak * float(chain.masses[-1] / chain.masses[0]))


@dataclass(frozen=True)
class Requirement:
    """A part's curve and its requirements.

    ``values`` and ``losses``: the curve (loss 1 - e/e_ideal against the parameter); ``limits``: for each of
    :data:`LOSS_TARGETS`, the largest parameter keeping the loss under it (None: under it over the whole range,
    0.0: over it already at the range's start).
    """

    part: Part
    values: tuple[float, ...]
    losses: tuple[float, ...]
    limits: tuple[float | None, ...]

    def statement(self, index: int, ladder: Ladder) -> str:
        """Requirement ``index`` in physical units."""
        limit = self.limits[index]
        if limit is None:
            high = self.values[-1]
            # the end of the range swept, not a limit: its physical statement ("... below k = 0.29") would read as one
            return f"no limit: the loss stays under the target up to {self.part.symbol} = {high:g}, the range's end"
        if limit == 0.0:
            return f"not met even at {self.part.symbol} = {self.values[0]:g}"
        return self.part.physical(limit, ladder)

    def to_dict(self, ladder: Ladder) -> JSONDict:
        return {"part": self.part.key, "symbol": self.part.symbol, "what": self.part.what,
                "values": list(self.values), "losses": list(self.losses),
                "limits": {f"{target:g}": limit for target, limit in zip(LOSS_TARGETS, self.limits, strict=True)},
                "statements": {f"{target:g}": self.statement(k, ladder) for k, target in enumerate(LOSS_TARGETS)}}


def requirement(ladder: Ladder, part: Part, *, points: int = GRID_POINTS,
                progress: Callable[[float], None] | None = None) -> Requirement:
    """The curve of ``part`` over its range and the largest values keeping the loss under each target."""
    chain = ladder.chain
    transit = normal_modes(chain).transit_time()
    ideal = first_arrival_energy(ladder, (), transit).energy

    def loss(x: float) -> float:
        built, effects = part.build(chain, x)
        return 1.0 - first_arrival_energy(Ladder(built, ladder.L0, ladder.C0), effects, transit).energy / ideal

    values = np.geomspace(*part.span(chain), points)
    losses = []
    for k, x in enumerate(values):
        losses.append(loss(float(x)))
        if progress is not None:
            progress((k + 1) / (points + 2 * len(LOSS_TARGETS)))
    limits: list[float | None] = []
    for target in LOSS_TARGETS:
        over = [k for k, value in enumerate(losses) if value > target]
        if not over:
            limits.append(None)
        elif over[0] == 0:
            limits.append(0.0)
        else:
            k = over[0]
            root = scipy.optimize.brentq(lambda u, aim=target: loss(math.exp(u)) - aim, math.log(values[k - 1]),
                                         math.log(values[k]), xtol=1e-4)
            limits.append(math.exp(root))
    return Requirement(part, tuple(float(v) for v in values), tuple(losses), tuple(limits))


def requirements_cost(chain: Chain, parts: Sequence[Part], points: int = GRID_POINTS) -> float:
    """Seconds of :func:`requirement` for ``parts``: about (points + 25) first arrivals each, a dense lossy
    circuit theory of about 3 N states (the slowest part) and its window's evaluations."""
    if not parts:
        raise ParameterError("parts", [], "at least one part")
    seconds, _ = exact_cost(3 * chain.N, 2000, lossy=True)
    return len(parts) * (points + 25) * seconds
