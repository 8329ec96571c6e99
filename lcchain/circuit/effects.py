"""Real-world effects on the LC ladder, each one frozen part (pure).

Every effect is a frozen :class:`Effect`: the ``[effects.<key>]`` table of a
scene, validated on construction, that says in one place what it does to the
circuit:

* :meth:`Effect.realise`: the chain it builds (walls change the end springs,
  coupling the mass matrix, preferred values every L and C);
* the element hooks (:data:`lcchain.circuit.elements.ELEMENT_HOOKS`): the
  elements it adds and where: :meth:`Effect.in_series` (after each coil),
  :meth:`Effect.across_coil`, :meth:`Effect.capacitor_series`,
  :meth:`Effect.across_capacitor`, :meth:`Effect.to_ground` (from each rail
  node) and :meth:`Effect.between_coils` (a ``K`` or an element spanning two
  neighbouring coils).  :func:`lcchain.circuit.elements.ladder_elements` lists
  them; the netlist writes that list and the circuit's exact theory
  (:mod:`lcchain.circuit.exact`) solves it, so neither can drop an effect;
* :meth:`Effect.response`: what the chain's own (fast) theory needs beyond the
  chain when the circuit stays a chain (losses: the quality factor Q).

:data:`EFFECTS` maps scene keys to the types, lcchain's own and those other
packages add through the ``lcchain.effects`` entry-point group; the scene
schema and the command line's options are read from it.  To add an effect:
write one frozen dataclass subclass of :class:`Effect` (a ``key``, its fields,
the hooks it needs) and register it (docs/extending.md).

The effects:

* walls: a wall spring K0 at both ends (the paper's bounded chain);
* coupling: mutual inductance k sqrt(L_i L_(i+1)) between neighbouring coils
  (``K`` elements), a tridiagonal mass matrix in theory;
* losses: a resistor R_i = L_i / (Q sqrt(L0 C0)) in series with every inductor;
* preferred values: every inductor and capacitor rounded to the nearest
  value of an IEC 60063 E-series (E12, E24, E96), in henry and farad;
* tolerances: every inductor (capacitor) multiplied by 1 + u, u uniform in
  [-tol_L, +tol_L] ([-tol_C, +tol_C]), drawn independently per component
  from ``numpy.random.default_rng``; sample k uses the k-th child of
  ``SeedSequence(seed)``, so samples are reproducible and independent of
  how many are drawn.  Tolerances apply to the rounded values (one buys E24
  parts, each within its tolerance);
* the real parts (:data:`REAL_PARTS`): a coil's self-capacitance (across it)
  and winding resistance (in series), a capacitor's ESR and ESL (in series
  with it): elements no chain has, whose theory is the circuit's own.

The chain changes' results are chains in bulk units again (masses = L/L0, springs =
C0/C): rounding and tolerances break the mirror symmetry, so their theory
comes from the exact modes of each chain.  Losses, the real parts and pulse
sources are circuit elements, not chain changes: see
:func:`lcchain.circuit.elements.ladder_elements`.

Rounding is vectorised (one numpy pass over every component) and done once
for the nominal chain; each tolerance sample only multiplies the rounded values.
"""

from __future__ import annotations

from dataclasses import Field, dataclass, fields
from typing import ClassVar

import numpy as np

from ..core.checks import choice, integer, is_number, real
from ..core.errors import ParameterError
from ..core.limits import MAX_PARASITIC, MAX_Q, MAX_SAMPLES, MAX_WALL_SPRING, MIN_Q
from ..core.registry import Registry
from ..core.types import E_SERIES_NAMES, ESeries
from ..theory.chain import MAX_COUPLING, Chain
from .ladder import Ladder

__all__ = ["E_SERIES", "preferred_value", "preferred_values", "with_walls", "rounded", "realise",
           "tolerance_samples", "cornered", "Effect", "Walls", "Coupling", "Losses", "Tolerance", "PreferredValues",
           "EFFECTS", "SeriesElement", "CoilCapacitance", "CoilResistance", "CapacitorESR", "CapacitorESL",
           "REAL_PARTS", "effect_fields"]

