"""Figures: the only module of lcchain that uses matplotlib.

matplotlib is imported inside the functions, never at import time, so that
``import lcchain`` (and ``import lcchain.plots``) stays light.  Figures are
built on :class:`matplotlib.figure.Figure` directly, not through pyplot: no
backend is selected, no global figure registry fills up, and nothing is ever
shown.  Every function takes plain arrays, an optional ``ax`` to draw into
and an optional ``path`` to save to (the caller creates the directory), and
returns the Figure.

Times are dimensionless, in units of sqrt(L0 C0); currents are relative to
the initial current of loop 1, I_1(0).
"""

from __future__ import annotations

import os
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, TypedDict

import numpy as np
from numpy.typing import ArrayLike

from ..core.checks import as_float, as_int
from ..core.errors import ParameterError
from .files import save_figure

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.axes._secondary_axes import SecondaryAxis
    from matplotlib.figure import Figure

    from ..scenes.run import OverlayPanel

__all__ = ["physical_axis", "OverlayCurves", "overlay", "side_by_side", "spacetime", "histogram", "pareto",
           "mode_density", "spectrum", "spacing_band", "TIME_LABEL", "set_title", "wrapped"]

#: Label of every time axis.
TIME_LABEL = r"$t\,/\sqrt{L_0 C_0}$"
#: Size of a new figure, in inches.
FIGSIZE = (8.0, 5.0)
#: Resolution of saved PNG files, in dots per inch.
DPI = 150
#: Most time columns :func:`spacetime` draws (see :func:`_decimate_max_abs`).
SPACETIME_MAX_COLUMNS = 2000

class _Grid(TypedDict):
    alpha: float
    linewidth: float


_GRID: _Grid = {"alpha": 0.3, "linewidth": 0.5}


class _LineStyle(TypedDict, total=False):
    linestyle: str
    marker: str
    markersize: float
    linewidth: float
_ARRIVAL_KEYS = ("index", "t_theory", "t_sim", "peak_theory", "peak_sim")
_RECORD_KEYS = ("method", "N", "wall_s", "error")


# --------------------------------------------------------------------------- helpers

def _new_figure() -> Figure:
    from matplotlib.figure import Figure

    return Figure(figsize=FIGSIZE, layout="constrained")


def _text(title: str) -> str:
    """A title as matplotlib should draw it: as written when its ``$...$`` parts are valid mathtext (a scene may
    write ``$\\alpha$``), else as plain text, its dollars escaped.  A title like ``$x`` or ``$\\frac{1}{$`` made
    matplotlib raise while saving, after the run, and lost the figure."""
    if title.replace(r"\$", "").count("$") < 2:
        return title  # no math in it: matplotlib draws it as it is
    from matplotlib.mathtext import MathTextParser

    try:
        MathTextParser("path").parse(title)
    except (ValueError, RuntimeError):
        return re.sub(r"(?<!\\)\$", r"\\$", title)
    return title


#: Average width of a character of a title, in ems (DejaVu Sans averages about 0.55 em; a little more keeps
#: capitals and wide digits inside).
_EM_PER_CHARACTER = 0.6


def wrapped(title: str, width_inches: float, fontsize: float) -> str:
    """``title`` broken at spaces into lines that fit ``width_inches`` at ``fontsize`` points (issue 33: a long
    scene title ran past both edges of the figure); a ``$...$`` math part is never broken."""
    columns = max(16, int(width_inches * 72.0 / (_EM_PER_CHARACTER * fontsize)))
    if len(title) <= columns or "\n" in title:
        return title
    import textwrap

    parts = re.split(r"((?<!\\)\$.*?(?<!\\)\$)", title)  # a math part keeps its spaces: no break inside it
    protected = "".join(part.replace(" ", "\0") if i % 2 else part for i, part in enumerate(parts))
    return textwrap.fill(protected, columns, break_long_words=False, break_on_hyphens=False).replace("\0", " ")


def set_title(target: Axes | Figure, title: str, fontsize: float | str | None = None) -> None:
    """An Axes' title or a figure's suptitle (``target``), its math checked (:func:`_text`) and wrapped to the
    width it has (:func:`wrapped`): no title is clipped by the figure."""
    from matplotlib import rcParams
    from matplotlib.axes import Axes
    from matplotlib.font_manager import FontProperties

    default = rcParams["axes.titlesize"] if isinstance(target, Axes) else rcParams["figure.titlesize"]
    points = FontProperties(size=fontsize if fontsize is not None else default).get_size_in_points()
    size = points  # the size the title had: the rcParams' title size unless given (never font.size's default)
    if isinstance(target, Axes):
        width = _root_figure(target).get_figwidth() * target.get_position().width
        target.set_title(wrapped(_text(title), width, points), fontsize=size)
    else:
        target.suptitle(wrapped(_text(title), target.get_figwidth(), points), fontsize=size)


