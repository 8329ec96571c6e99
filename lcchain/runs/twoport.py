"""The ladder as a two-port: its admittance and scattering matrices from two AC analyses, and from exact theory.

The ports
---------
Port 1 is the place of the AC source of :func:`lcchain.circuit.netlist.ac_netlist_text`: a break in loop 1 between
the first coil's free end ``s1`` and the rail (ground, or the wall's node); its voltage V_1 is the source's, its
current I_1 the current the source drives into ``s1``, ``-i(v1)``.  Port 2 is its mirror image in loop N: a break
between coil N's branch (``s<N>``) and the rail, closed by a 0 V ammeter ``VP2``, its current I_2 the current into
the circuit there, ``-i(vp2)`` (:func:`lcchain.circuit.netlist.port_elements`).  A port's current is its coil's
(``i(l1)``, ``-i(lN)``) only when nothing spans the coil: a coil's self-capacitance C_p carries omega^2 L C_p of it
more (at the band top 4 L/L0 % for C_p = 0.01 C0: 8 % at the end coil of a two-mass chain of N = 8).  Then
``I = Y V`` with::

    Y11 = I_1 / V_1, Y21 = I_2 / V_1   (V_2 = 0: port 2 shorted by its ammeter)
    Y22 = I_2 / V_2, Y12 = I_1 / V_2   (V_1 = 0: the mirrored chain, masses and springs reversed, driven in its
                                        loop 1, which is loop N: the same circuit seen from its other end)

so the engine runs the AC analysis twice, once per end, on the same frequencies (the netlists are lcchain's own,
never edited).  Reciprocity (Y12 = Y21) is a check, not an assumption.  The scattering matrix in a reference
impedance z0 on both ports is ``S = (1 - z0 Y)(1 + z0 Y)^-1``; a lossless ladder's is unitary.  The exact Y
(:func:`two_port_theory`) is the phasor solution of the very elements and sources the netlists are written from
(:func:`lcchain.circuit.phasor.source_currents`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..circuit.effects import Effect
from ..circuit.elements import adds_elements
from ..circuit.exact import CircuitTheory, circuit_cost, circuit_states, circuit_unknowns
from ..circuit.ladder import Ladder
from ..circuit.netlist import PORT_PROBES, ac_circuit_elements, ac_netlist_text, port_elements
from ..circuit.phasor import source_currents
from ..core.budget import RUN_START_SECONDS, SIMULATOR_BYTES, Estimate, ac_run_estimate
from ..core.checks import real
from ..core.errors import ParameterError, SimulationError
from ..core.limits import MAX_AC_POINTS, MIN_AC_POINTS
from ..theory.chain import Chain
from .execute import execute
from .request import AC, Request
from .spec import RunSpec

__all__ = ["TwoPort", "two_port", "two_port_theory", "two_port_estimate", "sweep_cost", "mirrored", "scattering",
           "DEFAULT_Z0", "DEFAULT_PORT_POINTS"]

#: Reference impedance of both ports, ohms, when none is given (Touchstone's default).
DEFAULT_Z0 = 50.0
#: Frequencies of the two-port's sweep when the request names none.
DEFAULT_PORT_POINTS = 401
#: The sweep's top, a margin above the circuit's highest normal frequency (as the spectrum's sweep).
_TOP_MARGIN = 1.05
#: The exact phasors' cost: seconds a frequency and end (one sparse LU of the nodal matrix), and more per unknown.
#: Measured (two-mass with a coil capacitance, 401 frequencies, both ends): 0.32 s at N = 100 (203 unknowns), 3.87 s
#: at N = 2000 (4003): 0.16 ms and 1.16 us; with a margin.
PHASOR_SECONDS_PER_SOLVE = 2e-4
PHASOR_SECONDS_PER_UNKNOWN = 1.5e-6
#: The sweep's poles of a lossless, uncoupled ladder (the tridiagonal eigenproblem, O(n^2)): seconds per state
#: squared (N = 2000, 3999 states, took 0.61 s: 3.8e-8 each; the dense bound of
#: :func:`lcchain.circuit.exact.circuit_cost` said 36 s).
TRIDIAGONAL_SECONDS_PER_STATE2 = 6e-8


def mirrored(chain: Chain) -> Chain:
    """The chain seen from its other end: masses and springs reversed (walls swap ends), coupling as it is."""
    return Chain(chain.masses[::-1], chain.springs[::-1], chain.name, chain.coupling)


def scattering(Y: np.ndarray, z0: float) -> np.ndarray:
    """S from Y (shape (..., 2, 2), siemens) in the reference impedance z0 (ohms) on both ports:
    (1 - z0 Y)(1 + z0 Y)^-1."""
    unit = np.eye(Y.shape[-1])
    return np.linalg.solve((unit + z0 * Y).swapaxes(-1, -2), (unit - z0 * Y).swapaxes(-1, -2)).swapaxes(-1, -2)


@dataclass(frozen=True, eq=False)
class TwoPort:
    """The ladder's two-port matrices at the sweep's frequencies.

    Attributes
    ----------
    frequency : ndarray
        Hz, ascending.
    Y : ndarray of complex, shape (points, 2, 2)
        Siemens, ports as the module docstring defines them.
    z0 : float
        Reference impedance, ohms.
    engine, engine_version : str
        What ran the two AC analyses ("theory" for :func:`two_port_theory`).
    reciprocity : float
        max |Y12 - Y21| / max |Y| (rounding of the two runs; 0 in theory).
    """

    frequency: np.ndarray
    Y: np.ndarray
    z0: float
    engine: str
    engine_version: str
    reciprocity: float

    @property
    def S(self) -> np.ndarray:
        """Scattering matrix, shape (points, 2, 2), in :attr:`z0`."""
        return scattering(self.Y, self.z0)


def _ladders(request: Request) -> tuple[Ladder, Ladder]:
    nominal = request.nominal()
    return Ladder(nominal, request.L0, request.C0), Ladder(mirrored(nominal), request.L0, request.C0)


def _sweep(ladder: Ladder, request: Request, points: int) -> tuple[float, float]:
    """(omega_min, omega_max) in units of 1/sqrt(L0 C0): up to 5 % above the circuit's highest normal frequency, its
    poles' oscillation as ``spectrum``'s sweep places it (a real pole, a coil's capacitor discharging through an
    ESR at omega 7e4, is no resonance: the sweep went to 35 GHz for a band ending at 1 MHz)."""
    theory = CircuitTheory(ac_circuit_elements(ladder, request.effects))
    poles, _, _ = theory.admittances(["i(l1)"])
    ringing = np.abs(poles.imag)
    top = _TOP_MARGIN * float(np.max(ringing if np.any(ringing > 0) else np.abs(poles))) * ladder.time_unit
    return top / points, top


def sweep_cost(ladder: Ladder, effects: tuple[Effect, ...]) -> tuple[float, float]:
    """(seconds, bytes) of the circuit theory that places the two-port's sweep (:func:`_sweep`): the bare ladder's
    poles are a tridiagonal problem; with any part (a coil's capacitance, a capacitor's ESL, lossless too) or a
    coupling the problem is dense (:func:`lcchain.circuit.exact.circuit_cost`)."""
    circuit = ac_circuit_elements(ladder, effects)
    seconds, memory = circuit_cost(circuit, 1)
    if not ladder.chain.coupled and not any(adds_elements(effect) for effect in effects):
        seconds = TRIDIAGONAL_SECONDS_PER_STATE2 * circuit_states(circuit) ** 2
    return seconds, memory


def two_port_estimate(request: Request) -> Estimate:
    """The price of :func:`two_port` and :func:`two_port_theory` together: the circuit's theory that places the
    sweep, two AC analyses of the ports' netlist (one per end) and the exact phasors at their frequencies."""
    points = (request.analysis.points if isinstance(request.analysis, AC) else None) or DEFAULT_PORT_POINTS
    ladder = _ladders(request)[0]
    elements, sources = port_elements(ladder, request.effects)
    unknowns = circuit_unknowns(elements) + len(sources)
    engine = ac_run_estimate(points=points, saved=len(sources), unknowns=unknowns)
    theory_seconds, theory_bytes = sweep_cost(ladder, request.effects)
    phasors = 2 * points * (PHASOR_SECONDS_PER_SOLVE + PHASOR_SECONDS_PER_UNKNOWN * unknowns)
    seconds = 2 * (engine.seconds + RUN_START_SECONDS) + theory_seconds + phasors
    memory = max(engine.memory + SIMULATOR_BYTES, theory_bytes, 16.0 * 64 * unknowns)
    return Estimate(f"a two-port: 2 x {points} frequencies x {unknowns} unknowns", memory, seconds)