#: An element in series with an inductor: its SPICE letter and its value (ohm for "R").
SeriesElement = tuple[str, float]

#: IEC 60063 series, mantissas in [1, 10).
E_SERIES: dict[str, tuple[float, ...]] = {
    "E12": (1.0, 1.2, 1.5, 1.8, 2.2, 2.7, 3.3, 3.9, 4.7, 5.6, 6.8, 8.2),
    "E24": (1.0, 1.1, 1.2, 1.3, 1.5, 1.6, 1.8, 2.0, 2.2, 2.4, 2.7, 3.0,
            3.3, 3.6, 3.9, 4.3, 4.7, 5.1, 5.6, 6.2, 6.8, 7.5, 8.2, 9.1),
    "E96": tuple(v / 100 for v in (
        100, 102, 105, 107, 110, 113, 115, 118, 121, 124, 127, 130, 133, 137, 140, 143, 147, 150, 154, 158,
        162, 165, 169, 174, 178, 182, 187, 191, 196, 200, 205, 210, 215, 221, 226, 232, 237, 243, 249, 255,
        261, 267, 274, 280, 287, 294, 301, 309, 316, 324, 332, 340, 348, 357, 365, 374, 383, 392, 402, 412,
        422, 432, 442, 453, 464, 475, 487, 499, 511, 523, 536, 549, 562, 576, 590, 604, 619, 634, 649, 665,
        681, 698, 715, 732, 750, 768, 787, 806, 825, 845, 866, 887, 909, 931, 953, 976)),
}



def _candidates(series: str, decades: np.ndarray) -> np.ndarray:
    """Every series value of the given decades and their neighbours, ascending."""
    exponents = np.unique(np.concatenate((decades - 1, decades, decades + 1)))
    # the text round trip removes the representation noise of mantissa * 10**exponent
    return np.array(sorted({float(f"{m * 10.0 ** int(e):.12g}") for e in exponents for m in E_SERIES[series]}))


def preferred_values(values: np.ndarray, series: str) -> np.ndarray:
    """Nearest values of the E-series, nearest in ratio (on a log scale), for an array.

    The nearest value in ratio is one of the two series values around each
    value, found by binary search on the sorted candidates; a tie goes to the
    smaller one.

    Parameters
    ----------
    values : array_like
        Positive component values (H or F).
    series : {"E12", "E24", "E96"}

    Returns
    -------
    ndarray
        Same shape.
    """
    choice("series", series, tuple(E_SERIES))
    array = np.asarray(values, dtype=float)
    if not np.all(np.isfinite(array) & (array > 0)):
        bad = array[~(np.isfinite(array) & (array > 0))].flat[0]
        raise ParameterError("value", float(bad), "a finite component value > 0")
    flat = array.ravel()
    table = _candidates(series, np.unique(np.floor(np.log10(flat)).astype(int)))
    above = np.clip(np.searchsorted(table, flat), 1, table.size - 1)
    low, high = table[above - 1], table[above]
    nearer_low = np.abs(np.log(low / flat)) <= np.abs(np.log(high / flat))
    return np.where(nearer_low, low, high).reshape(array.shape)


def preferred_value(value: float, series: str) -> float:
    """Nearest value of the E-series to one component value (see :func:`preferred_values`)."""
    return float(preferred_values(np.array([real("value", value, above=0.0)]), series)[0])


def with_walls(chain: Chain, K0: float) -> Chain:
    """The chain with a wall spring K0 (bulk units, > 0) at both ends."""
    K0 = real("K0", K0, above=0.0, allowed="a finite wall spring > 0 (bulk units)")
    springs = np.array(chain.springs)
    springs[0] = springs[-1] = K0
    return Chain(chain.masses, springs, name=chain.name, coupling=chain.coupling)


