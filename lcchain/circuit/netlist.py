"""The LC ladder equivalent to a chain, as SPICE netlist text (pure).

Mapping (last section of the paper, Fig. LCcircuit): mass m_i -> inductor
L_i = m_i L0, spring K_{i,i+1} -> capacitor C_{i,i+1} = C0 / K_{i,i+1}; the
loop charges Q_i play the coordinates and the loop currents I_i the
velocities; the time unit is sqrt(L0 C0).

Topology: nodes n0..nN along the top rail, ground below.  L_i joins
n(i-1) to n(i); the spring between masses i and i+1 is a capacitor from n(i)
to ground, shared by loops i and i+1, and carries Q_i - Q_{i+1}.  A wall
spring is a capacitor from n0 (nN) to ground; a free end (K = 0, infinite
capacitance) closes its loop with a wire: n0 (nN) *is* the ground node.

Excitations:

* kick: an initial current I0 in L_1 (``IC=`` on the inductor);
* displacement: an initial charge Q0 in loop 1, i.e. the capacitor
  voltages it implies, V(n1) = Q0 / C_12 and V(n0) = -Q0 / C_01.

Netlist text is deterministic (same inputs, same bytes), every number is a
plain float at full precision (``repr(float(v))``: never a SPICE suffix, where
``m`` is milli and ``F`` femto, never a numpy repr), ``.save`` lists only the
requested probes, ``.tran`` always has an explicit maximum step, and every
option is written out.  Text a user supplies (the title, comments) cannot add a
line.  Callers never edit the text: what a run needs beyond the defaults
(adaptive stepping, extra ``.options``, ngspice's own default tolerances, more
saved vectors) is said through :class:`SimulationOptions` and the arguments of
:func:`netlist_text`.
"""

from __future__ import annotations

import hashlib
import math
import re
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import cast

from ..core.checks import choice, instance, integer, real, strings, text_line
from ..core.checks import pulse as check_pulse
from ..core.errors import ParameterError
from ..core.limits import (
    MAX_AC_POINTS,
    MAX_COMMENT_LENGTH,
    MAX_DT,
    MAX_I0,
    MAX_TITLE_LENGTH,
    MIN_AC_POINTS,
    MIN_I0,
    MIN_TIME_UNIT,
)
from ..core.types import (
    DEFAULT_C0,
    DEFAULT_I0,
    DEFAULT_L0,
    EXCITATION_KINDS,
    METHODS,
    PROBES,
    PULSE_SHAPES,
    STEPPINGS,
    ExcitationKind,
    Method,
    Probes,
    PulseShape,
    Stepping,
)
from ..theory.arrivals import stop_time
from ..theory.chain import Chain
from ..theory.modes import Modes
from ..theory.spectrum import normal_modes
from .effects import Effect
from .elements import Element, Pulse, Source, card_number, ladder_elements, ladder_pulse
from .ladder import Ladder

__all__ = [
    "survey_netlist_text",
    "ac_circuit_elements",
    "Ladder",
    "SimulationOptions",
    "Drive",
    "NetlistOutput",
    "netlist_text",
    "circuit_elements",
    "ac_netlist_text",
    "port_elements",
    "PORT_PROBES",
    "AC_OFFSET",
    "ChainNetlist",
    "make_netlist",
    "check_run_length",
    "check_frequency_scale",
    "check_user_text",
    "probe_names",
    "card_number",
    "netlist_hash",
    "SCALED_TOLERANCES",
]

#: The tolerances lcchain scales to the circuit's own current, voltage and charge
#: (so results do not depend on the unit scale); ``SimulationOptions.ngspice_defaults``
#: may leave any of them at ngspice's default instead.
SCALED_TOLERANCES = ("abstol", "vntol", "chgtol")
#: An option name or flag ngspice understands: letters, digits and underscores.
_OPTION_NAME = re.compile(r"^[a-z][a-z0-9_]*$")
#: An option value: a plain number or word, nothing that could end the line or start another.
_OPTION_VALUE = re.compile(r"^[A-Za-z0-9_.+-]+$")
#: A vector name for .save: i(l1), v(n3), @c1[i], ... without spaces.
_VECTOR = re.compile(r"^[A-Za-z0-9_#@()\[\],.:+-]+$")


