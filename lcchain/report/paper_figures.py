"""The paper's figures drawn from lcchain's computation: each takes the data of
:mod:`lcchain.report.figure_data` and returns a matplotlib Figure (never shown).

:data:`FIGURES` lists them by the paper's label; :func:`make_figures` writes
one file per figure, its name the label (``cradle4.png``, ``vk.svg``, ...).
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Generic, Literal, TypeAlias, TypedDict, TypeVar

import numpy as np

from ..core.types import DesignCase
from .figure_data import (
    FULL_N,
    QUICK_N,
    CircuitData,
    Cradle4Data,
    DesignRows,
    IntRwData,
    MinimizData,
    OptimumData,
    PkData,
    VkData,
    circuit_data,
    cradle4_data,
    int_rw_data,
    minimiz_data,
    optimum_data,
    pk_data,
    vk_data,
)
from .figures import UNIFORM_LIMIT, DeltaData, delta_figure
from .files import save_figure

if TYPE_CHECKING:
    from matplotlib.artist import Artist
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure
    from matplotlib.patches import Rectangle

__all__ = ["FIGURES", "PaperFigure", "AnyPaperFigure", "make_figures", "cradle4_figure", "vk_figure", "x_xy_figure",
           "m_mmK_figure", "int_rw_figure", "minimiz_figure", "rw_figure", "pk_figure", "circuit_figure",
           "delta_from_optimum", "paper_delta_figure", "DELTA_ENLARGE"]

_BLUE, _RED, _GREEN = "#1f5fbf", "#c0282d", "#2f8f3f"
_AUX = "#7cc68a"  # Fig. cradle4's auxiliary (green) masses


def _figure(width: float = 7.5, height: float = 4.6) -> Figure:
    from matplotlib.figure import Figure

    return Figure(figsize=(width, height), layout="constrained")


# ------------------------------------------------------------------ cradle4
def _spring(ax: Axes, x0: float, x1: float, y: float, label: str, coils: int = 6) -> None:
    xs = np.linspace(x0, x1, 2 * coils + 3)
    ys = np.full_like(xs, y)
    ys[1:-1:2] += 0.12
    ys[2:-1:2] -= 0.12
    ys[1], ys[-2] = y, y
    ax.plot(xs, ys, color="0.25", linewidth=1.2)
    ax.text((x0 + x1) / 2, y + 0.28, label, ha="center", va="bottom", fontsize=9)


def _fraction(value: float) -> str:
    from fractions import Fraction

    exact = Fraction(value).limit_denominator(36)
    return str(exact) if abs(float(exact) - value) < 1e-9 else f"{value:.4g}"


def cradle4_figure(data: Cradle4Data) -> Figure:
    """Fig. cradle4: the chain (masses as blocks of area ∝ mass, springs labelled) and its pulse.

    Left below: each mass's velocity over two transits; right: the space-time map of the same.
    """
    fig = _figure(9.5, 6.0)
    top, bottom = fig.subfigures(2, 1, height_ratios=[1.0, 1.5], squeeze=False)[:, 0]
    ax = top.add_subplot()
    masses, springs = data["masses"], data["springs"]
    gap, touch = 1.6, 0.12
    # the auxiliary (green) masses, equal to the end ones, outside the chain with no spring: as in Newton's
    # cradle the left one hits mass 1 with v = 1 and stops; at t = T mass 4 passes v = 1 to the right one
    aux_side = 0.55 * math.sqrt(masses[0])
    x = aux_side + touch
    ax.add_patch(_rectangle(0.0, -aux_side / 2, aux_side, aux_side, colour=_AUX))
    ax.text(aux_side / 2, 0.0, _fraction(masses[0]), ha="center", va="center", fontsize=10)
    aux_centres = [aux_side / 2]
    centres = []
    for i, m in enumerate(masses):
        side = 0.55 * math.sqrt(m)
        if i:
            _spring(ax, x, x + gap, 0.0, f"K = {_fraction(springs[i])}")
            x += gap
        ax.add_patch(_rectangle(x, -side / 2, side, side, colour="#8fb3e0" if i in (0, len(masses) - 1) else "#d9d9d9"))
        ax.text(x + side / 2, 0.0, f"{_fraction(m)}", ha="center", va="center", fontsize=10)
        centres.append(x + side / 2)
        x += side
    x += touch
    ax.add_patch(_rectangle(x, -aux_side / 2, aux_side, aux_side, colour=_AUX))
    ax.text(x + aux_side / 2, 0.0, _fraction(masses[-1]), ha="center", va="center", fontsize=10)
    aux_centres.append(x + aux_side / 2)
    x += aux_side
    ax.annotate("", xy=(aux_centres[0] + 0.6, -0.75), xytext=(aux_centres[0] - 0.6, -0.75),
                arrowprops={"arrowstyle": "->", "color": _RED, "linewidth": 1.6})
    ax.text(aux_centres[0], -0.95, "v = 1 until t = 0:\nit stops, mass 1 takes v = 1", ha="center", va="top",
            fontsize=8, color=_RED)
    ax.annotate("", xy=(aux_centres[1] + 0.6, -0.75), xytext=(aux_centres[1] - 0.6, -0.75),
                arrowprops={"arrowstyle": "->", "color": _GREEN, "linewidth": 1.6})
    ax.text(aux_centres[1], -0.95, f"leaves with v = 1\nat T = √3 π = {data['T']:.4f}", ha="center", va="top",
            fontsize=8, color=_GREEN)
    ax.text((aux_centres[0] + aux_centres[1]) / 2, 0.75, "green: auxiliary masses (= the end masses, no spring)",
            ha="center", va="bottom", fontsize=8, color=_GREEN)
    ax.set_xlim(-0.9, x + 0.9)
    ax.set_ylim(-1.55, 1.05)
    ax.set_aspect("equal")
    ax.axis("off")
    ax.set_title("Fig. cradle4: the perfect 4-mass cradle (free ends; end masses 5/3, end springs 5/6 of the bulk)",
                 fontsize=10)

    left, right = bottom.subplots(1, 2, width_ratios=[1.3, 1.0])
    t, v, T = data["t"], data["velocities"], data["T"]
    for i, row in enumerate(v):
        left.plot(t / T, row, linewidth=1.4 if i in (0, len(v) - 1) else 0.9, label=f"mass {i + 1}")
    left.set_xlabel("t / T")
    left.set_ylabel("velocity (= I_i / I0 in the ladder)")
    left.grid(True, alpha=0.3, linewidth=0.5)
    left.set_ylim(-0.05, 1.32)  # a band above the curves (each peaks at 1) for the legend
    left.legend(fontsize=8, ncols=4, loc="upper center", handlelength=1.2, columnspacing=0.8)
    left.set_title("the kick leaves mass 1 and arrives whole at mass 4 at t = T", fontsize=9)
    mesh = right.pcolormesh(np.arange(len(v) + 1) + 0.5, _edges(t / T), v.T, cmap="RdBu_r", vmin=-1, vmax=1,
                            shading="flat")
    right.set_xlabel("mass")
    right.set_ylabel("t / T")
    right.set_xticks(range(1, len(v) + 1))
    right.set_title("space-time map of the velocities", fontsize=9)
    bottom.colorbar(mesh, ax=right, shrink=0.85)
    return fig


def _rectangle(x: float, y: float, w: float, h: float, colour: str) -> Rectangle:
    from matplotlib.patches import Rectangle

    return Rectangle((x, y), w, h, facecolor=colour, edgecolor="0.2", linewidth=1.0)


def _edges(centres: np.ndarray) -> np.ndarray:
    middle = 0.5 * (centres[1:] + centres[:-1])
    return np.concatenate(([centres[0] - (middle[0] - centres[0])], middle, [centres[-1] + (centres[-1] - middle[-1])]))


# ------------------------------------------------------------------ vk
#: The circuit's points on Figs. vk and Pk20-100: open black rings around the theory's symbols.
class _Markers(TypedDict):
    color: str
    markerfacecolor: str
    markeredgewidth: float
    linestyle: str


_CIRCUIT: _Markers = {"color": "k", "markerfacecolor": "none", "markeredgewidth": 0.9, "linestyle": "none"}


def vk_figure(data: VkData, circuit: Mapping[float, Mapping[str, np.ndarray]] | None = None) -> Figure:
    """Fig. vk: v_k (red) and P_k (blue dashed, arbitrary units) for N = 50 at three Δ; uniform v_k dotted.

    ``circuit`` maps a panel's Δ to a circuit's modes (:func:`~lcchain.report.figure_data.spectrum_points`),
    drawn on top as open rings: v from the measured omega_n at mid-k, as the modes' points, and |P_n|.
    """
    panels = data["panels"]
    fig = _figure(10.5, 4.0)
    axes = fig.subplots(1, len(panels), sharey=True)
    k = data["k"]
    for ax, panel in zip(np.atleast_1d(axes), panels, strict=True):
        ax.plot(k, panel["v"], color=_RED, linewidth=1.6, label="v_k")
        ax.plot(panel["k_mid"], panel["v_n"], "o", color=_RED, markersize=2.5, label="(N/π) Δω_n (modes)")
        ax.plot(k, data["uniform_v"], ":", color="0.3", linewidth=1.0, label="uniform chain")
        scale = 1.0 / float(np.max(panel["P"]))
        ax.plot(k, panel["P"] * scale, "--", color=_BLUE, linewidth=1.2, label="P_k (scaled)")
        ax.plot(panel["k_n"], np.asarray(panel["P_n"]) * scale * np.where(np.asarray(panel["k_n"]) == 0, 2.0, 1.0),
                "s", color=_BLUE, markersize=2.5, label="P_n (modes)")
        points = (circuit or {}).get(panel["Delta"])
        if points is not None:
            ax.plot(points["k_mid"], points["v"], marker="o", markersize=5.5, label="ngspice (AC): (N/π) Δω_n",
                    **_CIRCUIT)
            ax.plot(points["k"], points["P"] * scale * np.where(points["zero"], 2.0, 1.0), marker="s",
                    markersize=5.5, label="ngspice (AC): P_n", **_CIRCUIT)
        ax.set_title(f"Δ = {panel['Delta']:g}  (x = {panel['x']:.4f})", fontsize=9)
        ax.set_xlabel("k")
        ax.set_xlim(0, math.pi)
        ax.set_ylim(0, 1.15)
        ax.grid(True, alpha=0.3, linewidth=0.5)
    first = np.atleast_1d(axes)[0]
    first.set_ylabel("v_k, P_k (arb. units)")
    labels: dict[str, Artist] = {}
    for ax in np.atleast_1d(axes):  # every entry once, the circuit's from whichever panel has them
        for handle, label in zip(*ax.get_legend_handles_labels(), strict=True):
            labels.setdefault(label, handle)
    fig.legend(list(labels.values()), list(labels), fontsize=8, loc="outside lower center",
               ncols=min(len(labels), 5))  # off every panel
    fig.suptitle(f"Fig. vk: group velocity and mode density, one-mass chain of N = {data['N']}", fontsize=10)
    return fig


# ------------------------------------------------------------------ delta, x_xy, m_mmK, rw
#: Fig. delta's open symbols, "enlargements of the last two cases": each optimised case's loss times a
#: factor that brings its limit (0.1531, 0.01285) to the height of the uniform chain's curve on the linear axis.
DELTA_ENLARGE = {"one-mass": 5.0, "two-mass": 50.0}


def delta_from_optimum(data: OptimumData) -> DeltaData:
    """The data of Fig. delta taken from :func:`optimum_data`'s rows (no design computed twice)."""
    return {"N": data["N"], "uniform": [row["delta_uniform"] for row in data["one-mass"]],
            "one-mass": [max(row["delta"], 0.0) for row in data["one-mass"]],
            "two-mass": [max(row["delta"], 0.0) for row in data["two-mass"]],
            "asymptotes": {"uniform": UNIFORM_LIMIT, **data["asymptotes"]}}


