"""Running a scene: its run specs executed, and the records summed up in its report.

An ideal scene is a pure L-C ladder saving two currents; each effect adds
only its own elements (:mod:`lcchain.scenes.plan`).  A failed sample does not
stop a tolerance study: it is recorded with ngspice's reason and the others
still run (the scene is then not ok, exit status 1).

:func:`simulate_scene` runs the specs one after the other; any executor can
run :func:`lcchain.scenes.plan.scene_specs` instead and hand the records to
:func:`scene_result` (``lcchain run --workers``).  Files (the report, plots)
are written by :mod:`lcchain.report.scenes`.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, TypedDict

import numpy as np

from ..compare.extrapolate import WEIGHTS
from ..compare.spectral import OMEGA_WEIGHT_FLOOR, SpectrumMetrics
from ..compare.waveforms import Waveforms
from ..core.arrays import FloatArray
from ..core.blas import fixed_blas_threads
from ..core.budget import Budget
from ..core.checks import callback, instance
from ..core.errors import ParameterError
from ..core.json import JSONDict, LooseJSONObject
from ..core.show import Figure, html_table, plot, short_repr
from ..runs.execute import RunRecord, execute, loop_theory, pulse_centre
from ..runs.extrapolated import combined_record
from ..runs.spec import RunSpec, Theory
from ..spice.engines import find_engine
from ..spice.simulator import Simulator
from ..theory.arrivals import arrival_window, maximum_in_window
from ..theory.chain import Chain
from ..theory.exact import driven_modes
from .plan import ScenePlan, losses_and_pulse, scene_plan, scene_specs
from .schema import Scene

if TYPE_CHECKING:
    import xarray

__all__ = ["SampleResult", "SceneResult", "simulate_scene", "scene_result", "overlay_panel", "OverlayPanel",
           "transmitted_peaks", "nominal_peak"]


class SampleRecord(TypedDict, total=False):
    """One sample's line of a scene's JSON report (``error`` instead of the numbers when it failed)."""

    sample: int
    chain: str
    status: str
    error: str
    dt: float
    points: int
    engine: str
    engine_version: str
    ngspice_version: str
    netlist_sha256: str
    digest: str
    wall_s: float
    theory_and_compare_s: float
    max_abs_error: float
    arrivals: list[JSONDict]
    extrapolation: JSONDict
    max_rel_error_omega: float
    max_abs_error_P: float
    spacing_spread: float
    spacing_std: float
    modes_seen: int
    max_rel_error_Q: float
    effects: JSONDict


class SceneReport(TypedDict, total=False):
    """A scene's JSON report (:attr:`SceneResult.report`); the numbers over samples only when some ran."""

    scene: LooseJSONObject
    source: str | None
    N: int
    dt: float
    steps: list[float]
    tstop: float
    transit_time: float
    engine: str
    engine_version: str | None
    ngspice_version: str | None
    samples: list[SampleRecord]
    wall_s: dict[str, float]
    max_abs_error: float
    accuracy_met: bool
    arrivals: list[JSONDict]
    arrivals_sample: int
    transmitted_peak: dict[str, float]
    files: list[str]
    analysis: str
    points: int
    omega_max: float
    omega_nominal: list[float]
    max_rel_error_omega: float
    max_abs_error_P: float
    spacing_spread: dict[str, float]
    Q: float
    max_rel_error_Q: float


@dataclass(frozen=True, eq=False)
class SampleResult:
    """One realised circuit: its run record and its line in the report.

    Attributes
    ----------
    index : int
        Sample number from 1.
    chain : Chain
        The realised chain.
    record : dict
        Its entry of the report's ``samples`` (an ``"error"`` key when it failed).
    run : RunRecord
        The unit of work's record.
    netlist : str
        The netlist that was run.
    """

    index: int
    chain: Chain
    record: SampleRecord
    run: RunRecord
    netlist: str = ""

    @property
    def ok(self) -> bool:
        return self.run.ok

    @property
    def t(self) -> np.ndarray | None:
        """Time, units of sqrt(L0 C0)."""
        return None if self.run.signals is None else self.run.signals.t

    @property
    def sim(self) -> np.ndarray | None:
        """Simulated loop signals, one row per saved loop."""
        return None if self.run.signals is None else self.run.signals.sim

    @property
    def theory(self) -> np.ndarray | None:
        """The exact theory of the same loops."""
        return None if self.run.signals is None else self.run.signals.theory

    @property
    def waveforms(self) -> Waveforms | None:
        """Loops 1 and N, dimensionless."""
        return None if self.run.signals is None else self.run.signals.waveforms()