#: A two-port netlist's saved currents (:func:`ac_netlist_text` with ``ports``): through the AC source V1 at port 1
#: and the ammeter VP2 at port 2, each counted from the port's node (``s1``, ``s<N>``) through the source to the rail:
#: minus the current the port drives into the circuit.
PORT_PROBES = ("i(v1)", "i(vp2)")


def check_user_text(field_name: str, text: object, max_length: int = MAX_TITLE_LENGTH, *, title: bool = True) -> str:
    """Text a user puts in a netlist: its title line, or a ``*`` comment (``title=False``).

    What may reach ngspice as a command is refused, and only that: see
    :func:`lcchain.core.checks.text_line`.
    """
    return text_line(field_name, text, max_length, title=title)


@dataclass(frozen=True)
class SimulationOptions:
    """Transient-analysis settings, all written out in the netlist.

    Parameters
    ----------
    dt : float
        Print step, and the maximum step for ``stepping="fixed"``, in units of
        sqrt(L0 C0); 0 < dt <= 1.
    tstop : float
        Stop time in units of sqrt(L0 C0), > dt.
    method : {"trap", "gear"}
        Integration method (trapezoidal keeps energy; gear damps it).
    reltol : float
        ngspice's relative tolerance (it drives the step control), > 0.
    maxord : int
        Maximum order, 1..6 (2: trap is second order; higher changes nothing here).
    stepping : {"fixed", "adaptive"}
        ``"fixed"``: the maximum step is dt; ``"adaptive"``: ngspice's own
        step control with its default maximum step, tstop/50.
    extra : tuple of (name, value or None)
        More ``.options``: ``(("klu", None),)`` writes the flag ``klu``,
        ``(("itl4", "50"),)`` writes ``itl4=50``.
    ngspice_defaults : tuple of str
        Names from :data:`SCALED_TOLERANCES` to leave at ngspice's defaults.
    aligned : bool
        Steps the same at every dt up to scale (the members of an
        extrapolation, :mod:`lcchain.compare.extrapolate`): the print step is
        tstop, so no breakpoint at t = dt restarts the steps, and the
        truncation-error test is off (``trtol=1e9``), so after the start-up
        ramp (two steps of min(tstop/1000, dt)/10, then doubling) every step
        is exactly dt (:func:`lcchain.compare.extrapolate.aligned_grid`).
        Fixed stepping only.
    """

    dt: float
    tstop: float
    method: Method = "trap"
    reltol: float = 1e-3
    maxord: int = 2
    stepping: Stepping = "fixed"
    extra: tuple[tuple[str, str | None], ...] = ()
    ngspice_defaults: tuple[str, ...] = ()
    aligned: bool = False

    def __post_init__(self) -> None:
        dt = real("dt", self.dt, above=0.0, at_most=MAX_DT,
                  allowed=f"0 < dt <= {MAX_DT:g} (in units of sqrt(L0*C0); the bulk period is 2 pi)")
        object.__setattr__(self, "dt", dt)
        object.__setattr__(self, "tstop", real("tstop", self.tstop, above=dt,
                                               allowed=f"a finite stop time > dt = {dt!r}"))
        object.__setattr__(self, "reltol", real("reltol", self.reltol, above=0.0))
        choice("method", self.method, METHODS)
        choice("stepping", self.stepping, STEPPINGS)
        object.__setattr__(self, "maxord", integer("maxord", self.maxord, at_least=1, at_most=6))
        extra = _sequence("extra", self.extra, "a tuple of (name, value or None) pairs")
        for item in extra:
            if not (isinstance(item, tuple) and len(item) == 2 and isinstance(item[0], str)
                    and _OPTION_NAME.match(item[0]) and (item[1] is None or (isinstance(item[1], str)
                                                                            and _OPTION_VALUE.match(item[1])))):
                raise ParameterError("extra", item, "(name, value or None) with a plain option name and value")
        object.__setattr__(self, "extra", extra)
        defaults = strings("ngspice_defaults", self.ngspice_defaults)
        for name in defaults:
            choice("ngspice_defaults", name, SCALED_TOLERANCES)
        object.__setattr__(self, "ngspice_defaults", defaults)
        if not isinstance(self.aligned, bool):
            raise ParameterError("aligned", self.aligned, "True or False")
        if self.aligned and self.stepping != "fixed":
            raise ParameterError("aligned", self.aligned, "aligned steps with stepping='fixed' only")


