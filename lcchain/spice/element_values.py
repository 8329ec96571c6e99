"""A netlist's element cards read as names and numbers: what ``lcchain check`` builds its exact reference from.

This reads the text :func:`lcchain.spice.foreign.allowed_netlist` returns (includes inlined, ``+`` lines
joined, comments dropped), so it sees what ngspice will run.  It evaluates every value: SPICE numbers (``1k``,
``10meg``), ``.param`` names and ``{...}`` expressions (:func:`lcchain.spice.expressions.evaluate_expression`).
It knows no physics: an element is its letter, its nodes, its value and its keywords; an independent source its
DC value, its AC magnitude and phase, and its transient function's name and arguments, as written.  What the
elements mean (linear or not, a waveform's defaults) is decided by the caller (:mod:`lcchain.runs.check`).

An expression may call the netlist's ``.func`` functions.  A sub-circuit instance (``X``) is flattened as
ngspice 39 flattens it (:class:`_Flattening`: ``l.xa.x1.l1``, node ``xa.x1.mid``).  A card this module cannot
read as numbers (a keyword without a value, a device, an instance it cannot expand) is kept as an
:class:`OtherCard`, with why, so that the caller can say "no exact reference" rather than refuse the run: the
allow-list (:mod:`lcchain.spice.foreign`) has already decided what may run.  The cards of ``.control`` ...
``.endc`` blocks, and of ``.subckt`` ... ``.ends`` blocks where they are defined, are not the circuit's own.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field, replace

from ..core.errors import ParameterError
from .cards import MAX_SUBCKT_DEPTH, Header, command_of, func_card, instance, subckt_header
from .expressions import (
    UserFunctions,
    braced_expressions,
    evaluate_expression,
    is_param_card,
    param_assignments,
    param_values,
)
from .text import GROUND_NODES, logical_lines, parse_options, spice_number

__all__ = ["ElementCard", "SourceCard", "CouplingCard", "ControlledCard", "OtherCard", "NetlistCards", "read_cards",
           "SOURCE_FUNCTION_NAMES"]

#: The keywords a PWL may end with in ngspice 39: ``R=`` the time its repetition starts from, ``TD=`` its delay.
_PWL_KEYWORDS = ("r", "td")
#: Transient functions of an independent source, as ngspice 39 names them.
SOURCE_FUNCTION_NAMES = frozenset({"pulse", "sin", "pwl", "exp", "sffm", "am", "trnoise", "trrandom", "pat"})
# Blocks of cards that are not elements of the circuit (a netlist run as it is): their first and last words.
_BLOCKS = {".control": ".endc", ".subckt": ".ends"}


@dataclass(frozen=True)
class ElementCard:
    """An R, L or C: ``letter`` (upper case), ``name`` (lower case), nodes ``a`` and ``b`` (lower case), its
    value (ohm, henry, farad) and keywords such as ``ic`` (lower-case names, numbers)."""

    letter: str
    name: str
    a: str
    b: str
    value: float
    keywords: tuple[tuple[str, float], ...] = ()
    where: str = ""


@dataclass(frozen=True)
class SourceCard:
    """A V or I source: its DC value, its AC magnitude and phase (degrees), and its transient function (lower
    case, "" for none) with the arguments as written, read as numbers."""

    letter: str
    name: str
    a: str
    b: str
    dc: float | None
    ac: tuple[float, float] = (0.0, 0.0)
    function: str = ""
    arguments: tuple[float, ...] = ()
    where: str = ""
    #: A PWL's ``R=`` (the time its repetition starts from) and ``TD=`` (its delay), lower case, as written.
    keywords: tuple[tuple[str, float], ...] = ()


@dataclass(frozen=True)
class CouplingCard:
    """A K line: the two coils it couples (lower case) and its coefficient."""

    name: str
    first: str
    second: str
    k: float
    where: str = ""


@dataclass(frozen=True)
class ControlledCard:
    """A linear controlled source from ``a`` to ``b`` (lower case): ``E`` (VCVS) and ``G`` (VCCS) with their
    controlling nodes ``c`` and ``d``; ``F`` (CCCS) and ``H`` (CCVS) with the voltage source whose current
    controls them, ``control``; ``gain`` in V/V, A/V, A/A or V/A."""

    letter: str
    name: str
    a: str
    b: str
    gain: float
    c: str = ""
    d: str = ""
    control: str = ""
    where: str = ""


#: Words after a controlled source's nodes that make it one of ngspice's nonlinear forms (behavioural, polynomial,
#: table, Laplace): no exact reference.
_NONLINEAR_FORMS = ("value", "poly", "table", "vol", "cur", "laplace", "freq")


@dataclass(frozen=True)
class OtherCard:
    """An element this module does not read as numbers: its name (lower case) and why."""

    letter: str
    name: str
    why: str
    where: str = ""


@dataclass(frozen=True)
class NetlistCards:
    """Everything :func:`read_cards` read: the element cards in order, the ``.ic`` node voltages, the ``.tran``
    card's ``uic`` flag, and the options (``method``...)."""

    elements: tuple[ElementCard | SourceCard | CouplingCard | ControlledCard | OtherCard, ...]
    initial: tuple[tuple[str, float], ...] = ()
    uic: bool = False
    options: tuple[tuple[str, str], ...] = field(default=())

    @property
    def method(self) -> str:
        """The integration method ngspice uses (``trap`` unless ``.options method=gear``; ``trapezoidal`` is its
        other name for trap)."""
        method = dict(self.options).get("method", "trap").lower()
        return "trap" if method == "trapezoidal" else method


