"""What lcchain reads in netlist text: vector names, options, saved vectors, numbers.

Vector names
------------
The caller names vectors as the netlist ``.save``\\ s them; ngspice 39
accepts both ``.save i(l1)`` and ``.save l1#branch`` for an inductor current
and ``.save v(n3)`` (or ``n3``) for a node voltage.  The raw file calls them
``i(l1)`` and ``v(n3)``, the shared library's plot ``l1#branch`` and ``n3``.
lcchain normalises every name, requested or found, to the raw-file form in
lower case (SPICE names are case-insensitive):

====================  ==============
written               key in result
====================  ==============
``i(L1)``             ``"i(l1)"``
``l1#branch``         ``"i(l1)"``
``v(N3)``, ``n3``     ``"v(n3)"``
====================  ==============

Other names (``@l1[i]``, ``v(a,b)``) are only lower-cased.

What ngspice may be given of a netlist lcchain did not write is decided by
the allow-list of :mod:`lcchain.spice.foreign`.

One text, one way to split it
-----------------------------
Python's ``str.splitlines`` breaks a line at eleven characters (``\\v``,
``\\f``, ``\\x1c``-``\\x1e``, NEL, U+2028, U+2029, a lone CR, ...), ngspice's
file reader at ``\\n`` alone.  A check that splits one way and a transport
that splits the other would run a card the check took for part of a comment.
So a foreign netlist is made canonical once (:func:`canonical_text`: strict
UTF-8, CRLF read as LF, a leading byte-order mark dropped, and every other
line or paragraph separator, control character or mark refused, naming the
line and the character), and every reader of netlist text -- the allow-list,
each transport, each engine's dialect -- splits it with :func:`netlist_lines`,
which refuses a text that is not canonical (:func:`require_canonical`).
"""

from __future__ import annotations

import hashlib
import re
import unicodedata
from collections.abc import Sequence
from functools import lru_cache

from ..core.errors import ParameterError
from ..core.limits import MAX_TITLE_BYTES

__all__ = ["canonical_vector_name", "parse_options", "logical_lines", "spice_number", "saved_vectors",
           "canonical_text", "require_canonical", "netlist_lines", "circuit_lines", "text_digest", "NEWLINE",
           "DotCard", "dot_cards", "saved_in", "odd_lines"]

#: A card of :func:`dot_cards`: (line number, its first physical line, the logical line).
DotCard = tuple[int, str, str]
#: The one line separator of a canonical netlist.
NEWLINE = "\n"
# What a canonical netlist may not hold: every control character but tab and LF (C0, DEL, C1 with NEL), the
# Unicode line and paragraph separators, and a byte-order mark (U+FEFF) past the first character.
_NOT_CANONICAL = re.compile("[\x00-\x08\x0b-\x1f\x7f-\x9f\u2028\u2029\ufeff]")
# The ASCII characters a canonical netlist may hold: what _NOT_CANONICAL leaves of them.
_CANONICAL_ASCII = b"\t\n" + bytes(range(0x20, 0x7F))

_OPTIONS_LINE = re.compile(r"^\s*\.opt(ion|ions)?\b(.*)$", re.IGNORECASE)

# A "+" line that continues a blank one (the first line's, or one after an LF)
_BLANK_CONTINUED = re.compile(r"\n[^\S\n]*\n\+")
_FIRST_BLANK_CONTINUED = re.compile(r"[^\S\n]*\n\+")

_SAVE = re.compile(r"^\s*\.save\b(.*)$", re.IGNORECASE)
# A logical line whose first character that is not blank (str.isspace, as str.split and str.strip read it: the same
# set as \s) is a dot, with the physical lines that continue it (those that start with "+": logical_lines joins
# them, each's "+" replaced by a space).
# Searched for after an LF (a literal first: many times faster than a search for "^" at every character), and
# matched at the text's start for its first line.
_DOT_CARD_TEXT = r"[^\S\n]*\.[^\n]*(?:\n\+[^\n]*)*"
_DOT_CARD = re.compile(f"\\n({_DOT_CARD_TEXT})")
_FIRST_DOT_CARD = re.compile(_DOT_CARD_TEXT)
_NUMBER = re.compile(r"^([-+]?(?:\d+\.?\d*|\.\d+)(?:e[-+]?\d+)?)(meg|mil|[tgkmunpf])?[a-z]*$", re.IGNORECASE)
_SCALE = {"t": 1e12, "g": 1e9, "meg": 1e6, "k": 1e3, "m": 1e-3, "mil": 25.4e-6, "u": 1e-6, "n": 1e-9, "p": 1e-12,
          "f": 1e-15}

