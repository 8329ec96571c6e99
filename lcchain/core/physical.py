"""The bulk units in SI: what a time, a frequency and an impedance of the ladder are for given L0 and C0.

lcchain computes in the chain's bulk units (mass m = L0, spring K = 1/C0): times in units of sqrt(L0 C0),
angular frequencies in units of 1/sqrt(L0 C0).  These turn them into seconds and hertz; every output that gives
a bulk number can give these beside it (never instead: tests and scripts read the bulk ones).
"""

from __future__ import annotations

import math

__all__ = ["physical_scales", "seconds", "hertz"]


def seconds(t: float, L0: float, C0: float) -> float:
    """A time in units of sqrt(L0 C0) in seconds (L0 in H, C0 in F)."""
    return float(t) * math.sqrt(L0 * C0)


def hertz(omega: float, L0: float, C0: float) -> float:
    """An angular frequency in units of 1/sqrt(L0 C0) as a frequency in hertz: omega / (2 pi sqrt(L0 C0))."""
    return float(omega) / (2.0 * math.pi * math.sqrt(L0 * C0))


def physical_scales(L0: float, C0: float) -> dict[str, float]:
    """The bulk units in SI, as JSON reports give them.

    Returns
    -------
    dict
        ``L0_H``, ``C0_F``; ``time_unit_s`` = sqrt(L0 C0); ``frequency_unit_Hz``, what an angular frequency of 1
        is in hertz, 1 / (2 pi sqrt(L0 C0)); ``impedance_ohm`` = sqrt(L0 / C0), the ladder's characteristic
        impedance; ``band_top_Hz``, the top of a uniform chain's pass band (omega = 2 in bulk units, the bulk
        LC ladder's cut-off 1 / (pi sqrt(L0 C0))).
    """
    return {"L0_H": float(L0), "C0_F": float(C0), "time_unit_s": seconds(1.0, L0, C0),
            "frequency_unit_Hz": hertz(1.0, L0, C0), "impedance_ohm": math.sqrt(L0 / C0),
            "band_top_Hz": hertz(2.0, L0, C0)}