@dataclass(frozen=True, eq=False)
class SceneResult:
    """Everything a scene run produced; ``report`` is the JSON report."""

    scene: Scene
    report: SceneReport
    samples: tuple[SampleResult, ...] = field(default=())
    files: tuple[str, ...] = field(default=())

    @property
    def ok(self) -> bool:
        """Every sample ran, and met the scene's accuracy when it asked for one."""
        return all(s.ok for s in self.samples) and self.report.get("accuracy_met", True) is not False

    def good(self) -> list[SampleResult]:
        """The samples that ran."""
        return [s for s in self.samples if s.ok]

    def _rows(self) -> list[tuple[str, object]]:
        r: dict[str, object] = dict(self.report)
        failed = len(self.samples) - len(self.good())
        rows: list[tuple[str, object]] = [
            ("scene", self.scene.title), ("chain", f"{self.scene.chain.case}, N = {r.get('N')}"),
            ("engine", f"{r.get('engine')} {r.get('engine_version')}, {r.get('analysis', 'transient')}"),
            ("samples", f"{len(self.samples)}" + (f", {failed} failed" if failed else ""))]
        for key, name in (("max_abs_error", "max |simulation - theory|"), ("predicted_error", "predicted error"),
                          ("max_rel_error_omega", "max rel. error of omega_n"),
                          ("max_abs_error_P", "max abs. error of P_n"), ("accuracy_met", "accuracy met")):
            if r.get(key) is not None:
                rows.append((name, r[key]))
        return rows

    def __repr__(self) -> str:
        """A few lines (every sample's record: ``report``)."""
        return short_repr("SceneResult", self._rows())

    def _repr_html_(self) -> str:
        return html_table("SceneResult", self._rows())

    def plot(self, ax: object = None) -> Figure:
        """The first good sample's figure: a transient's end signals over theory (residual below), or an AC
        analysis's |P_n| against omega_n over theory.

        Returns
        -------
        matplotlib.figure.Figure
            Never shown.  matplotlib is imported here, not by ``import lcchain``.

        Raises
        ------
        SimulationError
            No sample ran.
        """
        return plot("scene", self, ax=ax)

    def to_xarray(self) -> xarray.Dataset:
        """Every sample as an xarray Dataset on ``sample``: its numbers (errors, step, points, times; NaN where it
        has none, a failed sample's ``status`` and ``error``), its first arrival's peaks, and its realised parts,
        ``L`` in henry on ``coil`` and ``C`` in farad on ``capacitor`` (NaN: a wire).  xarray is optional:
        ``pip install 'lcchain[data]'``."""
        from ..circuit.ladder import Ladder
        from ..runs.datasets import samples_dataset

        units = self.scene.units
        parts = [Ladder(sample.chain, units.L0, units.C0).parts() for sample in self.samples]
        dataset: xarray.Dataset = samples_dataset(self.scene.title, [s.record for s in self.samples], parts)
        return dataset

def _failed_record(index: int, chain: Chain, run: RunRecord) -> SampleRecord:
    error = run.reason + (f"\n{run.engine} said:\n{run.log_tail}" if run.log_tail else "")
    return {"sample": index, "chain": chain.name, "status": run.status, "error": error}


def _run_record(index: int, chain: Chain, run: RunRecord, netlist_sha256: str, points: int) -> SampleRecord:
    """What every sample that ran reports, whatever its analysis."""
    return {
        "sample": index, "chain": chain.name, "status": run.status, "points": points,
        "engine": run.engine, "engine_version": run.engine_version,
        "ngspice_version": run.ngspice_version, "netlist_sha256": netlist_sha256, "digest": run.digest,
        "wall_s": run.wall_s, "theory_and_compare_s": run.total_s - run.wall_s,
    }


