"""What a netlist lcchain did not write will cost ngspice, read from what it holds, not only from its analysis card.

A ``.tran`` card says how many time points a run has at least (its stop time over its largest step).  What the
netlist holds decides what each point costs, and how many more points ngspice takes:

* **unknowns and elements**: every Newton iteration loads each element and factors the matrix of the
  unknowns (the nodes, and the branch currents of inductors, voltage sources and ``B ... V=`` sources);
  setting the circuit up costs as much again per element and unknown;
* **K lines**: a coupled group of m inductors and k K lines fills its block of the matrix, which ngspice's
  sparse solver then factors at every iteration for about k^2 / m operations (m^3 / 4 when every pair is
  coupled, m for a chain);
* **source edges**: ngspice puts a breakpoint at every edge of a PULSE, every point of a PWL, every noise
  step of TRNOISE and TRRANDOM, and the start of SIN and EXP; after each it restarts from a tenth of the gap
  (or of its last step) and doubles its step until the next one or its largest step (:func:`gap_points`);
* **fast dynamics**: ngspice's truncation-error control takes about :data:`POINTS_PER_CYCLE` steps per cycle
  of what moves fastest: a SIN, SFFM or AM source driving a circuit with inductors or capacitors, or the
  ringing of a node where inductors and capacitors meet with no resistor (its frequency bounded by
  omega^2 <= 2 sum(1 / L) / C, each L shortened by its strongest coupling), at default tolerances;
* **sub-circuits**: every count above is of the flattened circuit, each ``.subckt``'s contents once per copy the
  netlist's ``X`` lines make of it, recursively (:func:`lcchain.spice.cards.multiplicities`): twenty lines can
  hold 10^10 elements;
* **nonlinear devices** (``D Q M J S W`` lines of a ``.model``): each costs its own load at every Newton iteration
  (:data:`SECONDS_PER_DEVICE_ITERATION`, a BSIM MOSFET 50 times a diode), and a netlist that holds one is priced at
  :data:`ITERATIONS_PER_FORCED_POINT` iterations at every time point;
* **operating points**: an ``.op`` or ``.dc`` card beside the analysis runs too (:func:`operating_price`);
* **text**: ngspice and lcchain read, check and copy every byte; a ``B`` source's expression is parsed once
  and evaluated at every iteration; a PWL source is scanned from its first point at every evaluation.

Every coefficient is a named constant below with the measurement that set it (ngspice 39 on this 2-core
machine, CPU times of ``ngspice -n -b`` with ``.options acct``; ``benchmarks/bench_foreign_pricing.py``
measures the prices against real runs, ``benchmarks/pricing.md``).

A source function lcchain cannot price (a name it does not know, or a value it cannot read as a plain number)
is refused: its edges decide the run's cost.

A priced run also gets limits from its own price (:meth:`Price.limits`): a timeout, a largest raw file and a
largest resident memory of the simulator, each :data:`RUN_LIMIT_FACTOR` times what was priced plus a floor,
and never more than the budget, so that a netlist that costs more than it seemed to is stopped long before it
can spend a study's whole budget.
"""

from __future__ import annotations

import math
import re
import string
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from ..core.budget import BYTES_PER_VALUE, INTERPRETER_BYTES, Budget, Estimate, ac_run_estimate
from ..core.errors import ParameterError
from .cards import (
    DEVICES,
    MAX_SUBCKT_DEPTH,
    Cycle,
    Model,
    TooDeep,
    command_of,
    device_model,
    instance,
    model_card,
    multiplicities,
    subckt_header,
)
from .expressions import is_param_card
from .text import NEWLINE, logical_lines, netlist_lines, odd_lines, spice_number

if TYPE_CHECKING:
    import numpy as np

__all__ = ["Contents", "Price", "RunLimits", "read_contents", "transient_price", "sweep_price", "gap_points",
           "raw_bytes_limit", "operating_price", "SOURCE_FUNCTIONS", "POINTS_PER_CYCLE", "RUN_LIMIT_FACTOR",
           "NGSPICE_START_SECONDS"]

# --------------------------------------------------------------------------- what each thing costs (measured)

# Seconds below are CPU seconds (user + system, ``ngspice -n -b`` with ``.options acct``), so that they do not
# depend on what else the machine ran while they were measured; a price is wall time: SHARED_MACHINE_FACTOR of them.