def _root_figure(ax: Axes) -> Figure:
    """The top-level Figure of ``ax`` (also when ``ax`` lives in a SubFigure); an ``ax`` that is no Axes (a
    Figure, a name) is a ParameterError naming it."""
    from matplotlib.axes import Axes as AxesType

    if not isinstance(ax, AxesType):
        raise ParameterError("ax", type(ax).__name__, "a matplotlib Axes to draw into (fig.add_subplot()), or None "
                             "for a new figure")
    try:
        figure = ax.get_figure(root=True)  # matplotlib >= 3.10
        assert figure is not None  # an Axes always belongs to a Figure
        return figure
    except TypeError:
        return ax.figure.figure  # SubFigure.figure and Figure.figure are the root


def _finish(fig: Figure, path: str | os.PathLike[str] | None) -> Figure:
    if path is not None:
        save_figure(fig, path, dpi=DPI)  # atomically, in the format the name says
    return fig


def _vector(name: str, values: ArrayLike, *, min_size: int = 1) -> np.ndarray:
    a = np.asarray(values, dtype=float)
    if a.ndim != 1:
        raise ParameterError(f"{name}.shape", a.shape, "a one-dimensional array")
    if a.size < min_size:
        raise ParameterError(f"len({name})", a.size, f"at least {min_size} values")
    return a


def _same_length(name: str, a: np.ndarray, ref_name: str, ref: np.ndarray) -> None:
    if a.shape != ref.shape:
        raise ParameterError(f"{name}.shape", a.shape, f"the shape of {ref_name}, {ref.shape}")


def _field(item: object, key: str, what: str, i: int) -> object:
    """``item[key]`` for a mapping, ``item.key`` for an object (e.g. ArrivalComparison)."""
    if isinstance(item, Mapping):
        if key in item:
            return item[key]
    elif hasattr(item, key):
        return getattr(item, key)
    raise ParameterError(f"{what}[{i}]", item, f"a mapping with key {key!r}")


# --------------------------------------------------------------------------- overlay

def physical_axis(ax: Axes, scale: float, unit: str, label: str) -> SecondaryAxis:
    """A secondary x axis on top of ``ax`` in SI (issue 33): the bulk axis times ``scale`` (seconds per unit of
    sqrt(L0 C0), or hertz per unit of angular frequency), labelled ``label [unit]``; the bulk axis stays below."""
    if not (np.isfinite(scale) and scale > 0):
        raise ParameterError("scale", scale, "a finite number > 0 (the SI value of one bulk unit)")
    def to_si(x: ArrayLike) -> np.ndarray:
        return np.asarray(x, dtype=float) * scale

    def to_bulk(x: ArrayLike) -> np.ndarray:
        return np.asarray(x, dtype=float) / scale

    secondary = ax.secondary_xaxis("top", functions=(to_si, to_bulk))
    secondary.set_xlabel(f"{label} [{unit}]", fontsize=8)
    secondary.tick_params(labelsize=7)
    return secondary


