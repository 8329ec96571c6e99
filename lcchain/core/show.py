"""How a result shows itself in a terminal and in a notebook: a few lines, or a small escaped HTML table.

A report holds arrays of thousands of points; its dataclass repr ran to 169,415 characters.  A result's
``__repr__`` and ``_repr_html_`` show the same few rows instead (what ran, its size, its errors and what was
predicted), made here once so that every result reads alike.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Protocol, cast

from .errors import ParameterError
from .registry import Registry

__all__ = ["short_repr", "html_table", "PLOTS", "plot", "Figure"]

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
    import html  # with html.entities, 4 to 8 ms: a notebook's table only, not every command's start

    body = "".join(f"<tr><th style=\"text-align:left\">{html.escape(name)}</th>"
                   f"<td style=\"text-align:left\">{html.escape(_text(value))}</td></tr>" for name, value in rows)
    return f"<table><caption>{html.escape(title)}</caption>{body}</table>"


def _figure_function(name: str, loaded: object) -> Callable[..., object]:
    if not callable(loaded):
        raise TypeError(f"{name} is not callable")
    return loaded


#: What draws each kind of result: ``(result, ax=None) -> matplotlib Figure``, read from the ``lcchain.plots``
#: entry points on first use (lcchain's own name :mod:`lcchain.report.shown`'s functions), as pandas finds its
#: plotting backend: a result never imports ``report`` (matplotlib is its alone), and another package may draw.
PLOTS: Registry[Callable[..., object]] = Registry("lcchain.plots", {}, _figure_function,
                                              "a function (result, ax=None) -> matplotlib Figure")


class Figure(Protocol):
    """What a result's ``plot()`` returns, as a type checker sees it: a matplotlib Figure, which only ``report``
    may name (the layers' contract), so here what a caller does with one: save it, and find its axes."""

    axes: Sequence[object]

    def savefig(self, fname: object, *args: object, **kwargs: object) -> None: ...


def plot(kind: str, result: object, ax: object = None, **options: object) -> Figure:
    """The figure of ``result`` by the registered drawing of its ``kind`` (``"simulation"``, ``"spectrum"``,
    ``"scene"``, ``"record"``, ``"store"``), given ``options`` as keywords.

    ``ax`` is typed ``object`` and the figure :class:`Figure`: both are matplotlib's, which only ``report`` may name
    (the drawing is any registered function, lcchain's or another package's: what it returns is taken as a
    figure, as its entry point's contract says)."""
    if kind not in PLOTS:
        raise ParameterError("plot", kind, f"a kind of result with a registered drawing ({', '.join(PLOTS)}; "
                             "lcchain's own come with its installed entry points: pip install lcchain)")
    return cast(Figure, PLOTS[kind](result, ax=ax, **options))