#: Wall seconds per CPU second on this 2-core machine, which other sessions share: ngspice's runs took 1.6 to 2.3
#: times their CPU time at the load averages of 3.6 to 5.5 it has while they work, and 1.0 idle; prices are wall
#: times at a load of about 4 (benchmarks/pricing.md: the hostile family took 0.28 to 0.68 of its prices at a load
#: of 2 to 3; with 1.5 here, 0.59 to 2.14 of theirs at 3.6 to 5.4).
SHARED_MACHINE_FACTOR = 2.0
#: Starting ngspice in its sandbox and reading its raw file back (a run of two unknowns and 12 points: 38 ms wall
#: at a load of 3.7, half of it CPU).
NGSPICE_START_SECONDS = 0.02
#: Newton iterations per time point: 2.0 on a ladder stepping at its largest step (two-mass N = 1000: 42,444
#: iterations for 21,222 points) ...
ITERATIONS_PER_POINT = 2.0
#: ... and 2.6 per point that edges or fast dynamics force, rejected steps included (an LC ladder of 2000 cells
#: driven by a PULSE: 9,006 iterations for 3,530 points, 974 steps rejected).
ITERATIONS_PER_FORCED_POINT = 2.6
#: Per iteration, per unknown and per element, in a circuit of :data:`SMALL_CIRCUIT` unknowns and elements or
#: fewer: an R ladder of 2,000 cells took 15 ns per unknown or resistor (60 us an iteration), an RLC ladder of
#: 2,000 cells 320 us an iteration, so 57 ns per inductor or capacitor (they integrate and keep their states) ...
SECONDS_PER_UNKNOWN_ITERATION = 1.5e-8
SECONDS_PER_ELEMENT_ITERATION = 1.5e-8
SECONDS_PER_REACTIVE_ITERATION = 5.7e-8
#: ... and more per unknown in larger circuits, whose matrix outgrows the caches: as (size / SMALL_CIRCUIT)^0.25
#: (R ladders of 20,000 and 200,000 cells: 25 and 57 ns; an RLC ladder of 20,000 cells: 7.1 ms an iteration,
#: as this says).
SMALL_CIRCUIT = 4000
#: Per iteration, per unit of coupled work (k^2 / m per group of m inductors and k K lines): 11 to 20 ns
#: (60, 100 and 200 inductors all coupled, 1770, 4950 and 19,900 K lines: the larger, the dearer; 1000 inductors
#: each coupled to its 8 neighbours: 17 ns).
SECONDS_PER_COUPLED_ITERATION = 1.5e-8
#: Per iteration, per byte of B-source expression: 4.2 to 5.6 ns (expressions of 120 and 300 kB).
SECONDS_PER_EXPRESSION_BYTE_ITERATION = 5.5e-9
#: Per iteration, per point of a PWL source (scanned from its start at each evaluation): 2.3 to 2.5 ns of wall time
#: at a load of 3, so about 2 ns of CPU (PWL of 3,000 and 10,000 points; 100,000 points ran 429 s for 445,169 time
#: points).
SECONDS_PER_PWL_PAIR_ITERATION = 2e-9
#: Per time point whatever the circuit: the step's control, the raw file's row (an RC driven by a PULSE of 4 ps
#: edges: 900,005 points in 4.1 s of CPU with lcchain's reading).
SECONDS_PER_POINT = 3e-6
#: Setting the circuit up, per unknown and per element (an R ladder of 200,000 cells: 1.6 s; 400,000 resistors
#: in parallel: 5.0 s, 6.9 us each at 100,000: it grows with the count) and per K line.
SETUP_SECONDS_PER_UNKNOWN = 5e-6
SETUP_SECONDS_PER_ELEMENT = 1.2e-5
SETUP_SECONDS_PER_COUPLING = 2e-5
#: Parsing a B-source expression, per byte: 0.44 us at 120 kB, 0.84 us at 300 kB (ngspice 39 crashes on a
#: sum of 200,000 terms, 1.2 MB).
PARSE_SECONDS_PER_EXPRESSION_BYTE = 1e-6
#: Reading, checking, copying and hashing the netlist, per byte: lcchain (a 32 MiB title: 4 s of checks, keys
#: and copies) and ngspice (a 32 MiB title read from its input: 3.3 s; 4 MiB of comments: 0.03 s).
SECONDS_PER_NETLIST_BYTE = 2.2e-7
#: Memory: ngspice keeps about 850 B per element and 450 B per unknown (400,000 resistors in parallel: 332 MB;
#: an R ladder of 400,000 cells: 493 MB; together the 1.3 kB per ladder cell measured before), 1 kB per K line
#: (19,900 K lines on 200 inductors: 31 MB against 13 MB for none) and 57 B per byte of B-source expression
#: (300 kB: 17 MB).
NGSPICE_BYTES_PER_ELEMENT = 850.0
NGSPICE_BYTES_PER_UNKNOWN = 450.0
NGSPICE_BYTES_PER_COUPLING = 1000.0
NGSPICE_BYTES_PER_EXPRESSION_BYTE = 60.0
#: ... and every byte of the netlist costs 5 B in ngspice (a 16 MiB title: 97 MB resident) and 10 B in lcchain
#: (a 32 MiB title: 327 MB more than an empty netlist).
NGSPICE_BYTES_PER_NETLIST_BYTE = 6.0
LCCHAIN_BYTES_PER_NETLIST_BYTE = 10.0
#: A simulator's own memory before any circuit: ngspice -b 13 MB, a warm worker 23 MB with the library loaded,
#: a PySpice child 30 MB (resident, with its launcher and sandbox).
SIMULATOR_BASE_BYTES = 32 * 2**20
#: What a warm or shared-library worker holds of each value it saves (the library's vector and the copy it sends).
WORKER_BYTES_PER_VALUE = 16.0
#: Time points per cycle of the fastest dynamics, at ngspice's default tolerances (reltol 1e-3, trtol 7): a SIN
#: of 1 and 10 GHz into an RC took 7.4 and 7.6 points a cycle; an LC ladder of 2000 cells ringing at up to
#: 318 MHz took 3,530 points in 1 us (11 a cycle).  Tighter tolerances take more: as (reltol trtol)^(-1/3).
POINTS_PER_CYCLE = 11.0
_DEFAULT_TOLERANCE = 1e-3 * 7.0
#: A complex solve (an AC frequency) does about four times a real one's arithmetic.
COMPLEX_SOLVE_FACTOR = 4.0
#: Nonlinear devices (``D Q M J S W`` lines), per Newton iteration: what loading one costs beyond a resistor.
#: Measured on 1000 devices each driven through 1 kOhm by a PULSE of 1 ns edges (``.options acct``'s transient
#: load time, less that of the same netlist with a resistor in each device's place): a diode 56 ns, a level-1
#: MOSFET 117 ns, a BJT 400 ns (with RB and CJE), a BSIM4 MOSFET (level 54) 5.2 us.  J is priced as a level-1
#: MOSFET and S and W as a diode (not measured).
SECONDS_PER_DEVICE_ITERATION: dict[str, float] = {"D": 6e-8, "Q": 4e-7, "M": 1.2e-7, "J": 1.2e-7, "S": 6e-8,
                                                  "W": 6e-8}
#: MOSFET model levels 1 to 3 are the simple ones; every higher level (BSIM3 8 and 49, BSIM4 14 and 54, ...) is
#: priced as the BSIM4 measured above.
MOS_SIMPLE_LEVELS = 3
SECONDS_PER_BSIM_ITERATION = 5e-6
#: Unknowns a device adds inside itself at most in its simple models (a diode's RS, a BJT's RB RC RE, a MOSFET's or
#: a JFET's RD RS); BSIM models add a few more, which their price per iteration already dwarfs.
DEVICE_INTERNAL_NODES: dict[str, int] = {"D": 1, "Q": 3, "M": 2, "J": 2, "S": 0, "W": 0}
#: Newton iterations of a nonlinear netlist: every time point is priced at ITERATIONS_PER_FORCED_POINT (2.6):
#: the runs above took 2.1 to 2.3 per point, and 2.0 per point of a ``.dc`` sweep of 1001 points.  An ``.op``
#: is priced at ngspice's ``itl1`` (100), the most iterations of its direct Newton solve before it steps gmin
#: (those runs took 3 to 8).
OP_ITERATIONS = 100.0
#: Breakpoints enumerated one by one to find their gaps; beyond, each source is priced alone, period by period.
MAX_ENUMERATED_BREAKPOINTS = 1_000_000

# --------------------------------------------------------------------------- the limits a run gets from its price

