"""One unit of work, executed: a :class:`~lcchain.runs.spec.RunSpec` in, a :class:`RunRecord` out.

:func:`execute` is the only function in lcchain that runs a netlist and
compares it with theory; :func:`lcchain.simulate`, scenes, the accuracy bench
and studies all go through it.  It never raises for a run that went wrong in
ngspice: the record says ``"failed"`` or ``"timeout"`` with the reason and the
end of ngspice's output, so that one bad run cannot stop a study.  It raises
for what no run can fix: a missing simulator
(:class:`~lcchain.core.errors.SimulatorMissingError`), an unsafe netlist
(:class:`~lcchain.core.errors.ParameterError`), an interrupt.

The record's :attr:`RunRecord.digest` is the SHA-256 of the saved arrays
(time and every vector, by name, as little-endian float64; an AC run's
frequency and complex vectors, as little-endian complex128): the same on any
host, in any process, at any time, for the same ngspice.

How a spec runs depends on its analysis (:attr:`RunSpec.analysis`), through
one registry, :data:`ANALYSIS_RUNS`: a transient is compared with its
:class:`~lcchain.runs.spec.Theory`, an AC run's poles and residues with its
:class:`~lcchain.runs.spec.SpectrumTheory` (:func:`lcchain.compare.spectral.compare_spectrum`).
"""

from __future__ import annotations

import hashlib
import logging
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, TypeAlias

from ..core import __version__
from ..core.analyses import analysis_kind
from ..core.blas import fixed_blas_threads
from ..core.budget import ac_run_estimate
from ..core.checks import instance
from ..core.errors import ParameterError, SimulationError, show_value
from ..core.frozen import FrozenArrays, FrozenMap
from ..core.json import JSONDict
from ..core.show import Figure, html_table, plot, short_repr
from ..core.types import DEFAULT_ENGINE, GAUSSIAN_CENTRE, AnalysisKind, Probes, RunStatus
from ..spice.engines import engine_named, find_engine, run_engine
from ..spice.job import RunJob
from ..spice.measure import Measurements, measurement_fields
from ..spice.result import RunResult
from ..spice.simulator import Simulator
from .spec import RunSpec, SpectrumTheory, Theory

# A foreign netlist's run (lcchain batch) compares nothing with theory: the comparisons, the circuit's theory and
# the AC fit load in the functions that use them, so that a batch starts without them (issue 35).
if TYPE_CHECKING:
    import numpy as np
    import xarray as xr

    from ..circuit.elements import Element, Pulse
    from ..circuit.exact import CircuitTheory
    from ..compare.metrics import EffectCost, Metrics
    from ..compare.poles import CircuitModes
    from ..compare.spectral import SpectrumMetrics
    from ..compare.waveforms import Signals
    from ..theory.modes import Modes
    from ..theory.response import Response

__all__ = ["signals_of", "loop_sims", "theory_at", "metrics_of", "CircuitResponse", "LoopTheory", "effect_cost",
           "loop_theory", "RunRecord", "Analysed", "execute", "waveform_digest", "pulse_centre", "ANALYSIS_RUNS",
           "ac_metrics", "circuit_modes", "sweep_omega", "circuit_predicted_error"]

log = logging.getLogger("lcchain")


