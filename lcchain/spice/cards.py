"""The grammar of the hierarchical and device cards of a netlist lcchain did not write, shared by the allow-list
(:mod:`lcchain.spice.foreign`) and the price (:mod:`lcchain.spice.pricing`).

Sub-circuits (``.subckt NAME NODES... [params: a=1 ...]`` ... ``.ends [NAME]``, instantiated by ``X`` lines),
device models (``.model NAME TYPE (name=value ...)`` for the types of :data:`MODEL_TYPES`, used by the ``D Q M J
S W`` lines of :data:`DEVICES` and by R, L and C), user functions (``.func NAME(ARGS) = {EXPR}``), ``.global``,
``.temp`` and the ``.dc`` sweep: each is parsed here into plain values, nothing more.  Whether a card's first word
is one of them follows ngspice 39's own reading (:func:`command_of`).

A sub-circuit is never expanded in the text ngspice receives (ngspice expands it); it is expanded here only to
count: :func:`multiplicities` gives how many copies of each definition's body the flattened circuit holds, so
that the elements, unknowns and couplings of ten sub-circuits each instantiating the next ten times are counted
as the 10^10 they are (and refused), not as the 20 lines they are written in.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

from .expressions import braced_expressions
from .text import spice_number

__all__ = ["MODEL_TYPES", "DEVICES", "MAX_SUBCKT_DEPTH", "MAX_FUNCTION_CHARS", "command_of", "Header", "Instance",
           "Model", "Function", "subckt_header", "instance", "model_card", "func_card", "dc_points",
           "multiplicities", "function_sizes", "device_model", "Cycle", "TooDeep", "NODE"]

#: ``.model`` types a netlist may define (ngspice's names), and the element letter that uses each.
MODEL_TYPES: Mapping[str, str] = {
    "r": "R", "c": "C", "l": "L", "d": "D", "npn": "Q", "pnp": "Q", "nmos": "M", "pmos": "M", "njf": "J",
    "pjf": "J", "sw": "S", "csw": "W",
}
#: Device lines that name a model: letter -> (fewest nodes, most nodes) before the model name.  ``W`` has two
#: nodes and the voltage source whose current controls it.
DEVICES: Mapping[str, tuple[int, int]] = {"D": (2, 2), "Q": (3, 5), "M": (4, 7), "J": (3, 3), "S": (4, 4),
                                          "W": (3, 3)}
#: How deep sub-circuits may nest: definitions inside definitions, and instances inside instances.
MAX_SUBCKT_DEPTH = 10
#: The longest a ``.func`` body may grow with every function it calls written out: ngspice 39 expands user
#: functions by substitution, so f18(x) = f17(x) + f17(x) ... costs 2^18 substitutions (it ran 20 s and was
#: killed), and a function that calls itself crashes it (a segmentation fault: measured).
MAX_FUNCTION_CHARS = 10_000

# ngspice 39 (measured, ``ngspice -b``): these dot-commands are read by their start, in any case (``.models``,
# ``.MODEL_X``, ``.funcx``, ``.globals``, ``.ENDSX``, ``.endsrdiv`` are the command; ``.mod``, ``.fun``, ``.glob``
# are "unimplemented control card" errors) ...
_PREFIXED = (".ends", ".model", ".func", ".global")
# ... and these only whole (``.subcktx``, ``.SUBCKT_X`` define nothing: "Cannot find called subcircuit";
# ``.tempx``, ``.opx``, ``.ops``, ``.dcx``, ``.dc_x`` are "unimplemented control card" errors).
_WHOLE = (".subckt", ".temp", ".op", ".dc")
_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
#: A node name: letters, digits and ``_ # . - + :``, not starting with a dot (no ``.control`` node a joined
#: continuation could make).
NODE = re.compile(r"[A-Za-z0-9_#][A-Za-z0-9_#.\-+:]*")
_EQUALS = re.compile(r"\s*=\s*")
_FUNC = re.compile(r"\s*([A-Za-z_][A-Za-z0-9_]*)\s*\(([^()]*)\)\s*=?\s*(.*)$", re.DOTALL)


def command_of(word: str) -> str | None:
    """The command ngspice 39 reads a card whose first word is ``word`` (lower case) as, among the cards of this
    module (``".model"`` for ``.models``), or None."""
    for command in _PREFIXED:
        if word.startswith(command):
            return command
    return word if word in _WHOLE else None


def _protected(text: str) -> tuple[str, list[str]]:
    """``text`` with each ``{...}`` replaced by ``{k}`` (k its index), ``=`` without spaces around it, and the
    groups: a braced expression may hold spaces, parentheses and commas of its own."""
    groups, _ = braced_expressions(text)
    parts = re.split(r"\{[^{}]*\}", text)
    out = parts[0]
    for k, part in enumerate(parts[1:]):
        out += "{" + str(k) + "}" + part
    return _EQUALS.sub("=", out), groups


def _value(word: str, groups: Sequence[str]) -> str | None:
    """An assignment's value: a braced expression's text, a number's or a name's; None if neither."""
    if word.startswith("{") and word.endswith("}") and word[1:-1].isdigit() and int(word[1:-1]) < len(groups):
        return groups[int(word[1:-1])]
    if spice_number(word) is not None or _NAME.fullmatch(word):
        return word
    return None


def _assignments(words: Sequence[str], groups: Sequence[str]) -> list[tuple[str, str]] | None:
    found = []
    for word in words:
        name, equals, value = word.partition("=")
        text = _value(value, groups) if equals else None
        if not _NAME.fullmatch(name) or text is None:
            return None
        found.append((name.lower(), text))
    return found


@dataclass(frozen=True)
class Header:
    """A ``.subckt`` card: its name, its nodes (lower case) and its parameters' defaults (expression text)."""

    name: str
    nodes: tuple[str, ...]
    params: tuple[tuple[str, str], ...]