#: A run may take this many times its priced seconds, raw file and simulator memory (plus the floors below)
#: before it is stopped: the prices hold within 2x on the hostile family of benchmarks/pricing.md, so only a
#: netlist that outgrows its price several times over is stopped.
RUN_LIMIT_FACTOR = 4.0
#: Floors of those limits: a start in the sandbox, a warm worker's start and a loaded machine's jitter (seconds);
#: a simulator's own memory before any circuit (ngspice 13 MB, a warm worker 23 MB, a PySpice child 30 MB); a raw
#: file's header and first points.
RUN_SECONDS_FLOOR = 2.0
RUN_RESIDENT_FLOOR = 64 * 2**20
RUN_OUTPUT_FLOOR = 16 * 2**20


def raw_bytes_limit(max_memory: float) -> float:
    """The raw file's size at which a run is stopped: lcchain holds :data:`BYTES_PER_VALUE` bytes in memory for
    every 8 in the raw file, so a raw file past ``max_memory * 8 / BYTES_PER_VALUE`` would outgrow the budget."""
    return max_memory * 8.0 / BYTES_PER_VALUE


# --------------------------------------------------------------------------- source functions


@dataclass(frozen=True)
class Edges:
    """Breakpoints of one source: the times ``once``, and ``offsets`` in each of ``count`` periods of ``period``
    seconds from ``start``; ``frequency`` (Hz) is what it drives the circuit at between them (0: nothing)."""

    once: tuple[float, ...] = ()
    period: float = 0.0
    offsets: tuple[float, ...] = ()
    start: float = 0.0
    count: float = 0.0
    frequency: float = 0.0

    @property
    def total(self) -> float:
        return len(self.once) + self.count * len(self.offsets)

    def times(self) -> np.ndarray:
        import numpy as np

        periodic = np.empty(0)
        if self.count and self.offsets:
            starts = self.start + self.period * np.arange(int(self.count))
            periodic = (starts[:, None] + np.asarray(self.offsets)[None, :]).ravel()
        return np.concatenate([np.asarray(self.once, dtype=float), periodic])


def _arg(values: Sequence[float], index: int, default: float) -> float:
    return values[index] if index < len(values) and values[index] != 0.0 else default


def _periods(start: float, period: float, stop: float, most: float = math.inf) -> float:
    return min(most, max(0.0, math.ceil((stop - start) / period))) if period > 0 else 0.0


def _pulse(values: Sequence[float], step: float, stop: float) -> Edges:
    # PULSE(V1 V2 TD TR TF PW PER NP): ngspice's defaults TR = TF = TSTEP, PW = PER = TSTOP.
    td = values[2] if len(values) > 2 else 0.0
    tr, tf = _arg(values, 3, step), _arg(values, 4, step)
    pw, per = _arg(values, 5, stop), _arg(values, 6, stop)
    most = values[7] if len(values) > 7 and values[7] > 0 else math.inf
    return Edges(period=per, offsets=(0.0, tr, tr + pw, tr + pw + tf), start=td,
                 count=_periods(td, per, stop, most))


def _sin(values: Sequence[float], step: float, stop: float) -> Edges:
    # SIN(VO VA FREQ TD THETA PHASE): FREQ defaults to 1 / TSTOP.
    return Edges(once=(values[3],) if len(values) > 3 else (), frequency=abs(_arg(values, 2, 1.0 / stop)))


def _exp(values: Sequence[float], step: float, stop: float) -> Edges:
    # EXP(V1 V2 TD1 TAU1 TD2 TAU2): TD2 defaults to TD1 + TSTEP.
    td1 = values[2] if len(values) > 2 else 0.0
    return Edges(once=(td1, _arg(values, 4, td1 + step)))


def _sffm(values: Sequence[float], step: float, stop: float) -> Edges:
    # SFFM(VO VA FC MDI FS): the instantaneous frequency reaches FC + MDI FS.
    fc, mdi, fs = _arg(values, 2, 1.0 / stop), abs(_arg(values, 3, 0.0)), _arg(values, 4, 1.0 / stop)
    return Edges(frequency=abs(fc) + mdi * abs(fs))


def _am(values: Sequence[float], step: float, stop: float) -> Edges:
    # AM(VA VO MF FC TD): the carrier FC, modulated at MF.
    return Edges(once=(values[4],) if len(values) > 4 else (),
                 frequency=abs(_arg(values, 3, 1.0 / stop)) + abs(_arg(values, 2, 0.0)))


def _trnoise(values: Sequence[float], step: float, stop: float) -> Edges:
    # TRNOISE(NA NT NALPHA NAMP RTSAM RTSCAPT RTSEMT): a new value every NT.
    nt = values[1] if len(values) > 1 else 0.0
    return Edges(period=nt, offsets=(0.0,), count=_periods(0.0, nt, stop))


def _trrandom(values: Sequence[float], step: float, stop: float) -> Edges:
    # TRRANDOM(TYPE TS TD PARAM1 PARAM2): a new value every TS from TD.
    ts, td = _arg(values, 1, step), values[2] if len(values) > 2 else 0.0
    return Edges(period=ts, offsets=(0.0,), start=td, count=_periods(td, ts, stop))


def _pwl(values: Sequence[float], step: float, stop: float, repeat: float | None = None,
         delay: float = 0.0) -> Edges:
    # PWL(T1 V1 T2 V2 ... [r=T] [td=D]): a breakpoint at every point; r= repeats the points from T on.
    times = [t + delay for t in values[0::2]]
    if repeat is None or len(times) < 2:
        return Edges(once=tuple(times))
    first = delay + repeat
    tail = tuple(t - first for t in times if t >= first)
    period = times[-1] - first
    if period <= 0 or not tail:
        return Edges(once=tuple(times))
    return Edges(once=tuple(times), period=period, offsets=tail, start=times[-1],
                 count=_periods(times[-1], period, stop))


_Function = Callable[[Sequence[float], float, float], Edges]
#: The source functions lcchain prices, by name: ``(values, TSTEP, TSTOP) -> Edges`` (PWL's ``r=`` and ``td=``
#: are read with it). A source function not here is refused: its edges could cost anything.
SOURCE_FUNCTIONS: dict[str, _Function] = {
    "pulse": _pulse, "pwl": _pwl, "sin": _sin, "sine": _sin, "exp": _exp, "sffm": _sffm, "am": _am,
    "trnoise": _trnoise, "trrandom": _trrandom,
}
#: Words of an independent source that take values but force no step: its DC and AC values, its distortion inputs.
_VALUE_WORDS = frozenset({"dc", "ac", "distof1", "distof2"})
_BRACES = re.compile(r"\{[^{}]*\}")
_SPLIT = re.compile(r"[\s,()=]+")
_B_VOLTAGE = re.compile(r"v\s*=", re.IGNORECASE)
#: The letters of the element lines :func:`_tally` reads first, and most often: inductors and capacitors.
_PLAIN_REACTIVE = frozenset("CL")
_ASSIGNMENT = re.compile(r"([A-Za-z_]\w*)\s*=\s*([^\s=]+)")  # of a .param or .options card


