"""Figures are readable: no overlapping tick labels, no text clipped by the figure (issue 33, item 6).

Checked on the drawn artists in display coordinates (``fig.canvas.draw()``), with typical data and with
awkward data: log axes spanning 3 to 4 (less than a decade), long titles."""

from __future__ import annotations

import numpy as np
import pytest
from helpers.figures import _drawn_tick_labels, assert_readable

from lcchain.report import plots
from lcchain.report.requirements import requirements_chart

LONG = ("Cradle of real parts, perfect against two-mass under E24 preferred values with one and five per cent "
        "tolerances, N = 200, every sample drawn from seed 2026 and simulated by ngspice")


def _wave(n: int = 400):
    t = np.linspace(0.0, 60.0, n)
    return t, np.sin(t) * np.exp(-((t - 40.0) / 5.0) ** 2)


@pytest.mark.parametrize(("title", "residual"), [("", False), ("two-mass chain, N = 20", True), (LONG, True)])
def test_overlay(title, residual):
    t, y = _wave()
    arrivals = [{"index": 1, "t_theory": 40.0, "t_sim": 40.01, "peak_theory": 0.99, "peak_sim": 0.98}]
    assert_readable(plots.overlay(plots.OverlayCurves(t, y, t, y, residual=(y * 1e-6) if residual else None, arrivals=arrivals, time_unit=1e-6), title=title))


@pytest.mark.parametrize("title", ["", LONG])
@pytest.mark.parametrize("weights", ["typical", "narrow", "deep"])
def test_spectrum(title, weights):
    N = 20
    omega = np.linspace(0.0, 2.0, N)
    P = {"typical": np.exp(-np.arange(N)) * (-1.0) ** np.arange(N),  # 8 decades
         "narrow": np.linspace(3.0, 4.0, N),  # a log axis inside one decade
         "deep": 2.0 ** -np.arange(0, 4 * N, 4)}[weights]
    circuit = np.where(np.arange(N) < N // 2, P, np.nan)
    fig = plots.spectrum(omega, P, omega, circuit, title=title, frequency_unit=1.6e5)
    assert_readable(fig)
    assert len(_drawn_tick_labels(fig.axes[0].yaxis)) >= 2  # |P_n|: read off its log axis


@pytest.mark.parametrize("title", ["", LONG])
@pytest.mark.parametrize("values", ["typical", "narrow"])
def test_histogram(title, values):
    rng = np.random.default_rng(3)
    data = rng.normal(0.97, 0.01, 300) if values == "typical" else 3.0 + rng.random(300)
    assert_readable(plots.histogram(data, theory=float(np.median(data)), title=title))


def test_study_histograms():
    from lcchain.report.studies import samples_figure
    from lcchain.studies.summary import Group

    rng = np.random.default_rng(5)
    groups = [Group({"case": case, "N": N}, np.abs(rng.normal(centre, centre / 4, 200)), 0)
              for N in (50, 200) for case, centre in (("perfect", 3.5), ("two-mass", 0.031))]
    assert_readable(samples_figure(groups, title=LONG, log=True, nominal=[0.0, 0.0312, 1e-17, 0.0297]))
    narrow = [Group({"case": "perfect", "N": N}, 3.0 + rng.random(200), 0) for N in (50, 200)]
    assert_readable(samples_figure(narrow, title=LONG, log=True, nominal=[3.5, 3.5]))


@pytest.mark.parametrize("title", ["", LONG])
@pytest.mark.parametrize("span", ["typical", "narrow"])
def test_requirements_chart(title, span):
    if span == "typical":
        x = np.logspace(-6, 2, 40)
        curves = [(name, x, 1e-3 * x, [10.0, 1.0]) for name in ("coil resistance R_L [ohm]", "ESR [ohm]", "ESL [H]")]
    else:
        x = np.linspace(3.0, 4.0, 20)
        curves = [(name, x, x, [None, None]) for name in ("coil resistance R_L [ohm]", "ESR [ohm]")]
    points = [(curves[0][0], float(x[3]), float(curves[0][2][3]))]
    fig = requirements_chart(curves, points, title=title)
    assert_readable(fig)
    for ax in fig.axes:  # a log axis of less than a decade still reads: two values at least on each
        if ax.get_visible():
            assert all(len(_drawn_tick_labels(axis)) >= 2 for axis in (ax.xaxis, ax.yaxis)), ax.get_xlabel()
