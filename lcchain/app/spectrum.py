"""``lcchain spectrum`` as functions: the ladder's normal frequencies and mode weights from an AC analysis,
beside theory (:func:`spectrum`); then its figure and, with ``touchstone``, the ladder as a two-port
(:func:`write_outputs`)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING

from ..circuit.effects import Effect
from ..core import __version__
from ..core.budget import Budget
from ..core.errors import ParameterError
from ..core.json import LooseJSONObject
from ..report.files import FIGURE_FORMATS
from .inputs import ChainOptions, Outputs, make_chain
from .simulate import with_physical_units

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import NDArray

    from ..runs.request import Request
    from ..runs.spectrum import SpectrumReport
    from ..runs.survey import ModeReport as ModeReport  # named for the command line, which prints it
    from ..theory.chain import Chain

__all__ = ["SpectrumRequest", "Spectrum", "TwoPortSummary", "spectrum", "write_outputs"]


@dataclass(frozen=True)
class SpectrumRequest:
    """The chain and its units, the engine, the AC sweep's ``points`` (None: twice the fewest that separate
    every pole), the chain's losses ``Q`` and the other effects (losses among them are refused), the figure
    ``plot``, the two-port file ``touchstone`` and its reference impedance ``z0`` (ohms), ``shapes`` every mode
    with its shape from a second AC run that drives every loop; ``progress(label)`` gives a callback of the
    fraction done."""

    chain: ChainOptions
    L0: float
    C0: float
    engine: str = "ngspice"
    points: int | None = None
    Q: float | None = None
    effects: tuple[Effect, ...] = ()
    plot: str | None = None
    touchstone: str | None = None
    z0: float | None = None
    shapes: bool = False
    budget: Budget = field(default_factory=Budget)
    progress: Callable[[str], Callable[[float], None]] | None = None


@dataclass(frozen=True)
class Spectrum:
    """The chain, the spectrum's report (:class:`lcchain.runs.spectrum.SpectrumReport`), its JSON with SI units,
    the effects compared, the outputs still to write, and the modes the losses merged, as a line says them."""

    request: SpectrumRequest
    chain: Chain
    report: SpectrumReport
    data: LooseJSONObject
    effects: tuple[Effect, ...]
    outputs: Outputs
    merged: str = ""


@dataclass(frozen=True)
class TwoPortSummary:
    """``--touchstone``: the frequencies (Hz), the reference impedance, the largest |S - exact| and the
    reciprocity |Y12 - Y21| / max |Y|."""

    frequency: NDArray[np.float64]
    z0: float
    error: float
    reciprocity: float


def spectrum(request: SpectrumRequest) -> Spectrum:
    """Check the outputs, build the chain, run the AC analysis and compare it with theory."""
    from ..runs.spectrum import SpectrumOptions, measure_spectrum, merged_text

    outputs = Outputs(inputs={"--chain": request.chain.chain} if request.chain.chain else {})
    outputs.check("--plot", request.plot, FIGURE_FORMATS)
    outputs.check("--touchstone", request.touchstone, ("s2p",))
    if request.z0 is not None and not request.touchstone:
        raise ParameterError("--z0", request.z0, "only with --touchstone FILE (the two-port's reference impedance)")
    if request.z0 is not None and not request.z0 > 0:
        raise ParameterError("--z0", request.z0, "a reference impedance > 0 ohms")
    chain = make_chain(request.chain, request.budget)
    # effects that are no chain's are compared with the circuit's own poles and residues (the chain's losses are
    # Q, measure_spectrum's own, refused under its name there)
    effects = request.effects
    progress = None if request.progress is None else request.progress(f"{request.engine} AC analysis, then the fit")
    options = SpectrumOptions(Q=request.Q, points=request.points, L0=request.L0, C0=request.C0,
                              engine=request.engine, effects=effects, shapes=request.shapes)
    budget = request.budget
    if request.touchstone:  # priced before anything runs; the spectrum has what is left of --max-time
        from ..runs.twoport import two_port_estimate

        ports = two_port_estimate(_two_port_request(request, chain, effects))
        ports.check(budget, "--touchstone", request.touchstone, "fewer --points or a smaller chain")
        budget = replace(budget, max_seconds=max(budget.max_seconds - ports.seconds, 1e-3))
    report = measure_spectrum(chain, options, budget=budget, progress=progress)
    data = with_physical_units(report.to_dict(), request.L0, request.C0, chain.coupling)
    merged = merged_text(report.merged_modes) if data["merged"] else ""
    return Spectrum(request, chain, report, data, effects, outputs, merged)


def write_outputs(result: Spectrum) -> TwoPortSummary | None:
    """Draw ``plot`` and write ``touchstone`` (after the spectrum was shown); the two-port's summary when one was
    made.  A file that cannot be written is said in a note of ``result.outputs`` and leaves its ``failed`` set."""
    request, chain, report, data = result.request, result.chain, result.report, result.data
    if request.plot:
        from ..report.plots import spectrum as spectrum_figure

        result.outputs.write("--plot", lambda path: spectrum_figure(
            report.theory.omega, report.P_theory, report.omega, report.P,
            title=f"{chain.name} chain, N = {chain.N}: {report.engine} AC against theory", path=path,
            frequency_unit=data["physical"]["frequency_unit_Hz"]))
    if request.touchstone:
        return _write_touchstone(request, chain, result.effects, result.outputs)
    return None


def _two_port_request(request: SpectrumRequest, chain: Chain, effects: tuple[Effect, ...]) -> Request:
    """The two-port's request: the spectrum's chain, effects (with its Q as losses), units and engine."""
    from ..circuit.effects import Losses
    from ..runs.request import AC, Request

    losses = (Losses(request.Q),) if request.Q is not None else ()
    return Request(chain, AC(request.points), effects=effects + losses, L0=request.L0, C0=request.C0,
                   engine=request.engine)


def _write_touchstone(request: SpectrumRequest, chain: Chain, effects: tuple[Effect, ...],
                      outputs: Outputs) -> TwoPortSummary:
    """``spectrum --touchstone FILE.s2p``: the ladder's two-port from two AC analyses (one per end), checked
    against the circuit's exact phasors (:mod:`lcchain.runs.twoport`), as Touchstone v1."""
    import numpy as np

    from ..circuit.effects import effect_fields
    from ..report.touchstone import touchstone_text
    from ..runs.twoport import DEFAULT_Z0, two_port, two_port_theory

    z0 = DEFAULT_Z0 if request.z0 is None else request.z0
    made = _two_port_request(request, chain, effects)
    measured = two_port(made, z0)
    exact = two_port_theory(made, measured.frequency, z0)
    error = float(np.max(np.abs(measured.S - exact.S)))
    written = ", ".join(f"{effect.key} " + " ".join(f"{field.name}={getattr(effect, field.name)!r}"
                                                    for field in effect_fields(type(effect)))
                        for effect in made.effects) or "none (the ideal ladder)"
    # "Port[n] = ..." is how a Touchstone reader (scikit-rf) names a port: a "port n:" comment it drops
    comments = [f"lcchain {__version__}: {chain.name} chain, N = {chain.N}, L0 = {request.L0:g} H, "
                f"C0 = {request.C0:g} F, {measured.engine} {measured.engine_version} AC analyses",
                f"effects: {written}",
                "Port[1] = a break in loop 1 (the AC source's place, between coil 1's branch and the rail); the "
                "current the source drives into it (-i(v1) in the netlist)",
                "Port[2] = its mirror image in loop N; the current into coil N's branch from that end (-i(vp2), "
                "a 0 V ammeter in the netlist)",
                f"max |S - S of the circuit's exact phasors| = {error:.3e}"]
    outputs.text("--touchstone", touchstone_text(measured.frequency, measured.S, z0, comments))
    return TwoPortSummary(measured.frequency, z0, error, measured.reciprocity)
