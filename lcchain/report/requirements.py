"""The requirements chart: the first arrival's energy loss against each real part's parameter (``lcchain
requirements --plot``), exact curves with ngspice's points on them and the 1 % and 0.1 % limits marked."""

from __future__ import annotations

import os
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from .plots import _finish, _new_figure

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["requirements_chart"]


def requirements_chart(curves: Sequence[tuple[str, Sequence[float], Sequence[float], Sequence[float | None]]],
                       points: Sequence[tuple[str, float, float]] = (), *, targets: Sequence[float] = (1e-2, 1e-3),
                       title: str = "", path: str | os.PathLike[str] | None = None) -> Figure:
    """One panel per part: |loss| against the parameter on log axes.

    Parameters
    ----------
    curves : sequence of (label, values, losses, limits)
        Each part's exact curve and its limit for each of ``targets`` (None: none in range; 0: none at all).
    points : sequence of (label, value, loss)
        ngspice's measurements, drawn on the panel of their label.
    targets : sequence of float
        The losses the limits are given for, drawn as dashed lines.
    title : str
    path : path-like, optional
        Saved there when given.
    """
    fig = _new_figure()
    count = max(len(curves), 1)
    columns = 2 if count > 1 else 1
    rows = -(-count // columns)
    fig.set_size_inches(9.0, 2.6 * rows + 0.6)
    axes = fig.subplots(rows, columns, squeeze=False).ravel()
    for ax, (label, values, losses, limits) in zip(axes, curves, strict=False):
        x, y = np.asarray(values, dtype=float), np.abs(np.asarray(losses, dtype=float))
        ax.loglog(x, np.where(y > 0, y, np.nan), "-", color="C0", label="circuit theory")
        mine = [(v, abs(loss)) for name, v, loss in points if name == label and loss != 0]
        if mine:
            ax.loglog(*zip(*mine, strict=True), "o", color="k", markersize=4, label="ngspice")
        for target, limit, colour in zip(targets, limits, ("C3", "C1"), strict=False):
            ax.axhline(target, color=colour, linestyle="--", linewidth=0.8)
            if limit:
                ax.axvline(limit, color=colour, linestyle=":", linewidth=0.8,
                           label=f"loss {target:.1%}: {limit:.3g}")
        ax.set_xlabel(label)
        ax.set_ylabel("|1 - e/e_ideal|")
        ax.grid(alpha=0.3, linewidth=0.5, which="both")
        ax.legend(loc="upper left", fontsize="x-small")
    for ax in axes[len(curves):]:
        ax.set_visible(False)
    if title:
        fig.suptitle(title)
    return _finish(fig, path)