@dataclass(frozen=True)
class _Source:
    """A source function as written: its name, its values, PWL's ``r=`` and ``td=``."""

    name: str
    values: tuple[float, ...]
    repeat: float | None = None
    delay: float = 0.0

    def edges(self, step: float, stop: float) -> Edges:
        if self.name == "pwl":
            return _pwl(self.values, step, stop, self.repeat, self.delay)
        return SOURCE_FUNCTIONS[self.name](self.values, step, stop)


def _source_functions(words: list[str], where: str, line: str) -> list[_Source]:
    """The source functions of an independent source's words after its nodes."""
    allowed = (f"a source of {', '.join(w.upper() for w in sorted(_VALUE_WORDS))} values and "
               f"{', '.join(w.upper() for w in SOURCE_FUNCTIONS)} functions with plain numbers (lcchain prices "
               "a run from its sources' edges before it starts)")
    found: list[_Source] = []
    current: list[float] | None = None
    name = ""
    pending = ""  # PWL's "r" or "td", waiting for its value
    extra: dict[str, float] = {}

    def close() -> None:
        if current is not None:
            found.append(_Source(name, tuple(current), extra.get("r"), extra.get("td", 0.0)))

    for word in words:
        lower = word.lower()
        if lower in SOURCE_FUNCTIONS or lower in _VALUE_WORDS:
            close()
            current, name, pending, extra = (([], lower, "", {}) if lower in SOURCE_FUNCTIONS else (None, "", "", {}))
            continue
        if current is not None and name == "pwl" and lower in ("r", "td") and not pending:
            pending = lower
            continue
        value = spice_number(word)
        if value is None or not math.isfinite(value):
            if current is None and word == "{}":  # a DC or AC value from a parameter: it forces no step
                continue
            raise ParameterError(where, line.strip()[:200], allowed)
        if pending:
            extra[pending], pending = value, ""
        elif current is not None:
            current.append(value)
    close()
    return found


# --------------------------------------------------------------------------- what a netlist holds


@dataclass(frozen=True)
class Contents:
    """What a netlist holds that its run's cost depends on.

    Attributes
    ----------
    elements : int
        Element lines.
    reactive_elements : int
        Of which inductors and capacitors.
    unknowns : int
        Nodes (ground excepted) and branch currents (L, V, ``B ... V=``).
    couplings : int
        K lines.
    coupled_work : float
        sum of k^2 / m over each coupled group of m inductors and k K lines.
    expression_bytes : int
        Bytes of B-source expressions.
    pwl_pairs : int
        Points of PWL sources (each scanned at every evaluation).
    text_bytes : int
        The netlist's size, UTF-8.
    reactive : bool
        Whether it has an inductor or a capacitor.
    ringing : float
        Hz: the highest frequency a node of inductors and capacitors without a resistor can ring at (0: none).
    tolerance : float
        reltol x trtol of its ``.options`` (ngspice's defaults 1e-3 x 7).
    nonlinear : int
        Nonlinear devices (D, Q, M, J, S, W lines), each sub-circuit's counted once per copy.
    device_seconds : float
        CPU seconds their loads take per Newton iteration beyond a resistor's
        (:data:`SECONDS_PER_DEVICE_ITERATION`).

    Every count is of the flattened circuit: a sub-circuit's contents once per copy of it that the netlist holds.
    """

    elements: int = 0
    reactive_elements: int = 0
    unknowns: int = 1
    couplings: int = 0
    coupled_work: float = 0.0
    expression_bytes: int = 0
    pwl_pairs: int = 0
    text_bytes: int = 0
    reactive: bool = False
    ringing: float = 0.0
    tolerance: float = _DEFAULT_TOLERANCE
    sources: tuple[_Source, ...] = field(default=(), repr=False)
    nonlinear: int = 0
    device_seconds: float = 0.0

    def describe(self) -> str:
        parts = [f"{self.unknowns} unknowns", f"{self.elements} elements"]
        if self.nonlinear:
            parts.append(f"{self.nonlinear} nonlinear devices")
        if self.couplings:
            parts.append(f"{self.couplings} K lines")
        if self.expression_bytes:
            parts.append(f"{self.expression_bytes} bytes of expressions")
        if self.pwl_pairs:
            parts.append(f"{self.pwl_pairs} PWL points")
        return ", ".join(parts)


#: The names of ground, which is no unknown (lower case).
_GROUND = frozenset({"0", "gnd"})


def _is_ground(node: str) -> bool:
    return node in _GROUND


def _value(word: str, params: dict[str, float]) -> float | None:
    """An element's value: a number, ``{name}`` or ``name`` of a plain ``.param``, or ``X=value``; else None."""
    text = word.partition("=")[2] if "=" in word else word
    text = text.strip("{}").lower()
    value = spice_number(text)
    return value if value is not None else params.get(text)


def _groups(pairs: list[tuple[str, str, float]]) -> dict[str, tuple[int, int]]:
    """(inductors, K lines) of each coupled group, keyed by one of its inductors (union-find on the K lines)."""
    parent: dict[str, str] = {}

    def root(name: str) -> str:
        parent.setdefault(name, name)
        while parent[name] != name:
            parent[name] = parent[parent[name]]
            name = parent[name]
        return name

    for a, b, _ in pairs:
        parent[root(a)] = root(b)
    members: dict[str, set[str]] = {}
    lines: dict[str, int] = {}
    for a, b, _ in pairs:
        top = root(a)
        members.setdefault(top, set()).update((a, b))
        lines[top] = lines.get(top, 0) + 1
    return {top: (len(members[top]), lines[top]) for top in members}


@dataclass
class _Scope:
    """What one body holds, the netlist's own or a ``.subckt``'s, before its copies are counted: its element lines
    (``lines``, each starting at line ``numbers[k]`` of the text)."""

    ports: frozenset[str] = frozenset()
    defaults: dict[str, float] = field(default_factory=dict)
    numbers: list[int] = field(default_factory=list)
    lines: list[str] = field(default_factory=list)
    calls: list[str] = field(default_factory=list)