@dataclass(frozen=True, eq=False)
class RunRecord(FrozenArrays):
    """What one run produced, frozen and picklable.

    Attributes
    ----------
    key : str
        :meth:`RunSpec.key` for the engine version that ran it.
    status : {"ok", "failed", "timeout", "refused"}
    reason : str
        Why it failed ("" when ok): ngspice's own words where it said any.
    log_tail : str
        The useful end of ngspice's output when it failed.
    run : RunResult or None
        What the engine returned, whichever the analysis (``run.data``: a transient's
        :class:`~lcchain.spice.result.TransientData`, time in seconds and vectors in amperes or volts, or an AC
        run's :class:`~lcchain.spice.result.AcData`, frequencies in Hz and complex vectors), and its metadata.
        None when the run failed, and for a record read back from a store or an extrapolation's.
    signals : Signals or None
        The compared loops, dimensionless, beside the theory (runs with a theory).
    metrics : Metrics or None
        Max errors and arrivals (runs with a theory).
    digest : str
        SHA-256 of the saved arrays (:func:`waveform_digest`); "" when failed.
    wall_s : float
        Seconds in ngspice.
    total_s : float
        Seconds in :func:`execute`, the simulator included.
    engine_version, lcchain_version : str
        The versions of the engine that ran it and of lcchain.
    label : str
        The spec's label.
    engine : str
        The engine's name (:data:`lcchain.spice.engines.ENGINES`).
    spectrum : SpectrumMetrics or None
        An AC run's poles and weights beside its theory (AC runs with a theory; ``metrics`` is then None).
    """

    key: str
    status: RunStatus
    reason: str = ""
    log_tail: str = ""
    run: RunResult | None = None
    signals: Signals | None = None
    metrics: Metrics | None = None
    digest: str = ""
    wall_s: float = 0.0
    total_s: float = 0.0
    engine_version: str = ""
    lcchain_version: str = __version__
    label: str = ""
    engine: str = DEFAULT_ENGINE
    spectrum: SpectrumMetrics | None = None

    @property
    def analysis(self) -> AnalysisKind:
        """The analysis of the run (``"transient"``, ``"ac"``); without arrays, ``"ac"`` where it has a spectrum."""
        if self.run is not None:
            return self.run.analysis
        return "ac" if self.spectrum is not None else "transient"

    @property
    def measurements(self) -> Measurements:
        """The netlist's ``.meas`` results by name: (value, "") or (None, ngspice's reason); empty without any."""
        return self.run.measurements if self.run is not None else FrozenMap()

    @property
    def points(self) -> int | None:
        """Time points, or an AC run's frequencies (None without arrays)."""
        return self.run.points if self.run is not None else None

    @property
    def ok(self) -> bool:
        return self.status == "ok"

    @property
    def ngspice_version(self) -> str:
        """The default engine's (ngspice's) version when it ran this, else "" (records made before engines had
        only this field)."""
        return self.engine_version if self.engine == DEFAULT_ENGINE else ""

    def summary(self) -> JSONDict:
        """Everything but the arrays, as JSON-serialisable data."""
        data: JSONDict = {
            "key": self.key, "label": self.label, "status": self.status, "reason": self.reason,
            "digest": self.digest, "wall_s": self.wall_s, "total_s": self.total_s,
            "engine": self.engine, "engine_version": self.engine_version,
            "ngspice_version": self.ngspice_version, "lcchain_version": self.lcchain_version,
        }
        if self.status != "ok":
            data["log_tail"] = self.log_tail
        if self.run is not None:
            data["points"] = self.run.points
            data["netlist_sha256"] = self.run.netlist_sha256
        for metrics in (self.metrics, self.spectrum):
            if metrics is not None:
                data.update(metrics.to_dict())
        if self.measurements:
            data.update(measurement_fields(self.measurements))
        return data

    def _rows(self) -> list[tuple[str, object]]:
        rows: list[tuple[str, object]] = [
            ("run", f"{self.label or self.analysis} ({self.key[:12]})"),
            ("engine", f"{self.engine} {self.engine_version}".strip()),
            ("status", self.status if self.ok else f"{self.status}: {self.reason[:120]}")]
        if self.points is not None:
            rows.append((analysis_kind(self.analysis).count, self.points))
        rows.append(("simulator wall time (s)", self.wall_s))
        if self.metrics is not None:
            rows.append(("max |simulation - theory|", self.metrics.max_abs_error))
            if self.metrics.predicted_error is not None:
                rows.append(("predicted error", self.metrics.predicted_error))
        if self.spectrum is not None:
            rows.append(("max rel. error of omega_n", self.spectrum.max_rel_error_omega))
        if self.measurements:
            rows.append(("measurements", ", ".join(list(self.measurements)[:6])
                         + (" ..." if len(self.measurements) > 6 else "")))
        return rows

    def __repr__(self) -> str:
        """A few lines (the arrays: ``run``, ``signals``; all of it: :meth:`summary`)."""
        return short_repr("RunRecord", self._rows())

    def _repr_html_(self) -> str:
        return html_table("RunRecord", self._rows())

    def plot(self, ax: object = None) -> Figure:
        """The run's figure: its compared loops over theory (the far end; residual below) where it had a theory,
        else its saved vectors against time (or their magnitudes against frequency).

        Returns
        -------
        matplotlib.figure.Figure
            Never shown.  matplotlib is imported here, not by ``import lcchain``.
        """
        return plot("record", self, ax=ax)

    def to_xarray(self) -> xr.Dataset:
        """The saved vectors as an xarray Dataset on ``time`` (s) or ``frequency`` (Hz), each with its ``units``
        (an AC phasor as ``*_real`` and ``*_imag``), the compared loops beside theory (``loop_signal``,
        ``loop_theory``, dimensionless, and ``t``) where the run had a theory, :meth:`summary` as attributes.
        xarray is optional: ``pip install 'lcchain[data]'``."""
        from .datasets import record_dataset

        return record_dataset(self.run, self.signals, self.summary())