def _sequence(name: str, values: object, allowed: str) -> tuple[object, ...]:
    """A list or tuple as a tuple (a string, a set or a number is refused, naming the field)."""
    if isinstance(values, (list, tuple)):
        return tuple(values)
    raise ParameterError(name, values, allowed)


def _effects(values: object) -> tuple[Effect, ...]:
    """A list or tuple of lcchain effects as a tuple, each checked."""
    parts = _sequence("effects", values, "a tuple of lcchain effects")
    return tuple(instance("effects", part, Effect) for part in parts)


def probe_names(N: int, probes: Probes = "ends") -> list[str]:
    """ngspice vectors saved for the probes: inductor currents ``i(l1)``..."""
    choice("probes", probes, PROBES)
    loops = [1, N] if probes == "ends" else list(range(1, N + 1))
    return [f"i(l{i})" for i in loops]


@dataclass(frozen=True)
class Drive:
    """How loop 1 is set in motion (a request's drive, and the netlist's).

    Parameters
    ----------
    kind : {"kick", "displacement", "pulse"}
        An initial current I0 in L_1, an initial charge I0 sqrt(L0 C0) in loop 1, or a voltage pulse in loop 1.
    I0 : float
        Scale of the excitation, ampere (> 0).
    pulse : (shape, width), optional
        With ``kind="pulse"`` only: ``"gaussian"`` or ``"rect"``, width in units of sqrt(L0 C0).
    """

    kind: ExcitationKind = "kick"
    I0: float = DEFAULT_I0
    pulse: tuple[PulseShape, float] | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "I0", real("I0", self.I0, at_least=MIN_I0, at_most=MAX_I0, unit="ampere"))
        spec = check_pulse(self.kind, self.pulse, EXCITATION_KINDS, PULSE_SHAPES)
        object.__setattr__(self, "pulse", spec)


@dataclass(frozen=True)
class NetlistOutput:
    """What a transient's netlist says and saves besides its circuit and its analysis.

    Parameters
    ----------
    title : str
        First line of the netlist (one line, :func:`check_user_text`).
    comments : tuple of str
        Extra ``*`` comment lines after the title (validated likewise).
    probes : {"ends", "all"}
        Save the two end-loop currents, or every loop current.
    extra_vectors : tuple of str
        More vectors to save after the probes (node voltages ``v(n3)``...).
    """

    title: str = "lcchain LC ladder"
    comments: tuple[str, ...] = ()
    probes: Probes = "ends"
    extra_vectors: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        object.__setattr__(self, "title", check_user_text("title", self.title))
        object.__setattr__(self, "comments", strings("comments", self.comments))
        for line in self.comments:
            check_user_text("comment", line, max_length=MAX_COMMENT_LENGTH, title=False)
        object.__setattr__(self, "extra_vectors", strings("extra_vectors", self.extra_vectors))
        for name in self.extra_vectors:
            if not isinstance(name, str) or not _VECTOR.match(name):
                raise ParameterError("extra_vectors", name, "vector names such as 'v(n3)' without spaces")
        choice("probes", self.probes, PROBES)


