"""Run a scene: exactly the circuit, vectors and theory it calls for.

The scene (parsed by :mod:`lcchain.scene`, no physics there) is turned into
chains (:mod:`lcchain.effects`: walls, preferred values, tolerance samples),
netlists (:func:`lcchain.netlist.netlist_text`: resistors only with losses, a
source only for a pulse, all loop currents only for ``probes = "all"``),
ngspice runs, and the exact linear response of each realised circuit
(:func:`lcchain.response.linear_response`).  An ideal scene is a pure L-C
ladder saving two currents.

A failed sample does not stop a tolerance study: it is recorded with its
error message and the report is still written (exit status 1).
"""

from __future__ import annotations

import json
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from scipy.optimize import minimize_scalar

from .arrivals import arrival_window
from .cases import chain_for_case
from .chain import Chain
from .compare import Waveforms, normalise, sample_peak
from .effects import realise, tolerance_samples, with_walls
from .errors import LcchainError, ParameterError
from .modes import EXACT_MAX_N, Modes, exact_modes, normal_modes
from .netlist import Ladder, SimulationOptions, netlist_text, probe_names
from .types import GAUSSIAN_CENTRE

__all__ = ["ScenePlan", "SceneResult", "SampleResult", "run_scene", "scene_chains", "scene_netlist", "scene_plan",
           "overlay_panel", "ACCURACY_LOOPS"]

#: With probes = "all", the step's error is predicted on at most this many loops, evenly spaced, ends included.
ACCURACY_LOOPS = 64


def base_chain(scene) -> Chain:
    """The nominal chain of the scene (case or custom), with walls if asked."""
    spec = scene.chain
    if spec.case == "custom":
        chain = Chain(list(spec.masses), list(spec.springs), name="custom")
    else:
        chain = chain_for_case(spec.case, spec.N)
    if scene.effects.walls is not None:
        chain = with_walls(chain, scene.effects.walls.K0)
    return chain


def scene_chains(scene) -> tuple[Chain, list[Chain]]:
    """(nominal chain, realised chains): one per tolerance sample, else one."""
    nominal = base_chain(scene)
    effects, units = scene.effects, scene.units
    series = effects.preferred_values.series if effects.preferred_values is not None else None
    tol = effects.tolerance
    if tol is not None and (tol.L or tol.C or tol.samples > 1):
        chains = tolerance_samples(nominal, units.L0, units.C0, samples=tol.samples, seed=tol.seed,
                                   tol_L=tol.L, tol_C=tol.C, series=series)
    elif series is not None:
        chains = [realise(nominal, units.L0, units.C0, series=series, name=f"{nominal.name} {series}")]
    else:
        chains = [nominal]
    return nominal, chains


@dataclass(frozen=True, eq=False)
class SampleResult:
    """One realised circuit: its netlist, run, theory and comparison."""

    index: int
    chain: Chain
    record: dict
    t: np.ndarray | None = None
    sim: np.ndarray | None = None
    theory: np.ndarray | None = None
    netlist: str = ""
    waveforms: Waveforms | None = None


@dataclass(frozen=True, eq=False)
class SceneResult:
    """Everything a scene run produced; ``report`` is the JSON report."""

    report: dict
    samples: tuple[SampleResult, ...] = field(default=())
    files: tuple[str, ...] = field(default=())

    @property
    def ok(self) -> bool:
        return all("error" not in s.record for s in self.samples)


def _pulse_centre(excitation) -> float:
    if excitation.kind != "pulse":
        return 0.0
    return GAUSSIAN_CENTRE * excitation.width if excitation.shape == "gaussian" else excitation.width / 2


def _choose_dt(scene, nominal: Chain, modes: Modes, tstop: float) -> float:
    analysis = scene.analysis
    if analysis.dt is not None:
        return float(analysis.dt)
    from .accuracy import dt_for_accuracy

    weights = None
    if scene.output.probes == "all":
        # Interior loops can have 4x the ends' error: predict it on up to ACCURACY_LOOPS of them.
        from .response import loop_weights

        _, every = loop_weights(nominal)
        loops = np.unique(np.linspace(0, every.shape[1] - 1, min(ACCURACY_LOOPS, every.shape[1])).round().astype(int))
        weights = [every[:, i] for i in loops]
    dt = dt_for_accuracy(modes, analysis.accuracy, tstop, method=analysis.method, weights=weights)
    if scene.excitation.kind == "pulse":
        # the accuracy model is for free oscillation; resolve the pulse too
        dt = min(dt, scene.excitation.width / 8)
    return dt


