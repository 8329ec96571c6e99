"""Netlists lcchain did not write: what of them it lets ngspice see (an allow-list), and what they cost.

ngspice executes ``shell`` commands from ``.control`` blocks, reads whatever
file an ``.include`` names, matches dot-commands by prefix (``.controls`` and
``.CONTROL_X`` open a control block, ``.inc_x`` includes a file) and treats a
file whose first card is ``*ng_script`` as a script.  A deny-list of such lines
is always one disguise short, so :func:`allowed_netlist` does the opposite: it
parses the netlist, and every file it includes, against what lcchain
understands, and refuses anything else before anything runs, naming the file,
the line number and the line.

Allowed
-------
* the title: the first non-blank line, any text but a dot-command (``.title
  TEXT``, as PySpice writes it, excepted), ``*#`` or ``*ng_script``;
* blank lines and ``*`` comments (not ``*#``, which ngspice may read as a
  command, nor ``*ng_script``); an inline comment after ``;`` or `` $`` is
  dropped;
* element lines whose first letter is one of :data:`ELEMENTS` (R, L, C, K,
  V, I, the controlled sources E, F, G, H, the behavioural source B that
  lcchain's own pulses use, the devices D, Q, M, J, S, W and sub-circuit
  instances X), written in :data:`_CHARACTERS` (no quotes, backslashes or
  control characters);
* the dot-commands of :data:`DOT_COMMANDS`, the word matched whole:
  ``.tran``, ``.ac``, ``.options`` with the names of :data:`OPTIONS`,
  ``.save``, ``.ic``, ``.nodeset`` (a guess for the operating point's solver, nothing more), ``.end``;
* ``.param name = value ...`` (and every word ngspice 39 reads as ``.param``: ``.params``, ``.PARAM_X``), its
  values, and every ``{...}`` expression of any card, held to numbers, ``.param`` names, arithmetic and
  ngspice's math functions (:mod:`lcchain.spice.expressions`), at most
  :data:`lcchain.spice.expressions.MAX_PARAMS` names;
* ``.meas``/``.measure`` of a ``tran`` or ``ac`` analysis, in the grammar of :mod:`lcchain.spice.measure`;
* sub-circuits: ``.subckt NAME NODE... [params: a=1 b={expr}]`` ... ``.ends [NAME]``, holding element lines and
  the cards of :data:`SUBCKT_COMMANDS` only (nested definitions at most
  :data:`lcchain.spice.cards.MAX_SUBCKT_DEPTH` deep, each name defined once), and ``X`` lines ``Xname NODE...
  NAME [params:] [a=3 ...]`` naming a ``.subckt`` of the netlist with as many nodes and parameters it declares;
  none may instantiate itself, directly or not, nest deeper than ``MAX_SUBCKT_DEPTH`` or make the flattened circuit
  larger than :data:`lcchain.core.limits.MAX_EXPANDED_ELEMENTS` elements (counted, never written out: ngspice
  expands the cards it receives);
* ``.model NAME TYPE (name=value ...)`` of a type of :data:`lcchain.spice.cards.MODEL_TYPES` (R C L D NPN PNP NMOS
  PMOS NJF PJF SW CSW), every value a number or a braced expression (no string, file name or bare word: none of
  ngspice's models of these types takes one), and the device lines ``D Q M J S W`` of
  :data:`lcchain.spice.cards.DEVICES`, each naming a ``.model`` of its type after its nodes;
* ``.func NAME(ARG, ...) = {EXPR}``, its expression held to the grammar of ``.param`` with its arguments as names;
  a user function may be called in any expression, but none may call itself (ngspice 39 crashes) or grow past
  :data:`lcchain.spice.cards.MAX_FUNCTION_CHARS` with the functions it calls written out (ngspice substitutes
  them: 18 functions each calling the last twice ran 20 s and were killed);
* ``.global NODE...``, ``.temp VALUE``, ``.op``, and ``.dc SRC START STOP STEP [SRC2 ...]`` of plain numbers
  (at most :data:`lcchain.core.limits.MAX_DC_POINTS` points), which ngspice runs beside the netlist's ``.tran``
  or ``.ac`` (lcchain reads that one and prices them too);
* and ``.include``/``.inc``/``.lib``
  of a regular file inside the top netlist's folder (symbolic links resolved),
  which is parsed by the same rules and inlined in place (``.lib FILE
  SECTION`` inlines that section), at most :data:`MAX_INCLUDE_DEPTH` deep and
  :data:`lcchain.core.limits.MAX_NETLIST_BYTES` in all;
* ``+`` continuation lines, joined to the card they continue before the check.

The netlist is first made canonical (:func:`lcchain.spice.text.canonical_text`: strict UTF-8, CRLF read as
LF, a leading byte-order mark dropped, every other line separator or control character refused, naming the line
and the character), so that the lines checked here are the lines every transport hands ngspice.

The text ngspice receives is rebuilt from the accepted cards only (includes
inlined, continuations joined, inline comments dropped), so it reads no other
file and runs exactly what was checked; for a netlist that needs none of that
(lcchain's own) it is the same text, byte for byte.

Prefixes
--------
ngspice 39 reads some dot-commands by their start and others only whole; what it did with each variant (``ngspice
-b`` on a small netlist using the card) is what is accepted, so that a card checked as one command cannot be read
as another:

* by their start, in any case: ``.param`` (``.params``, ``.PARAM_X``), ``.model`` (``.models``, ``.modelx``,
  ``.MODEL_X`` define the model), ``.func`` (``.funcx``, ``.funcs``, ``.FUNC_X`` define the function),
  ``.global`` (``.globalx``, ``.globals``, ``.GLOBAL_X`` make the node global) and ``.ends`` (``.endsx``,
  ``.ENDS_X``, ``.endsrdiv`` end the sub-circuit): each such word is checked as that command;
* only whole: ``.subckt`` (``.subcktx``, ``.SUBCKT_X``, ``.SUBCKTS`` define nothing: "Cannot find called
  subcircuit"; ``.subck`` is a fatal mismatch), ``.temp`` (``.tempx``, ``.temps``, ``.TEMP_X``, ``.tem``,
  ``.temperature``), ``.op`` (``.opx``, ``.ops``, ``.OP_X``), ``.dc`` (``.dcx``, ``.dcs``, ``.DC_X``): ngspice
  stops on the variants ("unimplemented control card"), and so are they refused here;
* shorter words are no command: ``.mod``, ``.mode``, ``.fun``, ``.glob``, ``.o``, ``.d`` are errors.

:func:`lcchain.spice.cards.command_of` holds this table.

Everything here is text: the caller gives a ``read`` function for included
files (:func:`lcchain.spice.inputs.read_input` checks that they are regular
files within their size limit).
"""

from __future__ import annotations

import math
import re
import string
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import ClassVar, NamedTuple