def paper_delta_figure(data: DeltaData) -> Figure:
    """Fig. delta as the caption has it: δ* on a linear axis, filled symbols, splines, the three limits
    1, δ*∞(one-mass), δ*∞(two-mass) dotted, and the two optimised cases enlarged (open symbols)."""
    return delta_figure(data, scale="linear", enlarge=DELTA_ENLARGE,
                        title="Fig. delta: minimal transmission loss δ* against N")


def _curve_N(data: OptimumData) -> np.ndarray:
    return np.geomspace(min(data["N"]), max(data["N"]), 200)


def _law(data: OptimumData, case: str, key: str, N: np.ndarray) -> np.ndarray:
    c, p = data["laws"][case][key]
    value = np.asarray(c * N**p, dtype=float)
    limit = _LAW_LIMITS.get((case, key))
    return value if limit is None else limit(value)


#: The laws that give a parameter's distance from its large-N limit (Table II's y -> sqrt 2, m2 -> 1/2), not
#: the parameter itself.
_LAW_LIMITS: dict[tuple[str, str], Callable[[np.ndarray], np.ndarray]] = {
    ("two-mass", "y"): lambda value: math.sqrt(2) - value,
    ("two-mass", "m2"): lambda value: 0.5 + value,
}


def _against_N(ax: Axes, ylabel: str, title: str, *, log_y: bool = True) -> None:
    """The axes of an optimum against N: N on a log scale (y too unless ``log_y`` is False), grid, a legend
    outside the frame (never on the data), title."""
    ax.set_xscale("log")
    if log_y:
        ax.set_yscale("log")
    ax.set_xlabel("N")
    ax.set_ylabel(ylabel)
    ax.grid(True, which="both", alpha=0.3, linewidth=0.5)
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
    ax.set_title(title, fontsize=10)


