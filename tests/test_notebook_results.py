"""Results as a scientist meets them in a notebook (issue 33): a short repr, a small escaped HTML table and a
``.plot()`` that returns a Figure; and the spectrum's public function, whose arrays have one entry per mode."""

import subprocess
import sys
import tomllib
from pathlib import Path

import matplotlib
import numpy as np
import pytest

import lcchain
from lcchain.scenes.bundled import example_text
from lcchain.scenes.load import parse_scene
from lcchain.scenes.run import simulate_scene

matplotlib.use("Agg")

ROOT = Path(__file__).resolve().parent.parent
#: A short repr: a few lines a person reads, not the arrays (a report's dataclass repr ran to 169,415 characters).
MAX_REPR_LINES, MAX_REPR_CHARS = 10, 800


def _short(text: str) -> None:
    assert len(text.splitlines()) <= MAX_REPR_LINES and len(text) <= MAX_REPR_CHARS, text


@pytest.mark.ngspice
def test_a_simulation_shows_itself_in_a_few_lines_and_plots(tmp_path):
    import matplotlib.pyplot as plt
    from matplotlib.figure import Figure

    report = lcchain.simulate(lcchain.chain_for_case("two-mass", 10), dt=0.05)
    text = repr(report)
    _short(text)
    assert "two-mass, N = 10" in text and "ngspice" in text and "max |simulation - theory|" in text
    assert "predicted error" in text
    table = report._repr_html_()
    assert table.startswith("<table>") and "two-mass, N = 10" in table
    figure = report.plot()
    assert isinstance(figure, Figure) and len(figure.axes) == 2  # overlay, residual below
    figure.savefig(tmp_path / "overlay.png")
    plt.close(figure)


@pytest.mark.ngspice
def test_a_scene_result_escapes_its_title_in_html():
    from matplotlib.figure import Figure

    data = tomllib.loads(example_text("cradle"))
    data["chain"]["N"] = 10
    data["title"] = "a <b>bold</b> & odd title"
    data.pop("output", None)
    result = simulate_scene(parse_scene(data))
    _short(repr(result))
    table = result._repr_html_()
    assert "<b>" not in table and "&lt;b&gt;bold&lt;/b&gt; &amp; odd title" in table
    assert isinstance(result.plot(), Figure)


@pytest.mark.ngspice
def test_the_spectrum_is_its_own_public_function_with_one_entry_per_mode():
    from matplotlib.figure import Figure

    request = lcchain.Request(lcchain.chain_for_case("perfect", 40), lcchain.AC())
    with pytest.raises(lcchain.ParameterError, match=r"lcchain\.spectrum\(request\)") as caught:
        lcchain.simulate(request)
    assert "\n" not in str(caught.value)
    report = lcchain.spectrum(request)
    assert isinstance(report, lcchain.SpectrumReport)
    N = 40
    for name in ("omega", "P", "gamma", "Q", "poles", "omega_theory", "P_theory", "Q_theory", "poles_theory",
                 "seen", "resolved"):
        assert np.shape(getattr(report, name)) == (N,), name
    # a perfect cradle's weakest end weights (2^-(2N-3)) are below what the samples resolve: unseen, NaN
    assert 0 < report.seen.sum() < N
    assert np.isnan(report.omega[~report.seen]).all() and np.isnan(report.P[~report.seen]).all()
    assert np.isfinite(report.omega[report.seen]).all()
    assert report.to_dict()["seen"] == int(report.seen.sum())
    text = repr(report)
    _short(text)
    assert f"{int(report.seen.sum())} of {N}" in text
    assert isinstance(report.plot(), Figure)
    with pytest.raises(lcchain.ParameterError, match="AC"):
        lcchain.spectrum(lcchain.Request(lcchain.chain_for_case("perfect", 10), lcchain.Transient(dt=0.1)))


@pytest.mark.ngspice
def test_repr_loads_no_matplotlib_and_plot_does(tmp_path):
    code = ("import sys, lcchain; r = lcchain.simulate(lcchain.chain_for_case('two-mass', 5), dt=0.1); "
            "repr(r); r._repr_html_(); print('matplotlib' in sys.modules); "
            "r.plot(); print('matplotlib' in sys.modules)")
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.split() == ["False", "True"]