from ..core.budget import Estimate, show_bytes
from ..core.errors import ParameterError
from ..core.limits import MAX_AC_POINTS, MAX_DC_POINTS, MAX_EXPANDED_ELEMENTS, MAX_NETLIST_BYTES
from ..core.types import AC_SPACINGS, AcSpacing, AnalysisKind
from .cards import (
    DEVICES,
    MAX_FUNCTION_CHARS,
    MAX_SUBCKT_DEPTH,
    MODEL_TYPES,
    NODE,
    Cycle,
    Function,
    Header,
    Instance,
    Model,
    TooDeep,
    command_of,
    dc_points,
    device_model,
    func_card,
    function_sizes,
    instance,
    model_card,
    multiplicities,
    subckt_header,
)
from .expressions import FUNCTIONS, MAX_PARAMS, braced_expressions, check_expression, is_param_card, param_assignments
from .measure import MEASURE_WORDS, check_measure, measure_names_in
from .pricing import Contents, Price, operating_price, read_contents, sweep_price, transient_price
from .text import (
    NEWLINE,
    DotCard,
    canonical_text,
    dot_cards,
    odd_lines,
    require_canonical,
    saved_in,
    spice_number,
)

__all__ = ["ALLOW_CONTROL_HINT", "ELEMENTS", "DOT_COMMANDS", "SUBCKT_COMMANDS", "OPTIONS", "MAX_INCLUDE_DEPTH",
           "Transient", "Sweep", "CheckedText", "allowed_netlist", "transient_of", "analysis_of", "log_sweep_count",
           "foreign_estimate", "foreign_price", "ForeignRun", "read_foreign", "includes_nothing"]

#: First letters of the element lines lcchain runs: resistors, inductors, capacitors, coupled inductors,
#: independent voltage and current sources, controlled sources (voltage- and current-controlled, E G F H: numbers
#: and expressions of numbers, as a behavioural source's), behavioural sources (lcchain's own gaussian pulses), the
#: devices of a ``.model`` (diodes, BJTs, MOSFETs, JFETs, voltage- and current-controlled switches) and
#: sub-circuit instances.
ELEMENTS = frozenset("RLCKVIEFGHBDQMJSWX")
#: Dot-commands run as they are (the word matched whole, in any case, except those ngspice 39 reads by their start:
#: ``.param``, ``.ends``, ``.model``, ``.func``, ``.global``, :func:`lcchain.spice.cards.command_of`); the includes
#: are inlined.
DOT_COMMANDS = frozenset({".tran", ".ac", ".options", ".option", ".opt", ".save", ".ic", ".nodeset", ".param", ".end",
                          *MEASURE_WORDS, ".subckt", ".ends", ".model", ".func", ".global", ".temp", ".op", ".dc"})
#: What a ``.subckt`` body may hold besides element lines: its definitions (ngspice runs analyses, options and
#: saves of the whole netlist only).
SUBCKT_COMMANDS = frozenset({".param", ".subckt", ".ends", ".model", ".func"})
_INCLUDES = frozenset({".include", ".inc", ".lib"})
#: ``.options`` names a netlist may set: tolerances, integration and solver settings, nothing that names a
#: file, changes the output format or loads code.
OPTIONS = frozenset({
    "method", "maxord", "reltol", "abstol", "vntol", "chgtol", "trtol", "gmin", "gminsteps", "srcsteps",
    "itl1", "itl2", "itl3", "itl4", "itl5", "itl6", "temp", "tnom", "numdgt", "pivtol", "pivrel", "xmu",
    "rshunt", "ramptime", "klu", "sparse", "noopac", "noinit", "nopage", "noacct", "nomod", "interp",
    "keepopinfo", "maxwarns", "warn", "savecurrents", "trytocompact",
})
#: How deep ``.include`` files may nest.
MAX_INCLUDE_DEPTH = 8

# Characters of an element or dot-command card: names, numbers, expressions, vector names. No quote (file
# names), backslash, backtick, control character or non-ASCII letter.
_CHARACTERS = re.compile(r"[A-Za-z0-9_.+\-*/^(){}\[\],=<>!&|?:%#@ \t]*")
_INLINE_COMMENT = re.compile(r"(;|\s\$).*$")
# An element line the checks of _allowed accept as it is, counting it and nothing more: its letter one of
# ELEMENTS that names no model nor sub-circuit, written in _CHARACTERS without braces (no expression to check) and
# without a blank at either end (it is its own stripped body), so without an inline comment (no ";" or "$").
_PLAIN_CHARACTER = r"A-Za-z0-9_.+\-*/^()\[\],=<>!&|?:%#@"  # _CHARACTERS but braces, space and tab
_PLAIN_ELEMENT = re.compile(rf"[BCIKLRVbciklrv](?:[{_PLAIN_CHARACTER} \t]*[{_PLAIN_CHARACTER}])?")
# The same line told by its bytes (lcchain.spice.text.odd_lines): its first one of _PLAIN_FIRST, every other one of
# _PLAIN_REST, the last no blank.
_PLAIN_FIRST = b"BCIKLRVbciklrv"
_PLAIN_REST = (string.ascii_letters + string.digits + "_.+-*/^()[],=<>!&|?:%#@ \t").encode("ascii")
#: Texts of this many lines or more are split into runs of such lines (a search of the text); shorter ones are
#: looked at line by line, which costs less for so few (a 25-line netlist: 10 % less).
_RUNS_FROM = 64
# A line that continues another (its first character that is not blank a "+"), past the first line.
_CONTINUED = re.compile(r"\n[^\S\n]*\+")
_SCRIPT = re.compile(r"^\s*\*\s*(#|ng_script)", re.IGNORECASE)
# A title ngspice would read as a command; ".title TEXT" (PySpice writes it) only sets the title.
_TITLE_COMMAND = re.compile(r"^\s*(\.(?!title\s)[A-Za-z]|\*\s*(#|ng_script))", re.IGNORECASE)
_ALLOWED = ("a netlist of comments, element lines (" + ", ".join(sorted(ELEMENTS)) + ") and the dot-commands "
            + ", ".join(sorted(DOT_COMMANDS | _INCLUDES)))
#: What to write instead of a character the allow-list refuses, where there is a plain way.
_CHARACTER_HINTS = {"'": "an expression in braces, {r0*2}: ngspice reads '...' as {...}",
                    "\u00b5": "u for micro, 1u (ngspice 39 reads the micro sign too)",
                    "\u03bc": "u for micro, 1u"}
#: What a refusal adds for ``lcchain batch``, whose ``--allow-control`` runs a netlist as it is.
ALLOW_CONTROL_HINT = " (lcchain batch --allow-control runs a netlist as it is, in a sandbox)"


# One card: (source, line number, text, joined: "+" lines were joined to it).
_Card = tuple[str, int, str, bool]


class _Plain(NamedTuple):
    """Consecutive lines of a file that ``_PLAIN_ELEMENT`` matches whole (a ladder's ``L`` and ``C`` lines): each is
    an element line the allow-list takes as it is, so they are counted and copied together (the first is line
    ``number`` of ``source``)."""

    source: str
    number: int
    lines: list[str]

    def card(self, k: int) -> _Card:
        """The card of its ``k``-th line."""
        return self.source, self.number + k, self.lines[k], False