def waveform_digest(time_s: np.ndarray, vectors: Mapping[str, np.ndarray], axis: str = "time") -> str:
    """SHA-256 of a run's saved arrays: the axis (``"time"``, or an AC run's ``"frequency"``), then every vector
    by sorted name, little-endian float64 (complex128 for a complex array)."""
    import numpy as np
    digest = hashlib.sha256()
    for name, values in [(axis, time_s), *sorted(vectors.items())]:
        digest.update(name.encode("utf-8") + b"\0")
        dtype = "<c16" if np.iscomplexobj(values) else "<f8"
        digest.update(np.ascontiguousarray(values, dtype=dtype).tobytes())
    return digest.hexdigest()


def pulse_centre(excitation: str, pulse: tuple[str, float] | None) -> float:
    """When a pulse delivers its kick: the gaussian's centre, or the rect's middle (units of sqrt(L0 C0))."""
    if excitation != "pulse" or pulse is None:
        return 0.0
    shape, width = pulse
    return GAUSSIAN_CENTRE * width if shape == "gaussian" else width / 2


def loop_sims(theory: Theory, time_s: np.ndarray, vectors: Mapping[str, np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """A run's saved loops as dimensionless times and signals (no theory): (t, sim), one row per loop."""
    import numpy as np

    from ..circuit.netlist import probe_names
    from ..compare.waveforms import loop_signals

    loops = probe_names(theory.chain.N, theory.probes)
    currents = np.array([vectors[name] for name in loops])
    return loop_signals(time_s, currents, time_unit=theory.time_unit, excitation=theory.excitation, I0=theory.I0)


def theory_at(theory: Theory, t: np.ndarray, modes: Modes | None = None) -> np.ndarray:
    """The theory of the compared loops at dimensionless times t, one row per loop."""
    return _response(theory, theory.probes, modes if modes is not None else _modes(theory))(t)


def signals_of(theory: Theory, result: RunResult, modes: Modes | None = None, *,
               response: LoopTheory | None = None) -> Signals:
    """A run's saved loops as dimensionless signals, with the theory of the same loops at the same times.

    ``response``: the theory of the compared loops already prepared (:func:`_response`), else prepared here."""
    from ..compare.waveforms import Signals

    t, sim = loop_sims(theory, result.time, result.vectors)
    if response is None:
        return Signals(t, sim, theory_at(theory, t, modes), theory.excitation)
    return Signals(t, sim, response(t), theory.excitation)


def _modes(theory: Theory) -> Modes:
    from ..theory.spectrum import normal_modes

    return theory.modes if theory.modes is not None else normal_modes(theory.chain)


class CircuitResponse:
    """The circuit's own exact theory of some loops, called with dimensionless times as a chain's
    :class:`~lcchain.theory.response.Response` is: I/I0 after a kick or a pulse, Q/Q0 after a displacement.

    Parameters
    ----------
    theory : Theory
        With its ``circuit``.
    loops : {"ends", "all"}
    exact : CircuitTheory, optional
        The circuit's theory when already built (its eigen-solution is most of the cost).
    """

    def __init__(self, theory: Theory, loops: Probes, exact: CircuitTheory | None = None):
        from ..circuit.exact import circuit_theory
        from ..circuit.netlist import probe_names

        assert theory.circuit is not None
        self.exact = exact if exact is not None else circuit_theory(theory.circuit)
        self.names = probe_names(theory.chain.N, loops)
        self.unit, self.excitation = theory.time_unit, theory.excitation
        self.scale = theory.I0 * (theory.time_unit if theory.excitation == "displacement" else 1.0)

    def __call__(self, t: np.ndarray) -> np.ndarray:
        import numpy as np
        times = np.asarray(t, dtype=float) * self.unit
        if self.excitation == "displacement":  # the loop charges: loop 1 starts with Q0
            start = [self.scale if k == 0 else 0.0 for k in range(len(self.names))]
            return self.exact.charges(times, self.names, start) / self.scale
        return self.exact.currents(times, self.names) / self.scale

    def predicted_error(self, dt: float, tstop: float, method: str) -> float | None:
        """The accuracy model's prediction for a fixed step, from the circuit's own modes (None with a pulse)."""
        return circuit_predicted_error(self.exact, self.names, self.unit, self.scale, self.excitation, dt, tstop,
                                       method)


def circuit_predicted_error(exact: CircuitTheory, names: Sequence[str], unit: float, scale: float, excitation: str,
                            dt: float, tstop: float, method: str) -> float | None:
    """The accuracy model's prediction of a fixed-step run of a circuit (dimensionless ``dt`` and ``tstop``, times
    ``unit`` seconds; loops ``names`` of ``scale`` amperes or, displaced, coulombs), from its own modes: the planner's
    (a step for an accuracy) and the comparison's alike (None with a pulse)."""
    from ..compare.accuracy import predicted_error, predicted_error_damped

    charges = excitation == "displacement"
    damped = exact.damped_weights(names, charges=charges)
    if damped is not None:
        poles, rows = damped
        return predicted_error_damped(poles * unit, list(rows / scale), dt, tstop, method=method)
    modal = exact.cosine_weights(names, charges=charges)
    if modal is None:
        return None
    omega, weights = modal
    from ..theory.modes import Modes

    modes = Modes(omega * unit, weights[0], weights[-1], "circuit")
    return predicted_error(modes, dt, tstop, method=method, weights=list(weights / scale))


#: The theory of some loops, callable with dimensionless times: the chain's or the circuit's.
LoopTheory: TypeAlias = "Response | CircuitResponse"


def _response(theory: Theory, probes: Probes, modes: Modes, exact: CircuitTheory | None = None) -> LoopTheory:
    """The theory of the loops ``probes``, prepared once for the grid and the peak search's ~75 calls: the
    circuit's own (:class:`CircuitResponse`) when the spec carries its elements, else the chain's."""
    from ..theory.response import prepare_response

    if theory.circuit is not None:
        return CircuitResponse(theory, probes, exact)
    return prepare_response(theory.chain, excitation=theory.excitation, Q=theory.Q, pulse=theory.pulse,
                            loops=probes, modes=modes)


def loop_theory(theory: Theory, loops: Probes = "ends") -> LoopTheory:
    """The exact theory of a run's loops, callable with dimensionless times: the circuit's own when the theory
    carries its elements, else the chain's."""
    return _response(theory, loops, _modes(theory))


def effect_cost(theory: Theory, circuit: LoopTheory, modes: Modes) -> EffectCost:
    """The first arrival at loop N in the circuit's exact response (``circuit``: its end loops) against the ideal
    chain's alpha_N(t) (``theory.chain`` without losses)."""
    import numpy as np

    from ..compare.metrics import EffectCost
    from ..theory.arrivals import arrival_window, maximum_in_window
    from ..theory.response import prepare_response

    ideal = prepare_response(theory.chain, excitation=theory.excitation, pulse=theory.pulse, loops="ends",
                             modes=modes)
    transit = theory.transit_time or modes.transit_time()
    window = tuple(edge + pulse_centre(theory.excitation, theory.pulse) for edge in arrival_window(1, transit))
    def last(theory_of: LoopTheory) -> Callable[[np.ndarray], np.ndarray]:
        return lambda times: theory_of(np.asarray(times))[-1]

    (t_circuit, peak_circuit), (t_ideal, peak_ideal) = (
        maximum_in_window(last(f), (window[0], window[1]), transit) for f in (circuit, ideal))
    energy = None
    if theory.excitation != "displacement":
        ratio = float(theory.chain.masses[-1] / theory.chain.masses[0])
        energy = (peak_circuit ** 2 * ratio, peak_ideal ** 2 * ratio)
    return EffectCost(float(t_circuit), float(t_ideal), float(peak_circuit), float(peak_ideal),
                      *(energy or (None, None)))


@fixed_blas_threads
def metrics_of(theory: Theory, signals: Signals, *, split: bool = True, modes: Modes | None = None,
               ends: LoopTheory | None = None) -> Metrics:
    """Errors and arrivals of signals against the theory (and, for a fixed-step lossless kick or displacement
    with ``split``, the error split of :func:`lcchain.compare.accuracy.split_error`).

    With the circuit's own theory (``theory.circuit``): the errors are against it, the prediction from its own
    modes, and :attr:`lcchain.compare.metrics.Metrics.effects` what its effects cost the pulse against the
    ideal chain (no error split: it models the chain's modes).

    ``ends``: the theory of loops 1 and N already prepared (:func:`_response`), else prepared here."""
    from ..compare.accuracy import split_error
    from ..compare.metrics import Metrics, compare_signals
    from ..theory.response import Response

    chain = theory.chain
    modes = modes if modes is not None else _modes(theory)
    theory_ends = ends if ends is not None else _response(theory, "ends", modes)
    each = theory_ends.each if isinstance(theory_ends, Response) else None
    metrics = compare_signals(
        signals, transit_time=theory.transit_time or modes.transit_time(), transits=theory.transits,
        shift=pulse_centre(theory.excitation, theory.pulse),
        theory_end=lambda row, times: theory_ends(times)[row],
        theory_each=None if each is None else (lambda row, times: each(times)[row]))
    integration = physics = effects = None
    predicted = theory.predicted_error
    if isinstance(theory_ends, CircuitResponse):
        effects = effect_cost(theory, theory_ends, modes)
        if predicted is None and theory.dt is not None and not theory.aligned:
            predicted = theory_ends.predicted_error(theory.dt, float(signals.t[-1]), theory.method)
    elif split and theory.dt is not None and theory.Q is None and theory.pulse is None:
        parts = split_error(signals.waveforms(), modes, theory.dt, method=theory.method,
                            exact=(signals.theory[0], signals.theory[-1]), breakpoint=not theory.aligned)
        integration, physics = parts.integration_error, parts.physics_error
    arrivals = metrics.arrivals
    if theory.excitation == "kick":  # the kick's energy is m_1 I0^2 / 2: the end holds m_end (peak I0)^2 / 2
        arrivals = tuple(replace(a, energy_sim=a.peak_sim**2 * float(chain.masses[-1 if a.end == "last" else 0]
                                                                      / chain.masses[0])) for a in arrivals)
    return Metrics(metrics.max_abs_error, metrics.max_abs_error_first, metrics.max_abs_error_last,
                   arrivals, predicted, integration, physics, effects)


@fixed_blas_threads
def _compare(theory: Theory, result: RunResult) -> tuple[Signals, Metrics]:
    from ..circuit.exact import circuit_theory

    modes = _modes(theory)
    exact = circuit_theory(theory.circuit) if theory.circuit is not None else None
    ends = _response(theory, "ends", modes, exact)
    every = ends if theory.probes == "ends" else _response(theory, theory.probes, modes, exact)
    signals = signals_of(theory, result, modes, response=every)
    # The error split models ngspice's own steps (its start-up ramp); an engine that steps otherwise gets none.
    return signals, metrics_of(theory, signals, split=engine_named(result.engine).steps_modelled, modes=modes,
                               ends=ends)


@dataclass(frozen=True, eq=False)
class Analysed:
    """What one analysis gives :func:`execute` for a run that went through its engine: the engine's run, the
    digest of its arrays (:func:`waveform_digest`), and its comparison with theory where the spec had one (a
    transient's ``signals`` and ``metrics``, an AC run's ``spectrum``)."""

    run: RunResult
    digest: str
    signals: Signals | None = None
    metrics: Metrics | None = None
    spectrum: SpectrumMetrics | None = None


def _run_transient(spec: RunSpec, simulator: Simulator, progress: Callable[[float], None] | None) -> Analysed:
    """A transient run in its engine, compared with its :class:`Theory`."""
    job = RunJob(spec.netlist, spec.vectors, spec.tstop, timeout=spec.timeout, cwd=spec.cwd, trusted=spec.trusted,
                 foreign=spec.foreign, max_output_bytes=spec.max_output_bytes,
                 max_resident_bytes=spec.max_resident_bytes)
    result = run_engine(job, simulator, progress)
    if spec.check:
        from .check import reference_measurements

        result = replace(result, measurements=FrozenMap({**result.measurements, **reference_measurements(
            spec.netlist, result.time, result.vectors, simulator.version, trusted=spec.trusted, cwd=spec.cwd)}))
    signals = metrics = None
    if isinstance(spec.theory, Theory):
        try:
            signals, metrics = _compare(spec.theory, result)
        except ParameterError as error:  # a sample's circuit whose exact theory float64 cannot give: this run's
            if spec.theory.circuit is None:  # result, not a traceback (the nominal one is refused when planned)
                raise
            raise SimulationError(f"the circuit's exact theory: {error}", engine=spec.engine) from None
    return Analysed(result, waveform_digest(result.time, result.vectors), signals=signals, metrics=metrics)


@fixed_blas_threads
def circuit_modes(elements: tuple[Element | Pulse, ...], N: int, time_unit: float, impedance: float) -> CircuitModes:
    """The exact modes of an AC run's circuit (its elements with the source's place,
    :func:`lcchain.circuit.netlist.ac_circuit_elements`): the poles and residues of its I_1/V and I_N/V
    (:meth:`lcchain.circuit.exact.CircuitTheory.admittances`), dimensionless (``time_unit`` s, ``impedance`` ohm)."""
    from ..circuit.exact import circuit_theory
    from ..compare.poles import CircuitModes

    exact = circuit_theory(elements)  # the planner's, when it ran in this process
    poles, residues, _ = exact.admittances(["L1", f"L{N}"])
    return CircuitModes.from_poles(poles, residues, time_unit, impedance, lossy=not exact.lossless)


@fixed_blas_threads
def circuit_admittance(elements: tuple[Element | Pulse, ...], omega: np.ndarray, time_unit: float,
                       impedance: float) -> np.ndarray:
    """The exact I_1/V of an AC run's circuit times ``impedance`` (sqrt(L0/C0), ohm) at ``omega`` (units of
    1/``time_unit``): the very poles and residues its modes are compared with (:func:`circuit_modes`), summed."""
    import numpy as np

    from ..circuit.exact import circuit_theory

    poles, residues, direct = circuit_theory(elements).admittances(["L1"])
    s = 1j * np.asarray(omega, dtype=float)[:, None]
    terms = residues[0] * time_unit / (s - poles * time_unit)
    return np.asarray((direct[0] + np.sum(terms, axis=1)) * impedance)


@fixed_blas_threads
def sweep_omega(theory: SpectrumTheory, result: RunResult) -> np.ndarray:
    """An AC run's angular frequencies in its chain's units, 1/sqrt(L0 C0): what its modes are compared on."""
    import numpy as np

    return np.asarray(2.0 * np.pi * result.frequency * theory.time_unit)


def ac_metrics(theory: SpectrumTheory, result: RunResult) -> SpectrumMetrics:
    """An AC run's I_1/V_1 and I_N/V_1 against the driven modes of its chain, or the circuit's own poles and
    residues when its theory carries its elements."""
    from ..circuit.netlist import probe_names
    from ..compare.poles import compare_poles
    from ..compare.spectral import compare_spectrum
    from ..theory.exact import driven_modes

    chain = theory.chain
    omega = sweep_omega(theory, result)
    first, last = (result.vectors[name] * theory.impedance for name in probe_names(chain.N, "ends"))
    if theory.circuit is not None:
        exact = circuit_modes(theory.circuit, chain.N, theory.time_unit, theory.impedance)
        # with resistors, the response their merged modes make together is compared over the sweep
        y11 = circuit_admittance(theory.circuit, omega, theory.time_unit, theory.impedance) if exact.lossy else None
        return compare_poles(exact, omega, first, last, float(chain.masses[0]), y11)
    modes = theory.modes if theory.modes is not None else driven_modes(chain)
    return compare_spectrum(modes, omega, first, last, float(chain.masses[0]), theory.Q, chain=chain)


def _run_ac(spec: RunSpec, simulator: Simulator, progress: Callable[[float], None] | None) -> Analysed:
    """An AC run (:func:`lcchain.spice.ac.run_ac`), its poles and weights against its :class:`SpectrumTheory`.
    ``progress`` hears 0 at the start, the engine's share of the priced work when the engine is done, and 1."""
    import numpy as np

    from ..compare.spectral import spectrum_estimate
    from ..spice.ac import AcJob, run_ac

    assert spec.points is not None  # the spec requires it for an AC run
    if progress is not None:
        progress(0.0)
    result = run_ac(AcJob(spec.netlist, spec.vectors, spec.points, timeout=spec.timeout, foreign=spec.foreign,
                          max_output_bytes=spec.max_output_bytes, max_resident_bytes=spec.max_resident_bytes),
                    simulator)
    if spec.check:
        from .check import reference_measurements

        result = replace(result, measurements=FrozenMap({**result.measurements, **reference_measurements(
            spec.netlist, result.frequency, result.vectors, simulator.version)}))
    spectrum = None
    if isinstance(spec.theory, SpectrumTheory):
        if progress is not None:  # the fit follows: most of the work beyond a few hundred modes
            N, lossy = spec.theory.chain.N, spec.theory.Q is not None or spec.theory.circuit is not None
            engine = ac_run_estimate(points=spec.points, saved=2, unknowns=(3 if lossy else 2) * N).seconds
            progress(engine / spectrum_estimate(spec.points, N, losses=lossy).seconds)
        try:
            spectrum = ac_metrics(spec.theory, result)
        except (ValueError, IndexError, ArithmeticError, np.linalg.LinAlgError) as error:
            # samples the fit cannot read as a ladder's (ParameterError is a ValueError): the comparison failed,
            # which is this run's result (exit 1), not a traceback
            if isinstance(error, ParameterError):  # the fit's own words: what it expected, what it found
                reason = f"expected {error.allowed}, found {error.field} {show_value(error.value)}"
            else:
                reason = str(error).splitlines()[0] if str(error) else type(error).__name__
            raise SimulationError(f"the modes could not be fitted to the {spec.engine} AC samples: {reason}",
                                  engine=spec.engine) from None
    if progress is not None:
        progress(1.0)
    return Analysed(result, waveform_digest(result.frequency, result.vectors, "frequency"), spectrum=spectrum)


#: How a spec of each analysis runs and is compared: ``(spec, simulator, progress) -> Analysed``.  A new analysis
#: adds its line here.
ANALYSIS_RUNS: dict[AnalysisKind, Callable[[RunSpec, Simulator, Callable[[float], None] | None], Analysed]] = {
    "transient": _run_transient,
    "ac": _run_ac,
}


def execute(spec: RunSpec, simulator: Simulator | None = None, *,
            progress: Callable[[float], None] | None = None) -> RunRecord:
    """Run one spec in its engine and compare it with its theory.

    Parameters
    ----------
    spec : RunSpec
        A transient or an AC run (:data:`ANALYSIS_RUNS`).
    simulator : Simulator, optional
        Found once by the caller (:func:`lcchain.spice.engines.find_engine`)
        and passed to every run; found here for ``spec.engine`` and
        ``spec.backend`` when omitted. Its engine must be the spec's.
    progress : callable, optional
        Called with the fraction of the analysis the simulator has done (0 to 1).

    Returns
    -------
    RunRecord
        ``"ok"``, or ``"failed"``/``"timeout"`` with the reason.

    Raises
    ------
    SimulatorMissingError
        The engine is not installed.
    ParameterError
        ``spec`` is not a RunSpec, its netlist holds a line lcchain does not run, or the simulator is
        another engine's.
    """
    instance("spec", spec, RunSpec)
    instance("simulator", simulator, Simulator, optional=True)
    start = time.perf_counter()
    simulator = simulator if simulator is not None else find_engine(spec.engine, spec.backend)
    if simulator.engine != spec.engine:
        raise ParameterError("simulator", simulator.engine, f"a simulator of the spec's engine, {spec.engine!r}")
    key = spec.key(simulator.version)
    try:
        done = ANALYSIS_RUNS[spec.analysis](spec, simulator, progress)
    except SimulationError as error:
        log.info("%s: %s (%s)", spec.label or key[:12], error.status, error.reason)
        spent = time.perf_counter() - start  # the simulator's share is not told apart: its wall time is all of it
        return RunRecord(key=key, status="timeout" if error.status == "timeout" else "failed", reason=error.reason,
                         log_tail=error.log_tail, wall_s=spent, total_s=spent, engine=spec.engine,
                         engine_version=simulator.version, label=spec.label)
    total, wall = time.perf_counter() - start, done.run.wall_s
    log.info("%s: ok, %d points, %s %.3f s, lcchain %.3f s", spec.label or key[:12], done.run.points, spec.engine,
             wall, total - wall)
    return RunRecord(key=key, status="ok", run=done.run, signals=done.signals, metrics=done.metrics,
                     digest=done.digest, wall_s=wall, total_s=total, engine=spec.engine,
                     engine_version=simulator.version, label=spec.label, spectrum=done.spectrum)