def spice_number(text: str) -> float | None:
    """A SPICE number: ``1e-6``, ``1u``, ``10meg``, ``2.5ns`` (the unit letters after the scale are ignored)."""
    match = _NUMBER.match(text.strip())
    if match is None:
        return None
    value = float(match.group(1))
    return value * _SCALE[match.group(2).lower()] if match.group(2) else value


def saved_vectors(netlist: str) -> tuple[str, ...]:
    """The vectors the ``.save`` lines name (empty: ngspice saves every node voltage and branch current)."""
    return saved_in(dot_cards(netlist))  # a .save line is a dot card: the other lines need not be read


def saved_in(cards: Sequence[DotCard]) -> tuple[str, ...]:
    """:func:`saved_vectors` of a netlist's :func:`dot_cards`."""
    names: list[str] = []
    for _, _, line in cards:
        match = _SAVE.match(line)
        if match:
            names += [w for w in match.group(1).split() if w.lower() not in ("all", "allv", "alli")]
    return tuple(dict.fromkeys(names))


def canonical_vector_name(name: str) -> str:
    """Normalise an ngspice vector name to lcchain's key convention.

    Parameters
    ----------
    name : str
        ``i(l1)``, ``l1#branch``, ``v(n3)``, ``n3``, ... in any case.

    Returns
    -------
    str
        ``"i(l1)"`` for a branch current, ``"v(n3)"`` for a node voltage,
        ``"time"`` for time and ``"frequency"`` for frequency (the scales of a
        transient and an AC analysis), otherwise the lower-cased name.
    """
    text = name.strip().lower()
    if text.endswith("#branch"):
        return f"i({text[: -len('#branch')]})"
    device = _DEVICE_VECTOR.match(text)
    if device:  # a raw file writes @r2[i] as i(@r2[i]); the shared library names it as .save does
        return device.group(1)
    if text in ("time", "frequency") or "(" in text or "@" in text or "#" in text or "[" in text:
        return text
    return f"v({text})"


_DEVICE_VECTOR = re.compile(r"^[iv]\((@[^()]+)\)$")
_DIFFERENCE = re.compile(r"^v\(([^(),\s]+),([^(),\s]+)\)$", re.IGNORECASE)
#: The names ngspice gives ground: a node voltage it never saves.
GROUND_NODES = ("0", "gnd")


def saved_names(name: str) -> tuple[str, ...]:
    """The vectors ngspice saves for a ``.save`` name, canonical: ``v(a,b)`` saves ``v(a)`` and ``v(b)`` (ground's
    voltage is no vector), any other name itself (:func:`canonical_vector_name`)."""
    difference = _DIFFERENCE.match(name.strip())
    if difference is None:
        return (canonical_vector_name(name),)
    return tuple(f"v({node.lower()})" for node in difference.groups() if node.lower() not in GROUND_NODES)


def _character(char: str) -> str:
    """A character as a message names it: ``U+2028 (LINE SEPARATOR)``."""
    name = unicodedata.name(char, "") or {"\r": "CARRIAGE RETURN", "\x85": "NEXT LINE",
                                          "\x0b": "LINE TABULATION", "\x0c": "FORM FEED",
                                          "\x00": "NULL"}.get(char, "a control character")
    return f"U+{ord(char):04X} ({name})"