def _sample_record(index: int, chain: Chain, dt: float, run: RunRecord) -> SampleRecord:
    if not run.ok:
        return _failed_record(index, chain, run)
    assert run.run is not None and run.metrics is not None
    record = _run_record(index, chain, run, run.run.netlist_sha256, run.run.points)
    record.update({"dt": dt, "max_abs_error": run.metrics.max_abs_error,
                   "arrivals": [a.to_dict() for a in run.metrics.arrivals]})
    if run.metrics.effects is not None:  # against the circuit's own theory: what its effects cost the pulse
        record["effects"] = run.metrics.effects.to_dict()
    return record


def _spectrum_record(index: int, chain: Chain, run: RunRecord) -> SampleRecord:
    if not run.ok:
        return _failed_record(index, chain, run)
    assert run.run is not None and run.spectrum is not None
    record = _run_record(index, chain, run, run.run.netlist_sha256, run.run.points)
    spectrum = run.spectrum  # its SPECTRAL_METRICS, in their order, as its to_dict has them
    # NaN where nothing is compared (every mode merged by the losses): no error, not an error of 0
    record.update({"max_rel_error_omega": spectrum.max_rel_error_omega, "max_abs_error_P": spectrum.max_abs_error_P,
                   "spacing_spread": spectrum.spacing_spread, "spacing_std": spectrum.spacing_std,
                   "modes_seen": spectrum.modes_seen})
    if spectrum.gamma is not None:  # losses: each mode's Q_n against omega_n Q
        record["max_rel_error_Q"] = spectrum.max_rel_error_Q
    return record


def _worst(errors: Iterable[float]) -> float:
    """The largest of the samples' errors, those not compared (NaN) left out: NaN when none was; an unseen mode's
    (infinite) is the largest."""
    compared = [error for error in errors if not math.isnan(error)]
    return max(compared) if compared else math.nan


def _spread(values: Sequence[float]) -> dict[str, float]:
    array = np.asarray(values, dtype=float)
    return {"mean": float(array.mean()), "std": float(array.std(ddof=1)) if array.size > 1 else 0.0,
            "worst": float(array.min()), "best": float(array.max()), "count": int(array.size)}


def nominal_peak(scene: Scene) -> tuple[float, float]:
    """The nominal circuit's theoretical first-arrival peak, and m_N / m_1 of its nominal chain (no simulation).

    For a study's figure, rebuilt from a store's scene: the value the tolerance samples spread around."""
    plan = scene_plan(scene)
    masses = plan.nominal.masses
    return _nominal_peak(scene, plan), float(masses[-1] / masses[0])


@fixed_blas_threads
def _nominal_peak(scene: Scene, plan: ScenePlan) -> float:
    """Theoretical first-arrival peak of the nominal (unrounded, untoleranced) circuit: the chain's, or the
    circuit's own with effects that are no chain's."""
    theory = plan.nominal_theory()
    lo, hi = arrival_window(1, plan.transit_time)
    shift = pulse_centre(theory.excitation, theory.pulse)
    ends = loop_theory(theory, "ends")

    def last(t: np.ndarray) -> np.ndarray:
        return np.asarray(ends(t)[-1])

    return maximum_in_window(last, (lo + shift, hi + shift), plan.transit_time)[1]


def transmitted_peaks(result: SceneResult) -> list[float]:
    """The first arrival's simulated peak of every sample that ran (its record's ``arrivals[0]["peak_sim"]``)."""
    peaks = []
    for s in result.good():
        assert s.run.metrics is not None  # a transient's sample that ran has its metrics (_sample_record)
        peaks.append(s.run.metrics.arrivals[0].peak_sim)
    return peaks