def _components(chain: Chain, L0: float, C0: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    inductance = np.asarray(chain.masses) * L0
    springs = np.asarray(chain.springs)
    wired = springs == 0  # free ends are wires: nothing to round or tolerance
    capacitance = np.where(wired, np.inf, C0 / np.where(wired, 1.0, springs))
    return inductance, capacitance, wired


def _chain(inductance: np.ndarray, capacitance: np.ndarray, wired: np.ndarray, L0: float, C0: float,
           name: str, coupling: float) -> Chain:
    springs = np.where(wired, 0.0, C0 / np.where(wired, 1.0, capacitance))
    return Chain(inductance / L0, springs, name=name, coupling=coupling)


def rounded(chain: Chain, L0: float, C0: float, series: str) -> Chain:
    """The chain built from the nearest E-series parts (every L and C rounded, free ends stay wires)."""
    inductance, capacitance, wired = _components(chain, L0, C0)
    inductance = preferred_values(inductance, series)
    capacitance = capacitance.copy()
    capacitance[~wired] = preferred_values(capacitance[~wired], series)
    return _chain(inductance, capacitance, wired, L0, C0, chain.name, chain.coupling)


def realise(chain: Chain, L0: float, C0: float, *, series: str | None = None, tol_L: float = 0.0,
            tol_C: float = 0.0, rng: np.random.Generator | None = None, name: str | None = None) -> Chain:
    """The chain actually built from components: rounded and/or toleranced.

    Parameters
    ----------
    chain : Chain
        Nominal chain (bulk units).
    L0, C0 : float
        Bulk inductance (H) and capacitance (F) that scale it.
    series : {"E12", "E24", "E96"}, optional
        Round every L and C to this series first (once: pass the already
        rounded chain and no series when realising many samples).
    tol_L, tol_C : float
        Relative tolerances, 0 <= tol < 1.
    rng : numpy.random.Generator, optional
        Required when a tolerance is non-zero.
    name : str, optional
        Name of the realised chain (default: the nominal's).
    """
    tol_L = real("tol_L", tol_L, at_least=0.0, below=1.0)
    tol_C = real("tol_C", tol_C, at_least=0.0, below=1.0)
    if series is not None:
        chain = rounded(chain, L0, C0, series)
    if not (tol_L or tol_C):
        return _scaled(chain, L0, C0, None, None, name or chain.name)
    if rng is None:
        raise ParameterError("rng", None, "a numpy Generator when a tolerance is non-zero")
    return _scaled(chain, L0, C0, tol_L * rng.uniform(-1.0, 1.0, chain.N),
                   tol_C * rng.uniform(-1.0, 1.0, chain.N + 1), name or chain.name)


def _scaled(chain: Chain, L0: float, C0: float, du_L: np.ndarray | None, du_C: np.ndarray | None,
            name: str) -> Chain:
    """The chain with every L_i times 1 + du_L[i] and every C_j times 1 + du_C[j] (None: unchanged)."""
    inductance, capacitance, wired = _components(chain, L0, C0)
    if du_L is not None and du_C is not None:
        inductance = inductance * (1 + du_L)
        capacitance = capacitance * (1 + du_C)
    return _chain(inductance, capacitance, wired, L0, C0, name, chain.coupling)


def cornered(chain: Chain, L0: float, C0: float, *, signs: tuple[float, ...], tol_L: float, tol_C: float,
             name: str | None = None) -> Chain:
    """The chain at a corner of its tolerances: L_i times 1 + s_i tol_L, C_j times 1 + s_j tol_C.

    Parameters
    ----------
    chain : Chain
        The nominal chain (already rounded to its series, if any).
    L0, C0 : float
        Bulk inductance (H) and capacitance (F).
    signs : tuple of int
        2N + 1 positions in [-1, 1] (signs -1, 0, 1 at a corner): L_1..L_N, then C_0_1..C_N_N+1 (a free end's
        is ignored: a wire).
    tol_L, tol_C : float
        Relative tolerances, 0 <= tol < 1.
    """
    if len(signs) != 2 * chain.N + 1:
        raise ParameterError("effects.tolerance.corner", f"{len(signs)} signs", f"2N+1 = {2 * chain.N + 1} signs "
                             "(L_1..L_N, then C_0_1..C_N_N+1) for this chain")
    values = np.asarray(signs, dtype=float)
    return _scaled(chain, L0, C0, tol_L * values[:chain.N], tol_C * values[chain.N:], name or chain.name)


def tolerance_samples(chain: Chain, L0: float, C0: float, *, samples: int, seed: int, tol_L: float,
                      tol_C: float, series: str | None = None) -> list[Chain]:
    """``samples`` realised chains; sample k draws from ``SeedSequence(seed).spawn(samples)[k]``.

    The nominal chain is rounded to ``series`` once, then every sample
    multiplies each rounded value by its own 1 + u.
    """
    samples = integer("samples", samples, at_least=1, at_most=MAX_SAMPLES)
    seed = integer("seed", seed, at_least=0)
    base = rounded(chain, L0, C0, series) if series is not None else chain
    children = np.random.SeedSequence(seed).spawn(samples)
    return [realise(base, L0, C0, tol_L=tol_L, tol_C=tol_C, rng=np.random.default_rng(child),
                    name=f"{chain.name} sample {k + 1}")
            for k, child in enumerate(children)]


# ------------------------------------------------------------------- the parts
def effect_fields(cls: type[Effect]) -> tuple[Field[object], ...]:
    """An effect type's fields: the keys of its scene table (every effect type is a dataclass)."""
    return fields(cls)  # type: ignore[arg-type]  # Effect's subclasses are dataclasses; Effect itself is not


class Effect:
    """One real-world effect on the ladder (subclasses are frozen dataclasses).

    A subclass sets ``key`` (its scene table, ``[effects.<key>]``), validates
    its fields in ``__post_init__`` naming them ``effects.<key>.<field>``, and
    overrides what it changes; the defaults change nothing.
    """

    key: ClassVar[str] = ""
    #: Whether it acts on the part values of a realised circuit (rounding them, drawing them within tolerances),
    #: after the nominal chain: the nominal chain is made without it.
    on_parts: ClassVar[bool] = False
    #: The command-line option that asks for this effect (``lcchain simulate --coil-capacitance 0.01``), or None;
    #: its value is the effect's one field.  ``option_help`` says what it adds, in bulk units.
    option: ClassVar[str | None] = None
    option_help: ClassVar[str] = ""
    #: Whether the elements it adds are properties of the chain's parts (a coil's self-capacitance, a capacitor's
    #: ESR), not parts of their own: a bill of materials lists them apart, as nothing to buy.
    parasitic: ClassVar[bool] = False

    @classmethod
    def from_option(cls, value: object) -> Effect:
        """The effect its option's value asks for (the value is its one field, checked there)."""
        names = [f.name for f in effect_fields(cls)]
        if len(names) != 1:
            raise ParameterError("option", cls.option, f"an effect with one field ({cls.__name__} has {names})")
        return cls(**{names[0]: value})

    def realise(self, chain: Chain, L0: float, C0: float) -> Chain:
        """The chain with this effect (bulk units; ``L0`` H and ``C0`` F give the components' scale)."""
        return chain

    def in_series(self, ladder: Ladder, loop: int) -> tuple[SeriesElement, ...]:
        """Elements in series with inductor L_loop (1-based), after it."""
        return ()

    def across_coil(self, ladder: Ladder, loop: int) -> tuple[SeriesElement, ...]:
        """Elements across coil ``loop`` (1-based): from its rail node to the next, across the inductor and what is
        in series with it."""
        return ()

    def capacitor_series(self, ladder: Ladder, spring: int) -> tuple[SeriesElement, ...]:
        """Elements in series with capacitor C_{spring,spring+1} (spring 0..N; 0 and N are the walls), between
        its rail node and the capacitor."""
        return ()

    def across_capacitor(self, ladder: Ladder, spring: int) -> tuple[SeriesElement, ...]:
        """Elements in parallel with capacitor C_{spring,spring+1} alone (spring 0..N; 0 and N are the walls):
        from the capacitor's own node to ground, inside what :meth:`capacitor_series` puts in series with it (a
        dielectric's leakage, with the capacitor's ESR and ESL outside it).  A wire (a free end) has none."""
        return ()

    def to_ground(self, ladder: Ladder, node: int) -> tuple[SeriesElement, ...]:
        """Elements from rail node ``node`` (0..N) to ground, beside the capacitor there (a free end's node is
        ground already: none)."""
        return ()

    def between_coils(self, ladder: Ladder, loop: int) -> tuple[SeriesElement, ...]:
        """Elements between loop ``loop`` and loop ``loop + 1`` (1..N-1): ``("K", k)`` couples coils L_loop and
        L_(loop+1) (a mutual inductance k sqrt(L_loop L_(loop+1))); an R, L or C joins loop ``loop``'s left rail
        node to loop ``loop + 1``'s right one, across both coils."""
        return ()

    def response(self) -> dict[str, float]:
        """Keywords of :func:`lcchain.theory.response.linear_response` beyond the chain (e.g. ``{"Q": 100.0}``)."""
        return {}


@dataclass(frozen=True)
class Walls(Effect):
    """``[effects.walls]``: a wall spring K0 at each end, as in the paper's bounded chain.

    Parameters
    ----------
    K0 : float
        Wall spring constant in bulk units (0 < K0 <= :data:`lcchain.core.limits.MAX_WALL_SPRING`); its capacitor is
        C0 / K0.
    """

    key: ClassVar[str] = "walls"
    K0: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "K0", real("effects.walls.K0", self.K0, above=0.0, at_most=MAX_WALL_SPRING,
                                            allowed=f"a number, 0 < K0 <= {MAX_WALL_SPRING:g} (a stiffer wall's mode "
                                            "needs steps no budget affords)"))

    def realise(self, chain: Chain, L0: float, C0: float) -> Chain:
        return with_walls(chain, self.K0)


