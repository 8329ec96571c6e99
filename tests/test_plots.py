"""Tests of lcchain.plots: files are written, axes are honoured, bad shapes are refused.

The data are synthetic (no ngspice): the figures' content is checked by eye
in the examples; here only behaviour is asserted.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from helpers.figures import assert_legends_off_lines, drawn, legend_boxes
from helpers.tolerances import ATOL_MARKER_POSITION

from lcchain import plots

REPO = Path(__file__).resolve().parents[1]
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
#: A blank 8 x 5 inch PNG at 150 dpi is a few kB; a drawn figure is well above.
MIN_PNG_BYTES = 10_000


def assert_png(path: Path) -> None:
    assert path.is_file()
    data = path.read_bytes()
    assert data[:8] == PNG_SIGNATURE
    assert len(data) > MIN_PNG_BYTES


def new_axes():
    from matplotlib.figure import Figure

    fig = Figure()
    return fig, fig.add_subplot()


@pytest.fixture
def wave():
    t_theory = np.linspace(0.0, 60.0, 1201)
    y_theory = np.exp(-((t_theory - 30.0) / 3.0) ** 2) * np.cos(t_theory)
    t_sim = np.linspace(0.0, 60.0, 301)
    y_sim = np.interp(t_sim, t_theory, y_theory) + 1e-4 * np.sin(7 * t_sim)
    residual = y_sim - np.interp(t_sim, t_theory, y_theory)
    arrivals = [{"index": 1, "t_theory": 30.0, "t_sim": 30.02, "peak_theory": 1.0, "peak_sim": 0.9998}]
    return t_sim, y_sim, t_theory, y_theory, residual, arrivals


RECORDS = [
    {"method": m, "N": n, "wall_s": w * n / 10, "error": e / w}
    for m, e in (("trap", 1e-3), ("gear", 3e-3)) for n in (10, 100) for w in (0.1, 0.3, 1.0)
]


# --------------------------------------------------------------------------- files

def test_overlay_writes_png_with_residual_panel(tmp_path, wave):
    t_sim, y_sim, t_th, y_th, res, arr = wave
    fig = plots.overlay(plots.OverlayCurves(t_sim, y_sim, t_th, y_th, residual=res, arrivals=arr), title="N = 10", path=tmp_path / "overlay.png")
    assert_png(tmp_path / "overlay.png")
    assert len(fig.axes) == 2
    assert fig.get_suptitle() == "N = 10"
    legend = [text.get_text() for text in fig.legends[0].get_texts()]
    assert any(f"{np.max(np.abs(res)):.2e}" in text for text in legend)


def test_overlay_without_residual_has_one_panel(wave):
    t_sim, y_sim, t_th, y_th, _, _ = wave
    assert len(plots.overlay(plots.OverlayCurves(t_sim, y_sim, t_th, y_th)).axes) == 1


def test_overlay_accepts_objects_with_arrival_attributes(wave):
    from lcchain.compare.metrics import ArrivalComparison

    t_sim, y_sim, t_th, y_th, _, _ = wave
    arr = ArrivalComparison(index=1, end="last", t_theory=30.0, t_sim=30.0, peak_theory=1.0, peak_sim=1.0)
    plots.overlay(plots.OverlayCurves(t_sim, y_sim, t_th, y_th, arrivals=[arr]))


def test_spacetime_writes_png(tmp_path):
    t = np.linspace(0.0, 40.0, 400)
    i = np.arange(1, 21)[:, None]
    currents = np.exp(-((t - 2.0 * i) / 1.5) ** 2)
    plots.spacetime(t, currents, title="pulse", path=tmp_path / "st.png")
    assert_png(tmp_path / "st.png")


def test_histogram_writes_png(tmp_path):
    values = np.random.default_rng(1).normal(0.9, 0.01, 500)
    plots.histogram(values, theory=0.92, path=tmp_path / "hist.png")
    assert_png(tmp_path / "hist.png")


def test_pareto_writes_png(tmp_path):
    fig = plots.pareto(RECORDS, path=tmp_path / "pareto.png")
    assert_png(tmp_path / "pareto.png")
    ax = fig.axes[0]
    assert ax.get_xscale() == ax.get_yscale() == "log"
    assert len(ax.get_lines()) == 4  # (trap, gear) x (10, 100)


def test_mode_density_writes_png(tmp_path):
    n = np.arange(1, 31)
    omega = 2 * np.sin(n * np.pi / 62)
    density = np.exp(-n / 5.0)
    fig = plots.mode_density(omega, density / density.sum(), path=tmp_path / "md.png")
    assert_png(tmp_path / "md.png")
    assert len(fig.axes) == 2  # P_n and the twin spacing axis


# --------------------------------------------------------------------------- ax=

def test_functions_draw_into_given_axes(wave):
    t_sim, y_sim, t_th, y_th, res, arr = wave
    calls = [
        lambda ax: plots.overlay(plots.OverlayCurves(t_sim, y_sim, t_th, y_th, residual=res, arrivals=arr), ax=ax),
        lambda ax: plots.spacetime(t_sim, np.vstack([y_sim, y_sim]), ax=ax),
        lambda ax: plots.histogram(y_sim, ax=ax),
        lambda ax: plots.pareto(RECORDS, ax=ax),
        lambda ax: plots.mode_density(t_sim, y_sim, ax=ax),
    ]
    for call in calls:
        fig, ax = new_axes()
        assert call(ax) is fig
        assert ax.has_data()
        # overlay adds no residual panel; only the colorbar or the twin axis may be added.
        assert len(fig.axes) <= 2


def test_overlay_into_axes_has_no_residual_panel(wave):
    t_sim, y_sim, t_th, y_th, res, _ = wave
    fig, ax = new_axes()
    plots.overlay(plots.OverlayCurves(t_sim, y_sim, t_th, y_th, residual=res), ax=ax)
    assert fig.axes == [ax]


def test_axes_in_subfigure_returns_root_figure(wave):
    from matplotlib.figure import Figure

    fig = Figure()
    ax = fig.subfigures(1, 2)[1].add_subplot()
    assert plots.histogram([1.0, 2.0, 2.5], ax=ax) is fig


# --------------------------------------------------------------------------- validation

@pytest.mark.parametrize("call", [
    lambda: plots.overlay(plots.OverlayCurves(np.arange(5.0), np.arange(4.0), np.arange(3.0), np.arange(3.0))),
    lambda: plots.overlay(plots.OverlayCurves(np.arange(5.0), np.arange(5.0), np.arange(3.0), np.arange(4.0))),
    lambda: plots.overlay(plots.OverlayCurves(np.arange(5.0), np.arange(5.0), np.arange(3.0), np.arange(3.0), residual=np.zeros(4))),
    lambda: plots.overlay(plots.OverlayCurves(np.arange(5.0), np.arange(5.0), np.arange(3.0), np.arange(3.0), residual=np.zeros(5), t_residual=np.arange(6.0))),
    lambda: plots.overlay(plots.OverlayCurves(np.arange(5.0), np.arange(5.0), np.arange(3.0), np.arange(3.0), arrivals=[{"index": 1, "t_theory": 1.0}])),
    lambda: plots.spacetime(np.arange(5.0), np.zeros((3, 4))),
    lambda: plots.spacetime(np.arange(5.0), np.zeros(5)),
    lambda: plots.histogram(np.zeros((2, 3))),
    lambda: plots.histogram([]),
    lambda: plots.histogram([1.0, np.nan]),
    lambda: plots.pareto([]),
    lambda: plots.pareto([{"method": "trap", "N": 10, "wall_s": 1.0}]),
    lambda: plots.pareto([{"method": "trap", "N": 10, "wall_s": 1.0, "error": 0.0}]),
    lambda: plots.mode_density(np.arange(5.0), np.arange(4.0)),
    lambda: plots.mode_density(np.zeros((2, 2)), np.zeros((2, 2))),
])
def test_bad_input_raises_value_error(call):
    with pytest.raises(ValueError):
        call()


def test_shape_error_names_the_argument():
    with pytest.raises(ValueError, match=r"y_sim\.shape = \(4,\).*t_sim, \(5,\)"):
        plots.overlay(plots.OverlayCurves(np.arange(5.0), np.arange(4.0), np.arange(3.0), np.arange(3.0)))


# --------------------------------------------------------------------------- decimation

def test_decimation_keeps_one_sample_spike_with_its_sign():
    t = np.linspace(0.0, 1.0, 100_003)  # not a multiple of the bin size: a short tail bin
    amplitude = 1e-3
    data = amplitude * np.sin(np.arange(3)[:, None] + 50 * t)
    data[1, 54_321] = -7.5
    data[2, -1] = 3.25  # in the tail bin
    t_bins, out = plots._decimate_max_abs(t, data, 2000)
    assert out.shape[0] == 3 and out.shape[1] <= 2000 and t_bins.shape == out.shape[1:]
    assert out[1].min() == -7.5
    assert out[2].max() == 3.25 and out[2, -1] == 3.25
    assert np.max(np.abs(out[0])) <= amplitude
    assert np.all(np.diff(t_bins) > 0) and t[0] <= t_bins[0] and t_bins[-1] <= t[-1]


def test_decimation_leaves_short_series_alone():
    t = np.arange(10.0)
    data = np.ones((2, 10))
    t_out, out = plots._decimate_max_abs(t, data, 10)
    np.testing.assert_array_equal(t_out, t)
    np.testing.assert_array_equal(out, data)


def test_spacetime_of_long_series_keeps_the_spike():
    t = np.linspace(0.0, 100.0, 50_000)
    currents = np.zeros((4, t.size))
    currents[2, 12_345] = 0.8
    fig = plots.spacetime(t, currents)
    mesh = fig.axes[0].collections[0]
    assert mesh.get_array().shape[-1] <= plots.SPACETIME_MAX_COLUMNS
    assert mesh.get_array().max() == 0.8
    assert mesh.norm.vmin == -0.8 and mesh.norm.vmax == 0.8


# --------------------------------------------------------------------------- imports

def _modules_after(code: str) -> str:
    env = dict(os.environ, PYTHONPATH=str(REPO))
    done = subprocess.run([sys.executable, "-c", code], cwd=REPO, env=env, capture_output=True,
                          text=True, timeout=60, check=True)
    return done.stdout.strip()


def test_import_lcchain_does_not_import_matplotlib():
    assert _modules_after("import lcchain, sys; print('matplotlib' in sys.modules)") == "False"


def test_plots_never_import_pyplot():
    code = ("import sys, lcchain.report.plots as p; a = 'matplotlib' in sys.modules; "
            "p.histogram([1.0, 2.0, 2.0, 3.0]); print(a, 'matplotlib' in sys.modules, "
            "'matplotlib.pyplot' in sys.modules)")
    assert _modules_after(code) == "False True False"


# --------------------------------------------------------------------------- labels off the data (issue 22)

def _assert_notes_inside(fig):
    renderer = drawn(fig)
    for ax in fig.axes:
        frame = ax.get_window_extent(renderer)
        for note in ax.texts:
            box = note.get_window_extent(renderer)
            assert frame.x0 <= box.x0 and box.x1 <= frame.x1 and frame.y0 <= box.y0 and box.y1 <= frame.y1, \
                (note.get_text(), box, frame)


def _cradle_arrivals(t_end):
    """Arrivals alternating ends, the last one near the right frame (where a note used to be cut)."""
    return [{"index": k, "end": "last" if k % 2 else "first", "t_theory": t, "t_sim": t + 0.01,
             "peak_theory": 0.9, "peak_sim": 0.9001} for k, t in enumerate((0.3 * t_end, 0.61 * t_end, 0.92 * t_end), 1)]


@pytest.fixture
def cradle():
    """Loop N peaks at the arrivals #1 and #3, loop 1 at t = 0 and #2; a tail after the last arrival."""
    t = np.linspace(0.0, 350.0, 3501)
    arrivals = _cradle_arrivals(350.0)
    bump = lambda t0: 0.9 * np.exp(-((t - t0) / 5.0) ** 2)  # noqa: E731
    last = bump(arrivals[0]["t_theory"]) + bump(arrivals[2]["t_theory"]) - 0.15 * np.exp(-((t - 340.0) / 8) ** 2)
    first = np.exp(-(t / 5.0) ** 2) + bump(arrivals[1]["t_theory"])
    return t, last, first, arrivals


