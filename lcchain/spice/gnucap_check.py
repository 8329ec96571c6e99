"""gnucap's run of a foreign linear netlist for ``lcchain check``: a netlist gnucap reads, written from numbers.

No text the user wrote reaches gnucap.  The netlist has passed the allow-list
(:func:`lcchain.spice.foreign.allowed_netlist`) and been read as numbers
(:func:`lcchain.spice.element_values.read_cards`); :func:`check_netlist` writes every card itself: nodes
renamed ``n1``, ``n2``... (``0`` for ground), elements renamed ``R1``, ``L1``, ``C1``, ``K1``, ``V1``, ``I1``...
by letter, every number written by ``repr(float)``.  Each saved vector (ngspice's name, e.g. ``v(out)``,
``i(v1)``) is read back as a sum of gnucap's printed columns, so the result carries ngspice's names and signs.

gnucap (``master 2017.10.03``), measured on this machine
--------------------------------------------------------
* sources: ``pulse(v1 v2 td tr tf pw per)``, ``sin(vo va f td theta)``, ``pwl(t v ...)``,
  ``exp(v1 v2 td1 tau1 td2 tau2)`` and a constant are read in SPICE's order; its SIN has no phase argument (a
  sixth argument is an error), so a phase other than 0 is refused, and so is ngspice's pulse count;
* ``i(X)`` of every element is the current from its first node to its second through it: ngspice's sign for a
  voltage source's ``i(v1)``;
* its voltage source is a Norton equivalent with the ``short`` option (1e-5 ohm) in series: with it the
  source's node is off by ``1e-5 I``; with ``short=1e-30`` the node is exact but its ``i(V1)`` prints 0 (and
  gnucap warns "open circuit: internal node 3" at the operating point, where its values are those of
  ``short=1e-15``, which warns not, to every digit: the warning is dropped).  ``noincmode`` is needed with it:
  gnucap's incremental matrix updates (its default) lose the circuit's conductances next to the source's
  1e30 S (without it, a Butterworth ladder with RS = 1 ohm and a SIN source grew to 1e288 V, and with
  ``short=1e-12`` erred 12 times the prediction; with it, ``short=1e-30`` and ``1e-12`` gave 0.96 .. 1.02 times
  the prediction, the default ``1e-5`` 1.2 to 3 times).  So
  the source runs with ``short=1e-30`` and its current is read by Kirchhoff's law at one of its nodes, from the
  currents of the other elements there (a node that only voltage sources share is refused);
* ``.ic``, ``uic`` and ``ic=`` are refused: gnucap reads a coil's ``ic=`` as its flux over its inductance
  (:func:`lcchain.spice.gnucap.coupled_initial_currents`) and starts from them without ngspice's operating
  point, which lcchain does not model for it;
* its table holds only multiples of the print step, so the run is at a fixed step h (the ``.tran`` step, or its
  maximum step if smaller, shortened to land on tstop) with ``dtmax=h``.  Between print points (``trace all``)
  gnucap starts from 2 ``dtmin`` and doubles up to h, and adds a step at each source corner off the grid (the
  band-pass at h = 0.3 us: 700 steps for 667 points); its error is the fixed-step prediction's, 1.01 times it
  there, 0.96 .. 1.02 times it on the Butterworth ladder (SIN, PWL, EXP, PULSE);
* ``.tran`` with a start time other than 0 is refused (gnucap's table would start at 0);
* ``.ac lin|dec|oct N f1 f2`` is read in SPICE's order (``oct``: gnucap's frequencies are a little off the
  octaves, 2.00000001 kHz from 1 kHz, and the last passes f2); a source's ``AC mag phase`` loses its phase in
  gnucap (measured: the phasor turned back by it), so a phase other than 0 is refused.  The phasors agreed
  with the exact ones to 1e-14 of their scale (the band-pass, 100 Hz to 1 MHz; the Butterworth ladder).
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

from ..core.errors import ParameterError
from .element_values import ControlledCard, CouplingCard, ElementCard, NetlistCards, OtherCard, SourceCard
from .gnucap import AC_DIGITS, DTMIN_FRACTION, GMIN, MAX_OUTPUT_BYTES, SOURCE_RESISTANCE, VOLTAGE_LIMIT, _run_child
from .gnucap_table import TITLE, read_ac_table, read_table
from .job import TransportJob
from .sandbox import find_sandbox
from .simulator import Simulator
from .text import canonical_vector_name

if TYPE_CHECKING:
    import numpy as np

__all__ = ["GnucapCheckNetlist", "CheckedRun", "check_netlist", "run_check", "GROUND", "CHECK_DIGITS"]

#: The ground node's names (ngspice's).
GROUND = frozenset({"0", "gnd"})
#: Significant digits of gnucap's table (as its AC analysis: read back as the doubles gnucap holds).
CHECK_DIGITS = 20
#: gnucap's series resistance of a voltage source in the check (its ``short`` option), ohm: see the docstring.
CHECK_SOURCE_RESISTANCE = SOURCE_RESISTANCE
_OPEN_NODE = re.compile(r"^open circuit: internal node [0-9]+\s*$")
#: Source functions gnucap reads in SPICE's order, with the most arguments it takes.
_FUNCTIONS = {"pulse": 7, "sin": 5, "pwl": None, "exp": 6}


def _refuse(what: str) -> ParameterError:
    return ParameterError("--engine", "gnucap", f"ngspice for {what}")


@dataclass(frozen=True)
class GnucapCheckNetlist:
    """gnucap's netlist, its fixed step h (0 for an AC sweep), and each saved vector (ngspice's name) as a sum of
    printed columns (gnucap's name, coefficient)."""

    text: str
    step: float
    vectors: tuple[tuple[str, tuple[tuple[str, float], ...]], ...]
    names: tuple[tuple[str, str], ...]  # (the user's element name, gnucap's)


@dataclass(frozen=True)
class CheckedRun:
    """gnucap's time points (the t = 0 row dropped) or frequencies (Hz; ``time`` then holds them), the saved
    vectors by ngspice's names (complex phasors in an AC sweep), its wall time."""

    time: np.ndarray
    vectors: Mapping[str, np.ndarray]
    wall_s: float
    engine_version: str


def _word(value: float) -> str:
    if not math.isfinite(value):
        raise _refuse(f"the value {value!r}")
    return repr(float(value))


def check_netlist(cards: NetlistCards, functions: Mapping[str, tuple[str, tuple[float, ...]]], step: float,
                  stop: float, start: float, vectors: Sequence[str],
                  sweep: tuple[str, int, float, float] | None = None) -> GnucapCheckNetlist:
    """gnucap's netlist of the cards.

    Parameters
    ----------
    cards : NetlistCards
        The netlist's elements, read as numbers (only R, L, C, K, V and I cards are written).
    functions : mapping
        Each source's (lower-case name) transient function and its arguments, every default filled in (as the
        exact reference reads them); absent: a constant.
    step, stop, start : float
        The run's fixed step (seconds, the smaller of the ``.tran`` step and its maximum step), its end, its start.
    vectors : sequence of str
        Canonical names (``v(out)``, ``v(a,b)``, ``i(v1)``, ``i(l1)``, ``@r1[i]``); empty: every node voltage and
        the current of every V source and coil, as ngspice saves them.
    sweep : (spacing, count, f1, f2), optional
        An AC analysis instead: ``.ac lin count f1 f2`` or ``.ac dec|oct count f1 f2`` (count per decade or
        octave); the sources' AC magnitudes, their transient functions left out (``step``, ``stop`` unused).

    Raises
    ------
    ParameterError
        What gnucap cannot run exactly, named in one line.
    """
    if cards.initial or cards.uic:
        raise _refuse(".ic or uic (gnucap starts from initial conditions without ngspice's operating point)")
    if cards.method != "trap":
        raise _refuse(f"method={cards.method} (lcchain runs gnucap with the trapezoidal rule only)")
    if start != 0 and sweep is None:
        raise _refuse("a .tran start time other than 0 (gnucap's table starts at 0)")
    nodes: dict[str, str] = {}

    def node(label: str) -> str:
        if label in GROUND:
            return "0"
        return nodes.setdefault(label, f"n{len(nodes) + 1}")

    counts: dict[str, int] = {}
    renamed: dict[str, str] = {}
    body: list[str] = []
    ends: dict[str, tuple[str, str]] = {}  # gnucap's name -> (node a, node b), for Kirchhoff's law

    def rename(letter: str, name: str) -> str:
        counts[letter] = counts.get(letter, 0) + 1
        renamed[name] = f"{letter}{counts[letter]}"
        return renamed[name]

    for card in cards.elements:
        if isinstance(card, OtherCard):
            raise _refuse(f"the element {card.name.upper()}")
        if isinstance(card, ControlledCard):  # its current's sign and Kirchhoff's law through it: not read here
            raise _refuse(f"the controlled source {card.name.upper()} (lcchain writes gnucap's copy of R, L, C, K, "
                          "V and I cards)")
        if isinstance(card, ElementCard):
            keywords = dict(card.keywords)
            if "ic" in keywords:
                raise _refuse(f"ic= on {card.name.upper()} (gnucap reads it without ngspice's uic)")
            if set(keywords) - {"m", "tc1", "tc2"} or keywords.get("tc1", 0.0) or keywords.get("tc2", 0.0):
                raise _refuse(f"the keywords of {card.name.upper()}")
            m = keywords.get("m", 1.0)
            value = card.value / m if card.letter in "RL" else card.value * m
            name = rename(card.letter, card.name)
            a, b = node(card.a), node(card.b)
            ends[name] = (a, b)
            body.append(f"{name} {a} {b} {_word(value)}")
        elif isinstance(card, CouplingCard):
            if card.first not in renamed or card.second not in renamed:
                raise _refuse(f"the coupling {card.name.upper()} before its coils")
            body.append(f"{rename('K', card.name)} {renamed[card.first]} {renamed[card.second]} {_word(card.k)}")
        else:
            name = rename(card.letter, card.name)
            if sweep is not None:
                if card.ac[1]:
                    raise _refuse(f"the source {card.name.upper()}: an AC phase (gnucap reads the magnitude only)")
                body.append(f"{name} {node(card.a)} {node(card.b)} DC 0.0 AC {_word(card.ac[0])}")
            else:
                body.append(_source(card, functions.get(card.name), name, node(card.a), node(card.b)))
            ends[renamed[card.name]] = (node(card.a), node(card.b))
    if not nodes:
        raise _refuse("a netlist without nodes")
    wanted = list(vectors) or [*(f"v({label})" for label in nodes),
                               *(f"i({name})" for name in renamed if name[0] in "vl")]
    read = tuple((name, _columns(name, nodes, renamed, ends)) for name in wanted)
    printed = sorted({column for _, terms in read for column, _ in terms})
    if not printed:
        raise _refuse("a run without a vector to print (only ground is saved)")
    if sweep is not None:
        spacing, count, f1, f2 = sweep
        if spacing not in ("lin", "dec", "oct") or count < 1 or not 0 < f1 <= f2:
            raise _refuse(f"the sweep {spacing} {count} {f1!r} {f2!r}")
        options = [f"numdgt={AC_DIGITS}", f"short={CHECK_SOURCE_RESISTANCE!r}", f"gmin={GMIN!r}"]
        ac = " ".join(f"{what[0]}r{what[1:]} {what[0]}i{what[1:]}" for what in printed)
        text = "\n".join([TITLE, *body, ".options " + " ".join(options), ".print ac " + ac,
                          f".ac {spacing} {int(count)} {_word(f1)} {_word(f2)}", ".end"]) + "\n"
        return GnucapCheckNetlist(text, 0.0, read, tuple(renamed.items()))
    h = stop / math.ceil(stop / step * (1 - 1e-12))  # gnucap prints, and stops, on multiples of its print step
    options = [f"numdgt={CHECK_DIGITS}", "method=trap", "noincmode", f"short={CHECK_SOURCE_RESISTANCE!r}",
               f"gmin={GMIN!r}", f"dtmin={h * DTMIN_FRACTION!r}", f"vmax={VOLTAGE_LIMIT!r}", f"vmin={-VOLTAGE_LIMIT!r}"]
    text = "\n".join([TITLE, *body, ".options " + " ".join(options), ".print tran " + " ".join(printed),
                      f".tran {h!r} {stop!r} 0 dtmax={h!r}", ".end"]) + "\n"
    return GnucapCheckNetlist(text, h, read, tuple(renamed.items()))


def _source(card: SourceCard, function: tuple[str, tuple[float, ...]] | None, name: str, a: str, b: str) -> str:
    if function is None or not function[0]:
        return f"{name} {a} {b} {_word(card.dc or 0.0)}"
    kind, arguments = function
    if kind not in _FUNCTIONS:
        raise _refuse(f"the source {card.name.upper()}: {kind.upper()}")
    most = _FUNCTIONS[kind]
    if kind == "sin" and len(arguments) > 5:
        if any(arguments[5:]):
            raise _refuse(f"the source {card.name.upper()}: SIN with a phase (gnucap's SIN has none)")
        arguments = arguments[:5]
    if most is not None and len(arguments) > most:
        raise _refuse(f"the source {card.name.upper()}: {kind.upper()} with {len(arguments)} arguments")
    if kind == "pwl":
        arguments = _steps_at_one_time(arguments)
    return f"{name} {a} {b} {kind}({' '.join(_word(v) for v in arguments)})"


def _steps_at_one_time(pairs: tuple[float, ...]) -> tuple[float, ...]:
    """A PWL's (time, value) pairs with a step written at one time: a point one rounding step before the next (a
    repeated PWL's jump back, ngspice's value at the jump being the new one) is moved onto it, as gnucap refuses
    two times that close ("PWL is out of order") and takes a step at one time."""
    times, values = list(pairs[0::2]), pairs[1::2]
    for k in range(len(times) - 1):
        if times[k] < times[k + 1] <= math.nextafter(times[k], math.inf):
            times[k] = times[k + 1]
    return tuple(x for point in zip(times, values, strict=True) for x in point)


def _columns(name: str, nodes: Mapping[str, str], renamed: Mapping[str, str],
             ends: Mapping[str, tuple[str, str]]) -> tuple[tuple[str, float], ...]:
    """A saved vector (ngspice's name) as gnucap's printed columns times coefficients."""
    def voltage(label: str) -> tuple[tuple[str, float], ...]:
        if label in GROUND:
            return ()
        if label not in nodes:
            raise _refuse(f"the vector {name} (no node {label!r})")
        return ((f"v({nodes[label]})", 1.0),)

    if name.startswith("v(") and name.endswith(")"):
        parts = name[2:-1].split(",")
        if len(parts) == 1:
            return voltage(parts[0])
        if len(parts) == 2:
            return (*voltage(parts[0]), *((c, -k) for c, k in voltage(parts[1])))
    label = name[2:-1] if name.startswith("i(") and name.endswith(")") else \
        name[1:-3] if name.startswith("@") and name.endswith("[i]") else ""
    element = renamed.get(label, "")
    if element[:1] in ("R", "L", "C", "I") and (name.startswith("@") or element[0] in "LI"):
        return ((f"i({element})", 1.0),)
    if element[:1] == "V":
        return _kirchhoff(name, element, ends)
    raise _refuse(f"the vector {name} (lcchain reads v(node), v(a,b), i(V or L name) and @R/@C/@L[i] from "
                  "gnucap)")


def _kirchhoff(name: str, source: str, ends: Mapping[str, tuple[str, str]]) -> tuple[tuple[str, float], ...]:
    """A voltage source's current (first node to second, through it) as minus the other elements' currents
    leaving its first node, or plus those leaving its second."""
    a, b = ends[source]
    for label, sign in ((a, -1.0), (b, 1.0)):
        if label == "0":
            continue
        others = [(element, ends[element]) for element in ends if element != source and label in ends[element]]
        if any(element[0] == "V" for element, _ in others):
            continue
        terms: list[tuple[str, float]] = []
        for element, (x, y) in others:
            if x != y:
                terms.append((f"i({element})", sign * (1.0 if x == label else -1.0)))
        return tuple(terms)
    raise _refuse(f"the vector {name} (gnucap prints no current of a voltage source; lcchain sums the currents at "
                  "one of its nodes, and each of its nodes is ground or another voltage source's)")


def run_check(netlist: GnucapCheckNetlist, stop: float, *, simulator: Simulator, timeout: float) -> CheckedRun:
    """Run gnucap's netlist (in the sandbox of foreign netlists where there is one, :mod:`lcchain.spice.sandbox`,
    else in a scratch folder; its process group killed after ``timeout``) and read its vectors back by ngspice's
    names.  ``simulator`` is gnucap's program, as an engine that ``checks_cards`` found it (the caller chose
    the engine by that attribute, :func:`lcchain.runs.check.check_text`; its name is not asked here)."""
    import numpy as np

    output, log, wall = _run_child(TransportJob(netlist.text, stop, timeout, MAX_OUTPUT_BYTES, None), simulator,
                                   sandbox=find_sandbox())
    # gnucap's warning at the operating point with short=1e-30 (the values are those of short=1e-15, which
    # prints none, to every digit): not a row of its table
    output = "\n".join(line for line in output.splitlines() if not _OPEN_NODE.match(line))
    ac = netlist.step == 0.0
    columns = read_ac_table(output, log) if ac else read_table(output, log)
    time = columns["frequency" if ac else "time"]
    vectors: dict[str, np.ndarray] = {}
    for name, terms in netlist.vectors:
        total = np.zeros(time.size, dtype=complex if ac else float)
        for column, k in terms:
            total = total + k * columns[canonical_vector_name(column)]
        vectors[name] = total
    return CheckedRun(time, vectors, wall, simulator.version)