#: The numbers of a design's row that are drawn against N.
_RowKey = Literal["m1", "m2", "K12", "x", "y", "r", "w"]


def _values(data: OptimumData, case: DesignCase, key: _RowKey) -> np.ndarray:
    return np.asarray([row[key] for row in data[case]], dtype=float)


def _points(ax: Axes, data: OptimumData, case: DesignCase, key: _RowKey, colour: str, marker: str,
            label: str | None = None) -> np.ndarray:
    """The optimum's ``key`` against N as filled symbols; returns the values drawn."""
    N = np.asarray(data["N"], dtype=float)
    values = _values(data, case, key)
    ax.plot(N, values, marker, color=colour, markersize=4.5, label=label)
    return values


def _frame(values: Sequence[np.ndarray], *, log_y: bool, floor: float | None = None) -> tuple[float, float]:
    """The y limits set by the data alone: every finite value with a margin (a fixed ``floor`` if given)."""
    finite = np.concatenate([np.asarray(v, dtype=float).ravel() for v in values])
    finite = finite[np.isfinite(finite) & ((finite > 0) if log_y else True)]
    lo, hi = float(finite.min()), float(finite.max())
    if log_y:
        return lo / 1.25, hi * 1.25
    pad = 0.06 * (hi - lo)
    return (floor if floor is not None else lo - pad), hi + pad


