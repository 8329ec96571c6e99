"""The figure of a study, rebuilt from its store alone (no ngspice).

* a sweep over N: the paper's Fig. delta (δ* against N, theory as curves)
  with ngspice's measured first-arrival loss, 1 - peak, on top;
* tolerance samples: the histogram of the transmitted peaks; with other axes
  varied too, one panel per combination of them, the chains (``chain.case``)
  overlaid in each panel so that designs compare side by side.
"""

from __future__ import annotations

import copy
from collections import defaultdict
from typing import TYPE_CHECKING

import numpy as np

from ..core.errors import ParameterError
from ..scenes.load import parse_scene
from ..scenes.run import nominal_peak
from ..scenes.schema import Scene
from ..studies.store import Store
from ..studies.summary import Group, check_metric, peak_groups
from .figures import delta_data, delta_figure, design_grid
from .plots import histogram
from .scenes import peak_label

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

#: Parameters that name the design: drawn as colours within a panel rather than as panels of their own.
_HUE_KEYS = ("chain.case", "case")

__all__ = ["study_figure", "samples_figure"]


_AXIS = {"peak": "transmitted peak, max I_N/I_1(0)", "energy": "energy fraction at the peak, peak² L_N/L_1",
         "loss": "energy lost, 1 - peak² L_N/L_1 (log scale)",
         "omega": "max |ω_n - theory| / theory", "P": "max |P_n - theory|",
         "spacing": "spacing spread (max - min) / mean of δω_n"}
#: What a group's values are, in a title.
_WHAT = {"peak": "transmitted peak", "energy": "energy fraction", "loss": "energy lost", "omega": "ω error",
         "P": "P error", "spacing": "spacing spread"}


def study_figure(store: Store, metric: str = "peak", ax: Axes | None = None) -> Figure:
    """The figure a study's results call for (see the module docstring); ``metric`` for the samples.  With
    ``ax``, a one-panel figure (one group's histogram, or Fig. delta) is drawn into it; several groups' panels
    are a figure of their own."""
    runs = [run for run in store.runs() if run.status == "ok" and run.metrics and not run.member]
    if not runs or not any(run.judged for run in runs):  # none finished, or none compared with a theory
        check_metric(metric, store.runs(), "metric")  # says which: no run finished, or a study of netlists
        raise ParameterError("metric", metric, "a metric of runs compared with a theory, to draw (a .meas's "
                             "distribution is `lcchain results STORE --summary --metric NAME`)")
    if any("sample" in run.params for run in runs):
        groups = [group for group in peak_groups(store.runs(), metric) if group.peaks.size]
        if not groups:
            raise ParameterError("--metric", metric, "peak (no run of this store has an energy: none was kicked)")
        what = _WHAT[metric]
        scenes = [_group_scene(store, group) for group in groups]
        kinds = {scene.excitation.kind for scene in scenes if scene is not None}
        xlabel = peak_label(kinds.pop()) if metric == "peak" and len(kinds) == 1 else _AXIS[metric]
        nominal = [_nominal(scene, metric) for scene in scenes]
        if len(groups) == 1:
            return histogram(groups[0].peaks, xlabel=xlabel, theory=nominal[0], ax=ax,
                             title=f"{what} over {groups[0].peaks.size} samples ({store.path.name})")
        return samples_figure(groups, title=f"{what} by group ({store.path.name})", xlabel=xlabel,
                              log=metric == "loss", nominal=nominal)
    Ns = sorted({run.params["N"] for run in runs if "N" in run.params})
    if len(Ns) >= 2 and all("case" in run.params and not run.spectral for run in runs):  # Fig. delta: transients
        measured: dict[str, list[tuple[int, float]]] = defaultdict(list)
        for run in runs:
            arrivals = (run.metrics or {}).get("arrivals") or []
            if arrivals:
                measured[run.params["case"]].append((run.params["N"], 1.0 - arrivals[0]["peak_sim"]))
        grid = sorted(set(design_grid(max(Ns))) | set(Ns))
        return delta_figure(delta_data(grid), measured, title=f"δ* against N: theory and ngspice ({store.path.name})",
                            ax=ax)
    raise ParameterError("--plot", str(store.path), "a sweep of transients over two or more N (with --case), or "
                         "tolerance samples (an AC sweep over N: --summary --metric omega, P or spacing)")


def _group_scene(store: Store, group: Group) -> Scene | None:
    """The scene a group of a scene sweep ran (its varied keys set), or None for a store without one."""
    data = store.description().get("scene_data")
    if not isinstance(data, dict):
        return None
    data = copy.deepcopy(data)
    for key, value in group.params.items():
        for dotted in key.split("+"):  # keys joined by + were varied together
            *tables, name = dotted.split(".")
            table = data
            for part in tables:
                table = table.setdefault(part, {})
            table[name] = value
    try:
        return parse_scene(data)
    except ParameterError:
        return None


def _nominal(scene: Scene | None, metric: str) -> float | None:
    """The untoleranced circuit's value of the metric, from theory (None without a scene, or for an energy a
    pulse does not define)."""
    if scene is None or metric not in ("peak", "energy", "loss") or (metric != "peak"
                                                                     and scene.excitation.kind != "kick"):
        return None  # an AC run's metrics are errors against theory: no nominal value to draw
    peak, mass_ratio = nominal_peak(scene)
    energy = peak ** 2 * mass_ratio
    return {"peak": peak, "energy": energy, "loss": 1.0 - energy}[metric]


