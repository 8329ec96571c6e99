"""Every netlist the tests and the repository hold, and variants of each written the other ways SPICE allows: a
corpus for checks that two ways of reading a netlist agree on all of it.

:func:`netlist_cases` gathers the files of every bad-input and boundary case (``CASES`` of the modules
``tests/catalogue.py`` runs: hostile cards, includes, bytes that are not canonical, prices at the limits), the
netlists the tests name at module level, the reference netlists in ``netlists/`` and those of
:mod:`helpers.netlists`; :func:`variants` writes one netlist with blanks before and after its cards, its cards
continued on ``+`` lines, in upper case, with CRLF line ends and with a ``.meas`` beside its analysis.
"""

from __future__ import annotations

import importlib
from pathlib import Path

from helpers import netlists

HERE = Path(__file__).resolve().parent.parent
#: The test modules whose ``CASES`` are bad or hostile inputs (those of ``tests/catalogue.py``).
CASE_MODULES = ("test_bad_inputs", "test_boundary_netlists", "test_boundary_inputs", "test_boundary_stores",
                "test_boundary_pricing", "test_canonical_text", "test_foreign_cards")
#: The test modules that name netlists at module level (upper-case names).
NETLIST_MODULES = ("test_foreign_cards", "test_measurements", "test_netlist_sweep", "test_check")
#: Where a case's file is a netlist: what ``lcchain batch`` or ``sweep --netlist`` is given.
SUFFIXES = (".cir", ".sp", ".net", ".inc", ".lib", ".txt", ".spi")


def _looks_like_netlist(text: str) -> bool:
    return "\n" in text and any(card in text.lower() for card in (".tran", ".ac ", ".end", ".op", ".dc "))


def netlist_cases() -> dict[str, dict[str, str | bytes]]:
    """Name -> the files of one case (a netlist and what it includes), the netlist first."""
    found: dict[str, dict[str, str | bytes]] = {}
    for module_name in CASE_MODULES:
        module = importlib.import_module(module_name)
        for name, case in getattr(module, "CASES", {}).items():
            files = {file: content for file, content in case.files.items() if file.endswith(SUFFIXES)}
            if files:
                found[f"{module_name}::{name}"] = files
    for module_name in NETLIST_MODULES:
        module = importlib.import_module(module_name)
        for name, value in vars(module).items():
            if name.isupper() and isinstance(value, str) and _looks_like_netlist(value):
                found[f"{module_name}.{name}"] = {"netlist.cir": value}
    for name, value in vars(netlists).items():
        if name.isupper() and isinstance(value, str) and _looks_like_netlist(value):
            found[f"helpers.netlists.{name}"] = {"netlist.cir": value}
    for path in sorted((HERE.parent / "netlists").glob("*.cir")):
        found[f"netlists/{path.name}"] = {"netlist.cir": path.read_text(encoding="utf-8")}
    return found


def variants(text: str) -> dict[str, str]:
    """``text`` and the same netlist written the other ways SPICE allows, by name."""
    lines = text.split("\n")
    head, body = lines[:1], lines[1:]
    continued = []
    for line in body:
        words = line.split()
        if len(words) > 2 and not line.lstrip().startswith("*"):  # each card's last word on a line of its own
            continued += [line[:line.rstrip().rfind(" ")], "+ " + words[-1]]
        else:
            continued.append(line)
    return {
        "as written": text,
        "blanks around each card": "\n".join(head + [f" \t{line}  " if line.strip() else line for line in body]),
        "continued": "\n".join(head + continued),
        "upper case": "\n".join(head + [line.upper() for line in body]),
        "crlf": text.replace("\n", "\r\n"),
        "measured": text.replace("\n.end", "\n.meas tran top max v(1)\n.meas ac peak max vm(1)\n.end", 1),
        "an op and a dc": text.replace("\n.end", "\n.op\n.dc temp 0 50 10\n.end", 1),
    }
