"""Results as a scientist meets them in a notebook (issue 33): a short repr, a small escaped HTML table and a
``.plot()`` that returns a Figure; and the spectrum's public function, whose arrays have one entry per mode."""

import subprocess
import sys
import tomllib
from pathlib import Path

import matplotlib
import numpy as np
import pytest
from helpers.tolerances import RTOL_ONE_OPERATION

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

    report = lcchain.simulate_chain(lcchain.chain_for_case("two-mass", 10), lcchain.ChainOptions(dt=0.05))
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
    code = ("import sys, lcchain; r = lcchain.simulate_chain(lcchain.chain_for_case('two-mass', 5), lcchain.ChainOptions(dt=0.1)); "
            "repr(r); r._repr_html_(); print('matplotlib' in sys.modules); "
            "r.plot(); print('matplotlib' in sys.modules)")
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.split() == ["False", "True"]


#: The issue's bound on a result's repr.
MAX_REPR_BYTES = 2048


def _every_result(tmp_path: Path) -> dict[str, object]:
    """One of every public result type, small."""
    from lcchain.cli import main
    from lcchain.studies.store import Store

    report = lcchain.simulate_chain(lcchain.chain_for_case("two-mass", 8), lcchain.ChainOptions(dt=0.1))
    data = tomllib.loads(example_text("cradle"))
    data["chain"]["N"] = 8
    data.pop("output", None)
    store = tmp_path / "s.sqlite"
    assert main(["sweep", "--case", "two-mass", "--N", "8,10", "--dt", "0.1", "--store", str(store),
                 "--executor", "serial", "--json"]) == 0
    return {"SimulationReport": report, "RunRecord": report.record,
            "SpectrumReport": lcchain.spectrum(lcchain.Request(lcchain.chain_for_case("two-mass", 8), lcchain.AC())),
            "SceneResult": simulate_scene(parse_scene(data)),
            "Modes": lcchain.normal_modes(lcchain.chain_for_case("perfect", 300)),
            "Store": Store(store, "read")}


@pytest.mark.ngspice
def test_every_public_result_shows_itself_plots_into_an_axes_and_becomes_a_dataset(tmp_path, capsys):
    """A notebook user's four expectations of every result type: a repr under 2 kB, a small HTML table, a figure
    drawn into the Axes given, and an xarray Dataset whose variables carry their units."""
    import matplotlib.pyplot as plt
    import xarray

    results = _every_result(tmp_path)
    capsys.readouterr()
    for name, result in results.items():
        text = repr(result)
        assert len(text.encode()) < MAX_REPR_BYTES and text.startswith(name), (name, len(text))
        table = result._repr_html_()
        assert table.startswith("<table>") and len(table) < 4 * MAX_REPR_BYTES, name
        figure, ax = plt.subplots()
        assert result.plot(ax=ax) is figure, name
        assert ax.has_data(), name
        plt.close(figure)
        dataset = result.to_xarray()
        assert isinstance(dataset, xarray.Dataset) and dataset.data_vars, name
        numeric = [v for v in dataset.data_vars.values() if v.dtype.kind == "f"]
        assert numeric and all("units" in v.attrs for v in numeric), name
    store = results["Store"]
    store.close()
    assert "closed" in repr(store) and len(repr(store)) < MAX_REPR_BYTES  # a closed store still shows itself


@pytest.mark.ngspice
def test_a_runs_dataset_holds_its_vectors_in_their_own_units(tmp_path):
    """RunRecord.to_xarray: ngspice's saved currents in amperes on time in seconds, the same numbers as the
    record's arrays; SimulationReport.to_xarray: the end loops on time in seconds = t sqrt(L0 C0)."""
    report = lcchain.simulate_chain(lcchain.chain_for_case("two-mass", 8), lcchain.ChainOptions(dt=0.1, L0=2e-6, C0=5e-9))
    record = report.record.to_xarray()
    result = report.record.run
    assert record["time"].attrs["units"] == "s"
    np.testing.assert_array_equal(record["time"].values, result.time)
    for vector, values in result.vectors.items():
        name = vector.replace("(", "_").rstrip(")")
        assert record[name].attrs["units"] == "A"
        np.testing.assert_array_equal(record[name].values, values)
    simulated = report.to_xarray()
    tau = (2e-6 * 5e-9) ** 0.5
    np.testing.assert_allclose(simulated["time"].values, report.waveforms.t * tau, rtol=RTOL_ONE_OPERATION)
    np.testing.assert_array_equal(simulated["last"].values, report.waveforms.last)
    assert simulated.attrs["N"] == 8 and simulated.attrs["case"] == "two-mass"