def netlist_text(ladder: Ladder, options: SimulationOptions, drive: Drive | None = None, *,
                 effects: tuple[Effect, ...] = (), output: NetlistOutput | None = None) -> str:
    """The SPICE netlist of the ladder and its transient analysis.

    Parameters
    ----------
    ladder : Ladder
        Chain and bulk values L0 (H), C0 (F).
    options : SimulationOptions
        Step, stop time (units of sqrt(L0 C0)) and integrator settings.
    drive : Drive, optional
        How loop 1 is set in motion (default ``Drive()``, a kick of :data:`lcchain.core.types.DEFAULT_I0`):
        an initial current I0 in L_1, an initial charge Q0 = I0 sqrt(L0 C0) in loop 1, or a voltage pulse in
        loop 1, v(t) = L_1 I0 g(t), g of unit area in units of sqrt(L0 C0): ``"gaussian"`` (standard deviation
        ``width``, centred at 4 width, a B-source) or ``"rect"`` (1/width on [0, width), a PWL source whose
        fall takes 1e-9 width).
    effects : tuple of Effect
        The elements each effect puts in series with the inductors
        (:meth:`lcchain.circuit.effects.Effect.in_series`), in order.  What
        effects do to the chain (walls, coupling, preferred values) is already
        in ``ladder.chain``: a coupled chain's neighbouring coils get ``K``
        elements.
    output : NetlistOutput, optional
        The title, the comment lines, the loops saved and more vectors (default ``NetlistOutput()``).

    Returns
    -------
    str
        Deterministic text ending in ``.end`` and a newline.
    """
    instance("ladder", ladder, Ladder)
    instance("options", options, SimulationOptions)
    drive = instance("drive", drive, Drive, optional=True) or Drive()
    parts = _effects(effects)
    output = instance("output", output, NetlistOutput, optional=True) or NetlistOutput()
    excitation, I0, spec = drive.kind, drive.I0, drive.pulse
    title, comments, probes, extra_vectors = output.title, output.comments, output.probes, output.extra_vectors
    chain = ladder.chain
    N = chain.N
    unit = ladder.time_unit

    lines = [title]
    lines += [f"* {line}" for line in comments]
    lines.append(
        f"* N={N} L0={card_number(ladder.L0)} H C0={card_number(ladder.C0)} F time unit={card_number(unit)} s "
        f"excitation={excitation} I0={card_number(I0)} A"
    )
    shaped = None if spec is None else (spec[0], spec[1])
    lines += [element.card() for element in circuit_elements(ladder, excitation=excitation, I0=I0, pulse=shaped,
                                                             effects=parts)]
    lines.append(_options_line(options, I0, ladder))
    step = options.dt * unit
    tstop = options.tstop * unit
    max_step = step if options.stepping == "fixed" else tstop / 50
    print_step = tstop if options.aligned else step  # aligned: no breakpoint at t = dt
    lines.append(f".tran {card_number(print_step)} {card_number(tstop)} 0 {card_number(max_step)} uic")
    lines.append(".save " + " ".join(probe_names(N, probes) + list(extra_vectors)))
    lines.append(".end")
    return "\n".join(lines) + "\n"


def circuit_elements(ladder: Ladder, *, excitation: ExcitationKind = "kick", I0: float = DEFAULT_I0,
                     pulse: tuple[PulseShape, float] | None = None, effects: tuple[Effect, ...] = ()
                     ) -> tuple[Element | Pulse, ...]:
    """The elements of a transient's netlist, in its order: the one description :func:`netlist_text` writes the
    cards of and the circuit's exact theory (:class:`lcchain.circuit.exact.CircuitTheory`) assembles.

    Parameters as :func:`netlist_text`'s (``effects`` with the losses already among them); ``I0`` in ampere: a
    kick's initial current in L_1, a displacement's charge ``I0 sqrt(L0 C0)`` in loop 1, or a pulse's area
    ``L_1 I0``.
    """
    elements: tuple[Element | Pulse, ...] = ladder_elements(
        ladder, effects, source=pulse is not None, kick=I0 if excitation == "kick" else None,
        charge=I0 * ladder.time_unit if excitation == "displacement" else None)
    if pulse is not None:
        elements += (ladder_pulse(ladder, pulse[0], pulse[1], I0),)
    return elements


def ac_circuit_elements(ladder: Ladder, effects: tuple[Effect, ...] = ()) -> tuple[Element | Pulse, ...]:
    """The elements of :func:`ac_netlist_text`'s netlist, for the circuit's own exact theory: the ladder's with loop 1
    open at ``s1``, and the AC source's place (``s1`` to the rail node n0, or ground) as a unit rect pulse, the
    source :class:`lcchain.circuit.exact.CircuitTheory` folds in: its admittances are per volt of it, whatever its
    shape (:meth:`lcchain.circuit.exact.CircuitTheory.admittances`)."""
    parts = _effects(effects)
    return (*ladder_elements(ladder, parts, source=True),
            Pulse("s1", ladder.node(0), "rect", ladder.time_unit, ladder.time_unit))