def _refuse(card: _Card, why: str) -> ParameterError:
    return ParameterError(f"{card[0]}: line {card[1]}", card[2].strip()[:200], why + ALLOW_CONTROL_HINT)


@dataclass
class _Names:
    """What the expressions of a netlist and its includes define and use, checked when all of it is read (ngspice
    reads every ``.param`` before it evaluates a value, so a name may be used before the card that defines it)."""

    params: set[str] = field(default_factory=set)
    uses: list[tuple[_Card, set[str]]] = field(default_factory=list)
    measurements: set[str] = field(default_factory=set)
    calls: list[tuple[_Card, set[str]]] = field(default_factory=list)  # user functions an expression calls
    functions: dict[str, tuple[_Card, Function]] = field(default_factory=dict)
    subckts: dict[str, tuple[_Card, Header]] = field(default_factory=dict)
    open: list[tuple[_Card, Header]] = field(default_factory=list)  # the .subckt cards not yet ended, innermost last
    instances: list[tuple[_Card, str, Instance]] = field(default_factory=list)  # (card, its body, the X line)
    elements: dict[str, int] = field(default_factory=dict)  # element lines of each body ("": the netlist's own)
    models: dict[str, Model] = field(default_factory=dict)
    devices: list[tuple[_Card, list[str]]] = field(default_factory=list)

    @property
    def body(self) -> str:
        """The body the next card belongs to: the innermost open ``.subckt``, or ``""``."""
        return self.open[-1][1].name if self.open else ""


def _where(card: _Card) -> str:
    return f"{card[0]}: line {card[1]}"


def _expression(card: _Card, text: str, state: _Names, local: tuple[str, ...] = ()) -> None:
    """Check one expression; its names (but ``local``, a ``.func``'s arguments) and calls are checked once the
    whole netlist is read."""
    calls: set[str] = set()
    used = check_expression(text, None, _where(card), card[2], calls=calls)
    if used:
        state.uses.append((card, used.difference(local) if local else used))
    if calls:
        state.calls.append((card, calls))


def _check_param(card: _Card, body: str, state: _Names) -> None:
    for name, value in param_assignments(body, _where(card), card[2]):
        state.params.add(name)
        _expression(card, value, state)
    if len(state.params) > MAX_PARAMS:
        raise _refuse(card, f"at most {MAX_PARAMS} .param names in a netlist, its includes included")


def _check_braces(card: _Card, body: str, state: _Names) -> None:
    groups, rest = braced_expressions(body)
    if "{" in rest.replace("{}", "") or "}" in rest.replace("{}", ""):
        raise _refuse(card, "braces around one expression each, not nested or unmatched")
    for group in groups:
        _expression(card, group, state)


def _check_names(state: _Names) -> None:
    for card, used in state.uses:
        unknown = sorted(used - state.params)
        if unknown:
            probed = re.search(r"\b[vi]\s*\(", card[2], re.IGNORECASE) is not None  # v(a) in braces: a node
            raise _refuse(card, f"expressions of names a .param defines (not {', '.join(unknown)}" + (
                "; a node's voltage or a branch's current in braces is a behavioural value, which --allow-control "
                "runs as it is" if probed else "") + ")")
    for card, calls in state.calls:
        unknown = sorted(calls - set(state.functions))
        if unknown:
            raise _refuse(card, f"calls of the functions {', '.join(sorted(FUNCTIONS))} and of those a .func "
                          f"defines (not {', '.join(unknown)})")


def _check_subckt(card: _Card, body: str, state: _Names) -> None:
    header = subckt_header(body)
    if header is None:
        raise _refuse(card, ".subckt NAME NODE... [params: name=value ...] (names of letters, digits and _; "
                      "values numbers or expressions)")
    if header.name in state.subckts:
        raise _refuse(card, f"one .subckt of each name ({header.name} is defined at "
                      f"{_where(state.subckts[header.name][0])})")
    if len(state.open) >= MAX_SUBCKT_DEPTH:
        raise _refuse(card, f"sub-circuit definitions nested at most {MAX_SUBCKT_DEPTH} deep")
    for name, value in header.params:
        state.params.add(name)
        _expression(card, value, state)
    state.subckts[header.name] = (card, header)
    state.open.append((card, header))
    state.elements.setdefault(header.name, 0)


def _check_ends(card: _Card, body: str, state: _Names) -> None:
    words = body.split()
    if not state.open:
        raise _refuse(card, "an .ends that closes a .subckt")
    if len(words) > 2 or (len(words) == 2 and words[1].lower() != state.body):
        raise _refuse(card, f".ends or .ends {state.body} (it closes the innermost open .subckt, "
                      f"{_where(state.open[-1][0])})")
    state.open.pop()


def _check_model(card: _Card, body: str, state: _Names) -> None:
    model = model_card(body)
    if model is None:
        raise _refuse(card, f".model NAME TYPE (name=value ...) of a type {', '.join(t.upper() for t in MODEL_TYPES)}, "
                      "each value a number or an expression in braces (no string, file name or bare word)")
    for _, value in model.params:
        if spice_number(value) is None:
            _expression(card, value, state)
    state.models[model.name] = model


def _check_func(card: _Card, body: str, state: _Names) -> None:
    function = func_card(body)
    if function is None:
        raise _refuse(card, ".func NAME(ARG, ...) = {EXPR} (names of letters, digits and _; the expression of "
                      "numbers, .param names, the arguments and functions)")
    if function.name in FUNCTIONS or function.name in state.functions:
        raise _refuse(card, "a .func of a name of its own (not one of ngspice's functions, nor one defined twice)")
    if len(function.body) > MAX_FUNCTION_CHARS:
        raise _refuse(card, f"a .func body of at most {MAX_FUNCTION_CHARS} characters")
    state.functions[function.name] = (card, function)
    _expression(card, function.body, state, function.args)


def _check_global(card: _Card, body: str, state: _Names) -> None:
    nodes = body.split()[1:]
    if not nodes or not all(NODE.fullmatch(n) for n in nodes):
        raise _refuse(card, ".global NODE... (node names)")


def _check_temp(card: _Card, body: str, state: _Names) -> None:
    value = body.split(None, 1)[1].strip() if len(body.split()) > 1 else ""
    number = spice_number(value)
    if value.startswith("{") and value.endswith("}") and "{" not in value[1:-1]:
        _expression(card, value[1:-1], state)
    elif number is None or not math.isfinite(number) or len(value.split()) != 1:
        raise _refuse(card, ".temp VALUE (degrees Celsius: a number or an expression in braces)")


def _check_op(card: _Card, body: str, state: _Names) -> None:
    if len(body.split()) != 1:
        raise _refuse(card, ".op alone")


def _check_dc(card: _Card, body: str, state: _Names) -> None:
    if dc_points(body, most=MAX_DC_POINTS) is None:
        raise _refuse(card, ".dc SRC START STOP STEP [SRC2 START2 STOP2 STEP2] (a V, I or R name or TEMP; plain "
                      f"numbers, STEP towards STOP; at most {MAX_DC_POINTS} points in all)")


