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
"""

from __future__ import annotations

import re

__all__ = ["canonical_vector_name", "parse_options", "logical_lines", "spice_number", "saved_vectors"]

_OPTIONS_LINE = re.compile(r"^\s*\.opt(ion|ions)?\b(.*)$", re.IGNORECASE)

_SAVE = re.compile(r"^\s*\.save\b(.*)$", re.IGNORECASE)
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
    names: list[str] = []
    for _, line in logical_lines(netlist):
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
    if text in ("time", "frequency") or "(" in text or "@" in text or "#" in text or "[" in text:
        return text
    return f"v({text})"


def logical_lines(netlist: str) -> list[tuple[int, str]]:
    """(first physical line number, text) of each logical line, ``+`` continuations joined."""
    lines: list[tuple[int, str]] = []
    for number, raw in enumerate(netlist.splitlines(), start=1):
        if raw.startswith("+") and lines:
            first, text = lines[-1]
            lines[-1] = (first, text + " " + raw[1:])
        else:
            lines.append((number, raw))
    return lines


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
    for _, line in logical_lines(netlist):
        match = _OPTIONS_LINE.match(line)
        if not match:
            continue
        body = re.sub(r"\s*=\s*", "=", match.group(2).strip())
        for token in body.split():
            key, sep, value = token.partition("=")
            options[key.lower()] = value if sep else "true"
    return options
