"""Variants of a netlist lcchain did not write: one value replaced, nothing else (``lcchain sweep --netlist``).

This is the one place where lcchain edits the text of a netlist it did not write.  It works on the text that
:func:`lcchain.spice.foreign.allowed_netlist` returned (one card per line: ``+`` continuations joined, includes
inlined, inline comments dropped), so the card whose value is replaced is a card that was checked; the caller
checks each variant again with the same allow-list and runs the text that comes back from it.

What may vary
-------------
* a ``.param`` name (any card ngspice reads as ``.param``): its right-hand side, a number or an expression,
  becomes the number;
* an element of :data:`VALUED` (R, L, C and the coupling K): its value field (the token after its two nodes, or
  after its two inductors for K) when that is a plain SPICE number.  An element whose value is a ``{...}``
  expression is refused, naming the ``.param`` names the expression uses: vary those instead.

Names are matched as ngspice matches them, in any case.  A value is written as ``repr(float(value))``: digits, a
point, a sign and an exponent, so nothing a value holds can be read as another token, card or command.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Literal

from ..core.errors import ParameterError
from .expressions import braced_expressions, check_expression, is_param_card
from .text import NEWLINE, netlist_lines, spice_number

__all__ = ["VALUED", "Target", "TargetKind", "netlist_targets", "find_target", "with_values", "spice_value"]

#: Element letters whose value field may vary, and that field's place among the card's tokens (0: the name).
VALUED: dict[str, int] = {"R": 3, "L": 3, "C": 3, "K": 3}
#: What a varied name is in the netlist.
TargetKind = Literal["param", "element"]
#: Most names a refusal lists (a netlist may define a thousand).
_LISTED = 40

# A token of an element card: a run of non-blank characters, a {...} group (which may hold blanks) counting as
# part of the token it is written in.
_TOKEN = re.compile(r"(?:\{[^{}]*\}|[^\s{}])+")
# "name =" where a .param assignment starts (as lcchain.spice.expressions reads them)
_ASSIGNMENT = re.compile(r"(?:^|(?<=\s))([A-Za-z_][A-Za-z0-9_]*)\s*=(?!=)")


@dataclass(frozen=True)
class Target:
    """Where a name's value is written in the checked text.

    Attributes
    ----------
    name : str
        As the netlist writes it.
    kind : {"param", "element"}
    line : int
        Its card's index among the text's lines (0: the title).
    start, end : int
        The value's span in that line.
    value : str
        The value as written (``"1k"``, ``"{rv}"``).
    subckt : str
        The sub-circuit whose body holds it ("" at the netlist's top level).
    """

    name: str
    kind: TargetKind
    line: int
    start: int
    end: int
    value: str
    subckt: str = ""

    def describe(self) -> str:
        return f".param {self.name}" if self.kind == "param" else f"the element {self.name}"


def netlist_targets(text: str) -> dict[str, list[Target]]:
    """Every ``.param`` name and every :data:`VALUED` element of a checked text, by lower-case name (a list: a
    name may be defined twice, or be both a ``.param`` and an element)."""
    found: dict[str, list[Target]] = {}
    lines = netlist_lines(text)
    inside: list[str] = []  # the sub-circuits whose body the line is in, innermost last
    for number, line in enumerate(lines[1:], start=1):  # line 0 is the title
        words = line.split(None, 1)
        if not words or words[0].startswith("*"):
            continue
        word = words[0]
        if word.lower() == ".subckt" and len(words) > 1:
            inside.append(words[1].split(None, 1)[0])
            continue
        if word.lower() == ".ends":
            if inside:
                inside.pop()
            continue
        if is_param_card(word.lower()):
            body = line[len(line) - len(line.lstrip()) + len(word):]
            offset = len(line) - len(body)
            starts = list(_ASSIGNMENT.finditer(body))
            for k, match in enumerate(starts):
                end = starts[k + 1].start() if k + 1 < len(starts) else len(body)
                value = body[match.end():end]
                left = match.end() + len(value) - len(value.lstrip())
                right = end - (len(value) - len(value.rstrip()))
                target = Target(match.group(1), "param", number, offset + left, offset + right,
                                body[left:right])
                found.setdefault(target.name.lower(), []).append(target)
        elif word[0] != ".":  # every element, so that a refusal can say why a source does not vary
            tokens = list(_TOKEN.finditer(line))
            place = VALUED.get(word[0].upper(), len(tokens))
            token = tokens[place] if len(tokens) > place else None
            target = Target(word, "element", number, token.start() if token else len(line),
                            token.end() if token else len(line), token.group() if token else "",
                            inside[-1] if inside else "")
            found.setdefault(word.lower(), []).append(target)
    return found


def _listed(targets: Mapping[str, list[Target]]) -> str:
    params = sorted({t.name for ts in targets.values() for t in ts if t.kind == "param"}, key=str.lower)
    elements = sorted({t.name + (f" (in .subckt {t.subckt})" if t.subckt else "") for ts in targets.values()
                       for t in ts if t.kind == "element" and t.name[0].upper() in VALUED}, key=str.lower)
    parts = []
    for what, names in ((".param names", params), (f"{', '.join(sorted(VALUED))} elements", elements)):
        shown = ", ".join(names[:_LISTED]) + (f" and {len(names) - _LISTED} more" if len(names) > _LISTED else "")
        parts.append(f"{what}: {shown or 'none'}")
    return "; ".join(parts)


def find_target(targets: Mapping[str, list[Target]], name: str, option: str = "--vary",
                shown: str | None = None) -> Target:
    """The one place ``name``'s value is written, or a refusal naming ``option``, ``shown`` (what the user typed;
    default the name) and the name: a name the netlist does not define (listing those it does), one it defines
    twice, an element without a value field lcchain varies (a source), or an element whose value is not a plain
    number (an expression: naming the ``.param`` names it uses)."""
    value = name if shown is None else shown
    found = targets.get(name.lower(), [])
    letters = ", ".join(sorted(VALUED))
    if not found:
        raise ParameterError(option, value, f"a .param name or an element ({letters}) of the netlist, which "
                             f"defines no {name}: it has {_listed(targets)}")
    if len(found) > 1:
        where = " and ".join(f"{t.describe()} (card {t.line + 1})" for t in found[:2])
        raise ParameterError(option, value, f"a name the netlist defines once ({name}: {where}); rename one to "
                             "vary the other")
    target = found[0]
    if target.kind == "element" and target.name[0].upper() not in VALUED:
        raise ParameterError(option, value, f"a .param name or an element ({letters}) of the netlist; "
                             f"{target.name} is a {target.name[0].upper()} element, whose value lcchain does not "
                             "vary: write the value it should vary as {p} with .param p = VALUE, and vary p")
    if target.kind == "element":
        if "{" in target.value:
            used: set[str] = set()
            for group in braced_expressions(target.value)[0]:
                used |= check_expression(group, None, option, value)
            names = ", ".join(sorted(used))
            params = {t.name.lower() for ts in targets.values() for t in ts if t.kind == "param"}
            if target.subckt and not any(name.lower() in params for name in used):
                advice = (f"it is in .subckt {target.subckt}, whose parameters ({names}) its X lines set: write an "
                          "X line's value as {p} with .param p = VALUE, and vary p")
            else:
                advice = (f"vary the .param it uses instead: {names}" if used else
                          "give it a .param (.param p = VALUE and {p} as its value) and vary that")
            raise ParameterError(option, value, f"an element whose value is a number; {target.name}'s value is "
                                 f"the expression {target.value}: {advice}")
        if not target.value or "=" in target.value or spice_number(target.value) is None:
            raise ParameterError(option, value, f"an element whose value field is a plain number; {target.name}'s "
                                 f"is {target.value or 'missing'!r}")
    return target


def spice_value(value: float) -> str:
    """A value as a variant writes it: ``repr(float(value))``, finite only (never a SPICE suffix: ``M`` is milli)."""
    value = float(value)
    if not math.isfinite(value):
        raise ParameterError("value", value, "a finite number")
    return repr(value)


def with_values(text: str, values: Mapping[Target, float]) -> str:
    """The text with each target's value replaced by its number (:func:`spice_value`), nothing else changed.

    Parameters
    ----------
    text : str
        The checked text the targets were found in (:func:`netlist_targets`).
    values : Mapping[Target, float]
        Each target's new value.
    """
    lines = netlist_lines(text)
    by_line: dict[int, list[tuple[Target, float]]] = {}
    for target, value in values.items():
        if not 0 < target.line < len(lines) or lines[target.line][target.start:target.end] != target.value:
            raise ParameterError("target", target.name, "a place found in this same text")
        by_line.setdefault(target.line, []).append((target, value))
    for number, changes in by_line.items():
        line = lines[number]
        for target, value in sorted(changes, key=lambda change: -change[0].start):  # right to left: spans hold
            line = f"{line[:target.start]}{spice_value(value)}{line[target.end:]}"
        lines[number] = line
    return NEWLINE.join(lines)