def test_overlay_legend_is_off_the_lines(cradle):
    t, last, first, arrivals = cradle
    fig = plots.overlay(plots.OverlayCurves(t, last + 1e-4, t, last, residual=np.full_like(t, 1e-4), first_sim=first, first_theory=first, arrivals=arrivals), title="two-mass chain, N = 100")
    assert_legends_off_lines(fig)


def test_overlay_notes_stay_inside_the_frame(cradle):
    t, last, first, arrivals = cradle
    fig = plots.overlay(plots.OverlayCurves(t, last, t, last, residual=np.zeros_like(t), first_sim=first, first_theory=first, arrivals=arrivals))
    assert len(fig.axes[0].texts) == 3
    _assert_notes_inside(fig)
    fig.set_size_inches(5.6, 3.8)  # the report's thumbnails
    _assert_notes_inside(fig)


def _markers_at(ax, t, peak):
    return [line for line in ax.get_lines() if line.get_marker() in ("+", "x")
            and np.allclose(line.get_xydata(), [[t, peak]], atol=ATOL_MARKER_POSITION)]


def test_overlay_marks_every_arrival_on_its_own_loop(cradle):
    t, last, first, arrivals = cradle
    fig = plots.overlay(plots.OverlayCurves(t, last, t, last, residual=np.zeros_like(t), first_sim=first, first_theory=first, arrivals=arrivals))
    top = fig.axes[0]
    colours = {line.get_label(): line.get_color() for line in top.get_lines()}
    for a in arrivals:
        theory, sim = _markers_at(top, a["t_theory"], a["peak_theory"]), _markers_at(top, a["t_sim"], a["peak_sim"])
        assert {line.get_marker() for line in theory + sim} == {"+", "x"}, a
        loop = "1" if a["end"] == "first" else "N"
        assert {line.get_color() for line in theory if line.get_marker() == "+"} == {colours[f"theory at loop {loop}"]}
        assert any(f"#{a['index']}" in note.get_text() for note in top.texts)
    assert any("#2 at loop 1" in note.get_text() for note in top.texts)