def _members(plan: ScenePlan, records: Sequence[RunRecord]) -> JSONDict:
    members: list[JSONDict] = [
        {"dt": h, "status": r.status, "points": r.run.points if r.run is not None else None,
         "wall_s": r.wall_s, "max_abs_error": r.metrics.max_abs_error if r.metrics is not None else None}
        for h, r in zip(plan.steps, records, strict=True)]
    return {"runs": plan.runs, "dt": list(plan.steps), "weights": list(WEIGHTS[plan.runs]), "members": members,
            "predicted_error": plan.predicted_error, "reason": plan.reason}


def scene_result(scene: Scene, plan: ScenePlan, specs: Sequence[RunSpec], records: Sequence[RunRecord],
                 total_s: float) -> SceneResult:
    """A scene's report from its executed runs (in the order of :func:`lcchain.scenes.plan.scene_specs`).

    With extrapolation, each sample's runs are combined into one record
    (:func:`lcchain.runs.extrapolated.combined_record`) and the sample's report lists them.  An AC scene
    reports each sample's spectrum against its own theory, and the spread of the spacings over the samples.
    """
    runs = plan.runs
    if len(specs) != runs * len(plan.chains) or len(records) != len(specs):
        raise ParameterError("records", len(records), f"{runs * len(plan.chains)} records, {runs} per sample, in "
                             "the order of the scene's specs")
    return _RESULTS[scene.analysis.kind](scene, plan, specs, records, total_s)


def _common_report(scene: Scene, plan: ScenePlan, samples: list[SampleResult], total_s: float) -> SceneReport:
    good = [s for s in samples if s.ok]
    return {
        "scene": scene.to_dict(),
        "source": scene.source,
        "N": plan.nominal.N,
        "engine": scene.analysis.engine,
        "engine_version": good[0].record["engine_version"] if good else None,
        "ngspice_version": good[0].record["ngspice_version"] if good else None,
        "samples": [s.record for s in samples],
        "wall_s": {"ngspice": float(sum(s.run.wall_s for s in samples)), "total": total_s},
    }


def _spectrum_result(scene: Scene, plan: ScenePlan, specs: Sequence[RunSpec], records: Sequence[RunRecord],
                     total_s: float) -> SceneResult:
    """An AC scene: each sample's modes against its own chain's, and the spread of delta omega_n over samples."""
    samples = [SampleResult(k, chain, _spectrum_record(k, chain, run), run, spec.netlist)
               for k, (chain, spec, run) in enumerate(zip(plan.chains, specs, records, strict=True), start=1)]
    assert plan.points is not None and plan.omega_max is not None  # an AC plan's
    report = _common_report(scene, plan, samples, total_s)
    nominal = driven_modes(plan.nominal)
    report.update({"analysis": "ac", "points": plan.points, "omega_max": plan.omega_max,
                   "omega_nominal": [float(w) for w in nominal.omega]})
    good = [s for s in samples if s.ok]
    if good:
        report["max_rel_error_omega"] = _worst(s.record["max_rel_error_omega"] for s in good)
        report["max_abs_error_P"] = _worst(s.record["max_abs_error_P"] for s in good)
        if all("max_rel_error_Q" in s.record for s in good):
            Q, _ = losses_and_pulse(scene)  # None: the decay rates are a real part's (each mode its own)
            if Q is not None:
                report["Q"] = Q
            report["max_rel_error_Q"] = _worst(s.record["max_rel_error_Q"] for s in good)
        spreads = np.array([s.record["spacing_spread"] for s in good], dtype=float)
        theory = SpectrumMetrics(nominal.omega, nominal.omega, nominal.transfer, nominal.transfer,
                                 np.abs(nominal.transfer) >= OMEGA_WEIGHT_FLOOR)
        report["spacing_spread"] = {"mean": float(spreads.mean()), "max": float(spreads.max()),
                                    "min": float(spreads.min()), "count": int(spreads.size),
                                    "theory_nominal": theory.spacing_spread}
    return SceneResult(scene, report, tuple(samples))