def _drive(ladder: Ladder) -> Source:
    """The AC drive of :func:`ac_netlist_text`: 1 V in loop 1, between ``s1`` and the rail node n0 (or ground)."""
    return ("V1", "s1", ladder.node(0), 1.0)


def _source_card(source: Source) -> str:
    """A source's card: the drive as loop 1's source always is, a 0 V one (an ammeter) plainly (gnucap's dialect
    takes both)."""
    name, a, b, volts = source
    return f"{name} {a} {b} " + (f"DC 0 AC {volts:g}" if volts else "0")


def port_elements(ladder: Ladder, effects: tuple[Effect, ...] = ()) -> tuple[tuple[Element, ...], tuple[Source, ...]]:
    """A two-port's circuit, as :func:`ac_netlist_text` with ``ports`` writes it and its exact phasors
    (:func:`lcchain.circuit.phasor.source_currents`) are solved from it: the ladder open in loop 1 at ``s1`` and in
    loop N at ``s<N>``, and its two sources (name, + node, - node, AC volts): the unit drive ``V1`` at port 1, the
    ammeter ``VP2`` (0 V) at port 2."""
    N = ladder.chain.N
    return (ladder_elements(ladder, _effects(effects), source=True, port2=True),
            (_drive(ladder), ("VP2", f"s{N}", ladder.node(N), 0.0)))


def ac_netlist_text(ladder: Ladder, *, points: int | None = None, omega_max: float | None = None,
                    omega_min: float | None = None, segments: Sequence[tuple[int, float, float]] | None = None,
                    title: str = "lcchain LC ladder, AC", effects: tuple[Effect, ...] = (),
                    ports: bool = False) -> str:
    """The ladder driven in loop 1 by a unit AC voltage, for its transfer admittances I_1/V_1 and I_N/V_1.

    Parameters
    ----------
    ladder : Ladder
    points : int
        Frequencies, evenly spaced (``.ac lin``), 16 to :data:`lcchain.core.limits.MAX_AC_POINTS`.
    omega_max : float
        The last angular frequency, in units of 1/sqrt(L0 C0) (> 0).
    omega_min : float, optional
        The first (default ``omega_max / points``: a free chain has a pole at 0, which a sweep may not hit).
    segments : sequence of (points, lowest, highest), optional
        Instead of ``points`` and ``omega_max``: several even sweeps, one ``.ac lin`` card each, of ``points``
        (>= 2) angular frequencies evenly inside (lowest, highest) (units of 1/sqrt(L0 C0), ascending and
        disjoint: :func:`lcchain.compare.grid.sweep_segments`, :func:`lcchain.compare.grid.segment_frequencies`);
        ngspice writes one plot per card.
    title : str
    effects : tuple of Effect
        Their series elements (losses: a resistor per inductor), as :func:`netlist_text`.
    ports : bool
        A two-port's netlist: loop N opens too, closed by an ammeter ``VP2 s<N> nN 0`` (:data:`PORT_PROBES`
        saved: the currents through the two ports, not the coils').

    Returns
    -------
    str
        No initial condition; ``V1 s1 n0 DC 0 AC 1`` in loop 1; ``.options noopac`` (the ladder is linear and
        a free one has no DC operating point: a loop of inductors); frequencies in Hz.
    """
    instance("ladder", ladder, Ladder)
    hertz = 1.0 / (2.0 * math.pi * ladder.time_unit)  # angular frequency 1/tau in Hz
    if segments is None:
        points = integer("points", points, at_least=MIN_AC_POINTS, at_most=MAX_AC_POINTS)
        omega_max = real("omega_max", omega_max, above=0.0)
        omega_min = real("omega_min", omega_min if omega_min is not None else omega_max / points, above=0.0,
                         below=omega_max)
        sweeps = [f".ac lin {points} {card_number(omega_min * hertz)} {card_number(omega_max * hertz)}"]
    else:
        sweeps = _ac_cards(segments, hertz)
    parts = _effects(effects)
    title = check_user_text("title", title)
    N = ladder.chain.N
    lines = [title, f"* N={N} L0={card_number(ladder.L0)} H C0={card_number(ladder.C0)} F time unit="
                    f"{card_number(ladder.time_unit)} s, AC drive of 1 V in loop 1"]
    elements, sources = port_elements(ladder, parts) if ports else (
        ladder_elements(ladder, parts, source=True), (_drive(ladder),))
    lines += [element.card() for element in elements]
    lines += [_source_card(source) for source in sources]
    lines.append(".options noopac")
    lines += sweeps
    lines.append(".save " + " ".join(PORT_PROBES if ports else probe_names(N, "ends")))
    lines.append(".end")
    return "\n".join(lines) + "\n"