def _law_in_frame(ax: Axes, N: np.ndarray, law: np.ndarray, frame: tuple[float, float], colour: str) -> None:
    """A large-N law drawn only where it lies inside the frame (outside it: not drawn, never clipped)."""
    inside = (law >= frame[0]) & (law <= frame[1])
    ax.plot(N, np.where(inside, law, np.nan), color=colour, linewidth=0.9, alpha=0.85)


def _tag(ax: Axes, N: float, value: float, text: str, colour: str = "0.15") -> None:
    """A quantity's name just right of its last point, where no data are (the x axis leaves room)."""
    ax.annotate(text, (N, value), textcoords="offset points", xytext=(9, 0), ha="left", va="center", fontsize=9,
                color=colour)


def _room_right(ax: Axes, data: OptimumData) -> None:
    """N limits with room right of the last point for the tags of :func:`_tag`."""
    ax.set_xlim(min(data["N"]) / 1.3, max(data["N"]) * 2.2)


def x_xy_figure(data: OptimumData) -> Figure:
    """Fig. x_xy: x* (one-mass, y = 1: blue squares) and x*, y* (two-mass: red circles) against N, with
    the large-N laws of Eqs. e.asymp_x and e.xy_N drawn where they stay inside the frame the data set."""
    fig = _figure(9.5, 4.6)
    ax = fig.add_subplot()
    N = _curve_N(data)
    Ns = np.asarray(data["N"], dtype=float)
    one = _points(ax, data, "one-mass", "x", _BLUE, "s", "one-mass chain (Sec. IV, y = 1): x*")
    two_x = _points(ax, data, "two-mass", "x", _RED, "o", "two-mass chain (Sec. V): x* and y*")
    two_y = _points(ax, data, "two-mass", "y", _RED, "o")
    frame = _frame([one, two_x, two_y], log_y=False, floor=0.0)
    for case, key, colour in (("one-mass", "x", _BLUE), ("two-mass", "x", _RED), ("two-mass", "y", _RED)):
        _law_in_frame(ax, N, _law(data, case, key, N), frame, colour)
    ax.plot([], [], color="0.3", linewidth=0.9, label="large-N laws, Eqs. e.asymp_x, e.xy_N")
    ax.set_ylim(*frame)
    _room_right(ax, data)
    _tag(ax, Ns[-1], two_y[-1], "y*")
    _tag(ax, Ns[-1], max(one[-1], two_x[-1]), "x*")
    _against_N(ax, "x*, y*", "Fig. x_xy: optimal x* and y* against N", log_y=False)
    return fig


#: The two-mass chain's end parameters, Fig. m_mmK's red circles.
_TWO_MASS_ENDS: tuple[_RowKey, ...] = ("m1", "m2", "K12")


