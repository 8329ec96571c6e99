"""``lcchain simulate`` as functions: run the ladder in one engine (or the same netlist in several) against
theory, then write what was asked for.

:func:`simulate` checks the outputs, builds the chain, keeps the netlist before the simulator starts and
runs it; the caller shows the result; :func:`write_outputs` then writes the waveforms and the figure.
With several engines it runs one netlist in each (an :class:`EnginesComparison`).
"""

from __future__ import annotations

import warnings
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

from ..circuit.effects import Effect
from ..core.budget import Budget
from ..core.errors import ParameterError
from ..core.json import LooseJSONObject
from ..core.physical import hertz, physical_scales, seconds
from ..core.types import BACKENDS, Backend, Method
from ..report.files import FIGURE_FORMATS
from .inputs import LadderRequest, Outputs, make_chain
from .netlist import DEFAULT_DT

if TYPE_CHECKING:
    from ..runs.request import Request
    from ..runs.simulate import SimulationReport
    from ..runs.spec import RunSpec
    from ..theory.chain import Chain

__all__ = ["SimulateRequest", "Simulation", "EnginesComparison", "simulate", "write_outputs",
           "with_physical_units"]


@dataclass(frozen=True)
class SimulateRequest(LadderRequest):
    """What ``lcchain simulate`` asks: the chain and its units, the drive, the step (``dt``, or ``accuracy``
    and ``extrapolate``), the engines (several: one netlist in each), backend and method, the effects, the files
    to write (``plot``, ``netlist_out``, ``waveform_out``; ``-``: stdout), whether the result goes out as JSON,
    the budget and ``progress(label)``, a callback of the fraction done."""

    accuracy: float | None = None
    extrapolate: int | None = None
    engines: tuple[str, ...] = ("ngspice",)
    backend: Backend = "batch"
    method: Method = "trap"
    effects: tuple[Effect, ...] = ()
    plot: str | None = None
    netlist_out: str | None = None
    waveform_out: str | None = None
    json: bool = False
    budget: Budget = field(default_factory=Budget)
    progress: Callable[[str], Callable[[float], None]] | None = None


@dataclass(frozen=True)
class Simulation:
    """One engine's run: the chain, the report (:class:`lcchain.runs.simulate.SimulationReport`), its JSON with
    SI units (:func:`with_physical_units`), the warnings it raised, the outputs still to write and the netlists
    kept."""

    request: SimulateRequest
    chain: Chain
    report: SimulationReport
    data: LooseJSONObject
    warnings: tuple[str, ...]
    outputs: Outputs
    kept: list[str]


@dataclass(frozen=True)
class EnginesComparison:
    """``simulate --engine A,B``: each engine's report, their JSON, the largest differences between them and the
    warnings the runs raised (each once)."""

    chain: Chain
    reports: list[SimulationReport]
    data: LooseJSONObject
    differences: dict[str, float]
    warnings: tuple[str, ...] = ()


def with_physical_units(data: LooseJSONObject, L0: float, C0: float, coupling: float = 0.0) -> LooseJSONObject:
    """A report's JSON with its bulk numbers also in SI (issue 33): ``physical`` (the units' scales,
    :func:`lcchain.core.physical.physical_scales`), ``dt_s`` and ``tstop_s``, each arrival's ``t_theory_s`` and
    ``t_sim_s``, each mode's ``omega_Hz`` and ``omega_theory_Hz``; the bulk keys stay as they are."""
    data["physical"] = physical_scales(L0, C0, coupling)  # the band top that of the chain's coupled coils
    for key in ("dt", "tstop"):
        if isinstance(data.get(key), (int, float)):
            data[f"{key}_s"] = seconds(data[key], L0, C0)
    for arrival in data.get("arrivals") or ():
        for key in ("t_theory", "t_sim"):
            value = arrival.get(key)
            arrival[f"{key}_s"] = None if value is None else seconds(value, L0, C0)
    for mode in data.get("modes") or ():
        for key in ("omega", "omega_theory"):
            value = mode.get(key)
            mode[f"{key}_Hz"] = None if value is None else hertz(value, L0, C0)
    if isinstance(data.get("omega_max"), (int, float)):
        data["omega_max_Hz"] = hertz(data["omega_max"], L0, C0)
    return data


