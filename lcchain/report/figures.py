"""The paper's figures, drawn from lcchain's own computation: data functions, then figure functions.

Each figure has a function that computes its data (pure, numbers only, tested
against the paper) and a function that takes that data and returns a
matplotlib Figure (never shown, saved by the caller).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Literal, TypedDict

import numpy as np

from ..theory.asymptotic import asymptotic_optimum
from ..theory.design import optimal_one_mass, optimal_two_mass

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

__all__ = ["delta_data", "delta_figure", "design_grid", "spline_through", "PERFECT_LOSS", "UNIFORM_LIMIT", "DeltaData"]

#: :func:`delta_data`: δ* of each chain against N (the uniform chain's None where a design has none), and the
#: limits for N -> infinity by case.
DeltaData = TypedDict("DeltaData", {"N": list[int], "uniform": list[float | None], "one-mass": list[float],
                                    "two-mass": list[float], "asymptotes": dict[str, float]})
#: The curves of Fig. delta.
_Curve = Literal["uniform", "one-mass", "two-mass"]

#: A loss below this is a perfect chain's (zero up to rounding: ~1e-16).
PERFECT_LOSS = 1e-9
#: The uniform chain's loss for N -> infinity: its pulse disperses and the transmitted amplitude vanishes
#: (the first of the three limits in the caption of Fig. delta).
UNIFORM_LIMIT = 1.0


def design_grid(largest: int, points: int = 14) -> list[int]:
    """Sizes from 3 to ``largest``, evenly spaced on a log scale (integers, distinct)."""
    return sorted({int(round(n)) for n in np.geomspace(3, max(largest, 4), points)})


def delta_data(Ns: Sequence[int]) -> DeltaData:
    """δ* against N for the uniform chain and the one-mass and two-mass optima, with their asymptotes.

    Returns
    -------
    dict
        ``N``; ``uniform``, ``one-mass``, ``two-mass``: the losses δ*(N)
        (Tables I and II: δ*(1), δ* of x*, δ* of (r*, w*)); ``asymptotes``:
        the limits for N -> infinity: 1 for the uniform chain, δ*_∞ of the one-mass and
        two-mass optima (Secs. IV.C and V.A).
    """
    sizes = sorted(set(int(n) for n in Ns))
    one = [optimal_one_mass(N) for N in sizes]
    two = [optimal_two_mass(N) for N in sizes]
    return {
        "N": sizes,
        "uniform": [d.delta_uniform for d in one],
        "one-mass": [max(d.delta, 0.0) for d in one],
        "two-mass": [max(d.delta, 0.0) for d in two],
        "asymptotes": {"uniform": UNIFORM_LIMIT,
                       **{case: asymptotic_optimum(case).delta for case in ("one-mass", "two-mass")}},
    }


def spline_through(N: Sequence[float] | np.ndarray, values: Sequence[float] | np.ndarray, *, log_values: bool = False,
                   points: int = 400) -> tuple[np.ndarray, np.ndarray]:
    """A smooth curve through the points (N, value): a PCHIP spline in log N, never beyond the first and last N.

    PCHIP (a monotone piecewise-cubic Hermite spline) passes through every point and adds no wiggle of its
    own between them. ``log_values`` interpolates log(value) instead (for a log axis; values must be > 0).
    Fewer than two points give the points themselves.
    """
    from scipy.interpolate import PchipInterpolator

    x = np.log(np.asarray(N, dtype=float))
    y = np.asarray(values, dtype=float)
    if x.size < 2:
        return np.exp(x), y
    order = np.argsort(x)
    x, y = x[order], y[order]
    spline = PchipInterpolator(x, np.log(y) if log_values else y)
    grid = np.linspace(x[0], x[-1], points)
    curve = spline(grid)
    return np.exp(grid), np.exp(curve) if log_values else curve


def delta_figure(data: DeltaData, measured: Mapping[str, Sequence[tuple[int, float]]] | None = None,
                 *, title: str = "", ax: Axes | None = None, scale: str = "log",
                 enlarge: Mapping[str, float] | None = None) -> Figure:
    """Fig. delta: the transmission loss δ* against N (N on a log axis), points joined by splines.

    Filled symbols are the losses (green triangles: uniform chain; blue squares: one optimal mass; red
    circles: two optimal masses and their spring), dotted lines their limits for N -> infinity (1, δ*∞ of
    the one-mass and two-mass optima), the curves PCHIP splines in log N through the points
    (:func:`spline_through`).

    Parameters
    ----------
    data : mapping
        From :func:`delta_data`.
    measured : mapping, optional
        Case -> [(N, loss)]: ngspice's first-arrival loss 1 - peak, drawn as markers.
    title : str
    ax : matplotlib Axes, optional
        Draw here instead of a new figure.
    scale : {"log", "linear"}
        The loss axis. On a log axis a perfect chain (δ* = 0) is listed in the legend, not drawn.
    enlarge : mapping, optional
        Case -> factor: that case drawn again multiplied by the factor, open symbols (the paper's
        "enlargements of the last two cases"), with its limit enlarged too.
    """
    from matplotlib.figure import Figure

    if scale not in ("log", "linear"):
        raise ValueError(f"scale = {scale!r}: expected 'log' or 'linear'")
    log = scale == "log"
    from .plots import _root_figure

    fig = Figure(figsize=(9.5, 4.8), layout="constrained") if ax is None else _root_figure(ax)
    ax = ax if ax is not None else fig.add_subplot()
    styles: dict[_Curve, tuple[str, str]] = {
        "uniform": ("#2f8f3f", "uniform chain, δ*(1)"), "one-mass": ("#1f5fbf", "one optimal mass"),
        "two-mass": ("#c0282d", "two optimal masses and their spring")}
    markers = {"uniform": "^", "one-mass": "s", "two-mass": "o"}
    asymptotes = {"uniform": UNIFORM_LIMIT, **data.get("asymptotes", {})}
    N = np.asarray(data["N"], dtype=float)
    perfect = []
    top = UNIFORM_LIMIT  # the linear axis' top: the highest point or limit drawn
    for case, (color, label) in styles.items():
        values = np.asarray(data[case], dtype=float)
        shown = values > PERFECT_LOSS if log else np.isfinite(values)  # zero has no place on a log axis
        if not np.all(shown):
            perfect.append(f"{case} N = {', '.join(str(int(n)) for n in N[~shown])}")
        copies: list[tuple[float, str | None, str]] = [(1.0, None, f"{label} (theory)")]
        if enlarge and case in enlarge:
            factor = float(enlarge[case])
            copies.append((factor, "none", f"{factor:g} × the same (open: enlarged)"))
        for factor, face, text in copies:
            top = max(top, float(np.max(factor * values[shown], initial=0.0)))
            curve_N, curve = spline_through(N[shown], factor * values[shown], log_values=log)
            ax.plot(curve_N, curve, color=color, linewidth=1.0)
            ax.plot(N[shown], factor * values[shown], linestyle="none", color=color, marker=markers[case],
                    markersize=4.5 if face is None else 5.5, markerfacecolor=face, label=text)
            if case in asymptotes:
                limit = factor * asymptotes[case]
                top = max(top, limit)
                scaled = f"{factor:g} × " if factor != 1 else ""
                ax.axhline(limit, color=color, linestyle=":", linewidth=1.0,
                           label=f"limit N → ∞: {scaled}{asymptotes[case]:.4g}")
    for name, points in (measured or {}).items():
        if points:
            xs, ys = zip(*points, strict=True)
            colour = styles[name][0] if name in styles else "k"
            ax.plot(xs, np.maximum(ys, PERFECT_LOSS) if log else ys, "o", color=colour,
                    markersize=8, markerfacecolor="none", markeredgewidth=1.5, label=f"{name}: ngspice, 1 - peak")
    if perfect:
        ax.plot([], [], " ", label="perfect (δ* = 0, not drawn): " + "; ".join(perfect))
    ax.set_xscale("log")
    if log:
        ax.set_yscale("log")
    else:
        ax.set_ylim(0.0, 1.06 * top)
    ax.set_xlabel("N (masses)")
    ax.set_ylabel("transmission loss δ* = 1 - α*")
    ax.grid(True, which="both", alpha=0.3, linewidth=0.5)
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
    ax.set_title(title or "Fig. delta: loss of the first arrival against N")
    return fig
