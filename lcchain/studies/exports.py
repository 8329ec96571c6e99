"""A study's store in other shapes: a pandas table (:func:`to_dataframe`), an xarray Dataset on the study's axes
(:func:`to_xarray`), and what exporting it will hold before it is built (:func:`export_size`).  pandas and xarray
are optional (``pip install 'lcchain[data]'``); :class:`lcchain.studies.store.Store`'s methods of the same names
call these."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from types import ModuleType
from typing import TYPE_CHECKING, Protocol

from ..core.extras import optional_module
from ..core.json import LooseJSONObject
from ..core.physical import quantity_units, vector_units
from .stored import ARRAY_AXES, StoredRun, study_constants, study_dims, value_key

if TYPE_CHECKING:
    import numpy as np
    import pandas as pd
    import xarray as xr

__all__ = ["ExportSize", "Readable", "to_dataframe", "to_xarray", "export_size", "table_rows",
           "measurement_column"]


class Readable(Protocol):
    """What an export reads of a store (:class:`lcchain.studies.store.Store` is one)."""

    path: Path

    def runs(self) -> list[StoredRun]: ...

    def light_runs(self) -> list[StoredRun]: ...

    def waveforms(self, key: str) -> dict[str, np.ndarray] | None: ...

    def metrics_bytes(self) -> int: ...

    def array_sizes(self, key: str) -> tuple[int, dict[str, tuple[int, int]]] | None: ...

    def description(self) -> LooseJSONObject: ...


@dataclass(frozen=True)
class ExportSize:
    """What exporting a store holds at once: the numbers ``lcchain results`` is priced by
    (:func:`lcchain.core.budget.export_estimate`).

    Attributes
    ----------
    runs : int
        Runs exported (extrapolation members left out).
    cells : int
        Points of the dataset's grid: the product of its dimensions' sizes (:func:`study_dims`).
    metrics : int
        Bytes of the stored metrics (JSON text), every row's.
    stored : int
        Bytes of the saved arrays read back (finished runs; 0 without waveforms).
    longest : int
        Points of the longest saved array (0 without waveforms).
    per_point : int
        Bytes per point of the dataset's waveform variables: every saved vector's and its axis's, each at its
        type's size (0 without waveforms).
    """

    runs: int
    cells: int
    metrics: int
    stored: int = 0
    longest: int = 0
    per_point: int = 0


def _on_frequency(dataset: xr.Dataset, axes: list[np.ndarray], longest: int, mixed: bool) -> xr.Dataset:
    """AC runs' spectra on a ``frequency`` coordinate (Hz): the dimension itself when every run is an AC run that
    swept the same frequencies, else a coordinate beside the ``point`` dimension (NaN where a run swept fewer, or
    is a transient: ``mixed``)."""
    import numpy as np
    if not axes:
        return dataset
    same = all(axis.shape == axes[0].shape and np.array_equal(axis, axes[0]) for axis in axes)
    if same and not mixed and axes[0].size == longest:
        dataset = dataset.drop_vars("frequency").rename({"point": "frequency"})
        return dataset.assign_coords(frequency=axes[0])
    return dataset.set_coords("frequency")


def _number(value: float | None) -> float:
    """A metric as a float column's value: NaN where the run has none (a batch run, a pulse's energy)."""
    return math.nan if value is None else float(value)


def measurement_column(name: str, row: Mapping[str, object]) -> str:
    """A measurement's column in a run's row: its name, or ``meas_NAME`` when the row has a column of that name
    already (a parameter, ``status``, a metric)."""
    return f"meas_{name}" if name in row else name



_ROOT_NAMES = {"t_sim": "first arrival's time (simulation), units of sqrt(L0 C0)",
               "t_theory": "first arrival's time (theory), units of sqrt(L0 C0)",
               "dt": "maximum time step, units of sqrt(L0 C0)", "wall_s": "simulator's wall time",
               "peak_sim": "first arrival's peak I_N / I_1(0) (simulation)",
               "peak_theory": "first arrival's peak I_N / I_1(0) (theory)",
               "max_abs_error": "max |simulation - theory|, units of I_1(0)", "points": "number of points",
               "L": "a sample's realised inductance L_i of coil i", "coil": "coil i = 1..N",
               "C": "a sample's realised capacitance C_j between masses j and j + 1 (NaN: a wire)",
               "capacitor": "capacitor j = 0..N (0 and N: the walls)"}


def _described(dataset: xr.Dataset, runs: list[StoredRun]) -> xr.Dataset:
    """The study's Dataset with every variable's ``long_name``, and its ``units`` where lcchain knows them (a
    ``.meas`` result's unit is whatever the netlist measured: named as such, no unit)."""
    measured = {str(name) for run in runs for name in run.measurements}
    measured |= {f"meas_{name}" for name in measured}
    for name in list(dataset.variables):
        variable = dataset[name]
        if str(name) in measured:
            variable.attrs.setdefault("long_name", f"{name}: a .meas result, in the unit of what the netlist "
                                      "measured (lcchain does not know it)")
            continue
        units = quantity_units(str(name)) if variable.dtype.kind in "fiubc" else None
        variable.attrs.setdefault("long_name", _ROOT_NAMES.get(str(name), str(name) if units is not None or
                                                               variable.dtype.kind not in "fiubc" else
                                                               f"{name} (its unit is not known to lcchain)"))
        if units is not None:
            variable.attrs.setdefault("units", units)
    return dataset


def _optional(module: str) -> ModuleType:
    """An optional package (pandas, xarray), or a one-line error saying how to install it."""
    found: ModuleType = optional_module(module, "data", "a study's results as a table (pandas, xarray)")
    return found


def to_dataframe(store: Readable) -> pd.DataFrame:
    """The runs as a pandas DataFrame: one row per task (index: the task's number), the study's parameters
    as columns, then kind, status, key, digest, points, the simulator's wall time and the metrics (NaN or
    None where a run has none). A sample's realised part values are left out of the table (N + 1 columns
    each would bury the metrics): they are :func:`to_xarray`'s ``L`` and ``C``, and each
    :attr:`StoredRun.parts`. pandas is optional: ``pip install 'lcchain[data]'``."""
    pd = _optional("pandas")
    return pd.DataFrame(table_rows(store.runs(), chain=not netlist_study(store.description()))).set_index("index")

def to_xarray(store: Readable, waveforms: bool = False) -> xr.Dataset:
    """The runs as an xarray Dataset whose dimensions are the study's axes.

    Each axis (a parameter that varies across the study's results: ``N``, ``case``, ``dt``, ``sample``,
    ``netlist``...) is a dimension with its values as coordinate; every metric is a variable on them (NaN
    where a combination did not run or has no such metric). An extrapolation's members are left out: its
    combined result is the point's. A study whose runs do not form a grid (two runs at the same point)
    has the task number as its one dimension, ``index``.

    Tolerance or preferred-value samples also have their realised part values: ``L`` (henry) on the
    dimension ``coil`` (1..N) and ``C`` (farad) on ``capacitor`` (0..N: C_j joins masses j and j + 1, 0 and N
    the walls; NaN where a wall is a wire, or a run had no such part).

    Parameters
    ----------
    waveforms : bool
        Also each run's saved vectors and their time, on a ``point`` dimension (a run's own time values,
        padded with NaN to the longest run): the variable ``time`` and one per vector.

    Notes
    -----
    xarray is optional: ``pip install 'lcchain[data]'``.
    """
    _optional("xarray")
    results = [run for run in store.runs() if not run.member]
    dims, along = study_dims(results)
    constants = study_constants(results)
    frame = _optional("pandas").DataFrame(table_rows(results, chain=not netlist_study(store.description())))
    dataset = frame.drop(columns=list(constants)).set_index(dims).to_xarray().set_coords(along)
    dataset.attrs.update({"store": str(store.path), **{key: str(value) for key, value in constants.items()}})
    dataset = _with_parts(dataset, dims, results)
    if waveforms:
        dataset = _with_waveforms(store, dataset, dims, [run for run in results if run.status == "ok"])
    return _described(dataset, results)


def export_size(store: Readable, waveforms: bool = False) -> ExportSize:
    """What :func:`to_xarray` (and the other exports) will hold, read without building any of it: the runs, the
    grid of the study's dimensions, the metrics' text and, with ``waveforms``, each finished run's saved arrays
    (their headers only, a run at a time)."""
    results = [run for run in store.light_runs() if not run.member]
    dims, _ = study_dims(results)
    cells = len(results) if dims == ["index"] else math.prod(
        len({value_key(run.params.get(d)) for run in results}) for d in dims)
    metrics = store.metrics_bytes()
    if not waveforms:
        return ExportSize(len(results), cells, metrics)
    stored = longest = 0
    per_name: dict[str, int] = {}
    for run in results:
        if run.status != "ok":
            continue
        saved = store.array_sizes(run.key)
        if saved is None:
            continue
        blob, sizes = saved
        stored += blob
        for name, (points, itemsize) in sizes.items():
            longest = max(longest, points)
            per_name[name] = max(per_name.get(name, 0), itemsize)
    return ExportSize(len(results), cells, metrics, stored, longest, sum(per_name.values()))


def netlist_study(description: Mapping[str, object]) -> bool:
    """Whether a store's description (:meth:`lcchain.studies.store.Store.description`) is of netlists lcchain did not
    write (a batch, a sweep of a netlist): its runs have no chain, so no chain's metrics either."""
    return description.get("command") == "batch" or "netlist" in description


def table_rows(runs: list[StoredRun], *, chain: bool = True) -> list[LooseJSONObject]:
    """One row per run: its parameters, status (with the first line of why it failed, ``reason``) and metrics (a
    transient's, an AC run's, or both kinds' in a store that holds both; a chain's only with ``chain``: not for a
    study of netlists, whose runs have none).  The one table every export writes: ``--csv``, ``--parquet``,
    :func:`to_dataframe` and :func:`to_xarray`."""
    spectral = any(run.spectral for run in runs)
    transient = chain and (not spectral or any(run.metrics is not None and not run.spectral for run in runs))
    costs = any(run.metrics is not None and "effects" in run.metrics for run in runs)
    measured = list(dict.fromkeys(name for run in runs for name in run.measurements))
    rows: list[LooseJSONObject] = []
    for run in runs:
        metrics = run.metrics or {}
        arrivals = metrics.get("arrivals") or []
        first = arrivals[0] if arrivals else {}
        row: LooseJSONObject = {
               "index": run.index, **run.params, "kind": run.kind, "status": run.status,
               # text in every row ("" where none: a column of None alone would be read as numbers)
               "reason": run.reason.splitlines()[0] if run.reason and run.status != "ok" else "", "key": run.key,
               "digest": run.digest or None, "points": run.points, "wall_s": run.wall_s,
               # the engine's name and its version apart, as the store's column holds them together
               "engine": run.engine if run.status != "pending" else None,
               "engine_version": run.engine_version if run.status != "pending" else None}
        if transient:
            row.update({name: _number(metrics.get(name)) for name in ("max_abs_error", "predicted_error")})
            row.update({name: _number(first.get(name)) for name in ("t_sim", "t_theory", "peak_sim",
                                                                      "peak_theory", "energy_sim")})
        if costs:  # runs against their circuit's own theory: what the effects cost the ideal chain's pulse
            cost = metrics.get("effects") or {}
            row.update({f"effects_{name}": _number(cost.get(name))
                        for name in ("peak_ideal", "energy_ideal", "energy_loss", "delay")})
        if spectral:
            from ..compare.spectral import SPECTRAL_METRICS  # with an AC run only: a batch starts without it

            row.update({name: _number(metrics.get(name)) for name in SPECTRAL_METRICS})
            seen = metrics.get("modes_seen")
            if isinstance(seen, int):  # a count: 0, not 0.0, in a CSV
                row["modes_seen"] = seen
        values = run.measurements
        row.update({measurement_column(name, row): _number(values.get(name)) for name in measured})
        rows.append(row)
    return rows


def _with_parts(dataset: xr.Dataset, dims: list[str], runs: list[StoredRun]) -> xr.Dataset:
    """The dataset with the samples' part values, ``L`` on ``coil`` and ``C`` on ``capacitor``."""
    pd = _optional("pandas")
    rows: dict[str, list[LooseJSONObject]] = {"L": [], "C": []}
    for run in runs:
        parts = run.parts
        if parts is None:
            continue
        at = {dim: run.index if dim == "index" else run.params.get(dim) for dim in dims}
        rows["L"] += [{**at, "coil": i + 1, "L": _number(v)} for i, v in enumerate(parts.get("L") or [])]
        rows["C"] += [{**at, "capacitor": j, "C": _number(v)} for j, v in enumerate(parts.get("C") or [])]
    for name, dim in (("L", "coil"), ("C", "capacitor")):
        if rows[name]:
            values = pd.DataFrame(rows[name]).set_index([*dims, dim]).to_xarray()
            dataset = dataset.merge(values, join="left")
            dataset[name].attrs["units"] = "H" if name == "L" else "F"
    return dataset


def _with_waveforms(store: Readable, dataset: xr.Dataset, dims: list[str], runs: list[StoredRun]) -> xr.Dataset:
    import numpy as np
    arrays = {run.index: store.waveforms(run.key) or {} for run in runs}
    longest = max((a[axis].size for a in arrays.values() for axis in ARRAY_AXES if axis in a), default=0)
    names = list(dict.fromkeys(name for a in arrays.values() for name in a))
    shape = [dataset.sizes[d] for d in dims] + [longest]
    positions = {d: {value: i for i, value in enumerate(dataset.indexes[d])} for d in dims}
    for name in names:
        complex_values = any(np.iscomplexobj(a[name]) for a in arrays.values() if name in a)
        # a complex vector's padding is NaN in both parts (nan + 0j would read as a real part of NaN and an
        # imaginary part of 0)
        values = np.full(shape, complex(np.nan, np.nan) if complex_values else np.nan,
                         dtype=complex if complex_values else float)
        for run in runs:
            series = arrays[run.index].get(name)
            if series is not None:
                where = tuple(positions[d][run.index if d == "index" else run.params[d]] for d in dims)
                values[where][: series.size] = series
        units = {"time": "s", "frequency": "Hz"}.get(name) or vector_units(name)
        dataset[name] = ([*dims, "point"], values, {"units": units, "long_name": name})
    sweeps = [a["frequency"] for a in arrays.values() if "frequency" in a]
    mixed = any("time" in a for a in arrays.values())  # a batch of .tran and .ac netlists: one point axis
    return _on_frequency(dataset, sweeps, longest, mixed)