#: How each card of :mod:`lcchain.spice.cards` is checked, by the command ngspice 39 reads it as
#: (:func:`lcchain.spice.cards.command_of`).
_CARD_CHECKS: dict[str, Callable[[_Card, str, _Names], None]] = {
    ".subckt": _check_subckt, ".ends": _check_ends, ".model": _check_model, ".func": _check_func,
    ".global": _check_global, ".temp": _check_temp, ".op": _check_op, ".dc": _check_dc,
}


def _count_element(card: _Card, state: _Names) -> None:
    """One more element line in the body it is in, refused past :data:`lcchain.core.limits.MAX_EXPANDED_ELEMENTS`
    in one body, before any copy."""
    body_name = state.open[-1][1].name if state.open else ""
    count = state.elements[body_name] = state.elements.get(body_name, 0) + 1
    if count > MAX_EXPANDED_ELEMENTS:
        raise _too_many_elements(card)


def _too_many_elements(card: _Card) -> ParameterError:
    return _refuse(card, f"a netlist of at most {MAX_EXPANDED_ELEMENTS} elements")


def _check_element(card: _Card, body: str, state: _Names) -> None:
    letter = body[0].upper()
    if letter != "X":
        _count_element(card, state)
        if letter in DEVICES:
            state.devices.append((card, body.split()))
        if "{" in body or "}" in body:
            _check_braces(card, body, state)
        return
    found = instance(body)
    if found is None:
        raise _refuse(card, "Xname NODE... SUBCKT [params:] [name=value ...] (values numbers or expressions)")
    state.instances.append((card, state.body, found))
    for _, value in found.params:
        _expression(card, value, state)


def _first_instance(state: _Names, body: str, subckt: str) -> _Card:
    return next(card for card, where, x in state.instances if where == body and x.subckt == subckt)


def _check_hierarchy(state: _Names) -> None:
    """What only the whole netlist shows: every ``.subckt`` ended, every ``X`` naming a ``.subckt`` with its
    nodes and parameters, none instantiating itself or nested too deep, the expanded circuit within
    :data:`lcchain.core.limits.MAX_EXPANDED_ELEMENTS`; every device naming a ``.model`` of its type; every
    ``.func`` within :data:`lcchain.spice.cards.MAX_FUNCTION_CHARS` written out, none calling itself."""
    if state.open:
        raise _refuse(state.open[-1][0], "a .subckt that an .ends closes")
    calls: dict[str, list[str]] = {}
    for card, body, x in state.instances:
        if x.subckt not in state.subckts:
            raise _refuse(card, f"an instance of a .subckt the netlist defines (not {x.subckt})")
        where, header = state.subckts[x.subckt]
        if len(x.nodes) != len(header.nodes):
            raise _refuse(card, f"{len(header.nodes)} nodes for {x.subckt}, as its .subckt has ({_where(where)}), "
                          f"not {len(x.nodes)}")
        unknown = sorted({n for n, _ in x.params} - {n for n, _ in header.params})
        if unknown:
            declared = ", ".join(n for n, _ in header.params) or "none"
            raise _refuse(card, f"parameters that {x.subckt} declares ({declared}), not {', '.join(unknown)}")
        calls.setdefault(body, []).append(x.subckt)
    try:
        copies = multiplicities(calls)
    except Cycle as error:
        raise _refuse(_first_instance(state, error.path[-2], error.path[-1]), "sub-circuits that do not instantiate "
                      f"themselves ({' -> '.join(error.path)}: ngspice would expand them forever)") from None
    except TooDeep as error:
        outer = error.path[-2] if len(error.path) > 1 else ""
        raise _refuse(_first_instance(state, outer, error.path[-1]), f"sub-circuit instances nested at most "
                      f"{MAX_SUBCKT_DEPTH} deep ({' -> '.join(error.path)})") from None
    if sum(state.elements.get(name, 0) * count for name, count in copies.items()) > MAX_EXPANDED_ELEMENTS:
        def expanded(name: str) -> int:
            return sum(state.elements.get(n, 0) * c for n, c in multiplicities(calls, name).items())
        card, _, x = max((i for i in state.instances if i[1] == ""), key=lambda i: expanded(i[2].subckt))
        raise _refuse(card, f"a netlist of at most {MAX_EXPANDED_ELEMENTS} elements once its sub-circuits are "
                      f"expanded (one {x.subckt} alone holds {expanded(x.subckt):.3g})")
    for card, words in state.devices:
        letter = words[0][0].upper()
        if device_model(letter, words, state.models) is None:
            kinds = " or ".join(t.upper() for t, used in MODEL_TYPES.items() if used == letter)
            raise _refuse(card, f"a {letter} line naming a .model of type {kinds} after its nodes")
    functions = {name: f for name, (_, f) in state.functions.items()}
    try:
        sizes = function_sizes(functions)
    except Cycle as error:
        raise _refuse(state.functions[error.path[0]][0], f"functions that do not call themselves "
                      f"({' -> '.join(error.path)}: ngspice 39 crashes on one)") from None
    for name, size in sizes.items():
        if size > MAX_FUNCTION_CHARS:
            raise _refuse(state.functions[name][0], f"a function of at most {MAX_FUNCTION_CHARS} characters with "
                          f"the functions it calls written out (ngspice substitutes them: this one makes {size})")


def _cards(text: str, source: str, *, title: bool) -> tuple[str, list[_Card | _Plain]]:
    """(title, cards) of a canonical text: comments and blank lines are cards too, ``+`` lines are joined to
    the card they continue; in a text without ``+`` lines, each run of lines that ``_PLAIN_ELEMENT`` matches whole
    is one :class:`_Plain` (found by :func:`lcchain.spice.text.odd_lines`, not line by line).

    The title is the first non-blank line (ngspice skips blank lines before it); with ``title=False`` (an
    included file) there is none.
    """
    lines = text.split(NEWLINE)  # canonical already (allowed_netlist made it so): LF alone
    head = ""
    start = 0
    if title:
        start = next((k for k, line in enumerate(lines) if line.strip()), len(lines))
        head = lines[start] if start < len(lines) else ""
        if _TITLE_COMMAND.match(head):
            raise _refuse((source, start + 1, head, False), "a title line (the first line is the netlist's title; "
                          "a dot-command, *# or *ng_script there would make ngspice read it as a command)")
        start += 1
    if _CONTINUED.search(text) is None and lines[0].lstrip()[:1] != "+":  # no line continues another
        if len(lines) >= _RUNS_FROM:
            return head, _runs(source, text, lines, start)
        return head, [(source, number, line, False) for number, line in enumerate(lines[start:], start + 1)]
    cards: list[_Card | _Plain] = []
    last = -1  # the card a "+" line continues: the last element or dot-command card
    for number in range(start + 1, len(lines) + 1):
        line = lines[number - 1]
        first = line[:1]
        if first.isspace():  # most lines start with their card
            first = line.lstrip()[:1]
        if first == "+":
            if last < 0:
                raise _refuse((source, number, line, False), "a continuation (+) of an element or dot-command line")
            previous = cards[last]
            assert not isinstance(previous, _Plain)  # this loop makes none
            cards[last] = (source, previous[1], previous[2] + " " + line.lstrip()[1:].lstrip(), True)
            cards.append((source, number, "", False))  # keeps the place of the joined line
            continue
        if first and first != "*":
            last = len(cards)
        cards.append((source, number, line, False))
    return head, cards