#: A value with digits after its scale (4k7, 1n5: a European 4.7k, 1.5n), which ngspice reads up to the scale.
_INFIX_SCALE = re.compile(r"(\d+)(meg|[tgkmunpf])(\d+)", re.IGNORECASE)


def _words(text: str) -> list[str]:
    """A card's words; parentheses and commas separate them, ``name=value`` and ``{...}`` stay one word."""
    groups, text = braced_expressions(text)
    text = re.sub(r"\s*=\s*", "=", text)
    words = [w for w in re.split(r"[\s,()]+", text) if w]
    found = iter(groups)
    return [re.sub(r"\{\}", lambda _: "{" + next(found) + "}", w) for w in words]


def _element_value(word: str, params: dict[str, float], where: str, line: str,
                   functions: UserFunctions | None = None) -> float | None:
    """A word as a number: a SPICE number, a ``{...}`` expression (calling the netlist's ``.func`` functions, if
    any), or a ``.param`` name; None if none of these."""
    if word.startswith("{") and word.endswith("}"):
        return evaluate_expression(word[1:-1], params, where, line, functions)
    found = spice_number(word)
    if found is not None:
        return found
    return params.get(word.lower())


def read_cards(text: str, source: str = "netlist") -> NetlistCards:
    """The element cards of a netlist that passed :func:`lcchain.spice.foreign.allowed_netlist`, read as numbers.

    Raises
    ------
    ParameterError
        A card whose value is missing or not a number (naming the source, the line and the card).
    """
    lines = logical_lines(text)[1:]  # the first line is the title
    functions = _functions(lines)
    try:  # a .param inside a sub-circuit's body is the body's own (_Flattening reads it there)
        params = param_values(_param_cards(lines, source), functions=functions)
    except ParameterError:  # a .param lcchain cannot evaluate: the elements that use it say so
        params = {}
    elements: list[ElementCard | SourceCard | CouplingCard | ControlledCard | OtherCard] = []
    initial: list[tuple[str, float]] = []
    uic = False
    block = ""  # inside a .control or .subckt block (a netlist run as it is): not the circuit's own cards
    flattening = _Flattening(_definitions(lines, source), _global_nodes(lines), params, elements, functions)
    for number, line in lines:
        where = f"{source}: line {number}"
        stripped = line.strip()
        if not stripped or stripped.startswith("*"):
            continue
        word = stripped.split(None, 1)[0].lower()
        if block or word in _BLOCKS:
            block = "" if word == _BLOCKS.get(block) else (block or word)
            continue
        head = stripped.split(None, 1)[0].lower()
        if head.startswith("."):
            if head == ".ic":
                body = stripped.split(None, 1)[1] if len(stripped.split(None, 1)) > 1 else ""
                pairs = re.findall(r"v\s*\(\s*([^()\s,]+)\s*\)\s*=\s*(\S+)", body, re.IGNORECASE)
                if not pairs or re.sub(r"v\s*\(\s*[^()\s,]+\s*\)\s*=\s*\S+", "", body, flags=re.IGNORECASE).strip():
                    raise ParameterError(where, line.strip()[:200], ".ic v(NODE)=VALUE ...")
                for node, value in pairs:  # not ``text``: the netlist's, whose options are read below
                    if node.lower() in GROUND_NODES:  # ngspice would hold ground at it: no circuit of lcchain's
                        raise ParameterError(where, line.strip()[:200], ".ic v(NODE)=VALUE of nodes other than "
                                             "ground (0, gnd)")
                    volts = _element_value(value, params, where, line, functions)
                    if volts is None:
                        raise ParameterError(where, line.strip()[:200], ".ic v(NODE)=VALUE ... with numbers")
                    initial.append((node.lower(), volts))
            elif head == ".tran":
                uic = "uic" in (w.lower() for w in _words(stripped))
            continue
        if head[0] == "x":  # a sub-circuit's instance: its elements, named and wired as ngspice flattens them
            flattening.instance(stripped, where, params, "", lambda node: node, 0)
            continue
        try:
            elements.append(_element(stripped, params, where, line, functions))
        except ParameterError:  # the allow-list let it run: no exact reference, not bad input
            name = stripped.split(None, 1)[0]
            infix = next((m for word in stripped.split()[1:] if (m := _INFIX_SCALE.fullmatch(word))), None)
            why = "a value lcchain cannot evaluate: a model name..." if infix is None else (
                f"a value written {infix.group(0)}, which ngspice reads as {infix.group(1)}{infix.group(2)} (the "
                f"digits after its scale ignored); meant as {infix.group(1)}.{infix.group(3)}{infix.group(2)}, it "
                "is written so")
            elements.append(OtherCard(name[0].upper(), name.lower(), why, where))
    return NetlistCards(tuple(elements), tuple(initial), uic, tuple(sorted(parse_options(text).items())))