@dataclass(frozen=True, eq=False)
class OverlayCurves:
    """What :func:`overlay` draws: loop N's simulated signal over its theory, the residual, loop 1's too when
    given, and the arrivals marked on them.

    Attributes
    ----------
    t_sim, y_sim : array_like, shape (n,)
        Simulated signal of loop N at the simulator's time points; time in
        units of sqrt(L0 C0), signal dimensionless (e.g. I_N / I_1(0)).
    t_theory, y_theory : array_like, shape (m,)
        Theory of loop N on its own (usually finer) time grid, same units.
    residual : array_like, optional
        Simulation minus theory, dimensionless; drawn in a lower panel with
        its largest absolute value in the legend.  Ignored (but checked) when
        the overlay is drawn into an ``ax``.
    t_residual : array_like, optional
        Times of `residual`, in units of sqrt(L0 C0); default `t_sim`.
    first_sim, first_theory : array_like, optional
        Loop 1's simulated signal (at `t_sim`) and theory (at `t_theory`),
        both or neither: the arrivals alternate ends (#1 at loop N, #2 back
        at loop 1, ...), and each is marked on the loop where it arrives.
    arrivals : sequence of mapping, optional
        One entry per arrival with keys ``index``, ``t_theory``, ``t_sim``,
        ``peak_theory``, ``peak_sim`` and optionally ``end`` (``"last"``, the
        default, or ``"first"``); objects with these attributes, such as
        :class:`lcchain.compare.metrics.ArrivalComparison`, work too.  Each is marked
        by a dotted vertical line at the theoretical time and a note of the
        time and peak differences, simulation minus theory; its peaks are
        marked on its loop's curves (an arrival at loop 1 without loop 1's
        curves keeps its line and note, its note naming the loop).
    time_unit : float, optional
        Seconds per unit of sqrt(L0 C0): a second time axis on top, in seconds (:func:`physical_axis`).

    The arrays are checked here (one-dimensional, each of its time grid's length; loop 1's both or neither; a
    residual's times only with a residual), and the arrivals (every key, ``end`` first or last), each refusal
    naming the field.
    """

    t_sim: ArrayLike
    y_sim: ArrayLike
    t_theory: ArrayLike
    y_theory: ArrayLike
    residual: ArrayLike | None = None
    t_residual: ArrayLike | None = None
    first_sim: ArrayLike | None = None
    first_theory: ArrayLike | None = None
    arrivals: Sequence[object] = ()
    time_unit: float | None = None

    def __post_init__(self) -> None:
        def keep(name: str, value: np.ndarray) -> None:
            object.__setattr__(self, name, value)

        t_sim = _vector("t_sim", self.t_sim)
        keep("t_sim", t_sim)
        keep("y_sim", _vector("y_sim", self.y_sim))
        _same_length("y_sim", self.sim, "t_sim", t_sim)
        t_theory = _vector("t_theory", self.t_theory)
        keep("t_theory", t_theory)
        keep("y_theory", _vector("y_theory", self.y_theory))
        _same_length("y_theory", self.theory, "t_theory", t_theory)
        if (self.first_sim is None) != (self.first_theory is None):
            raise ParameterError("first_sim, first_theory", "one of them", "both arrays or neither")
        if self.first_sim is not None and self.first_theory is not None:
            keep("first_sim", _vector("first_sim", self.first_sim))
            _same_length("first_sim", _array(self.first_sim), "t_sim", t_sim)
            keep("first_theory", _vector("first_theory", self.first_theory))
            _same_length("first_theory", _array(self.first_theory), "t_theory", t_theory)
        if self.residual is not None:
            residual = _vector("residual", self.residual)
            keep("residual", residual)
            t_residual = t_sim if self.t_residual is None else _vector("t_residual", self.t_residual)
            keep("t_residual", t_residual)
            _same_length("residual", residual, "t_residual" if t_residual is not t_sim else "t_sim", t_residual)
        elif self.t_residual is not None:
            raise ParameterError("t_residual", "an array", "None when residual is None")
        object.__setattr__(self, "arrivals", tuple(self.arrivals))
        self.marks()

    @property
    def sim(self) -> np.ndarray:
        return _array(self.y_sim)

    @property
    def theory(self) -> np.ndarray:
        return _array(self.y_theory)

    def marks(self) -> list[dict[str, float | bool]]:
        """Each arrival's numbers and whether it arrives at loop 1 (``first``)."""
        marks: list[dict[str, float | bool]] = []
        for i, a in enumerate(self.arrivals):
            mark: dict[str, float | bool] = {key: as_float(_field(a, key, "arrivals", i)) for key in _ARRIVAL_KEYS}
            end = a.get("end", "last") if isinstance(a, Mapping) else getattr(a, "end", "last")
            if end not in ("first", "last"):
                raise ParameterError("arrivals[].end", end, "'first' or 'last'")
            mark["first"] = end == "first"
            marks.append(mark)
        return marks


def _array(values: ArrayLike | None) -> np.ndarray:
    """An array :class:`OverlayCurves` checked already."""
    assert isinstance(values, np.ndarray)
    return values


