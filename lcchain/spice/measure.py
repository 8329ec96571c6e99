"""``.meas``/``.measure`` cards of a netlist lcchain did not write: their grammar, and their values read back.

Allowed (ngspice 39 syntax; the words in any case, ``=`` with or without spaces around it)::

    .meas[ure] tran|ac NAME TRIG OUT VAL=v [TD=t] [RISE=n|FALL=n|CROSS=n|CROSS=LAST...] TARG OUT VAL=v [...]
    .meas[ure] tran|ac NAME TRIG AT=t TARG OUT VAL=v [...]
    .meas[ure] tran|ac NAME WHEN OUT=v|OUT=OUT2 [TD=t] [RISE=n|FALL=n|CROSS=n]
    .meas[ure] tran|ac NAME FIND OUT AT=t
    .meas[ure] tran|ac NAME FIND OUT WHEN OUT2=v [...]
    .meas[ure] tran|ac NAME DERIV[ATIVE] OUT AT=t | WHEN OUT2=v [...]
    .meas[ure] tran|ac NAME AVG|MIN|MAX|PP|RMS|MIN_AT|MAX_AT|INTEG[RAL] OUT [FROM=t] [TO=t] [TD=t]

where OUT is a vector: ``v(node)``, ``v(a,b)``, ``i(source)`` and, for an AC sweep, ``vdb vm vp vr vi idb im
ip ir ii`` of the same; a value is a SPICE number, a number in braces or a braced expression
(:mod:`lcchain.spice.expressions`).  ngspice 39 reads ``.meas`` and ``.measure`` and nothing else (``.mea``,
``.measu``, ``.measures`` are errors there: checked), so only those two words are measurement cards.  A netlist
holds at most :data:`MAX_MEASUREMENTS`, each NAME once; no ``PARAM='...'`` (a quoted string) and nothing that
writes a file (ngspice's ``.meas`` has no such option; its ``meas`` command and ``print``/``write`` lines are in
control blocks, which stay refused).

Running them
------------
ngspice 39 does no measurement in batch mode with ``-r RAWFILE`` ("No .measure possible in batch mode (-b) with
-r rawfile set!").  So a netlist that holds ``.meas`` cards runs with a control block lcchain writes
(:func:`measure_control`: ``run``, ``write`` the raw file, ``quit``): the same analysis, once, the same raw file
(checked byte for byte past its date line), and the measurements printed on standard output as
``name = value ...`` lines, read back by :func:`read_measurements`.  A measurement ngspice could not make
prints ``Error: measure NAME ...: reason`` and `` .meas ... NAME ... failed!``: it is kept as missing (None) with
ngspice's reason, and does not fail the run.
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Mapping, Sequence

from ..core.errors import ParameterError
from .expressions import check_expression
from .text import DotCard, dot_cards

__all__ = ["valid_measure_name", "measurement_fields", "MEASUREMENTS", "MEASURE_REASONS", "MEASURE_WORDS",
           "MEASURE_KINDS", "MAX_MEASUREMENTS", "check_measure", "measure_names", "measure_names_in",
           "measure_control",
           "read_measurements", "Measurements"]

#: The dot-commands that are measurements in ngspice 39.
MEASURE_WORDS = frozenset({".meas", ".measure"})
#: What a measurement may be.
MEASURE_KINDS = frozenset({"trig", "when", "find", "deriv", "derivative", "avg", "min", "max", "pp", "rms",
                           "min_at", "max_at", "integ", "integral"})
#: Most measurements one netlist holds.
MAX_MEASUREMENTS = 100
#: Longest measurement name.
MAX_NAME_CHARS = 64

_ANALYSES = ("tran", "ac")
_KEYWORDS = frozenset({"trig", "targ", "when", "at", "val", "td", "cross", "rise", "fall", "from", "to", "last"})
_COUNTS = frozenset({"cross", "rise", "fall"})
_NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?[A-Za-z]*")
_NODE = r"[A-Za-z0-9_#][A-Za-z0-9_#.\-+:]*"  # as an element line's nodes (lcchain.spice.cards.NODE)
_VECTOR = re.compile(rf"(v|vdb|vm|vp|vr|vi|i|idb|im|ip|ir|ii)\(({_NODE})(,{_NODE})?\)", re.IGNORECASE)
_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
_CARD = re.compile(r"^\s*\.meas(?:ure)?\s+(?:tran|ac)\s+([A-Za-z_][A-Za-z0-9_]*)\b", re.IGNORECASE)
_CONTROL = re.compile(r"^\s*\.control", re.IGNORECASE | re.MULTILINE)
_END = re.compile(r"^[ \t]*\.end[ \t]*$", re.IGNORECASE | re.MULTILINE)

#: A run's measurements: name (lower case) -> (value, or None where ngspice could not make it; ngspice's reason).
Measurements = Mapping[str, tuple[float | None, str]]


def _value(token: str, used: set[str], where: str, line: str) -> None:
    if token.startswith("{") and token.endswith("}"):
        used |= check_expression(token[1:-1], None, where, line)
    elif _NUMBER.fullmatch(token) is None:
        raise ParameterError(where, line.strip()[:200], f"a number or a braced expression, not {token!r}")


def check_measure(body: str, taken: set[str], where: str, line: str) -> set[str]:
    """Check one ``.meas`` card (its text, the first word included) against the grammar above; its name (lower
    case) is added to ``taken``; return the ``.param`` names its braced values use."""
    names: set[str] = set()
    allowed = (".meas tran|ac NAME TRIG|WHEN|FIND|DERIV|AVG|MIN|MAX|PP|RMS|MIN_AT|MAX_AT|INTEG ... with vectors "
               "v(node), i(source) (vdb, vm, vp, vr, vi in an AC sweep), numbers and the keywords "
               f"{', '.join(sorted(_KEYWORDS))}")
    text = re.sub(r"\s*=\s*", "=", body.strip())
    text = re.sub(r"\{[^{}]*\}", lambda group: "".join(group.group().split()), text)  # one word per expression
    words = text.split()
    if len(words) < 4 or words[1].lower() not in _ANALYSES:
        raise ParameterError(where, line.strip()[:200], allowed)
    name = words[2].lower()
    if not valid_measure_name(name) or name in _KEYWORDS or name in MEASURE_KINDS:
        raise ParameterError(where, line.strip()[:200], f"a measurement name of at most {MAX_NAME_CHARS} letters, "
                             f"digits and _ that is no keyword, not {words[2]!r}")
    if name in taken:
        raise ParameterError(where, line.strip()[:200], f"a measurement name used once ({name!r} is taken)")
    if len(taken) >= MAX_MEASUREMENTS:
        raise ParameterError(where, line.strip()[:200], f"at most {MAX_MEASUREMENTS} measurements in a netlist")
    if words[3].lower() not in MEASURE_KINDS:
        raise ParameterError(where, line.strip()[:200], allowed)
    for token in words[4:]:
        key, equals, value = token.partition("=")
        lower = key.lower()
        if not equals:
            if lower not in _KEYWORDS and _VECTOR.fullmatch(key) is None:
                raise ParameterError(where, line.strip()[:200], f"{allowed}; not {token!r}")
            continue
        if lower in _COUNTS:
            if not (value.isdigit() or value.lower() == "last"):
                raise ParameterError(where, line.strip()[:200], f"{key}=N (a whole number) or {key}=LAST")
        elif lower in _KEYWORDS:
            _value(value, names, where, line)
        elif _VECTOR.fullmatch(key) is not None:  # WHEN OUT=value, or OUT=OUT2
            if _VECTOR.fullmatch(value) is None:
                _value(value, names, where, line)
        else:
            raise ParameterError(where, line.strip()[:200], f"{allowed}; not {token!r}")
    taken.add(name)
    return names


def valid_measure_name(name: str) -> bool:
    """Whether ``name`` could name a measurement (letters, digits and _, at most :data:`MAX_NAME_CHARS`)."""
    return _NAME.fullmatch(name) is not None and len(name) <= MAX_NAME_CHARS


def measure_names(text: str) -> list[str]:
    """The measurement names of a checked netlist's ``.meas`` cards, in order (lower case)."""
    return measure_names_in(dot_cards(text, canonical=False))  # a .meas card is a dot card