@dataclass(frozen=True)
class _Definition:
    """A ``.subckt`` block: its card (name, ports, parameters' defaults), where it is, and its body's lines (a
    definition nested in it among them)."""

    header: Header
    where: str
    line: str
    body: tuple[tuple[int, str], ...]


def _definitions(lines: Sequence[tuple[int, str]], source: str = "netlist") -> dict[str, _Definition]:
    """The ``.subckt`` blocks of ``lines`` at their top level, by name (those nested in one are in its body)."""
    found: dict[str, _Definition] = {}
    depth, opened, body = 0, (0, ""), list[tuple[int, str]]()
    for number, line in lines:
        command = command_of(line.split(None, 1)[0].lower()) if line.strip() else None
        if command == ".subckt":
            depth += 1
            if depth == 1:
                opened, body = (number, line), []
                continue
        elif command == ".ends" and depth:
            depth -= 1
            header = subckt_header(opened[1].strip()) if depth == 0 else None
            if header is not None and header.name not in found:  # ngspice keeps the first of one name
                found[header.name] = _Definition(header, f"{source}: line {opened[0]}", opened[1], tuple(body))
            if depth == 0:
                continue
        if depth:
            body.append((number, line))
    return found


def _outside_definitions(lines: Sequence[tuple[int, str]]) -> Iterator[tuple[int, str, str]]:
    """(number, line, first word in lower case, "" for a blank line) of each of ``lines`` outside the ``.subckt``
    blocks defined in them: a netlist's own cards, or a body's own (not those of a definition nested in it)."""
    depth = 0
    for number, line in lines:
        head = line.split(None, 1)[0].lower() if line.strip() else ""
        command = command_of(head) if head else None
        if command == ".subckt" or (command == ".ends" and depth):
            depth += 1 if command == ".subckt" else -1
        elif not depth:
            yield number, line, head