def overlay(curves: OverlayCurves, *, title: str = "", ylabel: str = r"$I_N\,/\,I_1(0)$",
            path: str | os.PathLike[str] | None = None, ax: Axes | None = None) -> Figure:
    """Simulated end-loop signal over the theory, with the residual below; loop 1 too when given.

    Parameters
    ----------
    curves : OverlayCurves
        The signals, the residual, the arrivals and the time unit.
    title, ylabel : str
        Figure title (top panel) and label of the signal axis.
    path : str or path-like, optional
        Save the figure there (PNG by the suffix); the directory must exist.
    ax : matplotlib.axes.Axes, optional
        Draw the overlay only into this Axes (no residual panel).

    Returns
    -------
    matplotlib.figure.Figure
        The new figure, or the figure of `ax`.  A new figure has one legend
        above the panels, off the data; into `ax`, the legend goes where it
        covers the fewest lines (matplotlib's ``"best"``).
    """
    t_sim, y_sim, t_theory, y_theory = _array(curves.t_sim), curves.sim, _array(curves.t_theory), curves.theory
    residual, t_residual, time_unit = curves.residual, curves.t_residual, curves.time_unit
    first_sim = None if curves.first_sim is None else _array(curves.first_sim)
    first_theory = None if curves.first_theory is None else _array(curves.first_theory)
    marks = curves.marks()

    if ax is not None:
        fig = _root_figure(ax)
        top, bottom = ax, None
    else:
        fig = _new_figure()
        if residual is None:
            top, bottom = fig.add_subplot(), None
        else:
            top, bottom = fig.subplots(2, 1, sharex=True, height_ratios=[2, 1])

    both = first_sim is not None
    # Markers let sparse simulator points be seen one by one; many points read better as a line.
    sim_style: _LineStyle = {"linestyle": "none", "marker": "o", "markersize": 3} if t_sim.size <= 200 else \
        {"linestyle": "--", "linewidth": 1.0}
    colours = {"last": ("C0", "C1"), "first": ("C2", "C4")}  # (theory, ngspice) of each loop
    loops: list[tuple[str, str, np.ndarray, np.ndarray]] = [("last", " at loop N" if both else "", y_sim, y_theory)]
    if first_sim is not None and first_theory is not None:
        loops.append(("first", " at loop 1", first_sim, first_theory))
    for end, where, sim, theory in loops:
        top.plot(t_theory, theory, color=colours[end][0], linewidth=1.2, label=f"theory{where}", zorder=2)
        top.plot(t_sim, sim, color=colours[end][1], label=f"ngspice{where}", zorder=3, **sim_style)

    from matplotlib.transforms import blended_transform_factory

    to_top = blended_transform_factory(top.transData, top.transAxes)
    x_low, x_high = top.get_xlim()
    level, previous = 0, -np.inf  # a note drops below its neighbour's only when they are close in time
    for m in marks:
        level = 1 - level if m["t_theory"] - previous < 0.2 * (x_high - x_low) else 0
        previous = m["t_theory"]
        end = "first" if m["first"] else "last"
        top.axvline(m["t_theory"], color="0.4", linestyle=":", linewidth=0.8, zorder=1)
        if not m["first"] or both:
            top.plot([m["t_theory"]], [m["peak_theory"]], marker="+", color=colours[end][0], markersize=8,
                     linestyle="none")
            top.plot([m["t_sim"]], [m["peak_sim"]], marker="x", color=colours[end][1], markersize=6,
                     linestyle="none")
        note = (f"#{m['index']:.0f}{' at loop 1' if m['first'] else ''}\n"
                f"Δt {m['t_sim'] - m['t_theory']:+.2g}\n"
                f"Δpeak {m['peak_sim'] - m['peak_theory']:+.2g}")
        # A note right of its line in the left half, left of it in the right half: never past the frame.
        right_half = (m["t_theory"] - x_low) > 0.5 * (x_high - x_low)
        top.annotate(note, (m["t_theory"], 0.98 - 0.13 * level), xycoords=to_top,
                     xytext=(-3 if right_half else 3, 0), textcoords="offset points", fontsize=7,
                     ha="right" if right_half else "left", va="top", color="0.25",
                     bbox={"boxstyle": "round,pad=0.2", "facecolor": "white", "edgecolor": "none", "alpha": 0.7})
    if marks:
        # Head room above the data for the notes, which sit at the arrival peaks.
        low, high = top.get_ylim()
        top.set_ylim(low, high + 0.4 * (high - low))
        top.set_xlim(x_low, x_high)  # the arrival lines must not widen the time axis

    top.set_ylabel(ylabel)
    top.grid(True, **_GRID)
    if time_unit is not None:
        physical_axis(top, time_unit, "s", "time")

    if bottom is not None:
        residual = np.asarray(residual, dtype=float)  # given whenever there is a residual panel
        worst = float(np.nanmax(np.abs(residual))) if residual.size else 0.0
        bottom.plot(t_residual, residual, color="C3", linewidth=0.8,
                    label=f"sim − theory{' at loop N' if both else ''}, max |·| = {worst:.2e}")
        bottom.axhline(0.0, color="0.5", linewidth=0.6)
        for m in marks:
            bottom.axvline(m["t_theory"], color="0.4", linestyle=":", linewidth=0.8)
        bottom.set_ylabel("sim − theory")
        bottom.set_xlabel(TIME_LABEL)
        bottom.grid(True, **_GRID)
        bottom.ticklabel_format(axis="y", style="sci", scilimits=(-2, 3))
    else:
        top.set_xlabel(TIME_LABEL)
    if ax is not None:
        top.legend(loc="best", fontsize=8)
        if title:
            set_title(top, title)
    else:
        # One legend below the panels: no corner of a long window is free of data.
        handles = [h for a in (top, bottom) if a is not None for h in a.get_legend_handles_labels()[0]]
        fig.legend(handles=handles, loc="outside lower center", ncols=min(3, len(handles)), fontsize=8,
                   frameon=False)
        if title:
            set_title(fig, title)
    return _finish(fig, path)


def side_by_side(panels: Sequence[OverlayPanel], *, title: str = "",
                 path: str | os.PathLike[str] | None = None) -> Figure:
    """Several overlays next to each other, on shared axes (e.g. uniform against optimal ends).

    Parameters
    ----------
    panels : sequence of mapping
        One per column, with keys ``t`` (time, units of sqrt(L0 C0)),
        ``sim`` and ``theory`` (the signal at those times, dimensionless),
        ``title`` and optionally ``arrivals`` and ``ylabel`` as for
        :func:`overlay`.  At least one.
    title : str
        Title over all the columns.
    path : str or path-like, optional
        Save the figure there (PNG by the suffix); the directory must exist.

    Returns
    -------
    matplotlib.figure.Figure
    """
    if isinstance(panels, Mapping) or not isinstance(panels, Sequence) or not panels:
        raise ParameterError("panels", type(panels).__name__, "a non-empty sequence of mappings")
    from matplotlib.figure import Figure

    fig = Figure(figsize=(FIGSIZE[0] * 0.75 * len(panels), FIGSIZE[1]), layout="constrained")
    axes = fig.subplots(1, len(panels), sharex=True, sharey=True, squeeze=False)[0]
    for i, panel in enumerate(panels):
        if not isinstance(panel, Mapping) or not {"t", "sim", "theory", "title"} <= panel.keys():
            keys = sorted(panel) if isinstance(panel, Mapping) else type(panel).__name__
            raise ParameterError(f"panels[{i}]", keys, "a mapping with keys t, sim, theory, title")
    for i, (ax, panel) in enumerate(zip(axes, panels, strict=False)):
        overlay(OverlayCurves(panel["t"], panel["sim"], panel["t"], panel["theory"],
                              arrivals=panel.get("arrivals", ())), title=str(panel["title"]),
                ylabel=panel.get("ylabel", r"$I_N\,/\,I_1(0)$") if i == 0 else "", ax=ax)
    # Shared y: each overlay set its own head room; span every panel's data instead.
    low = min(float(min(np.min(p["sim"]), np.min(p["theory"]))) for p in panels)
    high = max(float(max(np.max(p["sim"]), np.max(p["theory"]))) for p in panels)
    span = high - low or 1.0
    axes[0].set_ylim(low - 0.05 * span, high + 0.35 * span)
    if title:
        set_title(fig, title)
    return _finish(fig, path)