def _runs(source: str, text: str, lines: list[str], start: int) -> list[_Card | _Plain]:
    """The cards of ``lines[start:]`` (``text`` split at LF, no line continuing another): a :class:`_Plain` for
    each run of lines that ``_PLAIN_ELEMENT`` matches whole, a card for each other line."""
    cards: list[_Card | _Plain] = []
    at = start
    for k in odd_lines(text, _PLAIN_FIRST, _PLAIN_REST, blank_end=True):
        if k < start:
            continue
        if k > at:
            cards.append(_Plain(source, at + 1, lines[at:k]))
        cards.append((source, k + 1, lines[k], False))
        at = k + 1
    if at < len(lines):
        cards.append(_Plain(source, at + 1, lines[at:]))
    return cards


def _check_options(card: _Card, body: str) -> None:
    for word in re.sub(r"\s*=\s*", "=", body).split():
        name = word.partition("=")[0].lower()
        if name not in OPTIONS:
            raise _refuse(card, f"an option lcchain knows ({', '.join(sorted(OPTIONS))}), not {name!r}")


def _included(card: _Card, argument: str) -> tuple[str, str | None]:
    """(file, section) of an include card; quotes allowed around the file name only."""
    argument = argument.strip()
    if argument.startswith(("\"", "'")):  # not ``argument[:1] in ...``: "" is in every string
        end = argument.find(argument[0], 1)
        if end < 0:
            raise _refuse(card, "a file name between matching quotes")
        name, rest = argument[1:end], argument[end + 1:].split()
    else:
        words = argument.split()
        name, rest = (words[0], words[1:]) if words else ("", [])
    if not name or len(rest) > 1 or not _CHARACTERS.fullmatch(name + " ".join(rest)):
        # ngspice ends a card at " $" or ";" (an inline comment): ".include $HOME/x.inc" names no file at all
        comment = " (a ' $' or ';' starts a comment, so no variable such as $HOME is expanded)" if (
            "$" in card[2] or ";" in card[2]) else ""
        raise _refuse(card, "an include of one file name (and, for .lib, one section name)" + comment)
    return name, rest[0] if rest else None


def _section(text: str, name: str, source: str) -> str:
    """The lines of ``.lib NAME`` ... ``.endl`` in a library file."""
    lines = text.split("\n")
    start = None
    for number, line in enumerate(lines):
        words = line.split()
        if start is None and len(words) == 2 and words[0].lower() == ".lib" and words[1].lower() == name.lower():
            start = number + 1
        elif start is not None and words[:1] and words[0].lower() == ".endl":
            return "\n".join([""] * start + lines[start:number])  # blank lines keep the line numbers
    raise ParameterError(f"{source}", name, "a .lib section that the file holds between .lib NAME and .endl")


#: What only :func:`allowed_netlist` holds: the key that makes a :class:`CheckedText`.
_CHECKER = object()


class CheckedText(str):
    """Netlist text the allow-list accepted, exactly as :func:`allowed_netlist` returned it.

    Only :func:`allowed_netlist` makes one, and any edit of it (``+``, ``replace``, a slice) is a plain ``str``
    again: so a run handed a ``CheckedText`` (a batch's plan carries it in its :class:`~lcchain.runs.spec.RunSpec`)
    runs the text the allow-list checked without checking it again
    (:func:`lcchain.spice.ngspice.runner.run`), and any other text is checked there.  Sent to another process
    (pickled: a pool's or a Dask worker) it is checked again where it lands.
    """

    __slots__ = ()

    def __new__(cls, text: str, key: object = None) -> CheckedText:
        if key is not _CHECKER:
            raise TypeError("a CheckedText is made by lcchain.spice.foreign.allowed_netlist only")
        return super().__new__(cls, text)

    def __reduce__(self) -> tuple[Callable[..., CheckedText], tuple[str, str, None]]:
        return allowed_netlist, (str(self), "netlist", None)


def allowed_netlist(text: str, source: str, folder: Path | None,
                    read: Callable[[Path, str], str] | None = None) -> CheckedText:
    """The netlist as ngspice will receive it, or a refusal of its first line lcchain does not run.

    Parameters
    ----------
    text : str
        The netlist text.
    source : str
        Its name in messages (the file, or ``"netlist"``).
    folder : Path, optional
        The folder the top netlist's includes must stay in; None: no include
        is allowed.
    read : callable, optional
        ``read(path, field)`` reads an included file (a resolved path inside
        ``folder``) as text, refusing under ``field`` what is not a regular
        file or is too large.

    Returns
    -------
    CheckedText
        The title and the accepted cards, includes inlined: ``text``'s characters
        when there was nothing to inline, join or drop.

    Raises
    ------
    ParameterError
        Naming ``"<source>: line <n>"``, the line and what is allowed.
    """
    return CheckedText(_allowed(text, source, folder, read), _CHECKER)