def _param_cards(lines: Sequence[tuple[int, str]], source: str) -> dict[str, tuple[str, str, str]]:
    """The ``.param`` assignments of ``lines`` outside their sub-circuit definitions: name -> (expression, where,
    line), as :func:`lcchain.spice.expressions.param_values` takes them."""
    found: dict[str, tuple[str, str, str]] = {}
    for number, line, head in _outside_definitions(lines):
        if head and is_param_card(head):
            where = f"{source}: line {number}"
            words = line.split(None, 1)
            found |= {name: (value, where, line) for name, value in
                      param_assignments(words[1] if len(words) > 1 else "", where, line)}
    return found


def _functions(lines: Sequence[tuple[int, str]]) -> dict[str, tuple[tuple[str, ...], str]]:
    """The ``.func`` functions of ``lines`` outside their sub-circuit definitions, by name (lower case)."""
    found: dict[str, tuple[tuple[str, ...], str]] = {}
    for _, line, head in _outside_definitions(lines):
        function = func_card(line.strip()) if command_of(head) == ".func" else None
        if function is not None:
            found.setdefault(function.name.lower(), (tuple(a.lower() for a in function.args), function.body))
    return found


def _global_nodes(lines: Sequence[tuple[int, str]]) -> frozenset[str]:
    """The nodes ``.global`` cards name (lower case): one node wherever a sub-circuit names it."""
    return frozenset(node.lower() for _, line in lines if line.strip()
                     and command_of(line.split(None, 1)[0].lower()) == ".global" for node in line.split()[1:])


@dataclass
class _Flattening:
    """A sub-circuit instance's elements as ngspice 39 flattens them, appended to ``out``: an element ``L1`` of
    instance ``X1`` of ``XA`` is ``l.xa.x1.l1`` (its current ``i(l.xa.x1.l1)``), an internal node ``mid`` is
    ``xa.x1.mid``; a port is the node the instance connects, ``0`` and ``.global`` nodes are themselves.  Its
    values are read in the sub-circuit's scope: the instance's parameters (read in the scope that writes them),
    over the ``.subckt`` card's defaults and the body's ``.param`` cards, over the netlist's own ``.param``
    values.  An instance lcchain cannot expand is one :class:`OtherCard`, with why."""

    definitions: dict[str, _Definition]
    globals: frozenset[str]
    netlist: dict[str, float]
    out: list[ElementCard | SourceCard | CouplingCard | ControlledCard | OtherCard]
    functions: UserFunctions

    def instance(self, card: str, where: str, scope: dict[str, float], path: str, node: Callable[[str], str],
                 depth: int, definitions: dict[str, _Definition] | None = None,
                 functions: UserFunctions | None = None) -> None:
        name = card.split(None, 1)[0].lower()
        inner = f"{path}.{name}" if path else name
        source = where.split(": line")[0]  # the file the netlist is read from, as its lines name it
        known = self.definitions if definitions is None else definitions
        found = instance(card)
        definition = known.get(found.subckt) if found is not None else None
        why = ("an instance line lcchain cannot read" if found is None else
               f"no .subckt {found.subckt} defined where it is used" if definition is None else
               f"{len(found.nodes)} nodes for the {len(definition.header.nodes)} of .subckt {found.subckt}"
               if len(found.nodes) != len(definition.header.nodes) else
               f"sub-circuits nested more than {MAX_SUBCKT_DEPTH} deep" if depth >= MAX_SUBCKT_DEPTH else "")
        if found is None or definition is None or why:
            self.out.append(OtherCard("X", _flat_name(name, path), why, where))
            return
        try:
            calling = self.functions if functions is None else functions  # the functions where the instance is
            given = {key: evaluate_expression(text, scope, where, card, calling) for key, text in found.params}
            # the body's own .func, over those it sees from outside
            own_functions = {**calling, **_functions(definition.body)}
            header = definition.header
            defined = {key: (text, definition.where, definition.line) for key, text in header.params}
            defined |= _param_cards(definition.body, source)  # the body's own (its nested definitions' are theirs)
            own = {**self.netlist, **param_values(defined, given, self.netlist, own_functions)}
        except ParameterError as error:
            self.out.append(OtherCard("X", _flat_name(name, path), f"a parameter lcchain cannot evaluate ({error})",
                                      where))
            return
        ports = dict(zip(header.nodes, (node(n) for n in found.nodes), strict=True))

        def inside(n: str) -> str:  # ground ("0", "gnd") and a .global node are everywhere one node, a port of
            # that name too (ngspice 39's expansion keeps them); then a port is the instance's node
            if n in GROUND_NODES or n in self.globals:
                return n
            return ports.get(n) or f"{inner}.{n}"

        local = {**known, **_definitions(definition.body, source)}
        for number, line, head in _outside_definitions(definition.body):
            if not head or head.startswith(("*", ".")):
                continue
            stripped = line.strip()
            at = f"{source}: line {number}"
            if head[0] == "x":
                self.instance(stripped, at, own, inner, inside, depth + 1, local, own_functions)
                continue
            try:
                element = _element(stripped, own, at, line, own_functions)
            except ParameterError:
                element = OtherCard(head[0].upper(), head, "a value lcchain cannot evaluate: a model name...", at)
            self.out.append(_renamed(element, inner, inside))


