"""A study's runs as its store holds them (:class:`StoredRun`), and the study's shape read from them: the
parameters that vary (:func:`study_axes`), those every run shares (:func:`study_constants`), and the dataset's
dimensions (:func:`study_dims`).  No file here: :mod:`lcchain.studies.store` reads and writes them."""

from __future__ import annotations

import json
from dataclasses import dataclass

from ..core.analyses import ANALYSIS_KINDS_DATA, analysis_kind
from ..core.errors import ParameterError
from ..core.json import JSONDict, LooseJSONObject
from ..core.types import RUN_STATUSES
from ..runs.execute import RunRecord
from ..spice.engines import DEFAULT_ENGINE
from ..spice.measure import MEASURE_REASONS, MEASUREMENTS

__all__ = ["StoredRun", "PARTS", "ARRAY_AXES", "study_axes", "study_constants", "study_dims", "value_key"]

#: The key of a run's metrics that holds a tolerance or preferred-value sample's realised part values,
#: ``{"L": [...], "C": [...]}`` (henry, farad): ``lcchain results --json`` prints it as the run's ``parts``.
PARTS = "parts"#: The axis of a run's saved arrays: a transient's time, or an AC run's frequency.
ARRAY_AXES = ("time", "frequency")


@dataclass(frozen=True)
class StoredRun:
    """One task of a study as the store has it (``status`` is ``"pending"`` until it ran; ``"refused"``: a batch's
    netlist lcchain would not run, ``reason`` says why)."""

    index: int
    key: str
    params: LooseJSONObject  # JSON read from the store: its values are narrowed where they are read
    label: str
    status: str
    reason: str = ""
    log_tail: str = ""
    digest: str = ""
    wall_s: float | None = None
    total_s: float | None = None
    points: int | None = None
    metrics: LooseJSONObject | None = None  # JSON read from the store, as ``params``
    engine_version: str = ""
    lcchain_version: str = ""
    engine: str = DEFAULT_ENGINE

    @property
    def ngspice_version(self) -> str:
        """ngspice's version when ngspice ran it, else ""."""
        return self.engine_version if self.engine == DEFAULT_ENGINE else ""

    @property
    def kind(self) -> str:
        """``"run"``; ``"member"``, a run made to be extrapolated with others; or ``"combined"``, their
        extrapolation (its params hold ``runs``): the result, where the members are its ingredients."""
        return "member" if "member" in self.params else "combined" if "runs" in self.params else "run"

    @property
    def member(self) -> bool:
        return self.kind == "member"

    @property
    def spectral(self) -> bool:
        """An AC run compared with its theory (its metrics are :data:`lcchain.compare.spectral.SPECTRAL_METRICS`)."""
        kind = self.metrics.get("analysis") if self.metrics is not None else None
        return isinstance(kind, str) and kind in ANALYSIS_KINDS_DATA and analysis_kind(kind).swept

    @property
    def measurements(self) -> dict[str, float | None]:
        """The netlist's ``.meas`` values by name (None: ngspice could not make it, :attr:`measure_reasons`
        says why); empty for a run without any."""
        return dict((self.metrics or {}).get(MEASUREMENTS) or {})

    @property
    def measure_reasons(self) -> dict[str, str]:
        """ngspice's reason for each missing measurement."""
        return dict((self.metrics or {}).get(MEASURE_REASONS) or {})

    @property
    def judged(self) -> bool:
        """Compared with a theory: its metrics hold more than measurements."""
        return self.metrics is not None and any(k not in (MEASUREMENTS, MEASURE_REASONS, PARTS)
                                                for k in self.metrics)

    @property
    def parts(self) -> dict[str, list[float | None]] | None:
        """A tolerance or preferred-value sample's realised part values: ``{"L": L_1..L_N (henry), "C": C_01..
        C_N,N+1 (farad; None where a wall is a wire)}``; None for a nominal chain, and in stores made before."""
        value = (self.metrics or {}).get(PARTS)
        return dict(value) if isinstance(value, dict) else None

    def record(self) -> RunRecord:
        """The run as a record without its arrays (:meth:`lcchain.studies.store.Store.waveforms` has them)."""
        if self.status not in RUN_STATUSES:
            raise ParameterError("run", self.index, "a run that finished (this one is pending)")
        return RunRecord(key=self.key, status=self.status, reason=self.reason,
                         log_tail=self.log_tail, digest=self.digest, wall_s=self.wall_s or 0.0,
                         total_s=self.total_s or 0.0, engine=self.engine, engine_version=self.engine_version,
                         lcchain_version=self.lcchain_version, label=self.label)

    def to_dict(self) -> JSONDict:
        """The object ``lcchain results --json`` prints for this task."""
        data: JSONDict = {"index": self.index, "key": self.key, "kind": self.kind, "status": self.status,
                                "params": self.params, "label": self.label, "digest": self.digest or None,
                                "wall_s": self.wall_s, "points": self.points}
        if self.status != "pending":  # the engine that ran it (or refused it), its name and version apart
            data.update(engine=self.engine, engine_version=self.engine_version)
        if self.spectral:
            from ..compare.spectral import SPECTRAL_METRICS  # with an AC run only: a batch starts without it

            assert self.metrics is not None
            data.update({name: self.metrics.get(name) for name in SPECTRAL_METRICS})
        elif self.judged:
            assert self.metrics is not None
            data["max_abs_error"] = self.metrics.get("max_abs_error")
            data["predicted_error"] = self.metrics.get("predicted_error")
            data["arrivals"] = self.metrics.get("arrivals")
            if "effects" in self.metrics:  # against the circuit's own theory: what its effects cost the pulse
                data["effects"] = self.metrics["effects"]
        if self.parts is not None:
            data[PARTS] = self.parts
        if self.measurements:
            data[MEASUREMENTS] = self.measurements
            data[MEASURE_REASONS] = self.measure_reasons
        if self.status in ("failed", "timeout", "refused"):  # a refusal's reason: the netlist, line and field
            data["error"] = self.reason + (f"\n{self.engine} said:\n{self.log_tail}" if self.log_tail else "")
        return data