def test_overlay_wants_both_loop_1_signals(cradle):
    t, last, first, _ = cradle
    with pytest.raises(ValueError, match="first_sim"):
        plots.overlay(plots.OverlayCurves(t, last, t, last, first_sim=first))


def test_histogram_draws_the_nominal_line_and_keeps_its_legend_off_the_bars():
    values = np.random.default_rng(2).normal(0.73, 0.01, 30)
    fig = plots.histogram(values, theory=0.7336)
    ax = fig.axes[0]
    nominal = [line for line in ax.get_lines() if np.allclose(line.get_xdata(), 0.7336)]
    assert len(nominal) == 1 and nominal[0].get_label() == "nominal 0.7336"
    assert "nominal 0.7336" in [text.get_text() for text in ax.get_legend().get_texts()]
    assert_legends_off_lines(fig)
    box = legend_boxes(fig)[0]
    for bar in ax.patches:
        assert not box.overlaps(bar.get_window_extent(drawn(fig)))


@pytest.mark.ngspice
def test_study_histogram_of_a_pulse_has_the_nominal_line_and_a_pulse_label(tmp_path, monkeypatch):
    from lcchain.cli import main
    from lcchain.report.studies import study_figure
    from lcchain.studies.store import Store

    monkeypatch.chdir(tmp_path)
    assert main(["examples", "bench"]) == 0
    assert main(["sweep", "bench.toml", "--samples", "3", "--store", "mc.sqlite"]) == 0
    with Store("mc.sqlite", "read") as store:
        fig = study_figure(store)
    ax = fig.axes[0]
    assert "pulse source" in ax.get_xlabel() and "I_1(0)" not in ax.get_xlabel()
    nominal = [line for line in ax.get_lines() if line.get_label().startswith("nominal ")]
    assert len(nominal) == 1 and 0.5 < nominal[0].get_xdata()[0] < 1.0


def test_study_histograms_keep_their_legends_above_the_bars_and_a_zero_nominal_off_a_log_axis():
    """A real-parts study drawn on a log axis: the perfect cradle's nominal loss is 0 (its line would sit at the
    axis' far left), said in the legend; the legends' lines sit above the tallest bar of every panel."""
    from lcchain.report.studies import samples_figure
    from lcchain.studies.summary import Group

    rng = np.random.default_rng(5)
    groups = [Group({"case": case, "N": N}, np.abs(rng.normal(centre, centre / 4, 200)), 0)
              for N in (50, 200) for case, centre in (("perfect", 2e-4), ("two-mass", 0.031))]
    fig = samples_figure(groups, log=True, nominal=[0.0, 0.0312, 1e-17, 0.0297])
    renderer = drawn(fig)
    for ax in fig.axes:
        texts = [text.get_text() for text in ax.get_legend().get_texts()]
        assert any(text.startswith("nominal 0 (left of the axis)") or "1e-17 (left" in text for text in texts)
        assert not any("0.0000" in text for text in texts)
        box = ax.get_legend().get_window_extent(renderer)
        for bar in ax.patches:
            assert not box.overlaps(bar.get_window_extent(renderer)), texts