def _flat_name(name: str, path: str) -> str:
    """An element's name in the flattened circuit, as ngspice 39 gives it: ``l.xa.x1.l1`` for ``L1`` of ``XA.X1``."""
    return f"{name[0]}.{path}.{name}" if path else name


def _renamed(card: ElementCard | SourceCard | CouplingCard | ControlledCard | OtherCard, path: str,
             node: Callable[[str], str]) -> ElementCard | SourceCard | CouplingCard | ControlledCard | OtherCard:
    """A card of a sub-circuit's body as the flattened circuit has it: its name, its nodes, a coupling's coils."""
    if isinstance(card, ElementCard | SourceCard):
        return replace(card, name=_flat_name(card.name, path), a=node(card.a), b=node(card.b))
    if isinstance(card, CouplingCard):
        return replace(card, name=_flat_name(card.name, path), first=_flat_name(card.first, path),
                       second=_flat_name(card.second, path))
    if isinstance(card, ControlledCard):  # its controlling source is the sub-circuit's own
        return replace(card, name=_flat_name(card.name, path), a=node(card.a), b=node(card.b),
                       c=node(card.c) if card.c else "", d=node(card.d) if card.d else "",
                       control=_flat_name(card.control, path) if card.control else "")
    return replace(card, name=_flat_name(card.name, path))


def _element(card: str, params: dict[str, float], where: str, line: str, functions: UserFunctions | None = None
             ) -> ElementCard | SourceCard | CouplingCard | ControlledCard | OtherCard:
    words = _words(card)
    letter, name = words[0][0].upper(), words[0].lower()

    def value_of(word: str, what: str) -> float:
        value = _element_value(word, params, where, line, functions)
        if value is None:
            raise ParameterError(where, line.strip()[:200], f"{what} as a number, a .param name or a {{...}} "
                                 f"expression, not {word!r}")
        return value

    if letter in "RLC":
        if len(words) < 4:
            raise ParameterError(where, line.strip()[:200], f"{letter}NAME NODE NODE VALUE [KEY=VALUE ...]")
        rest = words[3:]
        value_word = rest[0]
        if "=" in value_word and value_word.split("=", 1)[0].lower() in ("r", "l", "c", "resistance",
                                                                          "inductance", "capacitance"):
            value_word = value_word.split("=", 1)[1]
        elif "=" in value_word:
            return OtherCard(letter, name, "a value given only by keywords", where)
        keywords = []
        for word in rest[1:]:
            key, sep, text = word.partition("=")
            if not sep:
                return OtherCard(letter, name, f"the word {word!r} after its value", where)
            keywords.append((key.lower(), value_of(text, key)))
        return ElementCard(letter, name, words[1].lower(), words[2].lower(), value_of(value_word, "the value"),
                           tuple(keywords), where)
    if letter == "K":
        if len(words) != 4:
            raise ParameterError(where, line.strip()[:200], "KNAME LNAME LNAME COEFFICIENT")
        return CouplingCard(name, words[1].lower(), words[2].lower(), value_of(words[3], "the coefficient"), where)
    if letter in "VI":
        return _source(words, letter, name, value_of, where)
    if letter in "EFGH":
        return _controlled(words, letter, name, value_of, where)
    return OtherCard(letter, name, "", where)


