"""The sensitivity chart: dp/d ln x of every inductor and capacitor along the chain (``lcchain sensitivity
--plot``)."""

from __future__ import annotations

import os
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from .plots import _finish, _new_figure, _root_figure

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

__all__ = ["sensitivity_chart"]


def sensitivity_chart(inductors: Sequence[tuple[int, float]], capacitors: Sequence[tuple[int, float]], *,
                      checked: Sequence[tuple[float, float, float]] = (), title: str = "", metric: str = "p",
                      path: str | os.PathLike[str] | None = None, ax: Axes | None = None) -> Figure:
    """Stems of dp/d ln x along the chain: inductor L_i at position i, capacitor C_j_j+1 at j + 1/2.

    Parameters
    ----------
    inductors : sequence of (i, dp/d ln L_i)
        Loop i = 1..N.
    capacitors : sequence of (j, dp/d ln C_j_j+1)
        Spring j = 0..N (walls at 0 and N).
    checked : sequence of (position, finite difference, error bar)
        ngspice's finite differences, drawn with their error bars.
    title : str
    metric : str
        The metric's symbol in the labels (``"p"``, ``"e"``).
    path : path-like, optional
        Saved there when given.
    ax : Axes, optional

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig = _new_figure() if ax is None else _root_figure(ax)
    ax = ax if ax is not None else fig.add_subplot()
    for parts, offset, colour, label in ((inductors, 0.0, "C0", rf"$\partial {metric}/\partial \ln L_i$"),
                                         (capacitors, 0.5, "C1", rf"$\partial {metric}/\partial \ln C_{{j,j+1}}$")):
        if parts:
            position = np.array([k for k, _ in parts], dtype=float) + offset
            value = np.array([v for _, v in parts], dtype=float)
            ax.vlines(position, 0.0, value, colors=colour, linewidth=1.5)
            ax.plot(position, value, "o", color=colour, markersize=4, label=label)
    if checked:
        position, value, bar = (np.array(column, dtype=float) for column in zip(*checked, strict=True))
        ax.errorbar(position, value, yerr=bar, fmt="x", color="k", markersize=7, capsize=3,
                    label="ngspice, central difference")
    ax.axhline(0.0, color="0.5", linewidth=0.5)
    ax.set_xlabel("position along the chain (loop i; capacitor j,j+1 at j + 1/2)")
    ax.set_ylabel(rf"$\partial {metric} / \partial \ln x$")
    ax.grid(alpha=0.3, linewidth=0.5)
    ax.legend(loc="best", fontsize="small")
    if title:
        ax.set_title(title)
    return _finish(fig, path)
