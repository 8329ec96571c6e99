"""Reading gnucap's output: its ``.print`` tables (transient and AC) and the lines worth quoting.

The output
----------
``gnucap -b /dev/stdin`` prints a banner, then the table: a ``#Time`` header
and one row per print step, numbers with SPICE suffixes
(``15.811388300842n``) or exponents (``-4.398E-18``).  gnucap exits 0 after
an error, so any message before the table, a malformed row or no table is a
:class:`~lcchain.core.errors.SimulationError`.  Its t = 0 row is printed
before the initial conditions apply (``i(L1) = 0`` where ``ic=1``: measured),
so it is dropped: a gnucap run's time starts at its first step.

An AC table (``#Freq``) holds each complex vector as its real and imaginary parts, ``ir(l1) ii(l1)``, which
:func:`read_ac_table` pairs into one complex column; several ``.ac`` cards print one table each, under the same
header, read one after the other.
"""

from __future__ import annotations

import re
from typing import TYPE_CHECKING

from ..core.errors import SimulationError
from .log import useful_output
from .text import canonical_vector_name

if TYPE_CHECKING:
    import numpy as np

__all__ = ["read_table", "read_ac_table", "table_number", "failure", "quiet", "quote", "without_rows", "TITLE"]

#: The title every translated netlist gets (none of the user's text reaches gnucap).
TITLE = "* lcchain ladder in gnucap's dialect"

_NUMBER = re.compile(r"^([-+]?(?:\d+\.?\d*|\.\d+)(?:e[-+]?\d+)?)(f|p|n|u|m|k|meg|g|t)?$", re.IGNORECASE)
#: The decimal exponent of each suffix gnucap prints (read as ``mantissa e exponent``: one correctly rounded float).
_EXPONENT = {"f": -15, "p": -12, "n": -9, "u": -6, "m": -3, "k": 3, "meg": 6, "g": 9, "t": 12}
_BANNER = re.compile(r"^(Gnucap\b|Never trust|Copyright|Gnucap comes|This is free|to redistribute|the GNU General"
                     r"|See the file|main version|core-lib version|default plugins)")
_PART = re.compile(r"^([iv])([ri])\((\w+)\)$")


def failure(reason: str, log_tail: str = "", status: str = "failed") -> SimulationError:
    """A failure said by gnucap."""
    return SimulationError(reason, log_tail, status, "gnucap")


def without_rows(log: str) -> str:
    """gnucap's output without its table's rows (what :attr:`RunResult.log` keeps)."""
    return "\n".join(line for line in log.splitlines()
                     if line.strip() and not (line.split() and table_number(line.split()[0]) is not None))


def quiet(log: str) -> str:
    """gnucap's output without its banner and its table's rows."""
    return "\n".join(line for line in without_rows(log).splitlines() if not _BANNER.match(line))


def quote(log: str) -> str:
    """gnucap's output worth quoting in an error: without its banner and its table's rows."""
    return useful_output(quiet(log))


def table_number(text: str) -> float | None:
    """A number as gnucap prints it (``15.811388300842n``, ``-4.398E-18``), or None for any other word."""
    match = _NUMBER.match(text)
    if match is None:
        return None
    mantissa, suffix = match.groups()
    if suffix is None:
        return float(mantissa)
    if "e" in mantissa.lower():  # never printed by gnucap: scale it
        return float(mantissa) * 10.0 ** _EXPONENT[suffix.lower()]
    return float(f"{mantissa}e{_EXPONENT[suffix.lower()]}")


def read_table(output: str, log: str = "") -> dict[str, np.ndarray]:
    """gnucap's ``.print tran`` table as columns keyed by canonical name (``"time"``, ``"i(l1)"``...).

    The t = 0 row is dropped (gnucap prints it before the initial conditions apply).

    Raises
    ------
    SimulationError
        No table, a message from gnucap before it (gnucap exits 0 after an error), or a malformed row.
    """
    import numpy as np

    names, table = _read_rows(output, log, "#Time")
    if len(table) and table[0, 0] == 0.0:
        table = table[1:]
    return {name: np.ascontiguousarray(table[:, j]) for j, name in enumerate(["time", *names])}


def read_ac_table(output: str, log: str = "") -> dict[str, np.ndarray]:
    """gnucap's ``.print ac`` table of real and imaginary parts (``ir(l1) ii(l1)``...) as ``"frequency"`` (Hz)
    and complex columns keyed by canonical name (``"i(l1)"``).

    Raises
    ------
    SimulationError
        As :func:`read_table`, or a part without its other half.
    """
    import numpy as np

    names, table = _read_rows(output, log, "#Freq")
    columns = {"frequency": np.ascontiguousarray(table[:, 0])}
    parts = {name: table[:, j] for j, name in enumerate(names, start=1)}
    for name in names:
        match = _PART.match(name)
        if match is None or f"{match[1]}i({match[3]})" not in parts or f"{match[1]}r({match[3]})" not in parts:
            raise failure(f"gnucap's AC table has a column lcchain cannot pair: {name!r}", quote(log or output))
        key = f"{match[1]}({match[3]})"
        columns[key] = parts[f"{match[1]}r({match[3]})"] + 1j * parts[f"{match[1]}i({match[3]})"]
    return columns


def _read_rows(output: str, log: str, first: str) -> tuple[list[str], np.ndarray]:
    """The canonical names of gnucap's printed columns after the first, and its table's rows (the first column
    headed ``first``)."""
    import numpy as np

    lines = output.splitlines()
    header = next((i for i, line in enumerate(lines) if line.startswith(first)), None)
    messages = [line.strip() for line in lines[: len(lines) if header is None else header]
                if line.strip() and not _BANNER.match(line) and line.strip() != TITLE]
    if messages:
        raise failure("gnucap reported: " + " | ".join(messages[:5]), quote(log or output))
    if header is None:
        raise failure(f"gnucap printed no table (no {first!r} header)", quote(log or output))
    names = [canonical_vector_name(n) for n in lines[header].split()[1:]]
    rows: list[list[float]] = []
    for line in lines[header + 1:]:
        words = line.split()
        if not words or line == lines[header]:  # several .ac cards: one table each, under the same header
            continue
        values = [table_number(word) for word in words]
        if len(values) != len(names) + 1 or any(v is None for v in values):
            raise failure(f"gnucap's table has a row lcchain cannot read: {line.strip()[:200]!r}",
                                  quote(log or output))
        rows.append(values)  # type: ignore[arg-type]
    return names, np.array(rows, dtype=np.float64).reshape(len(rows), len(names) + 1)