def subckt_header(body: str) -> Header | None:
    """``.subckt NAME NODE... [params:] [a=1 b={expr} ...]``, or None."""
    text, groups = _protected(body)
    words = text.split()[1:]
    if not words or not _NAME.fullmatch(words[0]):
        return None
    nodes = []
    rest: list[str] = []
    for k, word in enumerate(words[1:], start=1):
        if word.lower() == "params:" or "=" in word:
            rest = words[k + (word.lower() == "params:"):]
            break
        if not NODE.fullmatch(word):
            return None
        nodes.append(word.lower())
    params = _assignments(rest, groups)
    if params is None or not nodes:
        return None
    return Header(words[0].lower(), tuple(nodes), tuple(params))


@dataclass(frozen=True)
class Instance:
    """An ``X`` line: its nodes, the sub-circuit it names, its parameters (expression text)."""

    nodes: tuple[str, ...]
    subckt: str
    params: tuple[tuple[str, str], ...]


def instance(body: str) -> Instance | None:
    """``Xname NODE... SUBCKT [params:] [a=1 b={expr} ...]``, or None."""
    text, groups = _protected(body)
    words = text.split()[1:]
    end = next((k for k, w in enumerate(words) if "=" in w or w.lower() == "params:"), len(words))
    params = _assignments(words[end + (end < len(words) and words[end].lower() == "params:"):], groups)
    if end < 1 or params is None or not _NAME.fullmatch(words[end - 1]) or not all(
            NODE.fullmatch(w) for w in words[:end - 1]):
        return None
    return Instance(tuple(w.lower() for w in words[:end - 1]), words[end - 1].lower(), tuple(params))


@dataclass(frozen=True)
class Model:
    """A ``.model`` card: its name, type (lower case) and parameters (expression text)."""

    name: str
    kind: str
    params: tuple[tuple[str, str], ...]

    @property
    def level(self) -> float:
        """Its ``level=`` (1 when it gives none or not a plain number)."""
        value = spice_number(dict(self.params).get("level", "1"))
        return value if value is not None else 1.0


def model_card(body: str) -> Model | None:
    """``.model NAME TYPE [(] name=value ... [)]``, the values numbers or braced expressions, or None."""
    text, groups = _protected(body)
    words = text.replace("(", " ").replace(")", " ").replace(",", " ").split()[1:]
    if len(words) < 2 or not _NAME.fullmatch(words[0]) or words[1].lower() not in MODEL_TYPES:
        return None
    if any(spice_number(w.partition("=")[2]) is None and not re.fullmatch(r"\{\d+\}", w.partition("=")[2])
           for w in words[2:]):
        return None  # a model parameter is a number or an expression in braces, never a bare word
    params = _assignments(words[2:], groups)
    if params is None:
        return None
    return Model(words[0].lower(), words[1].lower(), tuple(params))


@dataclass(frozen=True)
class Function:
    """A ``.func`` card: its name, arguments (lower case) and body (expression text)."""

    name: str
    args: tuple[str, ...]
    body: str


def func_card(body: str) -> Function | None:
    """``.func NAME(ARG, ...) [=] {EXPR}`` (or the expression without braces), or None."""
    match = _FUNC.match(body.split(None, 1)[1] if len(body.split(None, 1)) > 1 else "")
    if match is None:
        return None
    name, args, expression = match.group(1), match.group(2).replace(",", " ").split(), match.group(3).strip()
    if expression.startswith("{") and expression.endswith("}"):
        expression = expression[1:-1]
    if not expression.strip() or "{" in expression or "}" in expression or not all(
            _NAME.fullmatch(a) for a in args) or len(set(a.lower() for a in args)) != len(args):
        return None
    return Function(name.lower(), tuple(a.lower() for a in args), expression)