@dataclass(frozen=True)
class Coupling(Effect):
    """``[effects.coupling]``: mutual inductance between neighbouring coils.

    Each pair L_i, L_(i+1) is coupled by M = k sqrt(L_i L_(i+1)) (a ``K``
    element); in theory the mass matrix becomes tridiagonal and the modes
    solve K u = omega^2 M u (:mod:`lcchain.theory.exact`).

    Parameters
    ----------
    k : float
        Coupling coefficient, -1/2 < k < 1/2 (the mass matrix stays positive definite for every N).
    """

    key: ClassVar[str] = "coupling"
    option: ClassVar[str | None] = "--coupling"
    option_help: ClassVar[str] = (f"mutual inductance k*sqrt(L_i*L_i+1) between neighbouring coils, -{MAX_COUPLING:g} "
                                  f"< K < {MAX_COUPLING:g} (default 0)")
    k: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "k", real("effects.coupling.k", self.k, above=-MAX_COUPLING, below=MAX_COUPLING,
                                           allowed=f"a number, -{MAX_COUPLING:g} < k < {MAX_COUPLING:g}"))

    def realise(self, chain: Chain, L0: float, C0: float) -> Chain:
        return chain.with_coupling(self.k)


@dataclass(frozen=True)
class Losses(Effect):
    """``[effects.losses]``: a series resistor R_i = L_i / (Q sqrt(L0*C0)) with every inductor.

    Every mode then decays at the same rate gamma = 1/Q (units of 1/sqrt(L0 C0)).

    Parameters
    ----------
    Q : float
        Quality factor of every inductor at 1/sqrt(L0*C0) (dimensionless, :data:`lcchain.core.limits.MIN_Q` to
        :data:`~lcchain.core.limits.MAX_Q`; an AC analysis refuses a Q above what its fit places,
        :func:`lcchain.compare.spectral.lossy_range`, and below its range says which modes merged,
        :func:`lcchain.compare.spectral.merged_modes`).
    """

    key: ClassVar[str] = "losses"
    option: ClassVar[str | None] = "--Q"
    option_help: ClassVar[str] = (f"losses: a resistor L_i/(Q*sqrt(L0*C0)) in series with every coil ({MIN_Q:g} <= Q "
                                  f"<= {MAX_Q:g})")
    Q: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "Q", real("effects.losses.Q", self.Q, at_least=MIN_Q, at_most=MAX_Q,
                                           allowed=f"a number, {MIN_Q:g} <= Q <= {MAX_Q:g} (below, the losses' decay "
                                           "rate leaves the band the step is chosen for; above, the resistors are "
                                           "beyond the simulator's resolution)"))

    def in_series(self, ladder: Ladder, loop: int) -> tuple[SeriesElement, ...]:
        # R_i = L_i / (Q tau): in bulk units a friction m_i / Q, the same rate 1/Q for every mode
        return (("R", ladder.inductance(loop) / (self.Q * ladder.time_unit)),)

    def response(self) -> dict[str, float]:
        return {"Q": self.Q}