def _label(key: str, value: object) -> str:
    name = "+".join(part.rsplit(".", 1)[-1] for part in key.split("+"))
    if isinstance(value, float) and name in ("L", "C", "L+C"):
        return f"{name} ±{100 * value:g} %"
    return f"{name} = {value}" if name not in ("case", "series") else str(value)


def samples_figure(groups: list[Group], title: str = "", xlabel: str = _AXIS["peak"], log: bool = False,
                   nominal: list[float | None] | None = None) -> Figure:
    """One panel per combination of the varied axes but the design; the designs' histograms overlaid.

    Rows follow the first varied axis (chain.N in a study of sizes), columns the others.  Each histogram's
    legend gives the design, its mean ± standard deviation and its worst sample, so the figure reads alone;
    ``nominal`` (one per group, None where unknown) is drawn as a dashed line in the design's colour.
    """
    nominal = list(nominal) if nominal is not None else [None] * len(groups)
    from matplotlib.figure import Figure

    keys = list(dict.fromkeys(key for group in groups for key in group.params))
    varied = [key for key in keys if len({repr(group.params.get(key)) for group in groups}) > 1]
    hue = next((key for key in _HUE_KEYS if key in varied), None)
    panel_keys = [key for key in varied if key != hue]
    row_key = panel_keys[0] if len(panel_keys) >= 2 else None
    column_keys = panel_keys[1:] if row_key else panel_keys

    def values_of(key_list: list[str], group: Group) -> tuple[str, ...]:
        return tuple(repr(group.params.get(key)) for key in key_list)

    rows = list(dict.fromkeys(values_of([row_key] if row_key else [], g) for g in groups))
    columns = list(dict.fromkeys(values_of(column_keys, g) for g in groups))
    hues = list(dict.fromkeys(repr(g.params.get(hue)) for g in groups)) if hue else ["None"]
    figure = Figure(figsize=(3.2 * len(columns) + 0.6, 2.6 * len(rows) + 0.8), layout="constrained")
    every = np.concatenate([g.peaks for g in groups])
    span = (float(np.maximum(every, 1e-16).min()) / 1.5, float(every.max()) * 1.5)  # one log axis for all panels
    axes = figure.subplots(len(rows), len(columns), squeeze=False)
    for r, row in enumerate(rows):
        for c, column in enumerate(columns):
            ax = axes[r][c]
            members = [g for g in groups if values_of([row_key] if row_key else [], g) == row
                       and values_of(column_keys, g) == column]
            if not members:
                ax.set_visible(False)
                continue
            for g in members:  # each its own bins: designs far apart would otherwise get one bin each
                count = min(30, max(6, int(np.sqrt(g.peaks.size))))
                if log:
                    positive = np.maximum(g.peaks, 1e-16)
                    bins = np.exp(np.histogram_bin_edges(np.log(positive), bins=count))
                else:
                    bins = np.histogram_bin_edges(g.peaks, bins=count)
                colour = f"C{hues.index(repr(g.params.get(hue))) if hue else 0}"
                stats = g.stats()
                name = str(g.params.get(hue)) if hue else "samples"
                worst = stats["max"] if log else stats["min"]  # a loss is worst at its largest
                ax.hist(g.peaks, bins=bins, color=colour, alpha=0.55, edgecolor="white", linewidth=0.4,
                        label=f"{name}: {stats['mean']:.4g}"
                        + (f" ± {stats['std']:.2g}" if stats["std"] is not None else " (one sample)")
                        + f", worst {worst:.4g}")
                ax.axvline(stats["mean"], color=colour, linewidth=1.0)
                value = nominal[next(i for i, other in enumerate(groups) if other is g)]
                if value is not None and log and value < span[0]:  # a perfect cradle's nominal loss: 0 or ~1e-16
                    ax.plot([], [], color=colour, linestyle="--", linewidth=1.0,
                            label=f"nominal {value:.2g} (left of the axis)")
                elif value is not None:
                    ax.axvline(value, color=colour, linestyle="--", linewidth=1.0, label=f"nominal {value:.4g}")
            if log:
                from matplotlib.ticker import NullFormatter

                ax.set_xscale("log")
                ax.set_xlim(*span)
                ax.xaxis.set_minor_formatter(NullFormatter())
            bottom, top = ax.get_ylim()
            ax.set_ylim(bottom, top * (1.0 + 0.14 * len(members) * 2))  # the legend's lines above the tallest bar
            ax.legend(fontsize=6.5, loc="upper left", frameon=False)
            parts = [_label(k, members[0].params.get(k)) for k in ([row_key] if row_key else []) + column_keys]
            ax.set_title(", ".join(parts), fontsize=8.5)
            ax.tick_params(labelsize=7)
            if r == len(rows) - 1:
                ax.set_xlabel(xlabel, fontsize=8)
            if c == 0:
                ax.set_ylabel("samples", fontsize=8)
    if title:
        from .plots import set_title

        set_title(figure, title, 10)
    return figure
