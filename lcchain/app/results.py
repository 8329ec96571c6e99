"""``lcchain results`` as a function: a store's runs read back, priced first, its exports written (netCDF,
Parquet, a figure), and what the command shows made from them (a summary per combination of the axes, JSON, CSV
rows, a table's columns)."""

from __future__ import annotations

import functools
import json
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Literal, TypeAlias

from ..core.budget import Budget
from ..core.errors import ExtraMissingError, ParameterError
from ..core.json import LooseJSONObject
from ..core.types import STUDY_METRICS
from ..report.files import FIGURE_FORMATS
from .inputs import Outputs

if TYPE_CHECKING:
    import xarray as xr

    from ..studies.store import Store
    from ..studies.stored import StoredRun

__all__ = ["ResultsRequest", "Results", "results"]


@dataclass(frozen=True)
class ResultsRequest:
    """A store and how to show it: ``summary`` (the ``metric``'s distribution per combination of the axes),
    ``json``, ``csv``, or a table; the files to write: ``plot``, ``netcdf`` (with ``waveforms``), ``parquet``."""

    store: str
    json: bool = False
    csv: bool = False
    summary: bool = False
    plot: str | None = None
    metric: str | None = None  # None: the first arrival's peak (with --summary or --plot; refused without them)
    netcdf: str | None = None
    parquet: str | None = None
    waveforms: bool = False
    budget: Budget = field(default_factory=Budget)


@dataclass(frozen=True)
class Results:
    """The store's runs (:class:`lcchain.studies.stored.StoredRun`) and their JSON, and what the request shows:
    ``groups`` and ``constants`` (a summary), ``runs_json`` (``--json``: arrival times also in seconds),
    ``rows`` (``--csv``), ``axes`` and each finished run's ``vectors`` (the table); ``written`` the files
    written, ``failed`` the options whose file could not be, and ``notes`` the lines that say why; ``measured``:
    the summary's metric is a ``.meas`` of the netlists."""

    stored: list[StoredRun]
    runs: list[LooseJSONObject]
    groups: list[LooseJSONObject] = field(default_factory=list)
    constants: LooseJSONObject = field(default_factory=dict)
    runs_json: list[LooseJSONObject] = field(default_factory=list)
    rows: list[LooseJSONObject] = field(default_factory=list)
    axes: list[str] = field(default_factory=list)
    vectors: dict[str, list[str] | None] = field(default_factory=dict)
    written: list[str] = field(default_factory=list)
    failed: list[str] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    measured: bool = False  # the summary's metric is one of the netlists' .meas (a .meas peak of a batch, say)