@dataclass(frozen=True)
class PreferredValues(Effect):
    """``[effects.preferred_values]``: every L and C rounded to a preferred-number series.

    Parameters
    ----------
    series : {"E12", "E24", "E96"}
    """

    key: ClassVar[str] = "preferred_values"
    on_parts: ClassVar[bool] = True
    series: ESeries

    def __post_init__(self) -> None:
        choice("effects.preferred_values.series", self.series, E_SERIES_NAMES)

    def realise(self, chain: Chain, L0: float, C0: float) -> Chain:
        return rounded(chain, L0, C0, self.series)


@dataclass(frozen=True)
class Tolerance(Effect):
    """``[effects.tolerance]``: component values drawn around their nominal ones.

    Parameters
    ----------
    L, C : float
        Relative tolerance of every inductor / capacitor, 0 <= tol < 1.
    samples : int
        Number of sampled circuits, 1..10000.
    seed : int
        Seed of ``numpy.random.default_rng`` (>= 0), so that a study repeats.
    corner : tuple of int or float, optional
        Instead of drawing: the one circuit with every component at nominal x (1 + s x its tolerance),
        2N + 1 positions s in [-1, 1] (signs in {-1, 0, 1} at the corners), L_1..L_N then C_0_1..C_N_N+1
        (:func:`cornered`; ``lcchain sweep SCENE --worst-case`` makes them, a point inside the box when its
        search's worst is there).  One sample.
    """

    key: ClassVar[str] = "tolerance"
    on_parts: ClassVar[bool] = True
    L: float = 0.0
    C: float = 0.0
    samples: int = 1
    seed: int = 0
    corner: tuple[float, ...] | None = None

    def __post_init__(self) -> None:
        for name in ("L", "C"):
            value = real(f"effects.tolerance.{name}", getattr(self, name), at_least=0.0, below=1.0,
                         allowed=f"a number, 0 <= {name} < 1")
            object.__setattr__(self, name, value)
        samples = integer("effects.tolerance.samples", self.samples, at_least=1, at_most=MAX_SAMPLES)
        object.__setattr__(self, "samples", samples)
        object.__setattr__(self, "seed", integer("effects.tolerance.seed", self.seed, at_least=0))
        if self.corner is not None:
            if not isinstance(self.corner, (list, tuple)) or any(
                    isinstance(v, bool) or not is_number(v) or not -1.0 <= v <= 1.0 for v in self.corner):
                raise ParameterError("effects.tolerance.corner", self.corner, "a list of numbers from -1 to 1, "
                                     "signs -1, 0 or 1 at the corners (one per component: L_1..L_N, then "
                                     "C_0_1..C_N_N+1)")
            if samples != 1:
                raise ParameterError("effects.tolerance.samples", samples, "1 with a corner (one circuit)")
            # integers stay integers (a corner's signs); a point inside the box (a worst-case search's) keeps floats
            object.__setattr__(self, "corner", tuple(int(v) if float(v).is_integer() else float(v)
                                                     for v in self.corner))

    @property
    def varies(self) -> bool:
        """Whether the samples differ from the nominal circuit (or there are several)."""
        return bool(self.L or self.C or self.samples > 1)

    def draw(self, chain: Chain, L0: float, C0: float, series: str | None = None) -> list[Chain]:
        """The sampled chains (:func:`tolerance_samples`), or the corner's one chain (:func:`cornered`)."""
        if self.corner is not None:
            base = rounded(chain, L0, C0, series) if series is not None else chain
            return [cornered(base, L0, C0, signs=self.corner, tol_L=self.L, tol_C=self.C,
                             name=f"{chain.name} corner")]
        return tolerance_samples(chain, L0, C0, samples=self.samples, seed=self.seed, tol_L=self.L, tol_C=self.C,
                                 series=series)