def _allowed(text: str, source: str, folder: Path | None, read: Callable[[Path, str], str] | None = None,
             *, _depth: int = 0, _seen: tuple[tuple[Path, str | None], ...] = (), _left: list[int] | None = None,
             _state: _Names | None = None) -> str:
    """:func:`allowed_netlist`'s check of a netlist (``_depth`` 0) or of a file it includes."""
    text = canonical_text(text, source, title=_depth == 0)  # the one text checked here and run by every transport
    left = _left if _left is not None else [MAX_NETLIST_BYTES - len(text)]  # what all includes may add, in all
    state = _state if _state is not None else _Names()
    head, cards = _cards(text, source, title=_depth == 0)
    out = [head] if _depth == 0 else []
    changed = _depth == 0 and not text.startswith(head)  # blank lines before the title are dropped
    plain = _PLAIN_ELEMENT.fullmatch
    elements = state.elements
    for card in cards:
        if isinstance(card, _Plain):  # element lines taken as they are: counted in their body, copied
            body_name = state.open[-1][1].name if state.open else ""
            count = elements[body_name] = elements.get(body_name, 0) + len(card.lines)
            if count > MAX_EXPANDED_ELEMENTS:  # refused at its line past the limit, as one by one
                raise _too_many_elements(card.card(MAX_EXPANDED_ELEMENTS - count + len(card.lines)))
            out += card.lines
            continue
        line = card[2]
        changed |= card[3]
        if plain(line):  # most lines of a ladder: what the checks below make of them, told by one match
            body_name = state.open[-1][1].name if state.open else ""
            count = elements[body_name] = elements.get(body_name, 0) + 1
            if count > MAX_EXPANDED_ELEMENTS:
                raise _too_many_elements(card)
            out.append(line)
            continue
        stripped = line.strip()
        if not stripped or stripped[0] == "*":
            if _SCRIPT.match(stripped):
                raise _refuse(card, "a comment that does not start with *# or *ng_script (ngspice reads those "
                              "as commands)")
            out.append(line)
            continue
        body = _INLINE_COMMENT.sub("", stripped).rstrip() if (";" in stripped or "$" in stripped) else stripped
        if not body:
            changed = True
            continue
        word = body.split(None, 1)[0].lower()
        if word in _INCLUDES:  # the one card whose file name may be quoted
            out.extend(_inline(card, body[len(word):], folder, read, _depth, _seen, left, state))
            changed = True
            continue
        if not _CHARACTERS.fullmatch(body):
            bad = next(ch for ch in body if not _CHARACTERS.fullmatch(ch))
            hint = _CHARACTER_HINTS.get(bad)
            raise _refuse(card, f"a line without {bad!r}" + (f" ({hint})" if hint else "") + f": {_ALLOWED}")
        if word[0] == ".":
            command = command_of(word)
            if state.open and not (is_param_card(word) or command in SUBCKT_COMMANDS):
                raise _refuse(card, "inside a .subckt, element lines and the cards " + ", ".join(
                    sorted(SUBCKT_COMMANDS)) + f" (the .subckt of {_where(state.open[-1][0])} is not ended)")
            if command is not None:  # .models, .funcx, .ENDSX: read by ngspice 39 as .model, .func, .ends
                _CARD_CHECKS[command](card, body, state)
                out.append(body)
                changed |= len(body) != len(line)
                continue
            if is_param_card(word):  # ngspice 39 reads .params, .PARAM_X as .param: checked as one
                _check_param(card, body[len(word):], state)
                out.append(body)
                changed |= len(body) != len(line)
                continue
            if word not in DOT_COMMANDS:
                raise _refuse(card, _ALLOWED)
            if word in (".options", ".option", ".opt"):
                _check_options(card, body[len(word):])
            if word in MEASURE_WORDS:
                state.uses.append((card, check_measure(body, state.measurements, _where(card), card[2])))
            else:
                _check_braces(card, body, state)
            if word == ".end" and _depth > 0:  # an included file's .end would end the top netlist
                changed = True
                continue
        elif word[0].upper() not in ELEMENTS:
            raise _refuse(card, _ALLOWED)
        else:
            _check_element(card, body, state)
        changed |= len(body) != len(line)
        out.append(body)
    if _depth == 0:
        _check_hierarchy(state)
        _check_names(state)
    if _depth == 0 and not changed:
        return text
    return "\n".join(out) + ("\n" if _depth == 0 else "")


def includes_nothing(text: str) -> bool:
    """Whether no card of ``text`` can include a file, told at once: none of the words ``.include``, ``.inc`` and
    ``.lib`` is in it, in any case (:func:`allowed_netlist` then never asks for its ``folder``)."""
    lower = text.lower()
    return ".inc" not in lower and ".lib" not in lower


def _inline(card: _Card, argument: str, folder: Path | None, read: Callable[[Path, str], str] | None, depth: int,
            seen: tuple[tuple[Path, str | None], ...], left: list[int], state: _Names) -> list[str]:
    name, section = _included(card, argument)
    if folder is None or read is None:
        raise _refuse(card, "a netlist without includes (this netlist has no folder of its own)")
    if depth + 1 > MAX_INCLUDE_DEPTH:
        raise _refuse(card, f"includes at most {MAX_INCLUDE_DEPTH} deep")
    if depth == 0:  # the top netlist's folder, resolved when an include first needs it
        folder = folder.resolve()
    base = Path(card[0]).parent if depth > 0 else folder
    path = (base / name).resolve()
    if not path.is_relative_to(folder):
        raise _refuse(card, f"an include of a file inside the netlist's folder {folder}")
    # a file, or one .lib section of it (named in any case, as ngspice reads them), already being included: a section
    # may include another section of its own file (a corner library's typical section includes a common one)
    place = (path, section.lower() if section is not None else None)
    if place in seen:
        raise _refuse(card, "includes without a cycle (this file includes itself)" if section is None else
                      f"includes without a cycle (section {section} of this file includes itself)")
    included = read(path, f"{card[0]}: line {card[1]}")
    left[0] -= len(included)
    if left[0] < 0:  # the same file included a thousand times is as large as a thousand files
        raise _refuse(card, f"includes of at most {show_bytes(MAX_NETLIST_BYTES)} in all, the netlist included")
    if section is not None:
        try:
            included = _section(included, section, str(path))
        except ParameterError:
            raise _refuse(card, f"a .lib section that {path.name} holds between .lib {section} and .endl "
                          f"(it has no section {section})") from None
    body = _allowed(included, str(path), folder, read, _depth=depth + 1, _seen=(*seen, place), _left=left,
                    _state=state)
    return [f"* lcchain: {card[2].strip()[:150]}", *body.split("\n")]


# --------------------------------------------------------------------------- what a netlist costs


@dataclass(frozen=True)
class Transient:
    """A ``.tran`` card read: seconds (``max_step``: ngspice's own default when the card gives none)."""

    step: float
    stop: float
    start: float
    max_step: float
    kind: ClassVar[AnalysisKind] = "transient"

    @property
    def points(self) -> float:
        """Time points ngspice computes at least: one per maximum step."""
        return self.stop / self.max_step + 1

    @property
    def tstop(self) -> float:
        return self.stop

    @property
    def frequencies(self) -> int | None:
        return None

    def price(self, contents: Contents, saved: int) -> Price:
        """Its time points, with those the netlist's edges and fast dynamics force (:mod:`lcchain.spice.pricing`)."""
        return transient_price(contents, step=self.step, stop=self.stop, max_step=self.max_step, saved=saved)

    def describe(self) -> str:
        return f".tran to {self.stop:g} s in steps of at most {self.max_step:g} s"


@dataclass(frozen=True)
class Sweep:
    """An ``.ac`` card read: its frequencies (Hz) from ``start`` to ``stop``, evenly spaced (``lin``) or a
    geometric series (``dec``, ``oct``: ``per`` points per decade or octave, counted by :func:`log_sweep_count`)."""

    count: int
    start: float
    stop: float
    spacing: AcSpacing = "lin"
    per: int = 0
    kind: ClassVar[AnalysisKind] = "ac"
    tstop: ClassVar[float] = 0.0

    @property
    def points(self) -> float:
        return float(self.count)

    @property
    def frequencies(self) -> int:
        return self.count

    def price(self, contents: Contents, saved: int) -> Price:
        """Its frequencies, each a complex solve of the netlist (:mod:`lcchain.spice.pricing`)."""
        return sweep_price(contents, frequencies=self.count, saved=saved)

    def describe(self) -> str:
        per = "" if self.spacing == "lin" else f" ({self.per} per {_PER[self.spacing][0]})"
        return f".ac {self.spacing} {self.count} frequencies{per} from {self.start:g} to {self.stop:g} Hz"


