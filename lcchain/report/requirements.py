"""How good must the parts be (issue 30, item 4): the requirements chart (``lcchain requirements --plot``) and the
validation report's section of the same name.

The chart: the first arrival's energy loss against each real part's parameter, exact curves with ngspice's points
on them and the 1 % and 0.1 % limits marked.  The section: for each of the report's cradles
(:func:`lcchain.studies.requirements.requirements_jobs`, run in the report's pool), the chart and a table of the
largest value of each parameter that keeps the loss under each target, in bulk units and in physical units for
the report's L0 and C0, and ngspice's points beside the exact losses.  This module draws and writes what the study
computed.
"""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING

import numpy as np

from ..circuit.requirements import LOSS_TARGETS, Requirement, si
from ..studies.requirements import ATOL_LOSS, CHECK_DT, RTOL_LOSS, CheckPoint, RequirementsCheck, point_agrees
from .markup import esc, figure_block, num, verdict_cell
from .plots import _finish, _new_figure, set_title

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

__all__ = ["requirements_chart", "requirements_figure", "requirements_figures", "requirements_html",
           "requirements_summary", "bulk_limit"]


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
    from matplotlib.ticker import NullLocator

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
        # no minor ticks: over the 6 to 12 decades of each axis they were most of the chart's drawing time (1.2 of
        # 1.6 s for five panels), and the decades' grid reads as well
        ax.xaxis.set_minor_locator(NullLocator())
        ax.yaxis.set_minor_locator(NullLocator())
        _few_decades(ax)
        ax.grid(alpha=0.3, linewidth=0.5)
        ax.legend(loc="upper left", fontsize="x-small")
    for ax in axes[len(curves):]:
        ax.set_visible(False)
    if title:
        set_title(fig, title)
    return _finish(fig, path)


#: A log axis spanning fewer decades than this gets ticks between its powers of ten: a range of 3 to 4 had none.
_FEW_DECADES = 2.0


def _few_decades(ax: Axes) -> None:
    """Ticks at 1, 2, 5 (under a decade: 1 to 9) times the powers of ten, each labelled, on a log axis of few
    decades; the decades alone otherwise."""
    from matplotlib.ticker import LogFormatterSciNotation, LogLocator

    for axis, limits in ((ax.xaxis, ax.get_xlim()), (ax.yaxis, ax.get_ylim())):
        low, high = sorted(limits)
        if not (low > 0 and np.isfinite(high)):
            continue
        decades = float(np.log10(high / low))
        if decades < _FEW_DECADES:
            subs = (1.0, 2.0, 5.0) if decades >= 1.0 else tuple(float(k) for k in range(1, 10))
            axis.set_major_locator(LogLocator(subs=subs))
            axis.set_major_formatter(LogFormatterSciNotation(labelOnlyBase=False))


def _label(requirement: Requirement) -> str:
    return f"{requirement.part.key} {requirement.part.symbol}"


def requirements_figure(requirements: Sequence[Requirement], points: Sequence[CheckPoint] = (), *, title: str = "",
                        path: str | os.PathLike[str] | None = None) -> Figure:
    """:func:`requirements_chart` of the study's results: each requirement's curve and limits, and the ngspice
    points of its part."""
    curves = [(_label(r), r.values, r.losses, r.limits) for r in requirements]
    label = {r.part.key: _label(r) for r in requirements}
    marks = [(label[point.part], point.value, point.loss) for point in points if point.part in label]
    return requirements_chart(curves, marks, targets=LOSS_TARGETS, title=title, path=path)


def requirements_figures(checks: Sequence[RequirementsCheck]) -> dict[str, Figure]:
    """Each cradle's chart (by its check's name); a cradle whose study failed has none."""
    return {check.name: requirements_figure(check.requirements, check.points,
                                            title=f"{check.what}: the first arrival's energy loss against each part")
            for check in checks if check.requirements}


def requirements_summary(checks: Sequence[RequirementsCheck]) -> tuple[int, int]:
    """How many of the cradles' ngspice points agree with the exact curves, of how many."""
    points = [point for check in checks for point in check.points]
    return sum(point_agrees(point) for point in points), len(points)


def bulk_limit(requirement: Requirement, index: int) -> str:
    """Requirement ``index`` (of :data:`LOSS_TARGETS`) in bulk units: ``r < 0.039``, ``none up to k = 0.96``,
    ``not met at R = 1e-06``."""
    part, limit = requirement.part, requirement.limits[index]
    if limit is None:
        return f"none up to {part.symbol} = {requirement.values[-1]:.3g}"
    if limit == 0.0:
        return f"not met at {part.symbol} = {requirement.values[0]:.3g}"
    return f"{part.symbol} < {limit:.3g}"