def _progress(request: SimulateRequest, label: str) -> Callable[[float], None] | None:
    return None if request.progress is None else request.progress(label)


def _simulation_request(request: SimulateRequest, chain: Chain, *, dt: float | None, accuracy: float | None,
                        extrapolate: int | None, engine: str, backend: Backend) -> Request:
    """What ``simulate`` asks for: the chain, the step, and the effects its options ask for (``--Q``,
    ``--coil-capacitance``, ...), as one Request."""
    import dataclasses

    from ..runs.simulate import ChainOptions

    effects = request.effects
    options = ChainOptions(dt=dt, accuracy=accuracy, extrapolate=extrapolate, transits=request.transits,
                           excitation=request.excitation, L0=request.L0, C0=request.C0, backend=backend,
                           method=request.method, title=request.title, engine=engine)
    made = options.request(chain)
    return dataclasses.replace(made, effects=effects) if effects else made


def _prepare(request: SimulateRequest) -> tuple[Outputs, Chain, float | None, list[str], Callable[[RunSpec], None]]:
    """The outputs checked, the chain, the step, and the hook that keeps each run's netlist before it starts."""
    from ..report.files import write_text

    outputs = Outputs(inputs={"--chain": request.chain.chain} if request.chain.chain else {})
    outputs.check("--plot", request.plot, FIGURE_FORMATS)
    outputs.check("--netlist-out", request.netlist_out)
    outputs.check("--waveform-out", request.waveform_out)
    if request.json and outputs.to_stdout:
        raise ParameterError(outputs.to_stdout, "-", "a file name with --json (both would write to stdout)")
    chain = make_chain(request.chain, request.budget)
    if request.accuracy is not None and request.dt is not None:
        raise ParameterError("--accuracy", request.accuracy, "either --dt or --accuracy, not both")
    dt = None if request.accuracy is not None else (request.dt if request.dt is not None else DEFAULT_DT)

    kept: list[str] = []

    def keep_netlist(spec: RunSpec) -> None:  # before ngspice starts: a failed run still leaves it
        if request.netlist_out == "-":  # stdout holds one netlist: the first run's
            if not kept:
                outputs.text("--netlist-out", spec.netlist)
            kept.append("-" if not kept else "(not written: - holds the first run's)")
            return
        if request.netlist_out:  # several runs (extrapolation): FILE holds the first, FILE-run2.cir ... the others
            path = Path(request.netlist_out)
            target = path if not kept else path.with_name(f"{path.stem}-run{len(kept) + 1}{path.suffix}")
            if kept and (target.exists() or target.is_symlink()):  # a name the user did not give: never replaced
                outputs.notes.append(f"warning: --netlist-out: {target} exists and was left as it is; run "
                                     f"{len(kept) + 1}'s netlist was not written")
                kept.append(f"{target} (not written)")
                return
            write_text(target, spec.netlist)
            kept.append(str(target))

    return outputs, chain, dt, kept, keep_netlist


def simulate(request: SimulateRequest) -> Simulation | EnginesComparison:
    """Run the ladder: one engine (a :class:`Simulation`, whose files :func:`write_outputs` writes), or the same
    netlist in several (an :class:`EnginesComparison`)."""
    from ..runs.simulate import run_simulation, simulation_runs

    outputs, chain, dt, kept, keep_netlist = _prepare(request)
    if len(request.engines) > 1:
        return _compare_engines(request, chain, dt, keep_netlist)
    engine = request.engines[0]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        made = _simulation_request(request, chain, dt=dt, accuracy=request.accuracy,
                                   extrapolate=request.extrapolate, engine=engine, backend=request.backend)
        planned = simulation_runs(made, budget=request.budget)
        for spec in planned.specs:  # before the simulator starts: a failed run still leaves them
            keep_netlist(spec)
        report = run_simulation(planned, progress=_progress(request, engine))
    data = with_physical_units(report.to_dict(), request.L0, request.C0, chain.coupling)
    return Simulation(request, chain, report, data, tuple(str(w.message) for w in caught), outputs, kept)