def _theory_peak(scene, chain: Chain, modes: Modes, row: int, t0: float, h: float, lo: float,
                 hi: float) -> tuple[float, float]:
    """(time, value) of the maximum of the exact response of loop ``row`` (0: first, -1: last) near t0.

    Bounded Brent on [t0 - 2h, t0 + 2h] within [lo, hi]; t0 is the best of a
    grid of spacing h.
    """
    from .response import linear_response

    Q, pulse = _losses_and_pulse(scene)

    def minus_response(t: float) -> float:
        return -float(linear_response(chain, np.array([t]), excitation=scene.excitation.kind, Q=Q, pulse=pulse,
                                      loops="ends", modes=modes)[row, 0])

    a, b = max(lo, t0 - 2 * h), min(hi, t0 + 2 * h)
    result = minimize_scalar(minus_response, bounds=(a, b), method="bounded", options={"xatol": 1e-9})
    return float(result.x), float(-result.fun)


def _losses_and_pulse(scene) -> tuple[float | None, tuple[str, float] | None]:
    excitation = scene.excitation
    Q = scene.effects.losses.Q if scene.effects.losses is not None else None
    pulse = (excitation.shape, excitation.width) if excitation.kind == "pulse" else None
    return Q, pulse


def scene_netlist(scene, chain: Chain, dt: float, tstop: float) -> str:
    """The netlist of one realised chain of the scene: only the elements its effects need.

    Parameters
    ----------
    scene : lcchain.scene.Scene
    chain : Chain
        The nominal chain or one of its realisations (:func:`scene_chains`).
    dt, tstop : float
        Maximum step and stop time in units of sqrt(L0 C0) (:func:`scene_plan`).
    """
    Q, pulse = _losses_and_pulse(scene)
    excitation = scene.excitation
    ladder = Ladder(chain, scene.units.L0, scene.units.C0)
    options = SimulationOptions(dt=dt, tstop=tstop, method=scene.analysis.method)
    return netlist_text(ladder, options, excitation=excitation.kind, I0=excitation.I0, probes=scene.output.probes,
                        title=scene.title, Q=Q, pulse=pulse)


@dataclass(frozen=True, eq=False)
class ScenePlan:
    """What a scene will run, decided before ngspice starts.

    Attributes
    ----------
    nominal : Chain
        The chain of the scene's case (with walls if asked), before rounding
        and tolerances.
    chains : tuple of Chain
        The realised chains, one per tolerance sample (else the nominal, or
        its preferred-value rounding).
    modes : Modes
        Normal modes of the nominal chain (transit time, step choice).
    transit_time, tstop, dt : float
        Units of sqrt(L0 C0): the end-to-end travel time, the end of the
        analysis (the window of the last requested transit, shifted by the
        pulse's centre) and the maximum step (``analysis.dt``, or the largest
        step whose predicted error meets ``analysis.accuracy``, at most
        width/8 for a pulse).
    """

    nominal: Chain
    chains: tuple[Chain, ...]
    modes: Modes
    transit_time: float
    tstop: float
    dt: float


def scene_plan(scene) -> ScenePlan:
    """Chains, stop time and step of a scene (no simulation)."""
    nominal, chains = scene_chains(scene)
    modes = normal_modes(nominal)  # raises for a chain beyond both exact and closed-form modes
    N = nominal.N
    realised = any(chain is not nominal for chain in chains)
    if N > EXACT_MAX_N and (realised or scene.output.probes == "all"):
        why = "every loop's response" if scene.output.probes == "all" else "tolerances or preferred values"
        raise ParameterError("chain.N", N, f"N <= {EXACT_MAX_N} with {why} (the theory needs the exact modes "
                             "of each realised chain)", where=scene.source)
    T = modes.transit_time()
    tstop = arrival_window(scene.analysis.transits, T)[1] + _pulse_centre(scene.excitation)
    dt = _choose_dt(scene, nominal, modes, tstop)
    return ScenePlan(nominal, tuple(chains), modes, T, tstop, dt)