def _limits_table(check: RequirementsCheck) -> list[str]:
    ladder = check.ladder
    units = f"L0 = {si(ladder.L0, 'H')}, C0 = {si(ladder.C0, 'F')}"
    head = "".join(f"<th>bulk</th><th class=l>for {esc(units)}</th>" for _ in LOSS_TARGETS)
    lines = ["<table><thead><tr><th class=l rowspan=2>part</th><th class=l rowspan=2>parameter (bulk units)</th>"
             + "".join(f"<th colspan=2>loss &lt; {target:.1%}</th>" for target in LOSS_TARGETS) + "</tr>"
             f"<tr>{head}</tr></thead><tbody>"]
    for requirement in check.requirements:
        cells = "".join(f"<td>{esc(bulk_limit(requirement, k))}</td>"
                        f"<td class=l>{esc(requirement.statement(k, ladder))}</td>" for k in range(len(LOSS_TARGETS)))
        lines.append(f"<tr><td class=l>{esc(requirement.part.key)}</td><td class=l>{esc(requirement.part.what)}</td>"
                     f"{cells}</tr>")
    lines.append("</tbody></table>")
    return lines


def _points_table(check: RequirementsCheck) -> list[str]:
    lines = ["<table><thead><tr><th class=l>part</th><th>value</th><th>loss, ngspice</th><th>loss, theory</th>"
             "<th>|difference|</th><th>tolerance</th><th>verdict</th></tr></thead><tbody>"]
    for point in check.points:
        agrees = point_agrees(point)
        lines.append(f"<tr><td class=l>{esc(point.part)}</td><td>{num(point.value, 3)}</td>"
                     f"<td>{num(point.loss, 6)}</td><td>{num(point.theory, 6)}</td>"
                     f'<td class="{"" if agrees else "off"}">{num(abs(point.loss - point.theory), 2)}</td>'
                     f"<td>{num(ATOL_LOSS + RTOL_LOSS * abs(point.theory), 2)}</td><td>{verdict_cell(agrees)}</td>"
                     "</tr>")
    lines.append("</tbody></table>")
    return lines


def _summary_table(checks: Sequence[RequirementsCheck]) -> list[str]:
    lines = ["<table><thead><tr><th class=l>cradle</th><th>e<sub>ideal</sub></th><th>t (√(L0 C0))</th>"
             "<th>ngspice points agreeing</th><th>worst × tolerance</th><th>priced s</th><th>took s</th>"
             "<th>verdict</th></tr></thead><tbody>"]
    for check in checks:
        ideal = check.ideal
        agreeing = sum(point_agrees(point) for point in check.points)
        lines.append(f"<tr><td class=l><a href=\"#requirements-{esc(check.name)}\">{esc(check.what)}</a></td>"
                     f"<td>{num(ideal.energy if ideal else None, 6)}</td><td>{num(ideal.time if ideal else None)}</td>"
                     f"<td>{agreeing} / {len(check.points)}</td><td>{num(check.worst, 2)}</td>"
                     f"<td>{num(check.estimate_s, 2)}</td><td>{num(check.wall_s, 2)}</td>"
                     f"<td>{verdict_cell(check.passed, check.reason)}</td></tr>")
    lines.append("</tbody></table>")
    return lines


def requirements_html(checks: Sequence[RequirementsCheck], figures: Mapping[str, bytes]) -> str:
    """The section: what is computed, a summary of the cradles, then for each its limits table, its chart
    (``figures["requirements:<name>"]``, PNG) and ngspice's points."""
    if not checks:
        return "<p>No cradle's requirements were computed.</p>"
    targets = " and ".join(f"{target:.1%}" for target in LOSS_TARGETS)
    lines = ["<p>Each parasitic of a real coil or capacitor (its self-capacitance, its winding resistance, a "
             "capacitor's ESR and ESL, the coupling between neighbouring coils), swept alone over decades in the "
             "circuit's own exact theory (<code>lcchain requirements</code>): the loss is 1 − e/e<sub>ideal</sub>, "
             "e the first arrival's energy at the far end after a kick of loop 1 and e<sub>ideal</sub> the ideal "
             f"ladder's. The limit is the largest value keeping the loss under {targets}: the first crossing of "
             "the curve, refined by Brent's method. A few values of each curve are run in ngspice at a fixed step "
             f"of {CHECK_DT:g} √(L0 C0) and measured the same way; they agree when within {ATOL_LOSS:g} + "
             f"{RTOL_LOSS:.0%} of the exact loss.</p>", *_summary_table(checks)]
    for check in checks:
        lines.append(f'<h3 id="requirements-{esc(check.name)}">{esc(check.what)}</h3>')
        if not check.requirements:
            lines.append(f"<p>Not computed: {esc(check.reason)}</p>")
            continue
        lines += _limits_table(check)
        png = figures.get(f"requirements:{check.name}")
        if png is not None:
            lines.append(figure_block(png, f"requirements of the {check.what}", f"requirements-{check.name}-chart",
                                      f"{esc(check.what)}: |1 − e/e<sub>ideal</sub>| against each parameter, the "
                                      "circuit theory's curve, ngspice's points and the limits (dotted)",
                                      f"requirements-{esc(check.name)}"))
        lines += _points_table(check)
    return "\n".join(lines)

