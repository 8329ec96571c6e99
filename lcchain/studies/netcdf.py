"""A store as CF-1.10 netCDF: the study's table on its axes, and each kind of waveform in a group of its own.

``lcchain results STORE --netcdf FILE [--waveforms]`` writes what :func:`cf_datasets` returns:

* the root: the study's runs on its axes (:meth:`lcchain.studies.store.Store.to_xarray`), each numeric variable
  and coordinate with ``units`` (``"s"`` for wall times, ``"1"`` for the dimensionless metrics: times in units of
  sqrt(L0 C0), currents over I_1(0)) except a foreign netlist's ``.meas`` results, whose unit lcchain does not
  know (their ``long_name`` says so), the engine's name and version as two variables, and the CF global
  attributes (``Conventions``, ``title``, ``history``, ``source``, ``institution``-free);
* with waveforms, one group per kind of run: ``transient`` (time in s, currents in A, voltages in V), ``ac``
  (frequency in Hz, each phasor as ``NAME_real`` and ``NAME_imag``, for the AC magnitudes of the circuit's sources:
  1 V in lcchain's own circuits, a foreign netlist's own) and ``extrapolated``
  (an extrapolation's combined signals, dimensionless).  No transient is ever complex, no AC vector is ever
  mixed with a time axis.

A group holds its runs end to end, as CF's *contiguous ragged array* (CF 1.10, section 9.3.3): a ``run``
dimension with the run's task number and study parameters, ``row_size(run)`` (``sample_dimension = "obs"``),
and each variable on ``obs``.  Run ``r``'s points are ``obs[start[r]:start[r] + row_size[r]]`` with ``start`` the
cumulative sum of ``row_size`` before it.  Nothing is padded: a file holds each run's points once (padding every
run to the longest, on every cell of the study's grid, is what made 15 small runs 40 MB); a vector a run did not
save is NaN over that run's points, in both its parts.  The writer compresses (zlib) where the netCDF engine can.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from datetime import UTC, datetime
from typing import TYPE_CHECKING

import numpy as np

from ..core import __version__
from ..core.physical import PHASOR_SCALE, quantity_units, variable_name, vector_units
from ..runs.datasets import Variable
from .store import Store
from .stored import StoredRun

if TYPE_CHECKING:
    import xarray as xr

__all__ = ["cf_datasets", "CONVENTIONS"]

#: The CF version the files follow.
CONVENTIONS = "CF-1.10"

@dataclass(frozen=True)
class _Group:
    """One group of a file's runs, by what their arrays are: a transient's, an AC run's or an extrapolation's."""

    axis: str
    axis_units: str
    axis_name: str
    parts: tuple[str, ...]  # a complex vector's parts, each its own variable; ("",): a real vector
    scaled: bool  # in units of the chain (I / I0 against t / sqrt(L0 C0)): every variable's unit is "1"


_GROUPS = {"ac": _Group("frequency", "Hz", "frequency", ("real", "imag"), scaled=False),
           "transient": _Group("time", "s", "time from the run's start", ("",), scaled=False),
           "extrapolated": _Group("time", "1", "time, units of sqrt(L0 C0)", ("",), scaled=True)}


def _kind(run: StoredRun, arrays: dict[str, np.ndarray]) -> str:
    if run.kind == "combined":
        return "extrapolated"
    return "ac" if "frequency" in arrays else "transient"


def _group(kind: str, runs: list[tuple[StoredRun, dict[str, np.ndarray]]], axes: list[str]) -> xr.Dataset:
    import xarray

    group = _GROUPS[kind]
    axis = group.axis
    sizes = np.array([arrays[axis].size for _, arrays in runs], dtype=np.int64)
    vectors = list(dict.fromkeys(name for _, arrays in runs for name in arrays if name != axis))
    data: dict[str, Variable] = {}
    coordinate = np.concatenate([arrays[axis] for _, arrays in runs])
    data[axis] = ("obs", coordinate, {"units": group.axis_units, "long_name": group.axis_name})
    for vector in vectors:
        for part in group.parts:
            values = np.concatenate([np.asarray(getattr(arrays[vector], part) if part else arrays[vector], float)
                                     if vector in arrays else np.full(arrays[axis].size, np.nan)
                                     for _, arrays in runs])
            name = variable_name(vector) + (f"_{part}" if part else "")
            what = f"{vector}{f', {part} part of its phasor, {PHASOR_SCALE}' if part else ''}"
            units = "1" if group.scaled else vector_units(vector)
            data[name] = ("obs", values, {"units": units, "long_name": what})
    data["row_size"] = ("run", sizes, {"long_name": "number of points of each run", "sample_dimension": "obs",
                                       "units": "1"})
    data["index"] = ("run", np.array([run.index for run, _ in runs], dtype=np.int64),
                     {"long_name": "the run's task number in the store", "units": "1"})
    data["key"] = ("run", np.array([run.key for run, _ in runs], dtype=str), {"long_name": "the run's key"})
    for name in axes:  # the study's parameters of each run, where it has them
        given = [run.params.get(name) for run, _ in runs]
        if all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in given):
            unit = quantity_units(name)
            data[f"param_{name}"] = ("run", np.array(given, dtype=float), {"long_name": f"study axis {name}"} | (
                {"units": unit} if unit is not None else {}))
        else:
            data[f"param_{name}"] = ("run", np.array([str(v) for v in given], dtype=str),
                                     {"long_name": f"study axis {name}"})
    dataset = xarray.Dataset({k: xarray.Variable(*v) for k, v in data.items() if k != axis})
    dataset = dataset.assign_coords({axis: xarray.Variable(*data[axis])})
    dataset.attrs.update({"Conventions": CONVENTIONS, "title": f"lcchain {kind} waveforms, one run after another "
                          "(contiguous ragged array: row_size points each)"})
    if axis == "time":  # a discrete sampling geometry (CF 9): a time series a run, each named by its key
        dataset.attrs["featureType"] = "timeSeries"
        dataset["key"].attrs["cf_role"] = "timeseries_id"
    return dataset


def _cf_names(dataset: xr.Dataset) -> xr.Dataset:
    """The dataset as CF names things (2.3: letters, digits and underscores; ``units.L0`` -> ``units_L0``, the
    name as lcchain gives it kept as ``long_name`` where there is none), and its coordinates without a fill value
    (5: a coordinate has no missing values)."""
    renamed = {name: re.sub(r"[^A-Za-z0-9_]+", "_", str(name)).strip("_") or "_" for name in dataset.variables}
    renamed = {old: new for old, new in renamed.items() if new != old and new not in dataset.variables}
    for old in renamed:
        dataset[old].attrs.setdefault("long_name", str(old))
    dataset = dataset.rename(renamed) if renamed else dataset
    for name in dataset.coords:
        dataset[name].encoding["_FillValue"] = None
    return dataset


def cf_datasets(store: Store, waveforms: bool = False) -> dict[str, xr.Dataset]:
    """The netCDF file's parts: ``{"": the study's table, "transient": ..., "ac": ..., "extrapolated": ...}``
    (a waveform group only where the store holds such runs, and only with ``waveforms``); module docstring."""
    root = store.to_xarray()  # its variables carry their units and names already
    now = datetime.now(UTC).strftime("%Y-%m-%dT%H:%M:%SZ")
    root.attrs.update({"Conventions": CONVENTIONS, "title": f"lcchain study {store.path.name}",
                       "history": f"{now} lcchain {__version__} results {store.path.name} --netcdf",
                       "source": f"lcchain {__version__}; simulator runs from the store {store.path.name}",
                       "comment": "the engines' versions are the variables engine and engine_version"})
    parts: dict[str, xr.Dataset] = {"": _cf_names(root)}
    if not waveforms:
        return parts
    results = [run for run in store.runs() if not run.member and run.status == "ok"]
    axes = [str(d) for d in root.dims if d != "index"]
    grouped: dict[str, list[tuple[StoredRun, dict[str, np.ndarray]]]] = {}
    for run in results:
        arrays = store.waveforms(run.key)
        if arrays:
            grouped.setdefault(_kind(run, arrays), []).append((run, arrays))
    for kind in ("transient", "ac", "extrapolated"):
        if kind in grouped:
            group = _group(kind, grouped[kind], axes)
            group.attrs["history"] = root.attrs["history"]
            parts[kind] = _cf_names(group)
    return parts