def survey_netlist_text(ladder: Ladder, segments: Sequence[tuple[int, float, float]], amplitudes: Sequence[complex],
                        *, title: str = "lcchain LC ladder, AC survey", effects: tuple[Effect, ...] = ()) -> str:
    """The ladder driven in every loop, for every loop's current: a mode survey
    (:mod:`lcchain.compare.survey`).

    Parameters
    ----------
    ladder : Ladder
    segments : sequence of (points, lowest, highest)
        The sweep's even segments, as :func:`ac_netlist_text` takes them (units of 1/sqrt(L0 C0)).
    amplitudes : sequence of complex
        The AC voltage b_k (V) of the source in series with each loop's coil, k = 1..N
        (:func:`lcchain.compare.survey.survey_amplitudes`).
    title : str
    effects : tuple of Effect
        Their elements, as :func:`netlist_text`.

    Returns
    -------
    str
        ``V<k> s<k> <rail node> DC 0 AC |b_k| arg(b_k)`` (degrees) before each coil L_k, whose current counts from
        ``s<k>``; ``.options noopac``; ``.save`` of every coil's current and nothing else (N x frequencies complex
        values: the node voltages would triple them).
    """
    instance("ladder", ladder, Ladder)
    N = ladder.chain.N
    given = list(_sequence("amplitudes", amplitudes, "a sequence of N complex amplitudes"))
    if len(given) != N or not all(isinstance(v, (int, float, complex)) and math.isfinite(abs(v)) for v in given):
        raise ParameterError("amplitudes", f"{len(given)} values", f"{N} finite complex amplitudes, one per loop")
    values = cast(list[complex], given)  # each an int, float or complex: checked just above
    hertz = 1.0 / (2.0 * math.pi * ladder.time_unit)
    sweeps = _ac_cards(segments, hertz)
    parts = _effects(effects)
    title = check_user_text("title", title)
    lines = [title, f"* N={N} L0={card_number(ladder.L0)} H C0={card_number(ladder.C0)} F time unit="
                    f"{card_number(ladder.time_unit)} s, AC drive in every loop"]
    inductors = {Ladder.inductor(i): i for i in range(1, N + 1)}
    for element in ladder_elements(ladder, parts):
        loop = inductors.get(element.name)
        if loop is None:
            lines.append(element.card())
            continue
        b = complex(values[loop - 1])
        lines.append(f"V{loop} s{loop} {element.a} DC 0 AC {card_number(abs(b))} "
                     f"{card_number(math.degrees(math.atan2(b.imag, b.real)))}")
        lines.append(Element(element.name, f"s{loop}", element.b, element.value).card())
    lines.append(".options noopac")
    lines += sweeps
    lines.append(".save " + " ".join(probe_names(N, "all")))
    lines.append(".end")
    return "\n".join(lines) + "\n"


#: Where a segment's samples sit within their steps: lowest + (k + AC_OFFSET) step, k = 0 .. points - 1.  Not on
#: a step's edge: segments meet halfway between two poles, so on evenly spaced poles a whole number of steps from
#: there would land on a pole (a lossless admittance is infinite there).  (3 - sqrt 5) / 2 keeps the samples as
#: far from such coincidences as any fraction can.
AC_OFFSET = (3.0 - math.sqrt(5.0)) / 2.0


