"""Results as xarray Datasets: ``to_xarray()`` of a run's record, a simulation's report, a scene's result.

Every Dataset follows what xarray users expect and what the CF conventions ask of the files they write: one
variable per quantity with a ``units`` attribute (seconds, hertz, amperes, volts, henries, farads, or ``"1"``
for lcchain's dimensionless units of sqrt(L0 C0) and I_1(0)); an AC run's complex phasors as separate real and
imaginary variables, so ``to_netcdf`` writes them as they are; the scalar summary (what ``to_dict`` gives) as
attributes.  xarray is optional (``pip install 'lcchain[data]'``) and imported only here, on first use.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from typing import TYPE_CHECKING, TypeAlias

import numpy as np

from ..core.analyses import analysis_kind
from ..core.extras import dataset_attrs, optional_module
from ..core.physical import PHASOR_SCALE, variable_name, vector_units

# The records give their parts (this module sits below the modules that define them: they import it on first use).
if TYPE_CHECKING:
    import xarray as xr

    from ..compare.metrics import Comparison
    from ..compare.waveforms import Signals, Waveforms
    from ..spice.result import RunResult

__all__ = ["record_dataset", "simulation_dataset", "samples_dataset", "make_dataset", "Variable"]

#: A Dataset's variable or coordinate as xarray takes it: (its dimensions, its values, its attributes).
Variable: TypeAlias = tuple[str | tuple[str, ...], np.ndarray, Mapping[str, str]] | tuple[str, np.ndarray]

_DIMENSIONLESS_TIME = {"units": "1", "long_name": "time, units of sqrt(L0 C0)"}


def make_dataset(purpose: str, variables: Mapping[str, Variable], coords: Mapping[str, Variable],
             attrs: Mapping[str, object]) -> xr.Dataset:
    """An xarray Dataset (xarray is optional: an :class:`~lcchain.core.errors.ExtraMissingError` without it)."""
    xarray = optional_module("xarray", "data", purpose)
    dataset: xr.Dataset = xarray.Dataset(variables, coords=coords, attrs=attrs)
    return dataset


def _loops(signals: Signals, time: str) -> dict[str, Variable]:
    """The compared loops beside theory, dimensionless, on ``(loop, time)``."""
    what = "I / I_1(0)" if signals.excitation != "displacement" else "Q / Q_1(0)"
    return {"loop_signal": (("loop", time), np.asarray(signals.sim),
                            {"units": "1", "long_name": f"compared loops in the simulation, {what}"}),
            "loop_theory": (("loop", time), np.asarray(signals.theory),
                            {"units": "1", "long_name": f"compared loops in exact theory, {what}"})}


def record_dataset(run: RunResult | None, signals: Signals | None, summary: Mapping[str, object]) -> xr.Dataset:
    """:meth:`RunRecord.to_xarray`: the saved vectors of the ``run`` on ``time`` (s) or ``frequency`` (Hz), the
    compared loops beside theory (``signals``) where the run had a theory, and the record's ``summary`` as
    attributes."""
    variables: dict[str, Variable] = {}
    coords: dict[str, Variable] = {}
    if run is not None and not analysis_kind(run.analysis).swept:
        time = np.asarray(run.data.axis)
        coords["time"] = ("time", time, {"units": "s", "standard_name": "time",
                                         "long_name": "time from the run's start"})
        for name, values in run.vectors.items():
            variables[variable_name(name)] = ("time", np.asarray(values),
                                              {"units": vector_units(name), "long_name": name})
        if signals is not None and signals.t.size == time.size:
            coords["t"] = ("time", np.asarray(signals.t), _DIMENSIONLESS_TIME)
            variables |= _loops(signals, "time")
    elif run is not None:
        coords["frequency"] = ("frequency", np.asarray(run.data.axis), {"units": "Hz", "long_name": "frequency"})
        for name, values in run.vectors.items():
            phasor = np.asarray(values)
            for part in ("real", "imag"):
                variables[f"{variable_name(name)}_{part}"] = (
                    "frequency", np.asarray(getattr(phasor, part), dtype=float),
                    {"units": vector_units(name), "long_name": f"{name}, {part} part of its phasor, {PHASOR_SCALE}"})
    attrs = dataset_attrs({key: value for key, value in summary.items() if key != "log_tail"})
    return make_dataset("RunRecord.to_xarray", variables, coords, attrs)


def simulation_dataset(w: Waveforms, c: Comparison, excitation: str, time_unit: float,
                       summary: Mapping[str, object]) -> xr.Dataset:
    """:meth:`SimulationReport.to_xarray`: the end loops simulated (``w``) and in theory (``c``) on ``time`` (s,
    with the dimensionless ``t`` beside it; ``time_unit`` seconds), and the report's ``summary`` as attributes."""
    what = "I / I_1(0)" if excitation != "displacement" else "Q / Q_1(0)"
    variables: dict[str, Variable] = {
        "first": ("time", np.asarray(w.first), {"units": "1", "long_name": f"loop 1 in the simulation, {what}"}),
        "last": ("time", np.asarray(w.last), {"units": "1", "long_name": f"loop N in the simulation, {what}"}),
        "theory_first": ("time", np.asarray(c.theory_first), {"units": "1",
                                                               "long_name": f"loop 1 in exact theory, {what}"}),
        "theory_last": ("time", np.asarray(c.theory_last), {"units": "1",
                                                             "long_name": f"loop N in exact theory, {what}"}),
    }
    coords: dict[str, Variable] = {
        "time": ("time", np.asarray(w.t) * time_unit,
                 {"units": "s", "standard_name": "time", "long_name": "time from the run's start"}),
        "t": ("time", np.asarray(w.t), _DIMENSIONLESS_TIME)}
    scalars = {key: value for key, value in summary.items()
               if key not in ("arrivals", "options", "timings", "extrapolation", "effects")}
    return make_dataset("SimulationReport.to_xarray", variables, coords,
                    dataset_attrs(scalars | {"time_unit_s": time_unit}))