#: The bytes an element line of :func:`_scopes`'s bulk starts with (lcchain.spice.text.odd_lines): ASCII letters.
_LETTERS = string.ascii_letters.encode("ascii")
#: Texts of this many lines or more are read in runs of element lines; shorter ones line by line, which costs less
#: for so few.
_RUNS_FROM = 64


@dataclass
class _Reader:
    """:func:`_scopes` as it goes: what it has read, the body it is in and whether in a ``.control`` block."""

    params: dict[str, float] = field(default_factory=dict)
    options: dict[str, float | None] = field(default_factory=dict)
    models: dict[str, Model] = field(default_factory=dict)
    globals_: set[str] = field(default_factory=set)
    scopes: dict[str, _Scope] = field(default_factory=lambda: {"": _Scope()})
    stack: list[str] = field(default_factory=lambda: [""])
    control: bool = False  # in a .control block (a netlist run as it is): commands, not elements

    def elements(self, first: int, lines: list[str]) -> None:
        """Element lines (each starts with a letter) numbered from ``first``, all in the body the reader is in."""
        if not self.control:
            scope = self.scopes[self.stack[-1]]
            scope.numbers += range(first, first + len(lines))
            scope.lines += lines

    def lines(self, lines: Iterable[tuple[int, str]]) -> None:
        """Logical lines (the title excepted) one by one."""
        scope = self.scopes[self.stack[-1]]  # the body the reader is in, again after each dot-command
        for number, line in lines:
            head = line[:1]
            if not head.isalpha():  # an element line starts with its letter, but may follow blanks
                head = line.lstrip()[:1]
            if head.isalpha():
                if not self.control:
                    scope.numbers.append(number)
                    scope.lines.append(line)
            elif head == ".":
                self.dot(number, line)
                scope = self.scopes[self.stack[-1]]

    def dot(self, number: int, line: str) -> None:
        """A line whose first character that is not blank is a dot (:meth:`lines` takes the others)."""
        head = line.lstrip()[:1]
        if head != ".":
            return
        word, _, rest = line.strip().partition(" ")
        word = word.lower()
        if word.startswith((".control", ".endc")):
            self.control = word.startswith(".control")
            return
        command = command_of(word)
        if is_param_card(word):  # .params, .PARAM_X: ngspice 39 reads them as .param
            for name, value in _ASSIGNMENT.findall(rest):
                number_ = spice_number(value.strip("{}"))
                if number_ is not None:
                    self.params[name.lower()] = number_
        elif word in (".options", ".option", ".opt"):
            for name, value in _ASSIGNMENT.findall(rest):
                self.options[name.lower()] = spice_number(value)
        elif command == ".subckt":
            header = subckt_header(line.strip())
            name = header.name if header is not None else f"?{number}"
            defaults = {k: v for k, v in ((k, spice_number(v)) for k, v in (header.params if header else ()))
                        if v is not None}
            self.scopes[name] = _Scope(frozenset(header.nodes if header else ()), defaults)
            self.stack.append(name)
        elif command == ".ends" and len(self.stack) > 1:
            self.stack.pop()
        elif command == ".model":
            model = model_card(line.strip())
            if model is not None:
                self.models[model.name] = model
        elif command == ".global":
            self.globals_.update(w.lower() for w in rest.split())


def _scopes(text: str) -> tuple[dict[str, _Scope], dict[str, float], dict[str, float | None], dict[str, Model],
                                 set[str]]:
    """(each body's element lines by definition, ``""`` the netlist's own; ``.param`` values; ``.options``;
    ``.model`` cards; ``.global`` nodes) of a netlist's text, in one pass over its lines.

    Without ``+`` lines (a logical line is a physical one), the lines that start with a letter are element lines
    of the body the line before them left open, so only the others are read one by one
    (:func:`lcchain.spice.text.odd_lines` finds them) and each run of element lines between them is taken at once.
    """
    reader = _Reader()
    if "\n+" in text or text.count(NEWLINE) + 1 < _RUNS_FROM:  # logical lines ("+" lines joined), or few
        reader.lines(logical_lines(text)[1:])  # the first line is the title
    else:
        physical = netlist_lines(text)
        at = 1
        for k in odd_lines(text, _LETTERS):
            if k > at:
                reader.elements(at + 1, physical[at:k])
            if k >= 1:
                reader.lines([(k + 1, physical[k])])
            at = max(at, k + 1)
        if at < len(physical):
            reader.elements(at + 1, physical[at:])
    return reader.scopes, reader.params, reader.options, reader.models, reader.globals_


@dataclass
class _Tally:
    """One body's contents, its copies not yet counted."""

    elements: int = 0
    reactive: int = 0
    nodes: int = 0
    branches: int = 0
    couplings: int = 0
    coupled_work: float = 0.0
    expression: int = 0
    pwl: int = 0
    nonlinear: int = 0
    device_seconds: float = 0.0
    omega2: float = 0.0
    sources: list[_Source] = field(default_factory=list)


