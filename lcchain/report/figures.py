"""The paper's figures, drawn from lcchain's own computation: data functions, then figure functions.

Each figure has a function that computes its data (pure, numbers only, tested
against the paper) and a function that takes that data and returns a
matplotlib Figure (never shown, saved by the caller).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from ..theory.asymptotic import asymptotic_optimum
from ..theory.design import optimal_one_mass, optimal_two_mass

__all__ = ["delta_data", "delta_figure", "design_grid", "PERFECT_LOSS"]

#: A loss below this is a perfect chain's (zero up to rounding: ~1e-16).
PERFECT_LOSS = 1e-9


def design_grid(largest: int, points: int = 14) -> list[int]:
    """Sizes from 3 to ``largest``, evenly spaced on a log scale (integers, distinct)."""
    return sorted({int(round(n)) for n in np.geomspace(3, max(largest, 4), points)})


def delta_data(Ns: Sequence[int]) -> dict[str, Any]:
    """δ* against N for the uniform chain and the one-mass and two-mass optima, with their asymptotes.

    Returns
    -------
    dict
        ``N``; ``uniform``, ``one-mass``, ``two-mass``: the losses δ*(N)
        (Tables I and II: δ*(1), δ* of x*, δ* of (r*, w*)); ``asymptotes``:
        δ*_∞ of the one-mass and two-mass optima (Secs. IV.C and V.A).
    """
    sizes = sorted(set(int(n) for n in Ns))
    one = [optimal_one_mass(N) for N in sizes]
    two = [optimal_two_mass(N) for N in sizes]
    return {
        "N": sizes,
        "uniform": [d.delta_uniform for d in one],
        "one-mass": [max(d.delta, 0.0) for d in one],
        "two-mass": [max(d.delta, 0.0) for d in two],
        "asymptotes": {case: asymptotic_optimum(case).delta for case in ("one-mass", "two-mass")},
    }


def delta_figure(data: Mapping[str, Any], measured: Mapping[str, Sequence[tuple[int, float]]] | None = None,
                 *, title: str = "", ax: Any = None) -> Any:
    """Fig. delta: the transmission loss δ* against N on log-log axes.

    Parameters
    ----------
    data : mapping
        From :func:`delta_data`.
    measured : mapping, optional
        Case -> [(N, loss)]: ngspice's first-arrival loss 1 - peak, drawn as markers.
    title : str
    ax : matplotlib Axes, optional
        Draw here instead of a new figure.
    """
    from matplotlib.figure import Figure

    fig = Figure(figsize=(9.5, 4.8), layout="constrained") if ax is None else ax.get_figure(root=True)
    ax = ax if ax is not None else fig.add_subplot()
    styles = {"uniform": ("#2f8f3f", "uniform chain, δ*(1)"), "one-mass": ("#1f5fbf", "one optimal mass"),
              "two-mass": ("#c0282d", "two optimal masses and their spring")}
    markers = {"uniform": "^", "one-mass": "s", "two-mass": "o"}
    N = np.asarray(data["N"], dtype=float)
    perfect = []
    for case, (color, label) in styles.items():
        values = np.asarray(data[case], dtype=float)
        shown = values > PERFECT_LOSS  # a perfect chain loses nothing: zero has no place on a log axis
        if not np.all(shown):
            perfect.append(f"{case} N = {', '.join(str(int(n)) for n in N[~shown])}")
        ax.plot(N[shown], values[shown], color=color, linewidth=1.0, marker=markers[case], markersize=4,
                label=f"{label} (theory)")
        if case in data.get("asymptotes", {}):
            ax.axhline(data["asymptotes"][case], color=color, linestyle=":", linewidth=1.0,
                       label=f"δ*∞ = {data['asymptotes'][case]:.4g}")
    for case, points in (measured or {}).items():
        if points:
            xs, ys = zip(*points, strict=True)
            ax.plot(xs, np.maximum(ys, PERFECT_LOSS), "o", color=styles.get(case, ("k", ""))[0], markersize=8,
                    markerfacecolor="none", markeredgewidth=1.5, label=f"{case}: ngspice, 1 - peak")
    if perfect:
        ax.plot([], [], " ", label="perfect (δ* = 0, not drawn): " + "; ".join(perfect))
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("N (masses)")
    ax.set_ylabel("transmission loss δ* = 1 - α*")
    ax.grid(True, which="both", alpha=0.3, linewidth=0.5)
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
    ax.set_title(title or "Fig. delta: loss of the first arrival against N")
    return fig
