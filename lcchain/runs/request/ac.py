"""The AC sweep's planner: one sweep per realised chain of an :class:`~lcchain.runs.request.types.AC` request, each
against its own driven modes (or, with effects that are no chain's, the circuit's own poles) on a grid placed from
them, priced before the samples are drawn (:func:`plan_ac`)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ...circuit.elements import Element, Pulse
from ...circuit.exact import circuit_cost, circuit_states
from ...circuit.ladder import Ladder
from ...circuit.netlist import ac_circuit_elements, ac_netlist_text, check_frequency_scale, probe_names
from ...compare.grid import Segment
from ...compare.poles import CIRCUIT_SPECTRUM_MAX_MODES, CircuitModes
from ...compare.spectral import SPECTRUM_MAX_N, check_lossy, spectrum_estimate, sweep_grid
from ...core.budget import RUN_START_SECONDS, Budget, Estimate, sample_theory_seconds
from ...core.errors import ParameterError
from ...spice.engines import ac_engine
from ...theory.chain import Chain
from ...theory.exact import driven_modes
from ...theory.modes import Modes
from ...theory.spectrum import normal_modes
from ..execute import circuit_modes
from ..spec import RunSpec, SpectrumTheory
from .types import AC, Request, RequestPlan, effect_named, netlist_title, nominal_ladder, realised_chains

__all__ = ["plan_ac"]

#: An AC sweep: its segments, its frequencies in all, its last angular frequency (:func:`sweep_grid`).
_Grid = tuple[list[Segment], int, float]


def _sample_grid(chain: Chain, request: Request, analysis: AC) -> tuple[Ladder, Modes, _Grid]:
    """A realised chain's circuit, its driven modes and its sweep (segments as fine as its own poles)."""
    driven = driven_modes(chain)
    return Ladder(chain, request.L0, request.C0), driven, sweep_grid(driven.omega, analysis.points)


def _check_ac_price(one: Estimate, request: Request, budget: Budget, N: int, frequencies: int,
                    design_seconds: float, extra: tuple[str, float, float] | None = None) -> None:
    """Check one AC run's estimate (the sweep and its fit, at the engine's relative cost, plus ``extra``: what,
    seconds, bytes of a circuit's own theory) and the request's samples of it against ``budget``, each refusal
    naming the option that shrinks it: the chain's and the circuit's planners price alike."""
    analysis = request.analysis
    assert isinstance(analysis, AC)
    samples = request.samples
    one = replace(one, seconds=one.seconds * ac_engine(request.engine).ac_relative_cost)
    if extra is not None:
        what, seconds, memory = extra
        one = Estimate(one.what + what, one.memory + memory, one.seconds + seconds)
    name, value = ("points", frequencies) if analysis.points is not None else ("N", N)
    one.check(budget, name, value, "fewer frequencies (--points) or a smaller chain")
    every = Estimate(f"{samples} runs of {one.what}", one.memory,
                     design_seconds + samples * (one.seconds + RUN_START_SECONDS + sample_theory_seconds(N)))
    every.check(budget, "effects.tolerance.samples" if samples > 1 else name, samples if samples > 1 else value,
                "fewer samples")


def plan_ac(request: Request, budget: Budget, modes: Modes | None, design_seconds: float) -> RequestPlan:
    """One AC sweep per realised chain, each against its own driven modes, on a grid placed from its own poles;
    priced (frequencies x unknowns, and the fit) on the nominal grid before the samples are drawn, and again on
    the largest sample's grid once their poles are known."""
    analysis = request.analysis
    assert isinstance(analysis, AC)  # its own plan method calls this
    nominal, ladder, circuit = nominal_ladder(request)
    N = nominal.N
    if N > SPECTRUM_MAX_N:
        raise ParameterError("N", N, f"N <= {SPECTRUM_MAX_N} for an AC analysis (exact modes of the chain, and the "
                             "fit's dense least squares)")
    if modes is not None and modes.N != N:
        raise ParameterError("modes", f"modes of N = {modes.N}", f"the modes of this chain (N = {N})")
    if circuit:
        return _plan_circuit_ac(request, budget, modes, design_seconds, nominal, ladder)
    theory = driven_modes(nominal)
    check_frequency_scale(nominal, float(np.max(theory.omega)), ladder.time_unit)
    if request.Q is not None:  # before the grid: its own refusals (points) would hide the cause
        check_lossy("effects.losses.Q", request.Q, theory)
    segments, points, omega_max = sweep_grid(theory.omega, analysis.points)

    def price(frequencies: int) -> None:
        one = spectrum_estimate(frequencies, N, losses=request.Q is not None)
        _check_ac_price(one, request, budget, N, frequencies, design_seconds)

    price(points)
    chains = realised_chains(request, nominal)
    drawn = [(ladder, theory, (segments, points, omega_max)) if chain is nominal else
             _sample_grid(chain, request, analysis) for chain in chains]  # a sample's sweep: from its own poles
    largest = max(grid[1] for _, _, grid in drawn)
    if largest > points:
        price(largest)
    sweeps = [(chain, sample, grid, SpectrumTheory(chain, ladder.time_unit, ladder.impedance, grid[2], modes=driven,
                                                   Q=request.Q))
              for chain, (sample, driven, grid) in zip(chains, drawn, strict=True)]
    return _ac_plan(request, nominal, modes, sweeps, (segments, points, omega_max))