def measure_names_in(cards: Sequence[DotCard]) -> list[str]:
    """:func:`measure_names` of a netlist's :func:`~lcchain.spice.text.dot_cards`."""
    names = []
    for _, line, _ in cards:  # each physical line that starts a card
        match = _CARD.match(line)
        if match:
            names.append(match.group(1).lower())
    return list(dict.fromkeys(names))


def measure_control(text: str, raw: str, *, always: bool = False) -> str | None:
    """The netlist with the control block that runs its measurements and writes the raw file to ``raw``, put
    before its ``.end`` (or after its last line), so that ngspice's line numbers in its messages are the user's
    (after the title, it moved every line by five); None when it has no ``.meas`` card, or has its own control
    block (a trusted netlist: it runs as written); ``always``: with no ``.meas`` too (a raw file written from
    what ngspice holds, not as it goes: with ``.options interp`` ngspice 39's ``-r`` file holds 16 points more
    than its header counts)."""
    if not (measure_names(text) or always) or _CONTROL.search(text):
        return None
    # the first line is the title, blank or not (ngspice 39 -b reads a blank first line as an empty title)
    if "\n" not in text:
        return None
    block = f".control\nrun\nwrite {raw}\nquit\n.endc\n"
    end = _END.search(text, text.index("\n") + 1)
    if end is None:
        return f"{text}{'' if text.endswith(chr(10)) else chr(10)}{block}"
    return f"{text[:end.start()]}{block}{text[end.start():]}"


