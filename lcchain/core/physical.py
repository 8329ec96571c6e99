"""The bulk units in SI: what a time, a frequency and an impedance of the ladder are for given L0 and C0.

lcchain computes in the chain's bulk units (mass m = L0, spring K = 1/C0): times in units of sqrt(L0 C0),
angular frequencies in units of 1/sqrt(L0 C0).  These turn them into seconds and hertz; every output that gives
a bulk number can give these beside it (never instead: tests and scripts read the bulk ones).
"""

from __future__ import annotations

import math
import re

__all__ = ["quantity_units", "physical_scales", "seconds", "hertz", "si_text", "units_sentence", "variable_name",
           "vector_units", "PHASOR_SCALE", "band_top"]


def seconds(t: float, L0: float, C0: float) -> float:
    """A time in units of sqrt(L0 C0) in seconds (L0 in H, C0 in F)."""
    return float(t) * math.sqrt(L0 * C0)


def hertz(omega: float, L0: float, C0: float) -> float:
    """An angular frequency in units of 1/sqrt(L0 C0) as a frequency in hertz: omega / (2 pi sqrt(L0 C0))."""
    return float(omega) / (2.0 * math.pi * math.sqrt(L0 * C0))


def band_top(coupling: float = 0.0) -> float:
    """The top of a uniform chain's pass band, in bulk units: omega = 2 / sqrt(1 - 2k) with neighbouring coils
    coupled by k (-1/2 < k < 1/2; 2 without coupling): omega^2 = 2 (1 - cos q) / (1 + 2k cos q) is largest at
    q = pi for every such k."""
    return 2.0 / math.sqrt(1.0 - 2.0 * coupling)


def physical_scales(L0: float, C0: float, coupling: float = 0.0) -> dict[str, float]:
    """The bulk units in SI, as JSON reports give them.

    Returns
    -------
    dict
        ``L0_H``, ``C0_F``; ``time_unit_s`` = sqrt(L0 C0); ``frequency_unit_Hz``, what an angular frequency of 1
        is in hertz, 1 / (2 pi sqrt(L0 C0)); ``impedance_ohm`` = sqrt(L0 / C0), the ladder's characteristic
        impedance; ``band_top_Hz``, the top of a uniform chain's pass band (omega = 2 in bulk units, the bulk
        LC ladder's cut-off 1 / (pi sqrt(L0 C0)); with its coils coupled by ``coupling``, :func:`band_top`).
    """
    return {"L0_H": float(L0), "C0_F": float(C0), "time_unit_s": seconds(1.0, L0, C0),
            "frequency_unit_Hz": hertz(1.0, L0, C0), "impedance_ohm": math.sqrt(L0 / C0),
            "band_top_Hz": hertz(band_top(coupling), L0, C0)}


def si_text(value: float, unit: str, digits: int = 6) -> str:
    """``1.7757e-05, "H"`` -> ``17.757 uH``: the value with an SI prefix (a number without unit as it is)."""
    if unit == "1" or value == 0:
        return f"{value:.{digits}g}"
    for prefix, scale in (("G", 1e9), ("M", 1e6), ("k", 1e3), ("", 1.0), ("m", 1e-3), ("u", 1e-6), ("n", 1e-9),
                          ("p", 1e-12), ("f", 1e-15)):
        if abs(value) >= scale * (1 - 1e-12):
            return f"{value / scale:.{digits}g} {prefix}{unit}"
    return f"{value:.{digits}g} {unit}"


def units_sentence(L0: float, C0: float, coupling: float = 0.0) -> str:
    """What the bulk units are for L0 and C0, in one line (the terminal's and the report's); the band top that of
    a uniform chain with the coils' ``coupling``."""
    scales = physical_scales(L0, C0, coupling)
    return (f"L0 = {si_text(L0, 'H')}, C0 = {si_text(C0, 'F')}: time unit sqrt(L0 C0) = "
            f"{si_text(scales['time_unit_s'], 's')}, angular frequency 1 (1/sqrt(L0 C0) rad/s) is "
            f"{si_text(scales['frequency_unit_Hz'], 'Hz')}, "
            f"band top {si_text(scales['band_top_Hz'], 'Hz')}, impedance sqrt(L0/C0) = "
            f"{si_text(scales['impedance_ohm'], 'ohm')}")


def variable_name(vector: str) -> str:
    """A saved vector's name as a variable (netCDF, xarray): ``i(l1)`` -> ``i_l1``, ``v(n3)`` -> ``v_n3`` (letters,
    digits, ``_``)."""
    return re.sub(r"[^A-Za-z0-9_]+", "_", vector).strip("_") or "_"


#: What an AC run's phasors are relative to (a netCDF variable's long_name says it): ngspice's ``.ac`` drives each
#: source at its own AC magnitude, 1 V in the circuits lcchain writes, a foreign netlist's as written.
PHASOR_SCALE = "for the AC magnitudes of the circuit's sources (1 V in lcchain's own circuits)"


def vector_units(vector: str) -> str:
    """A saved vector's unit: ``i(...)`` amperes, ``v(...)`` volts, anything else dimensionless."""
    kind = vector.lower()[:2]
    return {"i(": "A", "v(": "V"}.get(kind, "1")


#: The root's variables with a unit of their own (a scene's keys, a sweep's options, the realised parts).
_UNITS = {"wall_s": "s", "total_s": "s", "L": "H", "C": "F", "time": "s", "frequency": "Hz", "L0": "H", "C0": "F",
          "I0": "A", "units.L0": "H", "units.C0": "F", "excitation.I0": "A"}
#: The chain's own numbers by name, and every other key of a scene (dotted): in the ladder's units (bulk,
#: sqrt(L0 C0), I_1(0)) or counts, dimensionless.
_DIMENSIONLESS = {"index", "N", "dt", "accuracy", "transits", "points", "sample", "coil", "capacitor", "Q", "walls",
                  "coupling", "run", "runs", "member", "max_abs_error", "predicted_error", "t_sim", "t_theory",
                  "peak_sim", "peak_theory", "energy_sim", "mode", "n"}


def quantity_units(name: str) -> str | None:
    """The unit of a study's variable or axis named ``name``: SI where it has one, "1" for the ladder's own
    dimensionless numbers, None where lcchain does not know it: a netlist's swept name, an element (R1) or a
    .param (rload, whatever it measures), which the store does not tell apart (a unit read from the name's first
    letter would call a .param rload ohms)."""
    if name in _UNITS:
        return _UNITS[name]
    if name in _DIMENSIONLESS or name.startswith(("effects_", "max_", "spacing_", "modes_")) or "." in name:
        return "1"
    return None