def _ac_plan(request: Request, nominal: Chain, modes: Modes | None,
             sweeps: list[tuple[Chain, Ladder, _Grid, SpectrumTheory]], grid: _Grid, note: str = "") -> RequestPlan:
    """The plan of one AC sweep per realised chain: (chain, its ladder, its grid, its theory) each; ``grid`` is
    the nominal chain's, ``note`` ends each run's label."""
    N = nominal.N
    title = netlist_title(request, nominal, "AC")
    probes = tuple(probe_names(N, "ends"))
    specs = tuple(RunSpec(ac_netlist_text(sample, segments=own[0], title=title, effects=request.effects), probes, 0.0,
                          backend=request.backend, timeout=request.timeout, theory=spectrum, foreign=False,
                          label=f"{chain.name} N={N} AC {own[1]} frequencies{note}", engine=request.engine,
                          analysis="ac", points=own[1])
                  for chain, sample, own, spectrum in sweeps)
    modes = modes if modes is not None else normal_modes(nominal)
    return RequestPlan(request, nominal, tuple(chain for chain, *_ in sweeps), modes, modes.transit_time(), 0.0, (),
                       None, "", None, specs, grid[1], grid[2])


def _circuit_grid(chain: Chain, request: Request, analysis: AC, ladder: Ladder | None = None
                  ) -> tuple[Ladder, tuple[Element | Pulse, ...], CircuitModes, _Grid]:
    """A realised chain's circuit, its AC elements with the source's place, their exact modes and its sweep
    (segments as fine as the circuit's own poles, up to 5 % above the highest)."""
    sample = ladder if ladder is not None else Ladder(chain, request.L0, request.C0)
    elements = ac_circuit_elements(sample, request.effects)
    exact = circuit_modes(elements, chain.N, sample.time_unit, sample.impedance)
    if exact.N > CIRCUIT_SPECTRUM_MAX_MODES:
        raise ParameterError("N", chain.N, f"a circuit of at most {CIRCUIT_SPECTRUM_MAX_MODES} modes for an AC "
                             f"analysis with effects that are no chain's (this one has {exact.N}: its fit is dense)")
    if not np.any(exact.omega > 0):  # every pole real: a sweep placed by the resonances has none to place it
        named = effect_named(request, sample, lambda names: any(name.startswith("R") for name in names))
        raise ParameterError(*(named or ("effects", tuple(effect.key for effect in request.effects))),
                             "resistors that leave a mode ringing: with these every mode of the circuit is "
                             "overdamped (its poles are real), and an AC sweep has no resonance to find")
    # no range of decay rates is refused here: the fit tells apart modes whose resonances overlap (measured:
    # two-mass N = 20 with R = 0.01, two modes 0.018 apart whose decay rates add up to more, Q_n to 3e-13)
    try:
        grid = sweep_grid(exact.omega, analysis.points)
    except ParameterError as error:  # poles too far apart for a sweep: the parts' resonances (an ESL of 1e6 L0)
        named = effect_named(request, sample, lambda names: any(name[0] in "LC" for name in names))
        if error.field != "chain" or named is None:
            raise
        raise ParameterError(*named, error.allowed.replace("a chain whose", "a circuit whose", 1)) from None
    return sample, elements, exact, grid


def _plan_circuit_ac(request: Request, budget: Budget, modes: Modes | None, design_seconds: float, nominal: Chain,
                     ladder: Ladder) -> RequestPlan:
    """The AC sweeps of a circuit whose effects are no chain's: each realised chain's circuit against its own
    exact poles and residues (:class:`lcchain.compare.poles.CircuitModes`), on a grid placed from them, which
    covers every mode of the circuit (a coil's self-resonance, a capacitor's ESL resonance: as many as the
    circuit has, which may be more than N).  Priced as a chain's sweep of as many modes as the circuit has, plus
    the circuit's theory."""
    analysis = request.analysis
    assert isinstance(analysis, AC)
    N = nominal.N  # N and the modes checked by plan_ac
    _, elements, exact, (segments, points, omega_max) = _circuit_grid(nominal, request, analysis, ladder)
    check_frequency_scale(nominal, float(np.max(exact.omega)), ladder.time_unit)

    def price(frequencies: int, count: int) -> None:
        seconds, memory = circuit_cost(elements, 1)
        _check_ac_price(spectrum_estimate(frequencies, max(N, count), losses=exact.lossy, circuit=True), request,
                        budget, N, frequencies, design_seconds,
                        extra=(f" and the circuit's exact theory ({circuit_states(elements)} states)", seconds, memory))

    price(points, exact.N)
    chains = realised_chains(request, nominal)
    drawn = [(ladder, elements, exact, (segments, points, omega_max)) if chain is nominal else
             _circuit_grid(chain, request, analysis) for chain in chains]
    largest = max(grid[1] for *_, grid in drawn)
    if largest > points:
        price(largest, max(own.N for _, _, own, _ in drawn))
    # the circuit's theory carries its losses among its elements; the chain is the ideal ladder
    sweeps = [(chain, sample, grid, SpectrumTheory(chain, ladder.time_unit, ladder.impedance, grid[2], circuit=own))
              for chain, (sample, own, _, grid) in zip(chains, drawn, strict=True)]
    return _ac_plan(request, nominal, modes, sweeps, (segments, points, omega_max), " (circuit)")
