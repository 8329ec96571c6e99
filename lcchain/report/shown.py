"""A result's own figure, for ``result.plot()`` in a notebook: the registry ``lcchain.plots`` points here.

A :class:`~lcchain.runs.simulate.SimulationReport`, a :class:`~lcchain.runs.spectrum.SpectrumReport` and a
:class:`~lcchain.scenes.run.SceneResult` are data: they live below ``report/`` and never import it (matplotlib is
``report``'s alone).  Their ``plot()`` looks its drawing up by name in :data:`lcchain.core.show.PLOTS`, which
reads the ``lcchain.plots`` entry points (lcchain's own, in its ``pyproject.toml``, name these functions), as
pandas' ``DataFrame.plot`` finds its plotting backend: another package may draw them its own way.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import TYPE_CHECKING, Protocol

import numpy as np

from . import plots

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from ..circuit.ladder import Ladder
    from ..circuit.netlist import SimulationOptions
    from ..compare.metrics import Comparison
    from ..compare.waveforms import Signals, Waveforms
    from ..runs.spectrum import SpectrumReport
    from ..scenes.run import SceneResult
    from ..studies.store import Store
    from ..theory.chain import Chain
    from ..theory.modes import Modes

__all__ = ["simulation_figure", "spectrum_figure", "scene_figure", "record_figure", "store_figure", "modes_figure"]


class Simulated(Protocol):
    """What :func:`simulation_figure` reads of a :class:`~lcchain.runs.simulate.SimulationReport` (report renders
    it and never imports the modules that run a simulator, where it is defined)."""

    @property
    def waveforms(self) -> Waveforms: ...
    @property
    def comparison(self) -> Comparison: ...
    @property
    def ladder(self) -> Ladder: ...
    @property
    def chain(self) -> Chain: ...
    @property
    def options(self) -> SimulationOptions: ...
    @property
    def excitation(self) -> str: ...


def simulation_figure(report: Simulated, ax: Axes | None = None) -> Figure:
    """A :class:`~lcchain.runs.simulate.SimulationReport`'s end currents (or charges) over theory, the residual
    below (``lcchain simulate --plot``); with ``ax``, the far end's overlay in it alone."""
    w, c = report.waveforms, report.comparison
    curves = plots.OverlayCurves(w.t, w.last, w.t, c.theory_last,
                                 residual=None if ax is not None else w.last - c.theory_last, first_sim=w.first,
                                 first_theory=c.theory_first, arrivals=[a.to_dict() for a in c.arrivals],
                                 time_unit=report.ladder.time_unit)
    return plots.overlay(
        curves,
        title=f"{report.chain.name} chain, N = {report.chain.N}, dt = {report.options.dt:.4g}, {report.excitation}",
        ylabel=r"$I_1,\ I_N\;/\;I_1(0)$" if report.excitation == "kick" else r"$Q_1,\ Q_N\;/\;Q_1(0)$", ax=ax)


def spectrum_figure(report: SpectrumReport, ax: Axes | None = None) -> Figure:
    """A :class:`~lcchain.runs.spectrum.SpectrumReport`'s |P_n| against omega_n, the circuit's over theory, the
    spacing below (``lcchain spectrum --plot``); with ``ax``, the |P_n| panel alone in it.  A frequency axis in hertz
    on top."""
    return plots.spectrum(report.omega_theory, report.P_theory, report.omega, report.P,
                          title=f"{report.chain.name} chain, N = {report.chain.N}: {report.engine} AC against theory",
                          ax=ax, frequency_unit=1.0 / (2 * math.pi * report.time_unit))


def scene_figure(result: SceneResult, ax: Axes | None = None) -> Figure:
    """A :class:`~lcchain.scenes.run.SceneResult`'s first good sample's figure: a transient's end signals over
    theory (residual below), or an AC analysis's |P_n| against omega_n over theory."""
    from ..core.errors import SimulationError

    good = result.good()
    if not good:
        raise SimulationError(f"{result.scene.title}: no sample ran, so there is nothing to plot")
    s = good[0]
    title = f"{result.scene.title}, N = {s.chain.N}"
    if s.run.spectrum is not None:
        spectrum = s.run.spectrum
        return plots.spectrum(spectrum.omega_theory, spectrum.P_theory, spectrum.omega, spectrum.P, title=title)
    signals = s.run.signals
    assert signals is not None  # a sample that ran has one or the other
    displaced = result.scene.excitation.kind == "displacement"
    curves = plots.OverlayCurves(signals.t, signals.sim[-1], signals.t, signals.theory[-1],
                                 residual=None if ax is not None else signals.sim[-1] - signals.theory[-1],
                                 first_sim=signals.sim[0], first_theory=signals.theory[0],
                                 arrivals=s.record["arrivals"])
    return plots.overlay(curves, title=title, ylabel=r"$Q_1,\ Q_N\;/\;Q_1(0)$" if displaced else r"$I_1,\ I_N\;/\;I_0$",
                         ax=ax)