def results(request: ResultsRequest) -> Results:
    from ..spice.measure import valid_measure_name
    from ..studies.store import Store
    from ..studies.summary import check_metric, is_measurement, peak_groups, study_axes, study_constants

    outputs = Outputs(inputs={"STORE": request.store})
    outputs.check("--plot", request.plot, FIGURE_FORMATS)
    outputs.check("--netcdf", request.netcdf, ("nc",))
    outputs.check("--parquet", request.parquet, ("parquet",))
    if request.waveforms and not request.netcdf:
        raise ParameterError("--waveforms", True, "only with --netcdf FILE (the waveforms go into that file)")
    if request.metric is not None and not (request.summary or request.plot):  # as --waveforms without --netcdf
        raise ParameterError("--metric", request.metric, "only with --summary or --plot (what they show)")
    metric = request.metric if request.metric is not None else "peak"
    if metric not in STUDY_METRICS and not valid_measure_name(metric):  # no store needed to see it
        raise ParameterError("--metric", metric, f"one of {' | '.join(STUDY_METRICS)}, or the name of a "
                             ".meas of the store's netlists")
    if request.parquet:
        _require("pyarrow", "--parquet")
    with Store(request.store, "read", option="STORE") as store:  # read-only: nothing is created or changed
        _price_results(store, request)
        stored = store.runs()
        if request.summary or request.plot:
            # before any file is written; the default peak is named as the default (the user typed no --metric)
            check_metric(metric, stored, "--metric" if request.metric is not None else "--metric (default)")
        if request.plot and metric not in STUDY_METRICS:
            raise ParameterError("--metric", metric, f"one of {', '.join(STUDY_METRICS)} with --plot (a "
                                 "measurement's distribution is printed by --summary --metric NAME)")
        beside: list[str] = []  # scipy's netCDF3 has no groups: the waveforms' own files
        if request.netcdf:
            from ..studies.netcdf import cf_datasets

            parts = cf_datasets(store, waveforms=request.waveforms)
            outputs.write("--netcdf", lambda path: beside.extend(str(p) for p in _write_netcdf(parts, path)[1:]))
        if request.parquet:
            frame = store.to_dataframe()
            outputs.write("--parquet", lambda path: _write_atomic(path, frame.to_parquet))
        if request.plot:
            from ..report.files import save_figure
            from ..report.studies import study_figure

            figure = study_figure(store, metric)
            outputs.write("--plot", lambda path: save_figure(figure, path, dpi=150))
        runs = [run.to_dict() for run in stored]
        written = [path for option, path in (("--plot", request.plot), ("--netcdf", request.netcdf),
                                             ("--parquet", request.parquet)) if path and option not in outputs.failed]
        found = Results(stored, runs, written=written + beside, failed=list(outputs.failed),
                        notes=list(outputs.notes))
        if request.summary:
            return Results(stored, runs, groups=[group.to_dict() for group in peak_groups(stored, metric)],
                           constants=study_constants(stored), written=found.written, failed=found.failed,
                           notes=found.notes, measured=is_measurement(metric, stored))
        if request.json:
            return Results(stored, runs, runs_json=_with_seconds(runs, store), written=found.written,
                           failed=found.failed, notes=found.notes)
        if request.csv:  # the table the data frame, Parquet and netCDF hold, missing values blank
            from ..studies.exports import netlist_study, table_rows

            rows = [{name: None if isinstance(value, float) and math.isnan(value) else value
                     for name, value in row.items()}
                    for row in table_rows(stored, chain=not netlist_study(store.description()))]
            return Results(stored, runs, rows=rows, written=found.written, failed=found.failed, notes=found.notes)
        if request.plot or request.netcdf or request.parquet:
            return found
        spectral = any(run.spectral for run in stored)
        theory = not spectral and any(run.judged for run in stored)
        vectors = {} if spectral or theory else {run.key: store.vector_names(run.key) for run in stored
                                                 if run.status == "ok"}
        return Results(stored, runs, axes=study_axes(stored), vectors=vectors, written=found.written,
                       failed=found.failed, notes=found.notes)


def _price_results(store: Store, request: ResultsRequest) -> None:
    """Refuse, before the runs are read, a ``results`` whose reading and exports exceed --max-memory or
    --max-time (:func:`lcchain.core.budget.export_estimate`): the waveforms of a 259-corner store ran to 2.5 GiB
    and a MemoryError."""
    from ..core.budget import export_estimate

    waveforms = bool(request.netcdf and request.waveforms)
    size = store.export_size(waveforms=waveforms)
    files = bool(request.netcdf or request.parquet or request.plot)
    estimate = export_estimate(runs=size.runs, cells=size.cells if files else 0, metrics=size.metrics,
                               stored=size.stored, dense=float(size.cells) * size.longest * size.per_point,
                               files=files, text=bool(request.json or request.csv))
    option, value = ("--netcdf", request.netcdf) if request.netcdf else ("STORE", request.store)
    estimate.check(request.budget, option, value,
                   "--netcdf without --waveforms, or a larger --max-memory" if waveforms else "")


def _require(module: str, option: str) -> None:
    import importlib.util

    if importlib.util.find_spec(module) is None:
        raise ExtraMissingError(module, "data", option, more=(module,))