def m_mmK_figure(data: OptimumData) -> Figure:
    """Fig. m_mmK: m1* (one-mass, m2 = K12 = 1: blue squares) and m1*, m2*, K12* (two-mass: red circles)
    against N, with the large-N laws drawn where they stay inside the frame the data set."""
    fig = _figure(9.5, 4.6)
    ax = fig.add_subplot()
    N = _curve_N(data)
    Ns = np.asarray(data["N"], dtype=float)
    one = _points(ax, data, "one-mass", "m1", _BLUE, "s", "one-mass chain (Sec. IV, m2 = K12 = 1): m1*")
    two = {key: _points(ax, data, "two-mass", key, _RED, "o",
                        "two-mass chain (Sec. V): m1*, m2*, K12*" if key == "m1" else None)
           for key in _TWO_MASS_ENDS}
    ax.axhline(1.0, color=_BLUE, linestyle=":", linewidth=0.9, label="m2 = K12 = 1, one-mass chain")
    frame = _frame([one, *two.values(), np.ones(1)], log_y=True)
    _law_in_frame(ax, N, _law(data, "one-mass", "m1", N), frame, _BLUE)
    for key in two:
        _law_in_frame(ax, N, _law(data, "two-mass", key, N), frame, _RED)
    ax.plot([], [], color="0.3", linewidth=0.9, label="large-N laws, Eqs. e.asymp_x, e.m1m2K12-rw")
    ax.set_ylim(*frame)
    _room_right(ax, data)
    _tag(ax, Ns[-1], math.sqrt(one[-1] * two["m1"][-1]), "m1*")
    _tag(ax, Ns[-1], two["m2"][-1], "m2*")
    _tag(ax, Ns[-1], two["K12"][-1], "K12*")
    _against_N(ax, "m1*, m2*, K12* (bulk units)", "Fig. m_mmK: optimal end masses and spring against N")
    return fig


def rw_figure(data: OptimumData) -> Figure:
    """Fig. rw: r* (red squares) and w* (blue circles) against N, the laws of Eq. e.rw_N where they stay
    inside the frame, and w(r*) of Eq. e.wr (open circles)."""
    fig = _figure(9.5, 4.6)
    ax = fig.add_subplot()
    N = _curve_N(data)
    Ns = np.asarray(data["N"], dtype=float)
    r = _points(ax, data, "two-mass", "r", _RED, "s", "r*")
    w = _points(ax, data, "two-mass", "w", _BLUE, "o", "w*")
    ax.plot(Ns, data["w_of_r"], "o", color=_BLUE, markersize=8, markerfacecolor="none", label="w(r*), Eq. e.wr")
    frame = _frame([r, w, np.asarray(data["w_of_r"], dtype=float)], log_y=True)
    _law_in_frame(ax, N, _law(data, "two-mass", "r", N), frame, _RED)
    _law_in_frame(ax, N, _law(data, "two-mass", "w", N), frame, _BLUE)
    ax.plot([], [], color="0.3", linewidth=0.9, label="large-N laws, Eq. e.rw_N")
    ax.set_ylim(*frame)
    _against_N(ax, "r*, w*", "Fig. rw: optimal r* and w* against N")
    return fig


# ------------------------------------------------------------------ int_rw, minimiz
def int_rw_figure(data: IntRwData) -> Figure:
    """Fig. int_rw: the integrand of Eq. e.uinftyz; its area is α∞(τ, σ)."""
    fig = _figure()
    ax = fig.add_subplot()
    zeta = data["zeta"]
    styles = [(_BLUE, 0.9), (_RED, 2.0)]
    for curve, (colour, width) in zip(data["curves"], styles, strict=False):
        ax.plot(zeta, curve["integrand"], color=colour, linewidth=width,
                label=f"{curve['name']}: τ = {curve['tau']:.5f}, σ = {curve['sigma']:.4f}, α∞ = {curve['alpha']:.6f}")
    ax.plot(zeta, data["weight"], "--", color="0.3", linewidth=1.0, label="weighting function")
    ax.axhline(0.0, color="0.5", linewidth=0.5)
    ax.set_xlim(0, math.pi / 2)
    ax.set_xlabel("ζ")
    ax.set_ylabel("integrand of Eq. e.uinftyz")
    ax.set_ylim(top=1.6)  # room above the curves: the legend stays off the data
    ax.legend(fontsize=8, loc="upper right")
    ax.grid(True, alpha=0.3, linewidth=0.5)
    ax.set_title("Fig. int_rw: the integrand of α∞(τ, σ), two-mass chain (the paper prints +τ for the blue "
                 "pair, a slip)", fontsize=9)
    return fig