def samples_dataset(title: str, records: Iterable[Mapping[str, object]],
                    parts: Sequence[Mapping[str, list[float | None]]]) -> xr.Dataset:
    """:meth:`SceneResult.to_xarray`: every sample's numbers on ``sample`` (NaN where one has none, a failed one
    with its ``status`` and ``error``), its first arrival's peaks, and its realised parts, ``L`` (H) on ``coil``
    and ``C`` (F) on ``capacitor`` (NaN: a wire)."""
    rows: list[dict[str, object]] = [dict(record) for record in records]
    numbers: dict[str, list[float]] = {}
    counted: dict[str, int] = {}  # how many samples give each number as an int (points, modes seen)
    texts: dict[str, list[str]] = {}
    for i, row in enumerate(rows):
        arrivals = row.get("arrivals")
        if isinstance(arrivals, Sequence) and arrivals and isinstance(arrivals[0], Mapping):
            row |= {f"first_arrival_{key}": value for key, value in arrivals[0].items()}
        for key, value in row.items():
            if isinstance(value, bool) or key == "sample":
                continue
            if isinstance(value, int | float):
                numbers.setdefault(key, [np.nan] * len(rows))[i] = float(value)
                counted[key] = counted.get(key, 0) + isinstance(value, int)
            elif isinstance(value, str):
                texts.setdefault(key, [""] * len(rows))[i] = value
    # a count every sample gives stays an integer; one a sample lacks (a failed run's) is float, NaN there
    variables: dict[str, Variable] = {
        key: ("sample", np.array(values, dtype=int if counted.get(key) == len(rows) else float),
              {"units": "s" if key.endswith("_s") else "1"})
        for key, values in numbers.items()}
    variables |= {key: ("sample", np.array(values, dtype=str), {}) for key, values in texts.items()
                  if key not in numbers}
    coords: dict[str, Variable] = {
        "sample": ("sample", np.array([row.get("sample", i + 1) for i, row in enumerate(rows)], dtype=int))}
    if rows:  # None (a wire) becomes NaN
        L, C = (np.array([[np.nan if v is None else v for v in part[name]] for part in parts], dtype=float)
                for name in ("L", "C"))
        variables["L"] = (("sample", "coil"), L, {"units": "H", "long_name": "realised inductance L_i"})
        variables["C"] = (("sample", "capacitor"), C, {"units": "F", "long_name": "realised capacitance C_j between "
                                                                               "masses j and j + 1 (NaN: a wire)"})
        coords |= {"coil": ("coil", np.arange(1, L.shape[1] + 1)), "capacitor": ("capacitor", np.arange(C.shape[1]))}
    return make_dataset("SceneResult.to_xarray", variables, coords, {"title": title})