def _write_atomic(path: Path, writer: Callable[[Path], object]) -> None:
    """Write through a hidden temporary name in the same folder, renamed over ``path`` only when complete."""
    from ..report.files import atomic_path

    with atomic_path(path) as partial:
        writer(partial)


def _with_seconds(runs: list[LooseJSONObject], store: Store) -> list[LooseJSONObject]:
    """``results --json``: each arrival's times also in seconds (``t_sim_s``, ``t_theory_s``) where the study
    states one L0 and one C0 (a sweep's description); a batch of netlists or a study of scenes states none."""
    from ..core.physical import seconds

    try:
        described = json.loads(store.meta().get("description") or "{}")
    except ValueError:
        return runs
    given = [described.get(key) if isinstance(described, dict) else None for key in ("L0", "C0")]
    if not all(isinstance(v, (int, float)) and not isinstance(v, bool) and v > 0 for v in given):
        return runs
    L0, C0 = float(given[0]), float(given[1])  # type: ignore[arg-type]  # numbers: checked above
    for run in runs:
        for arrival in run.get("arrivals") or ():
            for key in ("t_sim", "t_theory"):
                if isinstance(arrival.get(key), (int, float)):
                    arrival[f"{key}_s"] = seconds(arrival[key], L0, C0)
    return runs


#: The engines xarray writes netCDF with, by the names its ``to_netcdf`` takes.
NetcdfEngine: TypeAlias = Literal["netcdf4", "h5netcdf", "scipy"]


def _to_netcdf(part: xr.Dataset, engine: NetcdfEngine, path: Path) -> None:
    part.to_netcdf(path, engine=engine)


def _write_netcdf(parts: dict[str, xr.Dataset], path: Path) -> list[Path]:
    """CF netCDF (:func:`lcchain.studies.netcdf.cf_datasets`) through whichever engine is there: netCDF4 or
    h5netcdf write one file, the waveforms in groups, compressed; scipy's netCDF3 has no groups, so each waveform
    group goes to a file of its own beside FILE (``FILE.stem.transient.nc``). Returns the files written."""
    import importlib.util

    # the engine's name as to_netcdf takes it ("netcdf4": the netCDF4 module), and the modules it needs
    needs: dict[NetcdfEngine, tuple[str, ...]] = {"netcdf4": ("netCDF4",), "h5netcdf": ("h5netcdf", "h5py")}
    engine: NetcdfEngine = next((e for e, modules in needs.items()
                                 if all(importlib.util.find_spec(m) for m in modules)), "scipy")
    groups = {name: part for name, part in parts.items() if name}
    root = parts[""]
    if engine == "scipy":
        written = [path]
        root = root.rename({name: _netcdf3_name(str(name)) for name in root.variables
                            if _netcdf3_name(str(name)) != name})
        _write_atomic(path, lambda partial: root.to_netcdf(partial, engine=engine))
        for name, part in groups.items():
            target = path.with_name(f"{path.stem}.{name}.nc")
            _write_atomic(target, functools.partial(_to_netcdf, part, engine))
            written.append(target)
        return written

    def write(partial: Path) -> None:
        root.to_netcdf(partial, engine=engine, mode="w")
        for name, part in groups.items():
            encoding = {str(v): {"zlib": True, "complevel": 4} | (
                            {"_FillValue": None} if v in part.coords else {}) for v in part.variables
                        if part[v].dtype.kind in "fiu"}
            part.to_netcdf(partial, engine=engine, mode="a", group=name, encoding=encoding)

    _write_atomic(path, write)
    return [path]


def _netcdf3_name(name: str) -> str:
    """``i(l1)`` -> ``i_l1``: netCDF3 names hold letters, digits and ``_.@+-`` only."""
    import re

    return re.sub(r"[^A-Za-z0-9_.@+-]+", "_", name).strip("_") or "_"