class _RunData(Protocol):
    @property
    def axis(self) -> np.ndarray: ...


class _Run(Protocol):
    """What :func:`record_figure` reads of a run's :class:`~lcchain.spice.result.RunResult`."""

    @property
    def analysis(self) -> str: ...
    @property
    def data(self) -> _RunData: ...
    @property
    def vectors(self) -> Mapping[str, np.ndarray]: ...


class Recorded(Protocol):
    """What :func:`record_figure` reads of a :class:`~lcchain.runs.execute.RunRecord` (report never imports the
    modules that run a simulator, where it and its run are defined)."""

    @property
    def ok(self) -> bool: ...
    @property
    def key(self) -> str: ...
    @property
    def status(self) -> str: ...
    @property
    def reason(self) -> str: ...
    @property
    def label(self) -> str: ...
    @property
    def engine(self) -> str: ...
    @property
    def engine_version(self) -> str: ...
    @property
    def signals(self) -> Signals | None: ...
    @property
    def run(self) -> _Run | None: ...


def record_figure(record: Recorded, ax: Axes | None = None) -> Figure:
    """A :class:`~lcchain.runs.execute.RunRecord`'s figure: its compared loops over theory (the far end, the first
    too; residual below) where it had a theory, else its saved vectors against time in seconds (an AC run's
    magnitudes against frequency in hertz, on log axes)."""
    from ..core.analyses import analysis_kind
    from ..core.errors import SimulationError
    from ..core.physical import vector_units

    if not record.ok:
        raise SimulationError(f"run {record.key[:12]} {record.status}: {record.reason}; there is nothing to plot")
    signals = record.signals
    if signals is not None:
        curves = plots.OverlayCurves(signals.t, signals.sim[-1], signals.t, signals.theory[-1],
                                     residual=None if ax is not None else signals.sim[-1] - signals.theory[-1],
                                     first_sim=signals.sim[0], first_theory=signals.theory[0])
        return plots.overlay(curves, title=f"{record.label or 'run'} ({record.engine} {record.engine_version})", ax=ax,
                             ylabel=r"$Q\,/\,Q_1(0)$" if signals.excitation == "displacement" else r"$I\,/\,I_1(0)$")
    fig = plots._new_figure() if ax is None else plots._root_figure(ax)
    if ax is None:
        ax = fig.subplots()
    run = record.run
    if run is None:
        raise SimulationError(f"run {record.key[:12]} saved no vectors: there is nothing to plot")
    kind = analysis_kind(run.analysis)
    x, vectors, xlabel = run.data.axis, run.vectors, f"{kind.axis} ({kind.axis_units})"
    for name, values in vectors.items():
        if kind.swept:  # complex phasors, for the sources' AC magnitudes (1 V in lcchain's own circuits)
            ax.loglog(x, np.abs(values), label=f"|{name}| ({vector_units(name)})")
        else:
            ax.plot(x, values, label=f"{name} ({vector_units(name)})")
    ax.set_xlabel(xlabel)
    if len(vectors) <= 8:
        ax.legend(fontsize=8)
    plots.set_title(ax, f"{record.label or 'run'} ({record.engine} {record.engine_version})")
    return fig


def store_figure(store: Store, ax: Axes | None = None, metric: str = "peak") -> Figure:
    """A :class:`~lcchain.studies.store.Store`'s figure: the one its results call for
    (:func:`lcchain.report.studies.study_figure`)."""
    from .studies import study_figure

    return study_figure(store, metric, ax=ax)


def modes_figure(modes: Modes, ax: Axes | None = None) -> Figure:
    """A :class:`~lcchain.theory.modes.Modes`' density P_n against omega_n, the spacing on a twin axis."""
    return plots.mode_density(modes.omega, modes.density, ax=ax)