def _broken_at(sigma: Sequence[float], values: Sequence[float], jumps: Sequence[tuple[float, float]]
               ) -> tuple[np.ndarray, np.ndarray]:
    """The curve with a gap (NaN) between the two sides of each jump: a jump is not a steep slope."""
    xs, ys = list(map(float, sigma)), list(map(float, values))
    for _lo, hi in jumps:
        i = xs.index(float(hi))
        xs.insert(i, math.nan)
        ys.insert(i, math.nan)
    return np.asarray(xs), np.asarray(ys)


def minimiz_figure(data: MinimizData) -> Figure:
    """Fig. minimiz: τ_m(σ) (blue line, left axis) and δ∞(σ, τ_m(σ)) (red line, right axis, log), its global
    minimum at σ*.  Where τ_m jumps (the minimum leaves τ = 0) the blue line breaks; a dotted segment joins
    the two sides."""
    fig = _figure()
    ax = fig.add_subplot()
    jumps = data.get("jumps", [])
    ax.plot(*_broken_at(data["sigma"], data["tau_m"], jumps), color=_BLUE, linewidth=1.6)
    for lo, hi in jumps:
        tau = dict(zip(data["sigma"], data["tau_m"], strict=True))
        ax.plot([lo, hi], [tau[lo], tau[hi]], ":", color=_BLUE, linewidth=1.0)
    ax.set_xlabel("σ")
    ax.set_ylabel("τ_m(σ)", color=_BLUE)
    right = ax.twinx()
    right.plot(data["sigma"], data["delta_m"], color=_RED, linewidth=1.6)
    right.set_yscale("log")
    right.set_ylabel("δ∞(σ, τ_m(σ))", color=_RED)
    right.plot([data["sigma_star"]], [data["delta_star"]], "o", color=_RED,
               label=f"global minimum: σ* = {data['sigma_star']:.4f}, τ* = {data['tau_star']:.5f}, "
                     f"δ*∞ = {data['delta_star']:.6f}")
    top = max(data["tau_m"])
    ax.set_ylim(-0.05 * top, 1.3 * top)  # room above both curves' middle for the legend
    low, high = min(data["delta_m"]), max(data["delta_m"])
    right.set_ylim(low / 1.3, high * (high / low) ** 0.3)
    right.legend(fontsize=8, loc="upper center")
    ax.grid(True, alpha=0.3, linewidth=0.5)
    ax.set_title(f"Fig. minimiz: minimising the asymptotic loss over τ ≥ 0 ({data['case']} chain)", fontsize=10)
    return fig


# ------------------------------------------------------------------ Pk20-100
def pk_figure(data: PkData, circuit: Mapping[int, Mapping[str, np.ndarray]] | None = None) -> Figure:
    """Fig. Pk20-100: P_n (squares, left) and (N/π) δω_n (circles, right) for N = 20 (filled), 100 (open).

    ``circuit`` maps a panel's N to a circuit's modes (:func:`~lcchain.report.figure_data.spectrum_points`),
    drawn on top as larger open black symbols of the same shapes.
    """
    fig = _figure(10.0, 4.6)
    ax = fig.add_subplot()
    right = ax.twinx()
    first_circuit = True
    for panel, filled in zip(data["panels"], (True, False), strict=False):
        face = None if filled else "none"
        ax.plot(panel["k"], panel["P"] * panel["N"], "s", color=_RED, markersize=4, markerfacecolor=face,
                label=f"N P_n, N = {panel['N']}")
        right.plot(panel["k"][1:], panel["spacing"], "o", color=_BLUE, markersize=4, markerfacecolor=face,
                   label=f"(N/π) δω_n, N = {panel['N']}")
        points = (circuit or {}).get(panel["N"])
        if points is not None:
            ax.plot(points["k"], points["P"] * panel["N"], marker="s", markersize=7,
                    label="ngspice (AC): N |P_n|" if first_circuit else None, **_CIRCUIT)
            right.plot(points["k_upper"], points["v"], marker="o", markersize=7,
                       label="ngspice (AC): (N/π) δω_n" if first_circuit else None, **_CIRCUIT)
            first_circuit = False
    right.plot(data["k"], data["uniform_v"], "--", color="0.3", linewidth=1.0, label="uniform v_k = cos(k/2)")
    ax.set_xlabel("k_n")
    ax.set_ylabel("N P_n", color=_RED)
    right.set_ylabel("(N/π) δω_n", color=_BLUE)
    right.set_ylim(0, 1.1)
    ax.set_xlim(0, math.pi)
    lines = ax.get_legend_handles_labels()
    more = right.get_legend_handles_labels()
    ax.legend(lines[0] + more[0], lines[1] + more[1], fontsize=8, loc="upper left", bbox_to_anchor=(1.09, 1.0),
              borderaxespad=0.0)  # outside the frame: inside, it hid the N = 100 spacings near k = 2.3
    ax.grid(True, alpha=0.3, linewidth=0.5)
    ax.set_title("Fig. Pk20-100: mode density and frequency spacing of the optimal two-mass chains", fontsize=10)
    return fig