def study_axes(runs: list[StoredRun]) -> list[str]:
    """The parameters that vary across the study's tasks, in the plan's order. A constant one is no axis (every
    run shares it), nor one only some tasks have (an extrapolation's ``dt`` and ``runs`` where other points
    ran once, a member's ``member``). A study of a single task has no axes."""
    values: dict[str, set[str]] = {}
    for run in runs:
        for key, value in run.params.items():
            values.setdefault(key, set()).add(repr(value))
    keys = list(dict.fromkeys(key for run in runs for key in run.params))
    return [key for key in keys if len(values[key]) > 1 and all(key in run.params for run in runs)]


def study_constants(runs: list[StoredRun]) -> LooseJSONObject:
    """The parameters every task (extrapolation members aside) shares, with their one value."""
    runs = [run for run in runs if not run.member]
    axes = set(study_axes(runs))
    keys = list(dict.fromkeys(key for run in runs for key in run.params))
    return {key: runs[0].params[key] for key in keys
            if key not in axes and all(key in run.params for run in runs)} if runs else {}


def value_key(value: object) -> str:
    return json.dumps(value, sort_keys=True, default=str)


def study_dims(runs: list[StoredRun]) -> tuple[list[str], list[str]]:
    """The dimensions of a study's dataset (:meth:`lcchain.studies.store.Store.to_xarray`), and the axes that are
    coordinates along them.

    Its axes (:func:`study_axes`), in order, except an axis whose value the dimensions before it already fix for
    every run: a worst case's ``signs``, one per ``corner``, is a coordinate along ``corner``, not a dimension of
    its own (259 corners made a grid of 259 x 259 points, all but 259 of them empty, 2.5 GB of waveforms). Runs
    that are no grid (two at the same point) have the task number, ``index``, as their one dimension.
    """
    axes = study_axes(runs)
    points = [tuple(value_key(run.params.get(axis)) for axis in axes) for run in runs]
    if not axes or len(set(points)) < len(points):
        return ["index"], []
    dims: list[int] = []
    along: list[int] = []
    for i in range(len(axes)):
        fixed: dict[tuple[str, ...], str] = {}
        if dims and all(fixed.setdefault(tuple(point[d] for d in dims), point[i]) == point[i] for point in points):
            along.append(i)
        else:
            dims.append(i)
    return [axes[i] for i in dims], [axes[i] for i in along]