def _simulate_sample(scene, plan: ScenePlan, index: int, chain: Chain,
                     progress: Callable[[float], None] | None = None) -> SampleResult:
    from . import ngspice
    from .response import linear_response

    units, excitation, analysis = scene.units, scene.excitation, scene.analysis
    dt, tstop, T = plan.dt, plan.tstop, plan.transit_time
    Q, pulse = _losses_and_pulse(scene)
    ladder = Ladder(chain, units.L0, units.C0)
    text = scene_netlist(scene, chain, dt, tstop)
    names = probe_names(chain.N, scene.output.probes)
    result = ngspice.run(text, names, tstop * ladder.time_unit, backend=analysis.backend, progress=progress)
    clock = time.perf_counter()
    currents = np.array([result.vectors[name] for name in names])
    kind = "displacement" if excitation.kind == "displacement" else "kick"
    ends = normalise(result.time, currents[0], currents[-1], time_unit=ladder.time_unit, excitation=kind,
                     I0=excitation.I0)
    t = ends.t
    modes = plan.modes if chain is plan.nominal else exact_modes(chain)
    loops = "all" if scene.output.probes == "all" else "ends"
    theory = linear_response(chain, t, excitation=excitation.kind, Q=Q, pulse=pulse, loops=loops, modes=modes)
    sim = currents / excitation.I0 if loops == "all" else np.vstack([ends.first, ends.last])
    if kind == "displacement" and loops == "all":
        sim = np.vstack([ends.first] + [normalise(result.time, c, c, time_unit=ladder.time_unit,
                                                  excitation="displacement", I0=excitation.I0).last
                                        for c in currents[1:]])
    first_sim, last_sim = sim[0], sim[-1]
    first_th, last_th = theory[0], theory[-1]
    error = float(np.max(np.abs(sim - theory)))  # every saved loop, not only the ends
    shift = _pulse_centre(excitation)
    arrivals = []
    for j in range(1, analysis.transits + 1):
        lo, hi = arrival_window(j, T)
        lo, hi = lo + shift, min(hi + shift, t[-1])
        end = "last" if j % 2 else "first"
        row = -1 if end == "last" else 0
        s_sim, s_th = (last_sim, last_th) if end == "last" else (first_sim, first_th)
        t_sim, peak_sim = sample_peak(t, s_sim, lo, hi)
        t_grid, _ = sample_peak(t, s_th, lo, hi)
        t_th, peak_th = _theory_peak(scene, chain, modes, row, t_grid, dt, lo, hi)
        arrivals.append({"index": j, "end": end, "t_theory": t_th, "t_sim": t_sim,
                         "peak_theory": peak_th, "peak_sim": peak_sim})
    record = {
        "sample": index, "chain": chain.name, "dt": dt, "points": result.points,
        "ngspice_version": result.ngspice_version, "netlist_sha256": result.netlist_sha256,
        "wall_s": result.wall_s, "theory_and_compare_s": time.perf_counter() - clock,
        "max_abs_error": error, "arrivals": arrivals,
    }
    return SampleResult(index, chain, record, t, sim, theory, text, ends)


def _spread(values: list[float]) -> dict:
    array = np.asarray(values, dtype=float)
    return {"mean": float(array.mean()), "std": float(array.std(ddof=1)) if array.size > 1 else 0.0,
            "worst": float(array.min()), "best": float(array.max()), "count": int(array.size)}


def run_scene(scene, *, netlist_out: str | None = None, waveform_out: str | None = None,
              write_outputs: bool = True, progress: Callable[[float], None] | None = None) -> SceneResult:
    """Run every sample of a scene, write its report and plots, return the result.

    Parameters
    ----------
    scene : lcchain.scene.Scene
    netlist_out, waveform_out : str, optional
        Keep the (first sample's) netlist, and its end waveforms as CSV
        ``t,first,last`` (dimensionless, as ``lcchain simulate`` writes them).
    write_outputs : bool
        Write the report file and plots named by the scene's [output].
    progress : callable, optional
        Called with the fraction of the scene's simulations done (0 to 1),
        across samples and within each ngspice run.
    """
    clock = time.perf_counter()
    plan = scene_plan(scene)
    nominal, chains, nominal_modes = plan.nominal, plan.chains, plan.modes
    T, tstop, dt = plan.transit_time, plan.tstop, plan.dt
    samples: list[SampleResult] = []
    for k, chain in enumerate(chains, start=1):
        try:
            report_to = None if progress is None else \
                (lambda f, k=k: progress((k - 1 + f) / len(chains)))
            samples.append(_simulate_sample(scene, plan, k, chain, report_to))
        except LcchainError as error:  # keep going: nothing is lost when one sample fails
            samples.append(SampleResult(k, chain, {"sample": k, "chain": chain.name, "error": str(error)}))
        if progress is not None:
            progress(k / len(chains))
    good = [s for s in samples if "error" not in s.record]
    report = {
        "scene": scene.to_dict(),
        "source": scene.source,
        "N": nominal.N,
        "dt": dt,
        "tstop": tstop,
        "transit_time": T,
        "ngspice_version": good[0].record["ngspice_version"] if good else None,
        "samples": [s.record for s in samples],
        "wall_s": {"ngspice": float(sum(s.record.get("wall_s", 0.0) for s in samples)),
                   "total": time.perf_counter() - clock},
    }
    if good:
        first = good[0].record
        report["max_abs_error"] = float(max(s.record["max_abs_error"] for s in good))
        report["arrivals"] = first["arrivals"]
        if len(chains) > 1:
            peaks = [s.record["arrivals"][0]["peak_sim"] for s in good]
            report["transmitted_peak"] = _spread(peaks)
            report["transmitted_peak"]["theory_nominal"] = _nominal_peak(scene, nominal, nominal_modes, T)
    files: list[str] = []
    if good and netlist_out:
        Path(netlist_out).write_text(good[0].netlist, encoding="utf-8")
        files.append(netlist_out)
    if good and waveform_out:
        Path(waveform_out).write_text(good[0].waveforms.to_csv(), encoding="utf-8")
        files.append(waveform_out)
    if write_outputs:
        files += _write_outputs(scene, report, good)
    report["files"] = files
    return SceneResult(report, tuple(samples), tuple(files))