# ------------------------------------------------------------------ LCcircuit
def _inductor(ax: Axes, x0: float, x1: float, y: float) -> None:
    turns = 4
    lead = 0.12 * (x1 - x0)
    ax.plot([x0, x0 + lead], [y, y], color="k", linewidth=1.2)
    ax.plot([x1 - lead, x1], [y, y], color="k", linewidth=1.2)
    width = (x1 - x0 - 2 * lead) / turns
    for j in range(turns):
        theta = np.linspace(math.pi, 0, 30)
        cx = x0 + lead + width * (j + 0.5)
        ax.plot(cx + width / 2 * np.cos(theta), y + width / 2 * np.sin(theta), color="k", linewidth=1.2)


def _capacitor(ax: Axes, x: float, y0: float, y1: float) -> None:
    mid = (y0 + y1) / 2
    ax.plot([x, x], [y0, mid + 0.06], color="k", linewidth=1.2)
    ax.plot([x, x], [mid - 0.06, y1], color="k", linewidth=1.2)
    ax.plot([x - 0.18, x + 0.18], [mid + 0.06, mid + 0.06], color="k", linewidth=2.0)
    ax.plot([x - 0.18, x + 0.18], [mid - 0.06, mid - 0.06], color="k", linewidth=2.0)


def _si(value: float, unit: str) -> str:
    for prefix, scale in (("", 1.0), ("m", 1e-3), ("µ", 1e-6), ("n", 1e-9), ("p", 1e-12), ("f", 1e-15)):
        if abs(value) >= scale * 0.9999:
            return f"{value / scale:.4g} {prefix}{unit}"
    return f"{value:.3g} {unit}"


def circuit_figure(data: CircuitData) -> Figure:
    """Fig. LCcircuit: the ladder drawn from the netlist's own elements, each with its value.

    Inductors (the masses) in series along the top carry the loop currents; capacitors (the springs) to
    ground between them; a free end closes its loop to ground directly.
    """
    elements = data["elements"]
    inductors = [e for e in elements if e["kind"] == "L"]
    capacitors = {frozenset(e["nodes"]): e for e in elements if e["kind"] == "C"}
    fig = _figure(2.0 + 1.9 * len(inductors), 2.9)
    ax = fig.add_subplot()
    top, ground, step = 1.0, 0.0, 1.9
    x = 0.0
    ax.plot([x, x], [ground, top], color="k", linewidth=1.2)
    for i, inductor in enumerate(inductors):
        _inductor(ax, x, x + step, top)
        ax.text(x + step / 2, top + 0.25, f"{inductor['name']}\n{_si(inductor['value'], 'H')}", ha="center",
                va="bottom", fontsize=8)
        ax.text(x + step / 2, top - 0.22, f"I{i + 1} →", ha="center", va="top", fontsize=7, color=_RED)
        x += step
        node = inductor["nodes"][1]
        capacitor = capacitors.get(frozenset((node, "0")))
        if capacitor is not None and i < len(inductors) - 1:
            _capacitor(ax, x, top, ground)
            ax.plot([x], [top], "o", color="k", markersize=3)
            ax.text(x + 0.22, (top + ground) / 2, f"{capacitor['name']}\n{_si(capacitor['value'], 'F')}", ha="left",
                    va="center", fontsize=7.5)
    ax.plot([x, x], [ground, top], color="k", linewidth=1.2)
    ax.plot([0.0, x], [ground, ground], color="k", linewidth=1.2)
    for gx in (0.0, x):
        ax.plot([gx - 0.15, gx + 0.15], [ground - 0.08, ground - 0.08], color="k", linewidth=1.0)
    ax.set_xlim(-0.4, x + 0.6)
    ax.set_ylim(-0.4, top + 0.9)
    ax.set_aspect("equal")
    ax.axis("off")
    ax.set_title(f"Fig. LCcircuit: the {data['case']} ladder of N = {data['N']} from its netlist "
                 f"(L_i = m_i L0, C = C0 / K; L0 = {_si(data['L0'], 'H')}, C0 = {_si(data['C0'], 'F')})", fontsize=9)
    return fig


# ------------------------------------------------------------------ the set
#: A figure's data (:mod:`.figure_data`).
_Data = TypeVar("_Data", Cradle4Data, VkData, DeltaData, OptimumData, IntRwData, MinimizData, PkData, CircuitData)