def read_measurements(log: str, names: Iterable[str]) -> dict[str, tuple[float | None, str]]:
    """Each measurement's value as ngspice printed it (``name = value``), or None and ngspice's reason."""
    found: dict[str, tuple[float | None, str]] = {}
    wanted = list(names)
    lines = log.splitlines()
    for name in wanted:
        value = re.compile(rf"^\s*{re.escape(name)}\s*=\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)(?:\s|$)",
                           re.IGNORECASE)
        error = re.compile(rf"^\s*Error:\s*measure\s+{re.escape(name)}\s+(.*)$", re.IGNORECASE)
        failed = re.compile(rf"^\s*\.meas\w*\s+\w+\s+{re.escape(name)}\s.*failed!\s*$", re.IGNORECASE)
        reason = said = ""
        before = ""  # the line before, blank lines aside
        for line in lines:
            match = value.match(line)
            if match:
                found[name] = (float(match.group(1)), "")
                break
            match = error.match(line)
            if match and not reason:
                reason = " ".join(match.group(1).split())
            if failed.match(line) and not said:  # the shared library prints this line, not "Error: measure ..."
                # after an "Error: ..." line that says why ("no such vector as v(zz)."), or after none
                why = before.strip()
                why = " ".join(why[len("error:"):].split()) if why.lower().startswith("error:") else ""
                said = why or "failed (it printed no reason)"
            if line.strip():
                before = line
        else:
            reason = reason or said
            found[name] = (None, f"ngspice: {reason}" if reason else "ngspice printed no value")
    return found


#: The keys under which a run's measurements are kept in its stored metrics (JSON): values by name (None: missing),
#: and ngspice's reason for each missing one.
MEASUREMENTS = "measurements"
MEASURE_REASONS = "measure_reasons"


def measurement_fields(measurements: Measurements) -> dict[str, dict[str, float | str | None]]:
    """A run's measurements as JSON: ``{"measurements": {name: value or None}, "measure_reasons": {name:
    reason}}`` (the reasons of the missing ones only)."""
    return {MEASUREMENTS: {name: value for name, (value, _) in measurements.items()},
            MEASURE_REASONS: {name: reason for name, (value, reason) in measurements.items() if value is None}}