def _ac_cards(segments: Sequence[tuple[int, float, float]], hertz: float) -> list[str]:
    """One ``.ac lin`` card per segment (points, lowest, highest): its points on (lowest, highest), offset by
    :data:`AC_OFFSET` steps."""
    cards, total, previous = [], 0, 0.0
    for k, segment in enumerate(_sequence("segments", segments, "a sequence of (points, lowest, highest)")):
        if not isinstance(segment, tuple) or len(segment) != 3:
            raise ParameterError(f"segments[{k}]", segment, "(points, lowest, highest)")
        count = integer(f"segments[{k}].points", segment[0], at_least=3, at_most=MAX_AC_POINTS,
                        allowed=f"3 to {MAX_AC_POINTS} frequencies (ngspice's .ac lin 2 gives one)")
        lowest = real(f"segments[{k}].lowest", segment[1], at_least=previous,
                      allowed=f"a number >= {previous:.17g} (the previous segment's end; segments ascend)")
        highest = real(f"segments[{k}].highest", segment[2], above=lowest)
        step = (highest - lowest) / count
        first, last = lowest + AC_OFFSET * step, highest - (1.0 - AC_OFFSET) * step
        cards.append(f".ac lin {count} {card_number(first * hertz)} {card_number(last * hertz)}")
        total, previous = total + count, highest
    integer("points", total, at_least=MIN_AC_POINTS, at_most=MAX_AC_POINTS,
            allowed=f"{MIN_AC_POINTS} to {MAX_AC_POINTS} frequencies in all segments")
    return cards


def _options_line(options: SimulationOptions, I0: float, ladder: Ladder) -> str:
    # Tolerances scaled to the circuit's own current, voltage and charge, so
    # that results do not depend on the unit scale (nH/pF/uA as 1 H/1 F/1 A).
    V0 = I0 * ladder.impedance
    Q0 = I0 * ladder.time_unit
    scaled = {"abstol": 1e-12 * I0, "vntol": 1e-12 * V0, "chgtol": 1e-15 * Q0}
    words = [f"method={options.method}", f"maxord={options.maxord}", f"reltol={card_number(options.reltol)}"]
    words += [f"{name}={card_number(value)}" for name, value in scaled.items() if name not in options.ngspice_defaults]
    words.append("trtol=1e9" if options.aligned else "trtol=7.0")
    words += [name if value is None else f"{name}={value}" for name, value in options.extra]
    return ".options " + " ".join(words)


def check_run_length(chain: Chain, tstop: float, time_unit: float, dt: float | None) -> None:
    """Refuse a chain whose run ngspice cannot step through, naming the chain (the user's ``--chain``, a scene's
    ``[chain]``): a run shorter than one step, or than :data:`lcchain.core.limits.MIN_TIME_UNIT` seconds (masses
    and springs far from bulk units: a spring of 1e300 ends the first transit at 1e-150)."""
    seconds = tstop * time_unit
    if math.isfinite(tstop) and seconds >= MIN_TIME_UNIT and (dt is None or tstop > dt):
        return
    if dt is not None and not 0.0 < dt <= MAX_DT:  # NaN too: the step is refused by its own name
        real("dt", dt, above=0.0, at_most=MAX_DT,
             allowed=f"0 < dt <= {MAX_DT:g} (in units of sqrt(L0*C0); the bulk period is 2 pi)")
    if not math.isfinite(tstop):  # a spring of ~0 cuts the chain: nothing ever arrives at its far end
        raise ParameterError("chain", f"{chain.name} N={chain.N}", "a chain whose first arrival comes in a finite "
                             "time: this one's transit time is infinite (a spring or mass of about 0 beside the "
                             "others cuts it in two)")
    step = f" and longer than one step, dt = {dt:g}" if dt is not None else ""
    raise ParameterError("chain", f"{chain.name} N={chain.N}", f"a chain whose run lasts at least {MIN_TIME_UNIT:g} "
                         f"s{step}: this one's ends at t = {tstop:.3g} sqrt(L0*C0) = {seconds:.3g} s (its masses and "
                         "springs are far from bulk units, where the central mass and spring are 1)")