# --------------------------------------------------------------------------- spacetime

def _decimate_max_abs(t: ArrayLike, data: ArrayLike, max_columns: int) -> tuple[np.ndarray, np.ndarray]:
    """Shrink the time axis of ``data`` to at most `max_columns` columns.

    The columns are cut into consecutive bins of ``b = ceil(n_times /
    max_columns)`` samples (the last bin may be shorter).  Each bin keeps,
    row by row, the sample of largest absolute value with its sign, so that
    a pulse one sample wide survives (a mean or a stride would lose it).
    A row whose bin holds a NaN keeps the NaN.

    Parameters
    ----------
    t : array_like, shape (n_times,)
        Time, any unit.
    data : array_like, shape (n_rows, n_times)
    max_columns : int
        At least 1.

    Returns
    -------
    t_bins : ndarray, shape (n_bins,)
        Middle of each bin: (first time + last time) / 2.
    data_bins : ndarray, shape (n_rows, n_bins)
        The inputs themselves (as arrays) when ``n_times <= max_columns``.
    """
    t = np.asarray(t, dtype=float)
    data = np.asarray(data, dtype=float)
    if data.ndim != 2 or t.shape != data.shape[1:]:
        raise ParameterError("data.shape", data.shape, f"(n_rows, len(t)) with t.shape = {t.shape}")
    if int(max_columns) < 1:
        raise ParameterError("max_columns", max_columns, "an integer >= 1")
    n_rows, n = data.shape
    if n <= max_columns:
        return t, data
    b = -(-n // int(max_columns))
    starts = np.arange(0, n, b)
    ends = np.minimum(starts + b, n) - 1
    t_bins = 0.5 * (t[starts] + t[ends])

    full = n // b  # bins with exactly b samples; the shorter tail bin is done apart
    out = np.empty((n_rows, starts.size))
    # Row blocks bound the temporary |data| to a few tens of MB for 1000 x 1e5 inputs.
    step = max(1, 4_000_000 // n)
    for r in range(0, n_rows, step):
        block = data[r:r + step, :full * b].reshape(-1, full, b)
        pick = np.argmax(np.abs(block), axis=2)
        out[r:r + step, :full] = np.take_along_axis(block, pick[..., None], axis=2)[..., 0]
        if full < starts.size:
            tail = data[r:r + step, full * b:]
            pick = np.argmax(np.abs(tail), axis=1)
            out[r:r + step, full] = np.take_along_axis(tail, pick[:, None], axis=1)[:, 0]
    return t_bins, out


def _edges(centres: np.ndarray) -> np.ndarray:
    """Cell edges halfway between centres, extended by half a cell at both ends."""
    mid = 0.5 * (centres[1:] + centres[:-1])
    return np.concatenate([[2 * centres[0] - mid[0]], mid, [2 * centres[-1] - mid[-1]]])


def spacetime(t: ArrayLike, currents: ArrayLike, *, title: str = "", max_columns: int = SPACETIME_MAX_COLUMNS,
              path: str | os.PathLike[str] | None = None, ax: Axes | None = None) -> Figure:
    """Loop currents as an image: loop index against time.

    Parameters
    ----------
    t : array_like, shape (n_times,)
        Time in units of sqrt(L0 C0), increasing; at least 2 points.
    currents : array_like, shape (n_loops, n_times)
        Current of loop i (row i - 1) relative to I_1(0), dimensionless.
    title : str
    max_columns : int, optional
        Longer time axes are decimated to at most this many columns by
        keeping the sample of largest absolute value in each bin of
        consecutive times (:func:`_decimate_max_abs`), so narrow pulses stay
        visible; the default suits a figure a few thousand pixels wide.
    path : str or path-like, optional
        Save the figure there (PNG by the suffix); the directory must exist.
    ax : matplotlib.axes.Axes, optional
        Draw into this Axes (the colorbar takes room from it).

    Returns
    -------
    matplotlib.figure.Figure

    Notes
    -----
    The colour map is diverging and centred at zero, with limits
    +- max |I_i / I_1(0)| over the finite values.

    Raises
    ------
    ValueError
        If `currents` is not two-dimensional or its second dimension is not
        ``len(t)``.
    """
    t = _vector("t", t, min_size=2)
    currents = np.asarray(currents, dtype=float)
    if currents.ndim != 2:
        raise ParameterError("currents.shape", currents.shape, "(n_loops, n_times), two-dimensional")
    if currents.shape[1] != t.size:
        raise ParameterError("currents.shape", currents.shape, f"(n_loops, len(t)) = (n_loops, {t.size})")
    if currents.shape[0] < 1:
        raise ParameterError("currents.shape", currents.shape, "at least one loop")

    t_img, img = _decimate_max_abs(t, currents, max_columns)
    finite = np.abs(img[np.isfinite(img)])
    vmax = float(finite.max()) if finite.size else 0.0
    vmax = vmax if vmax > 0 else 1.0

    fig = _new_figure() if ax is None else _root_figure(ax)
    ax = fig.add_subplot() if ax is None else ax
    loops = np.arange(1, img.shape[0] + 1, dtype=float)
    mesh = ax.pcolormesh(_edges(t_img), np.arange(0.5, img.shape[0] + 1), img, cmap="RdBu_r",
                         vmin=-vmax, vmax=vmax, shading="flat", rasterized=True)
    fig.colorbar(mesh, ax=ax, label=r"$I_i\,/\,I_1(0)$")
    ax.set_xlabel(TIME_LABEL)
    ax.set_ylabel("loop index i")
    if loops.size <= 12:
        ax.set_yticks(loops)
    if title:
        set_title(ax, title)
    return _finish(fig, path)


# --------------------------------------------------------------------------- histogram

def histogram(values: ArrayLike, *, theory: float | None = None, title: str = "", xlabel: str = "transmitted peak",
              path: str | os.PathLike[str] | None = None, ax: Axes | None = None) -> Figure:
    """Spread of the transmitted peak over tolerance samples.

    Parameters
    ----------
    values : array_like, shape (n_samples,)
        Transmitted peak of each sampled chain, dimensionless (e.g.
        max I_N / I_1(0)); NaNs are not allowed.
    theory : float, optional
        Peak of the nominal chain, drawn as a vertical line.
    title, xlabel : str
    path : str or path-like, optional
        Save the figure there (PNG by the suffix); the directory must exist.
    ax : matplotlib.axes.Axes, optional
        Draw into this Axes.

    Returns
    -------
    matplotlib.figure.Figure

    Notes
    -----
    The legend, right of the axes, gives the number of samples, the mean,
    the sample standard deviation (ddof = 1; 0 for a single sample), the
    worst (smallest) peak, marked by a dashed line, and the nominal value.

    Raises
    ------
    ValueError
        If `values` is not a non-empty one-dimensional array of finite numbers.
    """
    values = _vector("values", values)
    if not np.all(np.isfinite(values)):
        raise ParameterError("values", values, "finite numbers only")
    fig = _new_figure() if ax is None else _root_figure(ax)
    ax = fig.add_subplot() if ax is None else ax

    ax.hist(values, bins="auto", color="C0", alpha=0.75, edgecolor="white", linewidth=0.5)
    mean = float(values.mean())
    std = f"{float(values.std(ddof=1)):.3g}" if values.size > 1 else "none (one sample)"  # ddof 1: no spread of one
    worst = float(values.min())
    ax.axvline(worst, color="C3", linestyle="--", linewidth=1.0, label=f"worst {worst:.5g}")
    if theory is not None:
        ax.axvline(float(theory), color="k", linewidth=1.2, label=f"nominal {float(theory):.5g}")
    ax.set_xlabel(xlabel)
    ax.set_ylabel("samples")
    ax.grid(True, **_GRID)
    # Right of the axes, with the numbers as its title: the lines cross the whole height, the bars any corner.
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, title_fontsize=8, alignment="left",
              title=f"n = {values.size}\nmean = {mean:.5g}\nstd = {std}")
    if title:
        set_title(ax, title)
    return _finish(fig, path)


# --------------------------------------------------------------------------- pareto

def pareto(records: Sequence[Mapping[str, object]], *, path: str | os.PathLike[str] | None = None,
           ax: Axes | None = None) -> Figure:
    """Accuracy against cost of the simulation methods (log-log).

    Parameters
    ----------
    records : sequence of mapping
        One per run, with keys ``"method"`` (str), ``"N"`` (number of loops),
        ``"wall_s"`` (wall time, s, > 0) and ``"error"`` (max |sim - theory|,
        dimensionless, > 0).  Runs sharing (method, N) are joined by a line
        in order of wall time; colour tells the method, marker the N.
    path : str or path-like, optional
        Save the figure there (PNG by the suffix); the directory must exist.
    ax : matplotlib.axes.Axes, optional
        Draw into this Axes.

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    ValueError
        If `records` is empty, a record lacks a key, or a time or error is
        not positive (it could not be drawn on log axes).
    """
    groups: dict[tuple[str, int], list[tuple[float, float]]] = {}
    for i, rec in enumerate(records):
        method, n, wall, err = (_field(rec, key, "records", i) for key in _RECORD_KEYS)
        wall, err = as_float(wall), as_float(err)
        for key, v in (("wall_s", wall), ("error", err)):
            if not (np.isfinite(v) and v > 0):
                raise ParameterError(f"records[{i}][{key!r}]", v, "a finite number > 0 (log axes)")
        groups.setdefault((str(method), as_int(n)), []).append((wall, err))
    if not groups:
        raise ParameterError("records", records, "at least one record")

    fig = _new_figure() if ax is None else _root_figure(ax)
    ax = fig.add_subplot() if ax is None else ax
    methods = sorted({m for m, _ in groups})
    sizes = sorted({n for _, n in groups})
    markers = "osD^v<>pPhX*"
    for (method, n), points in sorted(groups.items()):
        wall, err = np.array(sorted(points)).T
        ax.plot(wall, err, marker=markers[sizes.index(n) % len(markers)], markersize=5, linewidth=1.0,
                color=f"C{methods.index(method) % 10}", label=f"{method}, N={n}")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("wall time / s")
    ax.set_ylabel("max |sim − theory|")
    ax.grid(True, which="major", **_GRID)
    ax.grid(True, which="minor", alpha=0.12, linewidth=0.4)
    ax.legend(fontsize=8, ncols=2 if len(groups) > 8 else 1)
    return _finish(fig, path)


# --------------------------------------------------------------------------- mode density

def mode_density(omega: ArrayLike, density: ArrayLike, *, path: str | os.PathLike[str] | None = None,
                 ax: Axes | None = None) -> Figure:
    """Weights of the normal modes and their frequency spacing.

    Parameters
    ----------
    omega : array_like, shape (N,)
        Normal-mode angular frequencies omega_n in units of 1/sqrt(L0 C0),
        increasing; at least 2.
    density : array_like, shape (N,)
        Mode density P_n (dimensionless weights, summing to 1 for a kick).
    path : str or path-like, optional
        Save the figure there (PNG by the suffix); the directory must exist.
    ax : matplotlib.axes.Axes, optional
        Axes for P_n; the spacing goes on a twin right axis made from it.

    Returns
    -------
    matplotlib.figure.Figure

    Notes
    -----
    P_n is drawn as stems against n = 1..N (markers only when N > 60) on the
    left axis; omega_n - omega_{n-1} for n = 2..N as a line on the right.

    Raises
    ------
    ValueError
        If the arrays are not one-dimensional of the same length >= 2.
    """
    omega = _vector("omega", omega, min_size=2)
    density = _vector("density", density, min_size=2)
    _same_length("density", density, "omega", omega)
    fig = _new_figure() if ax is None else _root_figure(ax)
    ax = fig.add_subplot() if ax is None else ax

    n = np.arange(1, omega.size + 1)
    if n.size <= 60:
        ax.vlines(n, 0.0, density, color="C0", linewidth=1.2)
    (h_p,) = ax.plot(n, density, "o", color="C0", markersize=4 if n.size <= 60 else 2, label="$P_n$")
    ax.axhline(0.0, color="0.5", linewidth=0.6)
    from matplotlib.ticker import MaxNLocator

    ax.xaxis.set_major_locator(MaxNLocator(integer=True))
    ax.set_xlabel("mode index n")
    ax.set_ylabel("mode density $P_n$", color="C0")
    ax.tick_params(axis="y", colors="C0")
    ax.grid(True, **_GRID)

    right = ax.twinx()
    (h_w,) = right.plot(n[1:], np.diff(omega), color="C1", linewidth=1.2, marker=".", markersize=3,
                        label=r"$\omega_n - \omega_{n-1}$")
    right.set_ylabel(r"spacing $\omega_n - \omega_{n-1}$  $[1/\sqrt{L_0 C_0}]$", color="C1")
    right.tick_params(axis="y", colors="C1")
    ax.legend(handles=[h_p, h_w], loc="upper right", fontsize=8)
    return _finish(fig, path)


def spectrum(omega_theory: ArrayLike, P_theory: ArrayLike, omega_circuit: ArrayLike, P_circuit: ArrayLike, *,
             title: str = "",
             path: str | os.PathLike[str] | None = None, ax: Axes | None = None,
             frequency_unit: float | None = None) -> Figure:
    """The paper's Fig. Pk20-100, with a circuit's modes on top: |P_n| against omega_n, and the spacing.

    Parameters
    ----------
    omega_theory, P_theory : array_like, shape (N,)
        Exact normal frequencies (units of 1/sqrt(L0 C0)) and weights P_n of alpha_N; a NaN weight (below the
        precision it was computed with) is not drawn.
    omega_circuit, P_circuit : array_like
        The modes the AC analysis found (NaN for a mode it did not see).
    title : str
    path : str or path-like, optional
        Save the figure there.
    ax : matplotlib.axes.Axes, optional
        Draw only the |P_n| panel into this Axes.
    frequency_unit : float, optional
        Hertz per unit of angular frequency, 1 / (2 pi sqrt(L0 C0)): a frequency axis on top, in Hz
        (:func:`physical_axis`).

    Returns
    -------
    matplotlib.figure.Figure
        Top: |P_n| on a log scale (the weights span many decades); bottom: omega_n - omega_(n-1).
    """
    omega_t = _vector("omega_theory", omega_theory, min_size=2)
    weight_t = _vector("P_theory", P_theory, min_size=2)
    omega_c = np.asarray(omega_circuit, dtype=float)
    weight_c = np.asarray(P_circuit, dtype=float)
    if ax is not None:
        fig, top, bottom = _root_figure(ax), ax, None
    else:
        fig = _new_figure()
        top, bottom = fig.subplots(2, 1, sharex=True, height_ratios=(3, 2))
    drawn = np.isfinite(weight_t) & (weight_t != 0)  # NaN: below the precision it was computed with
    top.semilogy(omega_t[drawn], np.abs(weight_t[drawn]), "-", color="0.6", linewidth=1.0, label="theory")
    top.semilogy(omega_t[drawn], np.abs(weight_t[drawn]), "o", color="0.6", markersize=3)
    seen = np.isfinite(omega_c) & (weight_c != 0)
    top.semilogy(omega_c[seen], np.abs(weight_c[seen]), "x", color="C3", markersize=5, label="ngspice (AC)")
    top.set_ylabel(r"$|P_n|$")
    top.grid(True, **_GRID)
    top.legend(loc="lower left", fontsize=8)
    if frequency_unit is not None:
        physical_axis(top, frequency_unit, "Hz", "frequency")
    if title:
        set_title(top, title, 10)
    if bottom is None:
        top.set_xlabel(r"$\omega_n$  $[1/\sqrt{L_0 C_0}]$")
        return _finish(fig, path)
    bottom.plot(omega_t[1:], np.diff(omega_t), "-", color="0.6", linewidth=1.0, label="theory")
    pairs = np.isfinite(omega_c[1:]) & np.isfinite(omega_c[:-1])
    bottom.plot(omega_c[1:][pairs], np.diff(omega_c)[pairs], "x", color="C3", markersize=5, label="ngspice (AC)")
    bottom.set_xlabel(r"$\omega_n$  $[1/\sqrt{L_0 C_0}]$")
    bottom.set_ylabel(r"$\omega_n - \omega_{n-1}$")
    bottom.grid(True, **_GRID)
    return _finish(fig, path)


def spacing_band(omega_nominal: ArrayLike, spacings: ArrayLike, *, title: str = "",
                 path: str | os.PathLike[str] | None = None,
                 ax: Axes | None = None) -> Figure:
    """What real parts do to the equal spacing: delta omega_n of tolerance samples against the nominal theory.

    Parameters
    ----------
    omega_nominal : array_like, shape (N,)
        The nominal chain's normal frequencies, units of 1/sqrt(L0 C0).
    spacings : array_like, shape (n_samples, N - 1)
        Each sample's measured omega_(n+1) - omega_n (NaN where a mode was not resolved).
    title : str
    path : str or path-like, optional
        Save the figure there.
    ax : matplotlib.axes.Axes, optional
        Draw into this Axes.

    Returns
    -------
    matplotlib.figure.Figure
        The band from the smallest to the largest sample's spacing at each n, their mean, each sample's points,
        and the nominal theory's spacing.
    """
    omega = _vector("omega_nominal", omega_nominal, min_size=2)
    values = np.asarray(spacings, dtype=float)
    if values.ndim != 2 or values.shape[1] != omega.size - 1 or values.shape[0] < 1:
        raise ParameterError("spacings", values.shape, f"one row of {omega.size - 1} spacings per sample")
    fig = _new_figure() if ax is None else _root_figure(ax)
    ax = fig.add_subplot() if ax is None else ax
    n = np.arange(1, omega.size)
    seen = np.isfinite(values).any(axis=0)
    with np.errstate(all="ignore"):
        low, high = np.nanmin(np.where(seen, values, 0.0), axis=0), np.nanmax(np.where(seen, values, 0.0), axis=0)
        mean = np.nanmean(np.where(seen, values, 0.0), axis=0)
    ax.fill_between(n[seen], low[seen], high[seen], color="C0", alpha=0.25, linewidth=0,
                    label=f"{values.shape[0]} samples: min to max")
    ax.plot(n[seen], mean[seen], "-", color="C0", linewidth=1.0, label="mean of the samples")
    for row in values:
        ax.plot(n, row, ".", color="C0", markersize=2, alpha=0.5)
    ax.plot(n, np.diff(omega), "-", color="k", linewidth=1.2, label="nominal theory")
    from matplotlib.ticker import MaxNLocator

    ax.xaxis.set_major_locator(MaxNLocator(integer=True))  # n is a mode's number
    ax.set_xlabel(r"$n$")
    ax.set_ylabel(r"$\delta\omega_n = \omega_{n+1} - \omega_n$  $[1/\sqrt{L_0 C_0}]$")
    ax.grid(True, **_GRID)
    ax.legend(loc="best", fontsize=8)
    if title:
        set_title(ax, title, 10)
    return _finish(fig, path)