def _bulk(key: str, name: str, value: object, what: str) -> float:
    """A parasitic's value in units of its bulk element: 0 < value <= :data:`MAX_PARASITIC`."""
    return real(f"effects.{key}.{name}", value, above=0.0, at_most=MAX_PARASITIC,
                allowed=f"a number, 0 < {name} <= {MAX_PARASITIC:g} ({what}; a parasitic larger than "
                        f"{MAX_PARASITIC:g} times its bulk part is another part)")


@dataclass(frozen=True)
class CoilCapacitance(Effect):
    """``[effects.coil_capacitance]``: a real coil's self-capacitance, a capacitor ``ratio`` C0 across every coil.

    Each coil then resonates by itself at 1/sqrt(L_i ratio C0): above the ladder's band top (omega = 2) when
    ratio < 1/4 for bulk coils.

    Parameters
    ----------
    ratio : float
        The capacitance in units of C0, 0 < ratio <= :data:`~lcchain.core.limits.MAX_PARASITIC`.
    """

    key: ClassVar[str] = "coil_capacitance"
    parasitic: ClassVar[bool] = True
    option: ClassVar[str | None] = "--coil-capacitance"
    option_help: ClassVar[str] = ("a coil's self-capacitance: a capacitor ratio*C0 across every coil "
                                  f"(0 < ratio <= {MAX_PARASITIC:g})")
    ratio: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "ratio", _bulk(self.key, "ratio", self.ratio, "capacitance / C0"))

    def across_coil(self, ladder: Ladder, loop: int) -> tuple[SeriesElement, ...]:
        return (("C", self.ratio * ladder.C0),)