#: What one step of a logarithmic sweep spans: (its name, the ratio of a decade or an octave).
_PER: dict[str, tuple[str, float]] = {"dec": ("decade", 10.0), "oct": ("octave", 2.0)}
#: ngspice's default relative tolerance (``.options reltol``), which widens the end of a logarithmic sweep.
_RELTOL = 1e-3


def log_sweep_count(spacing: AcSpacing, per: int, start: float, stop: float, *, reltol: float = _RELTOL,
                    version: int) -> int:
    """How many frequencies ngspice computes for ``.ac dec|oct PER START STOP``, exactly as its ``ACan`` does.

    ngspice starts at ``start`` and multiplies by a ratio ``delta`` while the frequency is at most
    ``stop + delta * stop * reltol``.  The ratio depends on its version (``src/spicelib/analysis/acan.c``):

    * ``oct``, and ``dec`` before ngspice 39: ``delta = 2 ** (1 / per)`` or ``10 ** (1 / per)``;
    * ``dec`` in ngspice 39 to 42 (commit 75c2a3c6, "start and stop frequency always exactly included"):
      ``steps = floor(|log10(stop / start)| * per)`` and ``delta = (stop / start) ** (1 / steps)``; with
      ``steps = 0`` (less than one step apart) that is a division by zero after which ngspice 39 sweeps
      ``inf`` Hz until it is killed, so it is refused here;
    * ``dec`` from ngspice 43 (commit f15a92d9): the same, except less than a decade apart, where the ratio is
      ``10 ** (1 / per)`` again.

    The arithmetic is the C library's (``math.log``, ``math.exp``, ``math.log10`` are glibc's, as in ngspice),
    so the boundary cases come out as ngspice's.

    Parameters
    ----------
    spacing : {"dec", "oct"}
    per : int
        Points per decade or octave, at least 1.
    start, stop : float
        Hz, ``0 < start < stop``.
    reltol : float
        The netlist's ``.options reltol`` (ngspice's default 1e-3).
    version : int
        ngspice's major version (``39``).

    Raises
    ------
    ParameterError
        A sweep ngspice 39 to 42 cannot make, or one of more than
        :data:`lcchain.core.limits.MAX_AC_POINTS` frequencies.
    """
    ratio = stop / start
    delta = math.exp(math.log(_PER[spacing][1]) / per)
    if spacing == "dec" and version >= 39 and not (version >= 43 and stop / 10.0 < start):
        steps = math.floor(abs(math.log10(ratio)) * per)
        if steps == 0:
            raise ParameterError("FSTOP", stop, f"at least one step of 1/{per} decade above FSTART = {start:g} "
                                 f"(ngspice {version} divides by zero steps and never ends such a sweep)")
        delta = math.exp(math.log(ratio) / steps)
    end = stop + delta * stop * reltol
    if math.log(end / start) / math.log(delta) + 1 > MAX_AC_POINTS:  # before counting them one by one
        raise ParameterError("N", per, f"a sweep of at most {MAX_AC_POINTS} frequencies")
    count, frequency = 0, start
    while frequency <= end:
        count += 1
        frequency *= delta
    return count


def _reltol(text: str) -> float:
    """The netlist's ``.options reltol`` (the last one given), or ngspice's default."""
    found = _RELTOL
    for line in text.split("\n"):
        words = re.sub(r"\s*=\s*", "=", line.strip()).split()
        if words and words[0].lower() in (".options", ".option", ".opt"):
            for word in words[1:]:
                name, _, value = word.partition("=")
                number = spice_number(value) if name.lower() == "reltol" else None
                if number is not None and math.isfinite(number) and number > 0:
                    found = number
    return found


def _analysis_cards(dots: Sequence[DotCard]) -> list[tuple[int, str]]:
    """(line number, card) of every analysis among a text's :func:`~lcchain.spice.text.dot_cards` (read as they
    are, canonical or not): ngspice runs each one it finds."""
    found: list[tuple[int, str]] = []
    for number, line, _ in dots:  # each physical line that starts a card
        word = line.split(None, 1)[0].lower() if line.strip() else ""
        if word in (".tran", ".ac"):
            found.append((number, line.strip()))
    return found


def _one_analysis(found: list[tuple[int, str]], source: str) -> None:
    if len(found) > 1:
        raise ParameterError(f"{source}: line {found[1][0]}", found[1][1][:200], "one analysis per netlist (ngspice "
                             "would run them all; lcchain prices and reads one .tran or .ac)")


def analysis_of(text: str, source: str, version: Callable[[], str] | None = None) -> Transient | Sweep:
    """The netlist's one analysis, a ``.tran`` (:func:`transient_of`) or an ``.ac lin|dec|oct`` sweep, or a
    refusal naming the card.

    ``version`` gives the ngspice version that will run it (``"39"``), asked only for an ``.ac dec`` card: how
    many frequencies ngspice makes of one depends on it (:func:`log_sweep_count`).
    """
    dots = dot_cards(text, canonical=False)
    return _analysis(text, dots, bool(measure_names_in(dots)), source, version)


def _analysis(text: str, dots: Sequence[DotCard], measured: bool, source: str,
              version: Callable[[], str] | None) -> Transient | Sweep:
    """:func:`analysis_of` of a text with its :func:`~lcchain.spice.text.dot_cards` (not required canonical) and
    whether it has ``.meas`` cards."""
    found = _analysis_cards(dots)
    if not found:
        raise ParameterError(source, ".tran/.ac", "a netlist with one .tran or .ac analysis (lcchain reads transients "
                             "and AC sweeps; .op and .dc cards run beside one)")
    _one_analysis(found, source)
    number, line = found[0]
    if line.split(None, 1)[0].lower() != ".ac":
        return _transient(found, source)
    words = [w for w in re.split(r"[\s,()]+", line) if w]
    values = [spice_number(w) for w in words[2:]]
    spacing = words[1].lower() if len(words) > 1 else ""
    allowed = (".ac lin|dec|oct N FSTART FSTOP with plain finite numbers, 1 <= N, 0 <= FSTART < FSTOP (= FSTOP for "
               "lin 1; 0 < FSTART "
               f"for dec and oct) and at most {MAX_AC_POINTS} frequencies (lcchain prices the run and checks what "
               "it reads back from them)")
    if len(words) != 5 or spacing not in AC_SPACINGS or any(v is None or not math.isfinite(v) for v in values):
        raise ParameterError(f"{source}: line {number}", line[:200], allowed)
    count, start, stop = (float(v) for v in values)  # type: ignore[arg-type]
    single = spacing == "lin" and count == 1 and start == stop  # one frequency, as ngspice runs it
    if not (count.is_integer() and 1 <= count <= MAX_AC_POINTS and (0 <= start < stop or single)) or (
            spacing != "lin" and start <= 0):
        raise ParameterError(f"{source}: line {number}", line[:200], allowed)
    if measured:
        require_canonical(text)
        _unmeasured_beside(dots, source)
    if spacing == "lin":
        return Sweep(int(count), start, stop)
    major = 0
    if spacing == "dec":
        said = version() if version is not None else ""
        if not said.split(".")[0].isdigit():
            raise ParameterError(f"{source}: line {number}", line[:200], "an .ac lin or oct sweep: the frequencies "
                                 "of an .ac dec sweep depend on the ngspice version, which is not known here")
        major = int(said.split(".")[0])
    try:
        frequencies = log_sweep_count(spacing, int(count), start, stop, reltol=_reltol(text), version=major)
    except ParameterError as error:
        raise ParameterError(f"{source}: line {number}", line[:200], error.allowed) from None
    return Sweep(frequencies, start, stop, spacing, int(count))