def dc_points(body: str, *, most: int) -> int | None:
    """How many points ngspice 39 computes for ``.dc SRC START STOP STEP [SRC2 START2 STOP2 STEP2]``: each sweep
    from START by STEP while not past STOP (measured: ``0 1 0.3`` is 4 points, ``1 0 -0.25`` 5), the second
    nested in the first; None when the card is not that with plain numbers, a STEP of the wrong sign (ngspice
    computes nothing) or more than ``most`` points."""
    words = body.split()[1:]
    if len(words) not in (4, 8):
        return None
    total = 1
    for k in range(0, len(words), 4):
        source = words[k]
        values = [spice_number(w) for w in words[k + 1:k + 4]]
        if not (_NAME.fullmatch(source) and source[0].upper() in "VIR" or source.lower() == "temp"):
            return None
        if any(v is None or not math.isfinite(v) for v in values):
            return None
        start, stop, step = (float(v) for v in values)  # type: ignore[arg-type]
        if step == 0 or (stop - start) * step < 0:
            return None
        count = math.floor((stop - start) / step * (1 + 1e-9) + 1e-9) + 1
        total *= count
        if total > most:
            return None
    return total


def device_model(letter: str, words: Sequence[str], models: Mapping[str, Model]) -> tuple[int, Model] | None:
    """(nodes, model) of a device line (``words``: its words, the name first), the model the first word after
    its fewest nodes that names one of ``models`` of its letter's type; None if there is none."""
    fewest, most = DEVICES[letter]
    for k in range(1 + fewest, min(2 + most, len(words))):
        found = models.get(words[k].lower())
        if found is not None and MODEL_TYPES[found.kind] == letter:
            return k - 1, found
    return None


class Cycle(Exception):
    """A definition that instantiates or calls itself, directly or not: the path, the first name again last."""

    def __init__(self, path: list[str]) -> None:
        super().__init__(path)
        self.path = path


class TooDeep(Exception):
    """Definitions nested deeper than allowed: the path from the top."""

    def __init__(self, path: list[str]) -> None:
        super().__init__(path)
        self.path = path


def _post_order(calls: Mapping[str, Sequence[str]], top: str, depth: int, done: set[str]) -> list[str]:
    """The definitions reached from ``top`` and not in ``done``, each after everything it instantiates (an
    iterative walk: a chain of thousands of definitions needs no deep recursion); raises :class:`Cycle` or
    :class:`TooDeep`."""
    order: list[str] = []
    walking: dict[str, int] = {top: 0}  # on the path being walked: its place there
    path = [top]
    children = [iter(calls.get(top, ()))]
    while children:
        child = next(children[-1], None)
        if child is None:
            children.pop()
            finished = path.pop()
            del walking[finished]
            done.add(finished)
            order.append(finished)
            continue
        if child in walking:
            raise Cycle(path[walking[child]:] + [child])
        if child in done:
            continue
        if len(path) > depth:
            raise TooDeep([*path[1:], child])
        walking[child] = len(path)
        path.append(child)
        children.append(iter(calls.get(child, ())))
    return order


def multiplicities(calls: Mapping[str, Sequence[str]], top: str = "", *, depth: int = MAX_SUBCKT_DEPTH
                   ) -> dict[str, int]:
    """How many copies of each definition's body the flattened circuit holds (``top``: 1), given what each
    definition instantiates (``calls[name]``, one entry per ``X`` line; ``calls[top]``: the netlist's own).
    Only definitions reached from ``top`` are counted.

    Raises
    ------
    Cycle
        A definition that instantiates itself, directly or not.
    TooDeep
        Instances nested more than ``depth`` deep.
    """
    order = _post_order(calls, top, depth, set())
    count = dict.fromkeys(order, 0)
    count[top] = 1
    for name in reversed(order):  # every definition before those it instantiates
        for child in calls.get(name, ()):
            count[child] += count[name]
    return count


def function_sizes(functions: Mapping[str, Function]) -> dict[str, int]:
    """The length of each function's body with every user function it calls written out (an argument's text
    counted once per use of the call; the arguments are short next to the bodies that matter).

    Raises
    ------
    Cycle
        A function that calls itself, directly or not.
    """
    calls = {name: [w.lower() for w in re.findall(r"([A-Za-z_][A-Za-z0-9_]*)\s*\(", f.body)
                    if w.lower() in functions] for name, f in functions.items()}
    sizes: dict[str, int] = {}
    done: set[str] = set()
    for name in functions:
        for each in _post_order(calls, name, len(functions) + 1, done):  # each after those it calls
            sizes[each] = len(functions[each].body) + sum(sizes[c] for c in calls[each])
    return sizes