@dataclass(frozen=True)
class CoilResistance(Effect):
    """``[effects.coil_resistance]``: a winding resistance ``R`` sqrt(L0/C0) in series with every coil, the same
    for every coil (losses not proportional to L: the modes decay at different rates).

    Parameters
    ----------
    R : float
        Ohm in units of the bulk impedance sqrt(L0/C0), 0 < R <= :data:`~lcchain.core.limits.MAX_PARASITIC`.
    """

    key: ClassVar[str] = "coil_resistance"
    parasitic: ClassVar[bool] = True
    option: ClassVar[str | None] = "--coil-resistance"
    option_help: ClassVar[str] = ("a coil's winding resistance: R*sqrt(L0/C0) ohm in series with every coil "
                                  f"(0 < R <= {MAX_PARASITIC:g})")
    R: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "R", _bulk(self.key, "R", self.R, "resistance / sqrt(L0/C0)"))

    def in_series(self, ladder: Ladder, loop: int) -> tuple[SeriesElement, ...]:
        return (("R", self.R * ladder.impedance),)


@dataclass(frozen=True)
class CapacitorESR(Effect):
    """``[effects.capacitor_esr]``: an equivalent series resistance ``R`` sqrt(L0/C0) with every capacitor.

    Parameters
    ----------
    R : float
        Ohm in units of the bulk impedance sqrt(L0/C0), 0 < R <= :data:`~lcchain.core.limits.MAX_PARASITIC`.
    """

    key: ClassVar[str] = "capacitor_esr"
    parasitic: ClassVar[bool] = True
    option: ClassVar[str | None] = "--capacitor-esr"
    option_help: ClassVar[str] = ("a capacitor's ESR: R*sqrt(L0/C0) ohm in series with every "
                                  f"capacitor (0 < R <= {MAX_PARASITIC:g})")
    R: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "R", _bulk(self.key, "R", self.R, "resistance / sqrt(L0/C0)"))

    def capacitor_series(self, ladder: Ladder, spring: int) -> tuple[SeriesElement, ...]:
        return (("R", self.R * ladder.impedance),)


