"""Real-world effects that change the chain itself (pure).

* walls: a wall spring K0 at both ends (the paper's bounded chain);
* preferred values: every inductor and capacitor rounded to the nearest
  value of an IEC 60063 E-series (E12, E24, E96), in henry and farad;
* tolerances: every inductor (capacitor) multiplied by 1 + u, u uniform in
  [-tol_L, +tol_L] ([-tol_C, +tol_C]), drawn independently per component
  from ``numpy.random.default_rng``; sample k uses the k-th child of
  ``SeedSequence(seed)``, so samples are reproducible and independent of
  how many are drawn.  Tolerances apply to the rounded values (one buys E24
  parts, each within its tolerance).

The results are chains in bulk units again (masses = L/L0, springs =
C0/C): rounding and tolerances break the mirror symmetry, so their theory
comes from the exact modes of each chain.  Losses and pulse sources are
circuit elements, not chain changes: see :func:`lcchain.netlist.netlist_text`.
"""

from __future__ import annotations

import math

import numpy as np

from .chain import Chain
from .errors import ParameterError

__all__ = ["E_SERIES", "preferred_value", "with_walls", "realise", "tolerance_samples"]

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


def preferred_value(value: float, series: str) -> float:
    """Nearest value of the E-series (nearest in ratio, i.e. on a log scale).

    Parameters
    ----------
    value : float
        A positive component value (H or F).
    series : {"E12", "E24", "E96"}
    """
    if series not in E_SERIES:
        raise ParameterError("series", series, " | ".join(E_SERIES))
    if not (math.isfinite(value) and value > 0):
        raise ParameterError("value", value, "a finite component value > 0")
    decade = math.floor(math.log10(value))
    best = None
    for exponent in (decade - 1, decade, decade + 1):
        scale = 10.0**exponent
        for mantissa in E_SERIES[series]:
            # round() removes the representation noise of mantissa * 10**exponent
            candidate = float(f"{mantissa * scale:.12g}")
            distance = abs(math.log(candidate / value))
            if best is None or distance < best[0]:
                best = (distance, candidate)
    return best[1]


def with_walls(chain: Chain, K0: float) -> Chain:
    """The chain with a wall spring K0 (bulk units, > 0) at both ends."""
    if isinstance(K0, bool) or not isinstance(K0, (int, float)) or not (math.isfinite(K0) and K0 > 0):
        raise ParameterError("K0", K0, "a finite wall spring > 0 (bulk units)")
    springs = np.array(chain.springs)
    springs[0] = springs[-1] = K0
    return Chain(chain.masses, springs, name=chain.name)


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
        Round every L and C to this series first.
    tol_L, tol_C : float
        Relative tolerances, 0 <= tol < 1.
    rng : numpy.random.Generator, optional
        Required when a tolerance is non-zero.
    name : str, optional
        Name of the realised chain (default: the nominal's).
    """
    for field_name, tol in (("tol_L", tol_L), ("tol_C", tol_C)):
        if not 0 <= tol < 1:
            raise ParameterError(field_name, tol, "0 <= tolerance < 1")
    inductance = np.asarray(chain.masses) * L0
    springs = np.asarray(chain.springs)
    wired = springs == 0  # free ends are wires: nothing to round or tolerance
    capacitance = np.where(wired, np.inf, C0 / np.where(wired, 1.0, springs))
    if series is not None:
        inductance = np.array([preferred_value(v, series) for v in inductance])
        capacitance = np.array([np.inf if w else preferred_value(v, series) for v, w in zip(capacitance, wired)])
    if tol_L or tol_C:
        if rng is None:
            raise ParameterError("rng", None, "a numpy Generator when a tolerance is non-zero")
        inductance = inductance * (1 + tol_L * rng.uniform(-1.0, 1.0, inductance.size))
        capacitance = capacitance * (1 + tol_C * rng.uniform(-1.0, 1.0, capacitance.size))
    masses = inductance / L0
    new_springs = np.where(wired, 0.0, C0 / np.where(wired, 1.0, capacitance))
    return Chain(masses, new_springs, name=name or chain.name)


def tolerance_samples(chain: Chain, L0: float, C0: float, *, samples: int, seed: int, tol_L: float,
                      tol_C: float, series: str | None = None) -> list[Chain]:
    """``samples`` realised chains; sample k draws from ``SeedSequence(seed).spawn(samples)[k]``."""
    children = np.random.SeedSequence(seed).spawn(samples)
    return [realise(chain, L0, C0, series=series, tol_L=tol_L, tol_C=tol_C, rng=np.random.default_rng(child),
                    name=f"{chain.name} sample {k + 1}")
            for k, child in enumerate(children)]