def write_outputs(simulation: Simulation) -> bool:
    """Write the waveforms and the figure of a run (after it was shown); returns whether the run failed: an
    accuracy not met, or an output that could not be written (each said in a note of ``simulation.outputs``)."""
    request, chain, report, data, outputs, kept = (simulation.request, simulation.chain, simulation.report,
                                                   simulation.data, simulation.outputs, simulation.kept)
    if len(kept) > 1:
        outputs.notes.append(f"--netlist-out: the {len(kept)} runs' netlists are in {', '.join(kept)} (dt = "
                             f"{', '.join(f'{h:.4g}' for h in data['extrapolation']['dt'])})")
    outputs.text("--waveform-out", report.waveforms.to_csv())
    if request.plot:
        from ..report.plots import OverlayCurves, overlay

        w, c = report.waveforms, report.comparison
        curves = OverlayCurves(w.t, w.last, w.t, c.theory_last, residual=w.last - c.theory_last, first_sim=w.first,
                               first_theory=c.theory_first, arrivals=[a.to_dict() for a in c.arrivals],
                               time_unit=data["physical"]["time_unit_s"])
        outputs.write("--plot", lambda path: overlay(
            curves, title=f"{chain.name} chain, N = {chain.N}, dt = {report.options.dt:.4g}, {request.excitation}",
            ylabel=r"$I_1,\ I_N\;/\;I_1(0)$" if request.excitation == "kick" else r"$Q_1,\ Q_N\;/\;Q_1(0)$",
            path=path))
    if report.accuracy_met is False:
        steps = ", ".join(f"{h:.4g}" for h in data["extrapolation"]["dt"])
        outputs.notes.append(f"--accuracy {request.accuracy:g} was not met: the run reached "
                             f"{data['max_abs_error']:.3g} (dt = {steps}, predicted {data['predicted_error']:.3g})")
        return True
    return bool(outputs.failed)


def _compare_engines(request: SimulateRequest, chain: Chain, dt: float | None,
                     keep_netlist: Callable[[RunSpec], None]) -> EnginesComparison:
    from ..compare.metrics import residual_difference
    from ..runs.simulate import run_simulation, simulation_runs

    if request.extrapolate is not None and request.extrapolate > 1:
        raise ParameterError("--extrapolate", request.extrapolate, "1 with several engines (they run one netlist)")
    if request.plot or request.waveform_out:
        option, value = ("--plot", request.plot) if request.plot else ("--waveform-out", request.waveform_out)
        raise ParameterError(option, value, "one engine (--engine NAME)")
    if request.backend != BACKENDS[0]:  # the default transport, which every engine has
        raise ParameterError("--backend", request.backend, f"{BACKENDS[0]} with several engines")
    reports: list[SimulationReport] = []
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        for engine in request.engines:
            # the first engine's step (given, or chosen for --accuracy) is every engine's: one netlist
            step = dt if not reports else reports[0].options.dt
            made = _simulation_request(request, chain, dt=step, accuracy=request.accuracy if not reports else None,
                                       extrapolate=1, engine=engine, backend="batch")
            planned = simulation_runs(made, budget=request.budget)
            if not reports:  # one netlist: the first engine's
                keep_netlist(planned.specs[0])
            reports.append(run_simulation(planned, progress=_progress(request, engine)))
    first = reports[0]
    differences = {}
    for other in reports[1:]:
        pair = f"{first.run.engine} - {other.run.engine}"
        a, b = first.waveforms, other.waveforms
        differences[pair] = max(
            residual_difference(a.t, a.first - first.comparison.theory_first, b.t,
                                b.first - other.comparison.theory_first),
            residual_difference(a.t, a.last - first.comparison.theory_last, b.t,
                                b.last - other.comparison.theory_last))
    data = {"engines": [report.to_dict() for report in reports], "max_abs_difference": differences,
            "netlist_sha256": first.run.netlist_sha256}
    return EnginesComparison(chain, reports, data, differences, tuple(sorted({str(w.message) for w in caught})))