@dataclass(frozen=True)
class PaperFigure(Generic[_Data]):
    """One figure of the paper: its label (the file's name), its data and how it is drawn.

    ``data(rows, quick)`` computes the numbers (:mod:`.figure_data`; ``rows`` None when ``uses_rows`` is False) and
    ``draw(data)`` returns the Figure.  Both are functions of a module, so that a figure pickles and may be computed
    in another process; ``seconds`` is roughly what its data take without ``quick`` (issue 35's profile), for the
    order a pool takes work in.
    """

    label: str
    caption: str
    data: Callable[[DesignRows | None, bool], _Data]
    draw: Callable[[_Data], Figure]
    uses_rows: bool = False
    seconds: float = 0.3

    def build(self, rows: DesignRows | None, quick: bool) -> Figure:
        """The Figure: its data drawn."""
        return self.draw(self.data(rows, quick))


#: One of the paper's figures, whatever its data.
AnyPaperFigure: TypeAlias = (PaperFigure[Cradle4Data] | PaperFigure[VkData] | PaperFigure[DeltaData]
                             | PaperFigure[OptimumData] | PaperFigure[IntRwData] | PaperFigure[MinimizData]
                             | PaperFigure[PkData] | PaperFigure[CircuitData])


def _rows(rows: DesignRows | None) -> DesignRows:
    if rows is None:
        raise ValueError("this figure is drawn from rows of Tables I and II: rows=None")
    return rows


def _optimum(rows: DesignRows | None, quick: bool) -> OptimumData:
    return optimum_data(_rows(rows), QUICK_N if quick else FULL_N)


def _delta(rows: DesignRows | None, quick: bool) -> DeltaData:
    return delta_from_optimum(_optimum(rows, quick))


def _cradle4(rows: DesignRows | None, quick: bool) -> Cradle4Data:
    return cradle4_data()


def _vk(rows: DesignRows | None, quick: bool) -> VkData:
    return vk_data()


def _int_rw(rows: DesignRows | None, quick: bool) -> IntRwData:
    return int_rw_data()


def _minimiz(rows: DesignRows | None, quick: bool) -> MinimizData:
    return minimiz_data(quick=quick)


def _pk(rows: DesignRows | None, quick: bool) -> PkData:
    return pk_data(_rows(rows))


def _circuit(rows: DesignRows | None, quick: bool) -> CircuitData:
    return circuit_data()


FIGURES: tuple[AnyPaperFigure, ...] = (
    PaperFigure("cradle4", "The perfect 4-mass cradle and its pulse", _cradle4, cradle4_figure),
    PaperFigure("vk", "Group velocity and mode density, N = 50, three Δ", _vk, vk_figure),
    PaperFigure("delta", "Transmission loss δ* against N", _delta, paper_delta_figure, uses_rows=True),
    PaperFigure("x_xy", "Optimal x*, y* against N", _optimum, x_xy_figure, uses_rows=True),
    PaperFigure("m_mmK", "Optimal m1*, m2*, K12* against N", _optimum, m_mmK_figure, uses_rows=True),
    PaperFigure("int_rw", "The integrand of α∞(τ, σ)", _int_rw, int_rw_figure),
    PaperFigure("minimiz", "Minimising δ∞(σ, τ)", _minimiz, minimiz_figure, seconds=15.0),
    PaperFigure("rw", "Optimal r*, w* against N", _optimum, rw_figure, uses_rows=True),
    PaperFigure("Pk20-100", "Mode density and spacing, N = 20 and 100", _pk, pk_figure, uses_rows=True),
    PaperFigure("LCcircuit", "The LC ladder", _circuit, circuit_figure),
)


def make_figures(out: str | os.PathLike[str], *, quick: bool = False, fmt: str = "png", rows: DesignRows | None = None,
                 progress: Callable[[int, int, str], None] | None = None) -> list[Path]:
    """Write every figure of :data:`FIGURES` into ``out`` as ``<label>.<fmt>``; return the paths."""
    rows = rows if rows is not None else DesignRows()
    folder = Path(out)
    folder.mkdir(parents=True, exist_ok=True)
    written = []
    for i, figure in enumerate(FIGURES):
        if progress is not None:
            progress(i, len(FIGURES), figure.label)
        path = folder / f"{figure.label}.{fmt}"
        save_figure(figure.build(rows, quick), path, dpi=150)
        written.append(path)
    if progress is not None:
        progress(len(FIGURES), len(FIGURES), "done")
    return written