def _ylabel(scene) -> str:
    return r"$Q_N\,/\,Q_1(0)$" if scene.excitation.kind == "displacement" else r"$I_N\,/\,I_0$"


def overlay_panel(scene, result: SceneResult) -> dict | None:
    """The far-end overlay of a scene's first good sample, for :func:`lcchain.plots.side_by_side`."""
    good = [s for s in result.samples if "error" not in s.record]
    if not good:
        return None
    s = good[0]
    return {"t": s.t, "sim": s.sim[-1], "theory": s.theory[-1], "title": f"{scene.title}",
            "arrivals": [a for a in s.record["arrivals"] if a["end"] == "last"], "ylabel": _ylabel(scene)}


def _nominal_peak(scene, nominal: Chain, modes, T: float) -> float:
    """Theoretical first-arrival peak of the nominal (unrounded, untoleranced) circuit."""
    from .response import linear_response

    excitation = scene.excitation
    Q, pulse = _losses_and_pulse(scene)
    lo, hi = arrival_window(1, T)
    shift = _pulse_centre(excitation)
    grid = np.linspace(lo + shift, hi + shift, 400)
    values = linear_response(nominal, grid, excitation=excitation.kind, Q=Q, pulse=pulse, loops="ends",
                             modes=modes)[-1]
    i = int(np.argmax(values))
    return _theory_peak(scene, nominal, modes, -1, grid[i], grid[1] - grid[0], grid[0], grid[-1])[1]


def _output_stem(scene) -> tuple[Path, str]:
    if scene.output.report:
        path = Path(scene.output.report)
        return path.parent, path.stem
    stem = Path(scene.source).stem if scene.source else "scene"
    return Path("."), stem


def _write_outputs(scene, report: dict, good: list[SampleResult]) -> list[str]:
    folder, stem = _output_stem(scene)
    written: list[str] = []
    wanted = set(scene.output.plots)
    if good and wanted:
        folder.mkdir(parents=True, exist_ok=True)
        from . import plots

        s = good[0]
        if "overlay" in wanted:
            path = folder / f"{stem}-overlay.png"
            plots.overlay(s.t, s.sim[-1], s.t, s.theory[-1], residual=s.sim[-1] - s.theory[-1],
                          arrivals=[a for a in s.record["arrivals"] if a["end"] == "last"],
                          title=f"{scene.title} (N = {s.chain.N})",
                          ylabel=_ylabel(scene), path=str(path))
            written.append(str(path))
        if "spacetime" in wanted and scene.output.probes == "all":
            path = folder / f"{stem}-spacetime.png"
            plots.spacetime(s.t, s.sim, title=f"{scene.title}: every loop current", path=str(path))
            written.append(str(path))
        if "histogram" in wanted and len(good) > 1:
            path = folder / f"{stem}-histogram.png"
            peaks = [g.record["arrivals"][0]["peak_sim"] for g in good]
            plots.histogram(peaks, theory=report.get("transmitted_peak", {}).get("theory_nominal"),
                            title=f"{scene.title}: transmitted peak over {len(good)} samples", path=str(path))
            written.append(str(path))
    if scene.output.report:
        path = Path(scene.output.report)
        path.parent.mkdir(parents=True, exist_ok=True)
        report_copy = dict(report, files=written + [str(path)])
        path.write_text(json.dumps(report_copy, indent=2), encoding="utf-8")
        written.append(str(path))
    return written