def _tally(scope: _Scope, top: bool, params: dict[str, float], models: dict[str, Model], globals_: set[str],
           source: str) -> _Tally:
    """What one body holds: its elements, its own nodes (a sub-circuit's ports, the global nodes and ground are
    its instance's or the netlist's), branches, couplings, devices and sources, and how fast it rings."""
    values = {**params, **scope.defaults}
    t = _Tally()
    nodes: set[str] = set()
    capacitance: dict[str, float] = {}
    inductors: dict[str, tuple[str, str, float]] = {}
    damped: set[str] = set()
    couples: list[tuple[str, str, float]] = []
    instances = branches = expression = reactive = 0  # counted in locals: this loop sees every element line
    known: dict[str, float | None] = {}  # each value's word read once: a ladder's repeat
    lines = scope.lines
    joined = NEWLINE.join(lines) if len(lines) >= _RUNS_FROM else ""
    # the lines of a long ASCII body lowered at once (each word of a line so lowered is the word lowered); in
    # another body none is, and every line takes the branches below
    lowered = joined.lower().split(NEWLINE) if joined and joined.isascii() else [""] * len(lines)
    short = {letter.lower() for letter in _PLAIN_REACTIVE} if joined else set()
    for number, line, low in zip(scope.numbers, lines, lowered, strict=True):
        if low[:1] in short and "{" not in low:  # the short branch below, of a line starting with its letter
            words = low.split()
            if len(words) > 3:
                a, b = words[1], words[2]
                nodes.add(a)
                nodes.add(b)
                reactive += 1
                word = words[3]
                value = abs((known[word] if word in known else known.setdefault(word, _value(word, values))) or 0.0)
                if low[0] == "c":
                    capacitance[a] = capacitance.get(a, 0.0) + value
                    capacitance[b] = capacitance.get(b, 0.0) + value
                else:
                    branches += 1
                    if value:
                        inductors[words[0]] = (a, b, value)
                continue
        words = line.split()
        letter = words[0][0].upper()
        if letter in _PLAIN_REACTIVE and len(words) > 3 and "{" not in line:
            # most lines of a ladder: what the branches below make of an inductor or a capacitor given a value
            a, b = words[1].lower(), words[2].lower()
            nodes.add(a)
            nodes.add(b)
            reactive += 1
            word = words[3]
            value = abs((known[word] if word in known else known.setdefault(word, _value(word, values))) or 0.0)
            if letter == "C":
                capacitance[a] = capacitance.get(a, 0.0) + value
                capacitance[b] = capacitance.get(b, 0.0) + value
            else:
                branches += 1
                if value:
                    inductors[words[0].lower()] = (a, b, value)
            continue
        if letter == "X":
            instances += 1
            found = instance(line.strip())
            if found is not None:
                scope.calls.append(found.subckt)
                nodes.update(found.nodes)
            continue
        if letter == "K":
            if len(words) >= 3:
                k = _value(words[3], values) if len(words) > 3 else None
                couples.append((words[1].lower(), words[2].lower(), abs(k) if k is not None else 0.5))
            continue
        if letter in DEVICES:
            device = device_model(letter, words, models)
            count = device[0] if device is not None else DEVICES[letter][0]
            nodes.update(w.lower() for w in words[1:1 + count][:2 if letter == "W" else count])
            kind = device[1] if device is not None else None
            t.nonlinear += 1
            t.nodes += DEVICE_INTERNAL_NODES[letter]
            heavy = letter == "M" and kind is not None and kind.level > MOS_SIMPLE_LEVELS
            t.device_seconds += SECONDS_PER_BSIM_ITERATION if heavy else SECONDS_PER_DEVICE_ITERATION[letter]
            if "{" in line:
                expression += sum(len(group) for group in _BRACES.findall(line))
            continue
        if letter in "EFGH" and len(words) >= 3:  # controlled: its nodes (E, G: its controlling ones too), and
            nodes.update(w.lower() for w in words[1:5 if letter in "EG" and len(words) > 5 else 3])  # E, H: a
            branches += letter in "EH"  # branch current
            if "{" in line:
                expression += sum(len(group) for group in _BRACES.findall(line))
            continue
        if letter not in "RLCVIB" or len(words) < 3:
            continue
        a, b = words[1].lower(), words[2].lower()
        nodes.add(a)
        nodes.add(b)
        if letter == "B":  # a voltage (V=) has a branch current; its expression is evaluated at every iteration
            body = " ".join(words[3:])
            branches += _B_VOLTAGE.match(body) is not None
            expression += len(body)
            continue
        branches += letter in "LV"
        if "{" in line:
            expression += sum(len(group) for group in _BRACES.findall(line))
        if letter == "R":
            damped.add(a)
            damped.add(b)
            continue
        if letter in "VI":
            tokens = [w for w in _SPLIT.split(_BRACES.sub(" {} ", " ".join(words[3:]))) if w]
            found_sources = _source_functions(tokens, f"{source}: line {number}", line)
            t.pwl += sum(len(s.values) // 2 for s in found_sources if s.name == "pwl")
            t.sources += found_sources
            continue
        reactive += 1
        if len(words) > 3:
            word = words[3]
            found_value = known[word] if word in known else known.setdefault(word, _value(word, values))
            value = abs(found_value or 0.0)
        else:
            value = 0.0
        if letter == "C":
            capacitance[a] = capacitance.get(a, 0.0) + value
            capacitance[b] = capacitance.get(b, 0.0) + value
        elif value:
            inductors[words[0].lower()] = (a, b, value)
    t.elements, t.branches, t.expression, t.reactive = len(scope.lines) - instances, branches, expression, reactive
    own = nodes | globals_ if top else nodes - scope.ports - globals_  # a port is the instance's node
    t.nodes += len(own - _GROUND)
    t.couplings = len(couples)
    t.coupled_work = sum(k * k / m for m, k in _groups(couples).values())
    coupling: dict[str, float] = {}
    for first, second, k in couples:
        for name in (first, second):
            coupling[name] = max(coupling.get(name, 0.0), min(k, 0.99))
    admittance: dict[str, float] = {}
    for name, (a, b, henry) in inductors.items():
        reciprocal = 1.0 / (henry * (1.0 - coupling.get(name, 0.0)))
        admittance[a] = admittance.get(a, 0.0) + reciprocal
        admittance[b] = admittance.get(b, 0.0) + reciprocal
    t.omega2 = max((2.0 * admittance[n] / c for n, c in capacitance.items()
                    if c > 0 and n in admittance and n not in damped and not _is_ground(n)), default=0.0)
    return t


def read_contents(text: str, source: str = "netlist") -> Contents:
    """What ``text`` holds that its cost depends on (:class:`Contents`), in one pass over its lines, every
    sub-circuit counted as many times as the flattened circuit holds it (:func:`lcchain.spice.cards.multiplicities`).

    Raises
    ------
    ParameterError
        A source function lcchain cannot price, naming the line, or sub-circuits that instantiate themselves
        or nest too deep (the allow-list refuses both first, naming the card).
    """
    scopes, params, options, models, globals_ = _scopes(text)
    tallies = {name: _tally(scope, name == "", params, models, globals_, source) for name, scope in scopes.items()}
    try:
        copies = multiplicities({name: scope.calls for name, scope in scopes.items()})
    except (Cycle, TooDeep) as error:
        raise ParameterError(source, " -> ".join(error.path), f"sub-circuits nested at most {MAX_SUBCKT_DEPTH} "
                             "deep, none instantiating itself") from None
    reached = [(tallies[name], count) for name, count in copies.items() if name in tallies]

    def total(attribute: str) -> int:
        return sum(getattr(t, attribute) * count for t, count in reached)

    reactive = total("reactive")
    reltol, trtol = options.get("reltol"), options.get("trtol")
    tolerance = (reltol if reltol and reltol > 0 else 1e-3) * (trtol if trtol and trtol > 0 else 7.0)
    return Contents(
        elements=total("elements"), reactive_elements=reactive, unknowns=max(total("nodes") + total("branches"), 1),
        couplings=total("couplings"), coupled_work=float(sum(t.coupled_work * count for t, count in reached)),
        expression_bytes=total("expression"), pwl_pairs=total("pwl"), text_bytes=len(text.encode("utf-8")),
        reactive=reactive > 0, ringing=math.sqrt(max((t.omega2 for t, _ in reached), default=0.0)) / (2 * math.pi),
        tolerance=tolerance, sources=tuple(s for t, _ in reached for s in t.sources), nonlinear=total("nonlinear"),
        device_seconds=float(sum(t.device_seconds * count for t, count in reached)))


# --------------------------------------------------------------------------- time points


def gap_points(gaps: np.ndarray, max_step: float) -> np.ndarray:
    """The steps ngspice takes across each gap between breakpoints (seconds, in order).

    After a breakpoint ngspice steps a tenth of the gap ahead, or of half its last step if smaller, then
    doubles its step until it reaches the gap's end or ``max_step``, and lands on the next breakpoint.
    Checked on an RC: a PULSE of 4 ps edges every 20, 200 and 2000 ps takes 1.1, 1.0 and 0.94 times the points
    this counts; PWL sources of 1,000 to 100,000 points 0.7 to 1.35 times.
    """
    import numpy as np

    gaps = np.asarray(gaps, dtype=float)
    if gaps.size == 0:
        return gaps
    before = np.concatenate([[max_step], gaps[:-1]])
    first = 0.1 * np.minimum(np.minimum(before / 2, max_step), gaps)
    reach = np.minimum(gaps, max_step)
    steps: np.ndarray = np.ceil(np.log2(reach / first + 1.0)) + 1.0 + np.maximum(gaps - 2.0 * reach, 0.0) / max_step
    return steps


def _one_gap_points(gap: float, max_step: float) -> float:
    """:func:`gap_points` of one gap after the run's start, in floats (the same operations in the same order):
    the price of a netlist without breakpoints needs no numpy (a batch's plan then loads none before its runs)."""
    first = 0.1 * min(min(max_step / 2, max_step), gap)
    reach = min(gap, max_step)
    return math.ceil(math.log2(reach / first + 1.0)) + 1.0 + max(gap - 2.0 * reach, 0.0) / max_step


def _distinct(values: np.ndarray) -> np.ndarray:
    """``np.unique(values)`` for floats without NaN, without importing ``numpy.ma`` (``np.unique`` does, 10 ms of a
    batch's start)."""
    import numpy as np

    ordered = np.sort(values)
    return ordered[np.concatenate([[True], ordered[1:] != ordered[:-1]])] if ordered.size else ordered


def _listed(times: np.ndarray, stop: float, max_step: float) -> float:
    """Time points from 0 to ``stop`` with breakpoints at ``times`` (at least one per ``max_step``)."""
    import numpy as np

    times = _distinct(np.concatenate([times[(times > 0.0) & (times < stop)], [0.0, stop]]))
    return float(gap_points(np.diff(times), max_step).sum()) + 1.0


def _edge_points(edges: list[Edges], stop: float, max_step: float) -> float:
    """Time points from 0 to ``stop`` with every source's breakpoints: listed together when there are at most
    :data:`MAX_ENUMERATED_BREAKPOINTS`, else each source alone (its listed times, and one period times its
    count) added to the points a run without breakpoints has."""
    if not edges and stop > 0.0:  # no source has an edge: one gap, what _listed makes of [0, stop]
        return _one_gap_points(stop, max_step) + 1.0
    import numpy as np

    if sum(e.total for e in edges) <= MAX_ENUMERATED_BREAKPOINTS:
        return _listed(np.concatenate([e.times() for e in edges] + [np.empty(0)]), stop, max_step)
    plain = _listed(np.empty(0), stop, max_step)
    points = plain
    for e in edges:
        points += _listed(np.asarray(e.once, dtype=float), stop, max_step) - plain
        if e.count and e.offsets:
            one = _distinct(np.concatenate([np.asarray(e.offsets) % e.period, [0.0, e.period]]))
            per_period = float(gap_points(np.diff(one), max_step).sum())
            points += e.count * max(per_period - e.period / max_step, 0.0)
    return points


def _transient_points(contents: Contents, step: float, stop: float, max_step: float) -> tuple[float, float]:
    """(time points, of which forced by edges or fast dynamics beyond one per ``max_step``)."""
    edges = [s.edges(step, stop) for s in contents.sources]
    points = _edge_points(edges, stop, max_step)
    driven = max((e.frequency for e in edges), default=0.0) if contents.reactive else 0.0
    fastest = max(driven, contents.ringing)
    per_cycle = POINTS_PER_CYCLE * (_DEFAULT_TOLERANCE / contents.tolerance) ** (1.0 / 3.0)
    plain = stop / max_step + 1.0
    points += max(0.0, per_cycle * fastest * stop - plain)
    return points, max(points - plain, 0.0)


# --------------------------------------------------------------------------- prices


@dataclass(frozen=True)
class RunLimits:
    """What one run may spend before it is stopped: seconds, its raw file's bytes, its simulator's resident bytes."""

    timeout: float
    max_output_bytes: float
    max_resident_bytes: float


@dataclass(frozen=True)
class Price:
    """What a foreign netlist's run is priced at.

    Attributes
    ----------
    what : str
        In words.
    points : float
        Time points (a transient) or frequencies (an AC sweep).
    seconds : float
        Wall time: the simulator's start, set-up and analysis, and lcchain's reading of the text.
    memory : float
        Bytes: lcchain's (the values it reads back, the text) and the simulator's own.
    simulator_memory : float
        Bytes the simulator's process holds: its own, and the values a shared-library worker keeps.
    output_bytes : float
        The raw file's size.
    """

    what: str
    points: float
    seconds: float
    memory: float
    simulator_memory: float
    output_bytes: float

    @property
    def estimate(self) -> Estimate:
        return Estimate(self.what, self.memory, self.seconds)

    def plus(self, other: Price) -> Price:
        """Both runs' prices in one (their points those of this one's analysis)."""
        return Price(f"{self.what}, and {other.what}", self.points, self.seconds + other.seconds,
                     self.memory + other.memory, self.simulator_memory + other.simulator_memory,
                     self.output_bytes + other.output_bytes)

    def limits(self, budget: Budget, timeout: float = math.inf) -> RunLimits:
        """The run's own limits: :data:`RUN_LIMIT_FACTOR` times its price plus a floor, within the budget (and
        ``timeout``, seconds, when the user gave one)."""
        return RunLimits(
            timeout=min(timeout, budget.max_seconds, RUN_LIMIT_FACTOR * self.seconds + RUN_SECONDS_FLOOR),
            max_output_bytes=min(raw_bytes_limit(budget.max_memory),
                                 RUN_LIMIT_FACTOR * self.output_bytes + RUN_OUTPUT_FLOOR),
            max_resident_bytes=min(max(budget.max_memory - INTERPRETER_BYTES, RUN_RESIDENT_FLOOR),
                                   RUN_LIMIT_FACTOR * self.simulator_memory + RUN_RESIDENT_FLOOR))


def _fixed(contents: Contents) -> tuple[float, float, float]:
    """(CPU seconds, lcchain's bytes, the simulator's bytes) whatever the analysis: start, set-up, text."""
    c = contents
    seconds = (NGSPICE_START_SECONDS + SETUP_SECONDS_PER_UNKNOWN * c.unknowns + SETUP_SECONDS_PER_ELEMENT * c.elements
               + SETUP_SECONDS_PER_COUPLING * c.couplings + PARSE_SECONDS_PER_EXPRESSION_BYTE * c.expression_bytes
               + SECONDS_PER_NETLIST_BYTE * c.text_bytes)
    simulator = (SIMULATOR_BASE_BYTES + NGSPICE_BYTES_PER_UNKNOWN * c.unknowns + NGSPICE_BYTES_PER_ELEMENT * c.elements
                 + NGSPICE_BYTES_PER_COUPLING * c.couplings + NGSPICE_BYTES_PER_EXPRESSION_BYTE * c.expression_bytes
                 + NGSPICE_BYTES_PER_NETLIST_BYTE * c.text_bytes)
    return seconds, LCCHAIN_BYTES_PER_NETLIST_BYTE * c.text_bytes, simulator


def _per_solve(contents: Contents) -> float:
    """CPU seconds of one Newton iteration: its unknowns and elements (dearer in a large circuit) and its coupled
    blocks."""
    c = contents
    size = c.unknowns + c.elements
    return ((SECONDS_PER_UNKNOWN_ITERATION * c.unknowns + SECONDS_PER_ELEMENT_ITERATION * (c.elements
             - c.reactive_elements) + SECONDS_PER_REACTIVE_ITERATION * c.reactive_elements)
            * math.pow(max(1.0, size / SMALL_CIRCUIT), 0.25) + SECONDS_PER_COUPLED_ITERATION * c.coupled_work
            + c.device_seconds)


def transient_price(contents: Contents, *, step: float, stop: float, max_step: float, saved: int) -> Price:
    """A ``.tran`` run's price: its time points (edges and fast dynamics included), each point's iterations, and
    the set-up.

    Parameters
    ----------
    contents : Contents
    step, stop, max_step : float
        TSTEP, TSTOP and the largest step (ngspice's default when the card gives none), seconds.
    saved : int
        Values saved per time point (the ``.save`` names, or every unknown), time excluded.
    """
    points, forced = _transient_points(contents, step, stop, max_step)
    if contents.nonlinear:  # every point is solved by Newton iterations that the devices keep busy
        forced = points
    iterations = ITERATIONS_PER_POINT * points + (ITERATIONS_PER_FORCED_POINT - ITERATIONS_PER_POINT) * forced
    per_iteration = (_per_solve(contents) + SECONDS_PER_EXPRESSION_BYTE_ITERATION * contents.expression_bytes
                     + SECONDS_PER_PWL_PAIR_ITERATION * contents.pwl_pairs)
    fixed, lcchain_bytes, simulator_bytes = _fixed(contents)
    values = points * ((saved or contents.unknowns) + 1)
    seconds = SHARED_MACHINE_FACTOR * (fixed + iterations * per_iteration + SECONDS_PER_POINT * points)
    what = f"{points:.3g} time points x {saved or contents.unknowns} saved values, {contents.describe()}"
    return Price(what, points, seconds, BYTES_PER_VALUE * values + lcchain_bytes + simulator_bytes,
                 simulator_bytes + WORKER_BYTES_PER_VALUE * values, 8.0 * values)


def sweep_price(contents: Contents, *, frequencies: int, saved: int) -> Price:
    """An ``.ac`` run's price: the AC model of :func:`lcchain.core.budget.ac_run_estimate` (frequencies x unknowns,
    measured on ladders), each coupled block solved in complex arithmetic (:data:`COMPLEX_SOLVE_FACTOR` times a
    real iteration's work), and the set-up."""
    fixed, lcchain_bytes, simulator_bytes = _fixed(contents)
    values = frequencies * ((saved or contents.unknowns) + 1)
    solves = ac_run_estimate(points=frequencies, saved=saved or contents.unknowns, unknowns=contents.unknowns).seconds
    coupled = COMPLEX_SOLVE_FACTOR * SECONDS_PER_COUPLED_ITERATION * contents.coupled_work * frequencies
    seconds = SHARED_MACHINE_FACTOR * (fixed + coupled) + solves
    what = f"{frequencies} frequencies x {saved or contents.unknowns} saved complex values, {contents.describe()}"
    return Price(what, float(frequencies), seconds, 2 * BYTES_PER_VALUE * values + lcchain_bytes + simulator_bytes,
                 simulator_bytes + 2 * WORKER_BYTES_PER_VALUE * values, 16.0 * values)


def operating_price(contents: Contents, *, points: int, saved: int) -> Price:
    """What the ``.op`` and ``.dc`` cards beside a netlist's analysis add to its price: ``points`` operating
    points (an ``.op`` is one; a ``.dc`` sweep one per value), the first at :data:`OP_ITERATIONS` Newton
    iterations, each other one at :data:`ITERATIONS_PER_FORCED_POINT` from its neighbour, and their rows of the
    raw file."""
    iterations = OP_ITERATIONS + ITERATIONS_PER_FORCED_POINT * max(points - 1, 0)
    values = points * ((saved or contents.unknowns) + 1)
    seconds = SHARED_MACHINE_FACTOR * (iterations * _per_solve(contents) + SECONDS_PER_POINT * points)
    return Price(f"{points} operating points", float(points), seconds, 0.0, 0.0, 8.0 * values)