def check_frequency_scale(chain: Chain, omega_max: float, time_unit: float) -> None:
    """Refuse a chain whose AC sweep ngspice cannot make, naming the chain: its highest normal frequency's period
    below :data:`lcchain.core.limits.MIN_TIME_UNIT` seconds (a spring of 1e300 puts a mode at 1e150)."""
    period = 2.0 * math.pi * time_unit / omega_max if omega_max > 0 else math.inf
    if math.isfinite(omega_max) and period >= MIN_TIME_UNIT:
        return
    raise ParameterError("chain", f"{chain.name} N={chain.N}", f"a chain whose modes are slower than one period per "
                         f"{MIN_TIME_UNIT:g} s: this one's highest is omega = {omega_max:.3g} / sqrt(L0*C0), a period "
                         f"of {period:.3g} s (its masses and springs are far from bulk units, where the central mass "
                         "and spring are 1)")


@dataclass(frozen=True)
class ChainNetlist:
    """What :func:`make_netlist` writes of a chain: the step, how long, the units, the drive and the effects.

    Parameters
    ----------
    dt : float
        Maximum step, units of sqrt(L0 C0).
    transits : int
        Arrivals to watch; the run stops at :func:`lcchain.theory.arrivals.stop_time`.
    tstop : float, optional
        The stop time (units of sqrt(L0 C0)) instead of the one the transits give.
    method : {"trap", "gear"}
    aligned : bool
        Steps the same at every dt up to scale (:attr:`SimulationOptions.aligned`).
    L0, C0 : float
        Bulk inductance (H) and capacitance (F).
    drive : Drive
        A kick or a displacement of loop 1 (default: a kick of :data:`lcchain.core.types.DEFAULT_I0`).
    title : str, optional
        First line (default: the chain's name and N).
    comments : tuple of str
        ``*`` lines after the title.
    effects : tuple of Effect
        The elements each effect adds (:func:`netlist_text`); what they do to the chain (walls, coupling) is
        already in the chain.

    The numbers are checked where they are used, each naming its field and range: the units by
    :class:`~lcchain.circuit.ladder.Ladder`, the step, stop time and method by :class:`SimulationOptions`, the run's
    length by :func:`check_run_length`, the title and comments by :class:`NetlistOutput`; here, the parts' types.
    """

    dt: float
    transits: int = 1
    tstop: float | None = None
    method: Method = "trap"
    aligned: bool = False
    L0: float = DEFAULT_L0
    C0: float = DEFAULT_C0
    drive: Drive = field(default_factory=Drive)
    title: str | None = None
    comments: tuple[str, ...] = ()
    effects: tuple[Effect, ...] = ()

    def __post_init__(self) -> None:
        instance("drive", self.drive, Drive)
        object.__setattr__(self, "effects", _sequence("effects", self.effects, "a tuple of lcchain effects"))


def make_netlist(chain: Chain, options: ChainNetlist, *, modes: Modes | None = None
                 ) -> tuple[str, Ladder, SimulationOptions]:
    """The netlist :func:`lcchain.simulate_chain` runs: a chain, kicked or displaced, over some transits.

    Parameters
    ----------
    chain : Chain
    options : ChainNetlist
        The step, the transits or the stop time, the units, the drive, the title, the effects.
    modes : Modes, optional
        The chain's modes, when already computed (they give the stop time).

    Returns
    -------
    text, ladder, options
    """
    instance("options", options, ChainNetlist)
    dt, transits, tstop = options.dt, options.transits, options.tstop
    ladder = Ladder(chain, options.L0, options.C0)
    if tstop is None:
        modes = modes if modes is not None else normal_modes(chain)
        tstop = stop_time(modes, transits)
        check_run_length(chain, tstop, ladder.time_unit, dt)
    analysis = SimulationOptions(dt=dt, tstop=tstop, method=options.method, aligned=options.aligned)
    title = options.title if options.title is not None else \
        f"lcchain {chain.name} chain N={chain.N}, {options.drive.kind}"
    text = netlist_text(ladder, analysis, options.drive, effects=options.effects,
                        output=NetlistOutput(title=title, comments=options.comments))
    return text, ladder, analysis


def netlist_hash(text: str) -> str:
    """SHA-256 of the netlist text (UTF-8), as recorded with every run."""
    return hashlib.sha256(text.encode("utf-8")).hexdigest()