def canonical_text(text: str | bytes, source: str, *, title: bool = True) -> str:
    """A netlist's one canonical text: what the allow-list checks and every transport runs.

    Parameters
    ----------
    text : str or bytes
        The netlist as read (bytes are decoded as strict UTF-8: an invalid or
        overlong sequence, a lone surrogate or a UTF-16 file is refused).
    source : str
        Its name in messages (the file, or ``"netlist"``).
    title : bool
        Its first line that is not blank is a title (a netlist, not an included file): at most
        :data:`lcchain.core.limits.MAX_TITLE_BYTES` bytes.

    Returns
    -------
    str
        The text with CRLF read as LF and a leading byte-order mark dropped;
        ``text`` itself when it needed neither.

    Raises
    ------
    ParameterError
        Naming ``"<source>: line <n>"``, the line and the character: any
        control character but tab and LF (a CR alone, NUL, form feed, vertical
        tab, NEL, ...), U+2028, U+2029, or a byte-order mark past the start.
    """
    if isinstance(text, bytes):
        data = text
        try:
            text = data.decode("utf-8")
        except UnicodeDecodeError as error:
            number = data.count(b"\n", 0, error.start) + 1
            line = data.split(b"\n")[number - 1]
            raise ParameterError(f"{source}: line {number}", line[:200], f"UTF-8 text ({error.reason}: byte "
                                 f"{data[error.start]:#04x} at byte {error.start} of the file)") from None
    if text.startswith("\ufeff"):
        text = text[1:]
    if "\r\n" in text:
        text = text.replace("\r\n", NEWLINE)
    require_canonical(text, source)
    # the title, the first line that is not blank: ngspice 39 reads it into a fixed buffer
    match = re.search(r"[^\s]", text) if title else None
    if match is not None:
        number = text.count(NEWLINE, 0, match.start()) + 1
        head = text.split(NEWLINE, number)[number - 1]
        size = len(head.encode("utf-8"))
        if size > MAX_TITLE_BYTES:
            raise ParameterError(f"{source}: line {number}", head[:200], f"a title of at most {MAX_TITLE_BYTES} "
                                 f"bytes (this one has {size}; ngspice 39 reads the title into a fixed buffer: 505 "
                                 "bytes abort it, a longer title spills into the next card)")
    return text


def require_canonical(text: str, source: str = "netlist") -> str:
    """``text``, if it is canonical (what :func:`canonical_text` returns unchanged); else the refusal.

    Every transport calls it (through :func:`netlist_lines`) on what it is about to run, so that a text no
    check has made canonical can never reach an engine that would split it otherwise.
    """
    if text.isascii() and not text.encode("ascii").translate(None, _CANONICAL_ASCII):
        return text  # the common case, told without a search of every character for a class of them
    bad = _NOT_CANONICAL.search(text)
    if bad is not None:
        number = text.count(NEWLINE, 0, bad.start()) + 1
        line = text.split(NEWLINE)[number - 1]
        raise ParameterError(f"{source}: line {number}", line[:200], f"a line without {_character(bad.group())} "
                             "(lines end at LF alone; ngspice and lcchain's checks could split such a line "
                             "differently)")
    return text


def netlist_lines(text: str) -> list[str]:
    """The lines of a canonical netlist, split at LF alone, as ngspice reads a file (refused if not canonical)."""
    return require_canonical(text).split(NEWLINE)


def circuit_lines(text: str) -> list[str]:
    """The lines a shared-library transport hands ``ngSpice_Circ``: :func:`netlist_lines`, ending with an empty
    line (ngspice 33 and later want one; a text ending in LF has it already)."""
    lines = netlist_lines(text)
    return lines if lines[-1] == "" else [*lines, ""]


def text_digest(lines: list[str]) -> str:
    """SHA-256 of lines joined by LF: a worker tells the parent the digest of the lines it handed its engine,
    and the parent compares it with the digest of :func:`circuit_lines` of the text it checked."""
    return hashlib.sha256(NEWLINE.join(lines).encode("utf-8")).hexdigest()


def logical_lines(netlist: str) -> list[tuple[int, str]]:
    """(first physical line number, text) of each logical line, ``+`` continuations joined."""
    physical = netlist_lines(netlist)
    if "\n+" not in netlist:  # no line continues another (a first line's "+" continues nothing): one per line
        return list(enumerate(physical, start=1))
    lines: list[tuple[int, str]] = []
    for number, raw in enumerate(physical, start=1):
        if raw.startswith("+") and lines:
            first, text = lines[-1]
            lines[-1] = (first, text + " " + raw[1:])
        else:
            lines.append((number, raw))
    return lines