def _transient_result(scene: Scene, plan: ScenePlan, specs: Sequence[RunSpec], records: Sequence[RunRecord],
                      total_s: float) -> SceneResult:
    runs = plan.runs
    samples = []
    for k, chain in enumerate(plan.chains, start=1):
        own_specs, own = specs[(k - 1) * runs:k * runs], records[(k - 1) * runs:k * runs]
        record = own[0]
        if runs > 1:
            assert isinstance(own_specs[0].theory, Theory)
            record = combined_record(own_specs[0].theory, own, plan.steps, predicted_error=plan.predicted_error,
                                     modes=plan.modes if chain is plan.nominal else None)
        data = _sample_record(k, chain, plan.dt, record)
        if runs > 1 or plan.reason:
            data["extrapolation"] = _members(plan, own)
        samples.append(SampleResult(k, chain, data, record, own_specs[0].netlist))
    good = [s for s in samples if s.ok]
    report = _common_report(scene, plan, samples, total_s)
    report.update({"dt": plan.dt, "steps": list(plan.steps), "tstop": plan.tstop,
                   "transit_time": plan.transit_time})
    result = SceneResult(scene, report, tuple(samples))
    if good:
        report["max_abs_error"] = float(max(s.record["max_abs_error"] for s in good))
        if scene.analysis.accuracy is not None:
            report["accuracy_met"] = report["max_abs_error"] <= scene.analysis.accuracy
        report["arrivals"] = good[0].record["arrivals"]
        report["arrivals_sample"] = int(good[0].record["sample"])  # whose arrivals these are
        if len(plan.chains) > 1:
            report["transmitted_peak"] = _spread(transmitted_peaks(result))
            report["transmitted_peak"]["theory_nominal"] = _nominal_peak(scene, plan)
    return result


#: How each ``[analysis] kind``'s runs are summed up.
_RESULTS: dict[str, Callable[[Scene, ScenePlan, Sequence[RunSpec], Sequence[RunRecord], float], SceneResult]] = {
    "transient": _transient_result,
    "ac": _spectrum_result,
}


def simulate_scene(scene: Scene, *, progress: Callable[[float], None] | None = None,
                   simulator: Simulator | None = None, budget: Budget | None = None) -> SceneResult:
    """Run every sample of a scene, one after the other, and sum them up (no file is written).

    Parameters
    ----------
    scene : Scene
    progress : callable, optional
        Called with the fraction of the scene's simulations done (0 to 1),
        across samples and within each ngspice run.
    simulator : Simulator, optional
        Found once by the caller (for the scene's engine); found here for the scene's engine and backend when
        omitted.
    budget : Budget, optional
        The most memory and time the scene may take (checked before anything runs).
    """
    clock = time.perf_counter()
    instance("scene", scene, Scene)
    instance("simulator", simulator, Simulator, optional=True)
    instance("budget", budget, Budget, optional=True)
    callback("progress", progress)
    plan = scene_plan(scene, budget)
    specs = scene_specs(scene, plan)
    simulator = simulator if simulator is not None else find_engine(scene.analysis.engine, scene.analysis.backend)
    records = []
    for k, spec in enumerate(specs):
        report_to = None if progress is None else (lambda f, k=k: progress((k + f) / len(specs)))
        records.append(execute(spec, simulator, progress=report_to))
        if progress is not None:
            progress((k + 1) / len(specs))
    return scene_result(scene, plan, specs, records, time.perf_counter() - clock)


class OverlayPanel(TypedDict):
    """A column of :func:`lcchain.report.plots.side_by_side`: loop N's signal over its theory, and its arrivals."""

    t: FloatArray
    sim: FloatArray
    theory: FloatArray
    title: str
    arrivals: list[JSONDict]
    ylabel: str


def overlay_panel(result: SceneResult) -> OverlayPanel | None:
    """The far-end overlay of a scene's first good sample, for :func:`lcchain.report.plots.side_by_side`."""
    good = result.good()
    if not good:
        return None
    s = good[0]
    signals = s.run.signals
    assert signals is not None
    ylabel = r"$Q_N\,/\,Q_1(0)$" if result.scene.excitation.kind == "displacement" else r"$I_N\,/\,I_0$"
    return {"t": signals.t, "sim": signals.sim[-1], "theory": signals.theory[-1], "title": result.scene.title,
            "arrivals": [a for a in s.record["arrivals"] if a["end"] == "last"], "ylabel": ylabel}