def _controlled(words: list[str], letter: str, name: str, value_of: Callable[[str, str], float], where: str
                ) -> ControlledCard | OtherCard:
    """``Ename A B C D GAIN``, ``Gname A B C D GAIN``, ``Fname A B VNAME GAIN``, ``Hname A B VNAME GAIN``; any other
    form (``value=``, ``poly``, ``table``...) is ngspice's nonlinear one: an :class:`OtherCard`."""
    rest = [w.lower() for w in words[3:]]
    if any(w.split("=", 1)[0] in _NONLINEAR_FORMS or w.startswith(_NONLINEAR_FORMS) for w in rest):
        return OtherCard(letter, name, "a nonlinear form (value, poly, table...)", where)
    a, b = words[1].lower(), words[2].lower()
    if letter in "EG" and len(words) == 6:
        return ControlledCard(letter, name, a, b, value_of(words[5], "the gain"), words[3].lower(), words[4].lower(),
                              where=where)
    if letter in "FH" and len(words) == 5:
        return ControlledCard(letter, name, a, b, value_of(words[4], "the gain"), control=words[3].lower(),
                              where=where)
    return OtherCard(letter, name, f"{len(words) - 1} words (a linear {letter} source has "
                     f"{5 if letter in 'EG' else 4})", where)


def _source(words: list[str], letter: str, name: str, value_of: object, where: str) -> SourceCard | OtherCard:
    read = value_of  # (word, what) -> float
    if len(words) < 3:
        return OtherCard(letter, name, "no nodes", where)
    a, b = words[1].lower(), words[2].lower()
    rest = words[3:]
    dc: float | None = None
    ac = (0.0, 0.0)
    function, arguments = "", tuple[float, ...]()
    keywords: list[tuple[str, float]] = []
    k = 0
    while k < len(rest):
        word = rest[k].lower()
        if word == "dc" and k + 1 < len(rest):
            dc = read(rest[k + 1], "the DC value")  # type: ignore[operator]
            k += 2
        elif word == "ac":
            values: list[float] = []
            k += 1
            while k < len(rest) and len(values) < 2 and rest[k].lower() not in SOURCE_FUNCTION_NAMES | {"dc"}:
                values.append(read(rest[k], "the AC magnitude and phase"))  # type: ignore[operator]
                k += 1
            ac = (values[0] if values else 1.0, values[1] if len(values) > 1 else 0.0)
        elif word in SOURCE_FUNCTION_NAMES:
            function = word
            k += 1
            found = []
            while k < len(rest) and rest[k].lower() not in ("dc", "ac"):
                key, equals, text = rest[k].lower().partition("=")
                value = _maybe(text if equals else rest[k], read)
                if equals and function == "pwl" and key in _PWL_KEYWORDS and value is not None:
                    keywords.append((key, value))
                elif value is None or equals:
                    return OtherCard(letter, name, f"{function.upper()} argument {rest[k]!r}", where)
                else:
                    found.append(value)
                k += 1
            arguments = tuple(found)
        elif dc is None and _maybe(rest[k], read) is not None:
            dc = _maybe(rest[k], read)
            k += 1
        else:
            return OtherCard(letter, name, f"the word {rest[k]!r}", where)
    return SourceCard(letter, name, a, b, dc, ac, function, arguments, where, tuple(keywords))


def _maybe(word: str, read: object) -> float | None:
    try:
        return read(word, "")  # type: ignore[operator, no-any-return]
    except ParameterError:
        return None
