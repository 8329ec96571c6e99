"""How a result shows itself in a terminal and in a notebook: a few lines, or a small escaped HTML table.

A report holds arrays of thousands of points; its dataclass repr ran to 169,415 characters.  A result's
``__repr__`` and ``_repr_html_`` show the same few rows instead (what ran, its size, its errors and what was
predicted), made here once so that every result reads alike.
"""

from __future__ import annotations

import html
from collections.abc import Sequence

__all__ = ["short_repr", "html_table"]

Row = tuple[str, object]


def _text(value: object) -> str:
    if isinstance(value, float):
        return f"{value:.4g}"
    return str(value)


def short_repr(title: str, rows: Sequence[Row]) -> str:
    """``title`` then one ``name: value`` line per row (floats to four digits)."""
    return "\n".join([title, *(f"  {name}: {_text(value)}" for name, value in rows)])


def html_table(title: str, rows: Sequence[Row]) -> str:
    """The same rows as a small HTML table, every text escaped (a chain's name or a scene's title is the
    user's)."""
    body = "".join(f"<tr><th style=\"text-align:left\">{html.escape(name)}</th>"
                   f"<td style=\"text-align:left\">{html.escape(_text(value))}</td></tr>" for name, value in rows)
    return f"<table><caption>{html.escape(title)}</caption>{body}</table>"