def _unmeasured_beside(dots: Sequence[DotCard], source: str) -> None:
    """Refuse an ``.op`` or ``.dc`` beside an ``.ac`` that is measured: ngspice 39 runs them after the sweep and
    measures the last plot it made, so every ``.meas ac`` would come back empty (measured: "Measurements for AC
    Analysis" and no value)."""
    for number, _, line in dots:
        word = line.split(None, 1)[0].lower() if number > 1 else ""  # the first line is the title
        if word in (".op", ".dc"):
            raise ParameterError(f"{source}: line {number}", line.strip()[:200], "no .op or .dc beside a measured "
                                 ".ac (ngspice 39 runs them after the sweep and measures their plot instead)")


def transient_of(text: str, source: str) -> Transient:
    """The netlist's one ``.tran`` analysis, or a refusal naming the card.

    ngspice runs every analysis card it finds, so a second one (a cheap ``.tran`` priced, a dear one run)
    is refused, and so is an ``.ac`` beside it: lcchain reads one transient.
    """
    return _transient(_analysis_cards(dot_cards(text, canonical=False)), source)


def _transient(found: list[tuple[int, str]], source: str) -> Transient:
    """:func:`transient_of` of the analysis cards ``found`` (:func:`_analysis_cards`)."""
    if not found or found[0][1].split(None, 1)[0].lower() != ".tran":
        raise ParameterError(source, ".tran", "a netlist with a .tran analysis (lcchain reads transients)")
    _one_analysis(found, source)
    number, line = found[0]
    words = [w for w in re.split(r"[\s,()]+", line) if w]
    values = [spice_number(w) for w in words[1:] if w.lower() != "uic"]
    numbers = [v for v in values if v is not None and math.isfinite(v)]
    if not 2 <= len(values) <= 4 or len(numbers) != len(values):
        raise ParameterError(f"{source}: line {number}", line[:200], ".tran TSTEP TSTOP [TSTART [TMAX]] [uic] with "
                             "plain finite numbers (lcchain prices a run from them before it starts)")
    step, stop, start, tmax = (numbers + [0.0, 0.0])[:4]
    if not (step > 0 and stop > 0 and 0 <= start < stop and tmax >= 0):
        raise ParameterError(f"{source}: line {number}", line[:200], "0 < TSTEP, 0 <= TSTART < TSTOP, TMAX >= 0")
    default = min(step, (stop - start) / 50)
    return Transient(step, stop, start, min(tmax, default) if tmax > 0 else default)


def _operating_points(dots: Sequence[DotCard]) -> int:
    """The operating points of a netlist's ``.op`` (one each) and ``.dc`` cards
    (:func:`lcchain.spice.cards.dc_points`), among its :func:`~lcchain.spice.text.dot_cards`."""
    points = 0
    for number, _, line in dots:
        word = line.split(None, 1)[0].lower() if number > 1 else ""  # the first line is the title
        if word == ".op":
            points += 1
        elif word == ".dc":
            points += dc_points(line, most=MAX_DC_POINTS) or 0
    return points


def foreign_price(text: str, analysis: Transient | Sweep, saved: int, source: str = "netlist") -> Price:
    """What running a foreign netlist costs, read from its elements, couplings, sources and text
    (:mod:`lcchain.spice.pricing`), with the limits its run gets from it (:meth:`~lcchain.spice.pricing.Price.limits`).

    Parameters
    ----------
    text : str
        The netlist as ngspice will receive it (:func:`allowed_netlist`).
    analysis : Transient or Sweep
        Its analysis (:func:`analysis_of`).
    saved : int
        Its ``.save`` names (0: ngspice saves every unknown).
    source : str
        Its name in messages.

    Raises
    ------
    ParameterError
        A source function lcchain cannot price, naming the line.
    """
    contents = read_contents(text, source)
    dots = dot_cards(text)
    return _priced(contents, dots, bool(measure_names_in(dots)), analysis, saved)


def _priced(contents: Contents, dots: Sequence[DotCard], measured: bool, analysis: Transient | Sweep,
            saved: int) -> Price:
    """:func:`foreign_price` of a netlist's contents, :func:`~lcchain.spice.text.dot_cards` and whether it has
    ``.meas`` cards."""
    price = analysis.price(contents, saved)
    points = _operating_points(dots)
    if points:  # ngspice runs every .op and .dc card beside the analysis lcchain reads
        price = price.plus(operating_price(contents, points=points, saved=saved))
    if measured:  # measured, ngspice keeps every value in memory (no raw file streamed): vectors
        kept = MEASURED_BYTES_FACTOR * price.output_bytes  # that grow by doubling
        price = replace(price, memory=price.memory + kept, simulator_memory=price.simulator_memory + kept)
    return price


#: What ngspice holds of a run with ``.meas`` cards, per byte of its raw file: it keeps every vector in memory to
#: measure them (the raw file is written at the end, :mod:`lcchain.spice.measure`), in arrays grown by doubling.
MEASURED_BYTES_FACTOR = 2.0


def foreign_estimate(text: str, analysis: Transient | Sweep, saved: int, source: str = "netlist") -> Estimate:
    """:func:`foreign_price` as the estimate a budget checks."""
    return foreign_price(text, analysis, saved, source).estimate


@dataclass(frozen=True)
class ForeignRun:
    """What a checked foreign netlist will run and cost (:func:`read_foreign`).

    Attributes
    ----------
    analysis : Transient or Sweep
        Its one analysis (:func:`analysis_of`).
    saved : tuple of str
        The vectors its ``.save`` lines name (:func:`lcchain.spice.text.saved_vectors`).
    price : Price
        What its run costs (:func:`foreign_price` with ``len(saved)``).
    """

    analysis: Transient | Sweep
    saved: tuple[str, ...]
    price: Price


def read_foreign(text: str, source: str, version: Callable[[], str] | None = None) -> ForeignRun:
    """:func:`analysis_of`, :func:`lcchain.spice.text.saved_vectors` and :func:`foreign_price` of one netlist (as
    ngspice will receive it), each exactly as called alone and in that order (the same refusals first), its text
    searched once for the dot-commands all three read: what a batch's plan needs of each netlist.

    Raises
    ------
    ParameterError
        As those three.
    """
    dots = dot_cards(text, canonical=False)
    measured = bool(measure_names_in(dots))
    analysis = _analysis(text, dots, measured, source, version)
    require_canonical(text)  # as saved_vectors refuses a text that is not
    saved = saved_in(dots)
    price = _priced(read_contents(text, source), dots, measured, analysis, len(saved))
    return ForeignRun(analysis, saved, price)