@dataclass(frozen=True)
class CapacitorESL(Effect):
    """``[effects.capacitor_esl]``: an equivalent series inductance ``L`` L0 with every capacitor (each capacitor
    then resonates by itself at 1/sqrt(L L0 C): above the band top when L K < 1/4).

    Parameters
    ----------
    L : float
        Henry in units of L0, 0 < L <= :data:`~lcchain.core.limits.MAX_PARASITIC`.
    """

    key: ClassVar[str] = "capacitor_esl"
    parasitic: ClassVar[bool] = True
    option: ClassVar[str | None] = "--capacitor-esl"
    option_help: ClassVar[str] = ("a capacitor's ESL: L*L0 henry in series with every "
                                  f"capacitor (0 < L <= {MAX_PARASITIC:g})")
    L: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "L", _bulk(self.key, "L", self.L, "inductance / L0"))

    def capacitor_series(self, ladder: Ladder, spring: int) -> tuple[SeriesElement, ...]:
        return (("L", self.L * ladder.L0),)


#: The parts of real coils and capacitors, which no chain can say: their theory is the circuit's own
#: (:mod:`lcchain.circuit.exact`).
REAL_PARTS: tuple[type[Effect], ...] = (CoilCapacitance, CoilResistance, CapacitorESR, CapacitorESL)

def _admit(name: str, loaded: object) -> type[Effect]:
    """An ``lcchain.effects`` entry point's object: a frozen dataclass subclass of Effect whose key is its name."""
    if not isinstance(loaded, type):
        raise TypeError(f"{loaded!r} is not a class")
    if not issubclass(loaded, Effect):
        raise TypeError(f"{loaded.__name__} is not a subclass of lcchain.circuit.effects.Effect")
    if "__dataclass_fields__" not in vars(loaded):
        raise TypeError(f"{loaded.__name__} is not a dataclass (its fields are its scene table's keys)")
    if loaded.key != name:
        raise TypeError(f"its key is {loaded.key!r}, not the entry point's name")
    return loaded


#: Scene keys to effect types (``[effects.<key>]``): lcchain's own, then those of the ``lcchain.effects``
#: entry points of installed packages (read the first time the registry is).  The scene schema, its loader
#: and the command line's effect options all read this registry.
_OWN: tuple[type[Effect], ...] = (Losses, Walls, Coupling, Tolerance, PreferredValues, *REAL_PARTS)
EFFECTS: Registry[type[Effect]] = Registry(
    "lcchain.effects", {cls.key: cls for cls in _OWN}, _admit,
    "a frozen dataclass subclass of lcchain.circuit.effects.Effect, its key the entry point's name",
    name_of=lambda part: str(getattr(part, "key", "")))