def dot_cards(netlist: str, *, canonical: bool = True) -> list[DotCard]:
    """(line number, physical line, logical line) of each logical line whose first character that is not blank is
    a dot, in order: what :func:`logical_lines` gives of them (``+`` continuations joined), with the first
    physical line of each, found by one search of the text rather than a look at every line.

    A netlist of a thousand element lines has a handful of dot-commands (its analysis, options, saves), which
    every reader of those needs: so each reads only these.  With ``canonical`` (the default) the text is refused
    as :func:`logical_lines` refuses it (:func:`require_canonical`); without, it is split at LF alone, as
    ``text.split("\\n")`` splits it.
    """
    if canonical:
        require_canonical(netlist)
    found: list[DotCard] = []
    first = _FIRST_DOT_CARD.match(netlist)
    if first is not None:
        card = first.group()
        found.append((1, card.partition(NEWLINE)[0], card.replace("\n+", " ")))
    number, at = 1, 0
    for match in _DOT_CARD.finditer(netlist, first.end() if first is not None else 0):
        start = match.start(1)
        number += netlist.count(NEWLINE, at, start)
        at = start
        card = match.group(1)
        found.append((number, card.partition(NEWLINE)[0], card.replace("\n+", " ")))
    return found


@lru_cache(maxsize=8)
def _odd_start(first: bytes) -> re.Pattern[bytes]:
    """An LF not followed by a byte of ``first``: the start of a line :func:`odd_lines` returns (a search for a
    literal LF first, then one byte looked at)."""
    return re.compile(b"\\n(?![" + re.escape(first) + b"])")


def odd_lines(text: str, first: bytes, rest: bytes | None = None, *, blank_end: bool = False) -> list[int]:
    """The indices, in order, of the lines of ``text`` (split at LF, as ``text.split("\\n")``) that do not start
    with a byte of ``first``, or (given ``rest``) hold a character that is in neither (a non-ASCII one is in
    neither), or (with ``blank_end``) end with a space or a tab; ``first`` and ``rest`` are ASCII.

    Found by a search of the text for each kind of odd line, not by a look at each line: a reader whose common
    line is simple (a ladder's ``L`` and ``C`` lines) takes the others in bulk and looks only at these.
    """
    if not first:  # no line starts with a byte of none
        return list(range(text.count(NEWLINE) + 1))
    data = text.encode("utf-8", "surrogatepass")
    starts = [] if data[:1] and data[:1] in first else [0]  # a byte of each odd line, its line counted below
    starts += [match.end() for match in _odd_start(first).finditer(data)]
    if rest is not None:
        for byte in set(data.translate(None, first + rest + b"\n")):  # each character of neither: its lines
            at = data.find(byte)
            while at >= 0:
                starts.append(at)
                end = data.find(b"\n", at)
                at = data.find(byte, end) if end >= 0 else -1
    if blank_end:
        for needle in (b" \n", b"\t\n"):
            at = data.rfind(needle)
            while at >= 0:
                starts.append(at)
                at = data.rfind(needle, 0, at)
        if data.endswith((b" ", b"\t")):
            starts.append(len(data) - 1)
    found: list[int] = []
    line, counted = 0, 0
    for at in sorted(starts):
        line += data.count(b"\n", counted, at)
        counted = at
        if not found or found[-1] != line:
            found.append(line)
    return found


def parse_options(netlist: str) -> dict[str, str]:
    """The ``.options`` a netlist sets, read from its text.

    Parameters
    ----------
    netlist : str
        Netlist text. ``.option``, ``.options`` and ``.opt`` lines count, with
        ``+`` continuation lines; later settings override earlier ones.

    Returns
    -------
    dict[str, str]
        Lower-cased option name -> value as written (``"1e-6"``, ``"trap"``);
        a bare flag such as ``noinit`` maps to ``"true"``.
    """
    options: dict[str, str] = {}
    # an options line is a dot card, the other lines not looked at; unless a "+" line continues a blank one, which
    # logical_lines joins into a line that may start with a dot (dot_cards does not: it starts at a dot)
    blank_continued = _BLANK_CONTINUED.search(netlist) or _FIRST_BLANK_CONTINUED.match(netlist)
    for line in (line for _, line in logical_lines(netlist)) if blank_continued else \
            (line for _, _, line in dot_cards(netlist)):
        match = _OPTIONS_LINE.match(line)
        if not match:
            continue
        body = re.sub(r"\s*=\s*", "=", match.group(2).strip())
        for token in body.split():
            key, sep, value = token.partition("=")
            options[key.lower()] = value if sep else "true"
    return options