def two_port(request: Request, z0: float = DEFAULT_Z0) -> TwoPort:
    """The ladder's Y (and S in ``z0``) from two AC analyses of the request's engine, one per end.

    Parameters
    ----------
    request : Request
        With ``analysis=AC(points)`` (points: evenly spaced frequencies, default :data:`DEFAULT_PORT_POINTS`); its
        chain, effects, L0 (H), C0 (F), engine and timeout (s).  Tolerance samples are refused: a two-port is one
        circuit.
    z0 : float
        Reference impedance of both ports, ohms (> 0).
    """
    z0 = real("z0", z0, above=0.0)
    if not isinstance(request.analysis, AC):
        raise ParameterError("analysis", type(request.analysis).__name__, "AC(...) for a two-port")
    if request.samples > 1:
        raise ParameterError("effects.tolerance.samples", request.samples, "1 for a two-port (one circuit)")
    request.analysis.check(request)
    points = request.analysis.points or DEFAULT_PORT_POINTS
    if not MIN_AC_POINTS <= points <= MAX_AC_POINTS:
        raise ParameterError("points", points, f"{MIN_AC_POINTS} to {MAX_AC_POINTS}")
    ladders = _ladders(request)
    omega_min, omega_max = _sweep(ladders[0], request, points)
    columns = []
    for ladder in ladders:
        text = ac_netlist_text(ladder, points=points, omega_max=omega_max, omega_min=omega_min,
                               title="lcchain LC ladder, two-port", effects=request.effects, ports=True)
        probes = PORT_PROBES
        spec = RunSpec(text, probes, 0.0, backend=request.backend, timeout=request.timeout, foreign=False,
                       label=f"two-port, N={ladder.chain.N}", engine=request.engine, analysis="ac", points=points)
        record = execute(spec)
        if not record.ok or record.run is None:
            raise SimulationError(record.reason, record.log_tail, record.status)
        columns.append((record.run, probes))
    (first, ends), (second, mirror_ends) = columns
    if not np.array_equal(first.frequency, second.frequency):  # the same cards: a difference is the engine's
        raise SimulationError("the two ends' AC analyses swept different frequencies", "", "failed")
    Y = np.empty((first.points, 2, 2), dtype=complex)  # each port's current into the circuit: minus its source's
    Y[:, 0, 0] = -first.vectors[ends[0]]
    Y[:, 1, 0] = -first.vectors[ends[1]]
    Y[:, 1, 1] = -second.vectors[mirror_ends[0]]
    Y[:, 0, 1] = -second.vectors[mirror_ends[1]]
    return TwoPort(np.asarray(first.frequency, dtype=float), Y, z0, first.engine, first.engine_version,
                   _reciprocity(Y))


def _reciprocity(Y: np.ndarray) -> float:
    scale = float(np.max(np.abs(Y))) or 1.0
    return float(np.max(np.abs(Y[:, 0, 1] - Y[:, 1, 0]))) / scale


def two_port_theory(request: Request, frequency: np.ndarray, z0: float = DEFAULT_Z0) -> TwoPort:
    """The same two-port, exact, at ``frequency`` (Hz): the phasor currents of the ports' sources
    (:func:`lcchain.circuit.phasor.source_currents`) in the very elements and sources the netlists are written
    from (:func:`lcchain.circuit.netlist.port_elements`), no simulator."""
    z0 = real("z0", z0, above=0.0)
    frequency = np.asarray(frequency, dtype=float)
    Y = np.empty((frequency.size, 2, 2), dtype=complex)
    for k, ladder in enumerate(_ladders(request)):
        elements, sources = port_elements(ladder, request.effects)
        currents = source_currents(elements, sources, frequency)
        Y[:, k, k] = -currents[0]
        Y[:, 1 - k, k] = -currents[1]
    return TwoPort(frequency, Y, z0, "theory", "", _reciprocity(Y))

