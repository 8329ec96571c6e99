"""Conventions a user expects of a command line (issue 33): ``-`` is stdout, a missing optional extra has an
the usage status (2, naming the extra; not ngspice's 3), and ``lcchain doctor`` never asks to install what it found."""

import json
import os
import pickle
import subprocess
import sys
from pathlib import Path

import pytest

from lcchain.cli import main
from lcchain.core.errors import ExtraMissingError

ROOT = Path(__file__).resolve().parent.parent


def _without(modules: list[str], argv: list[str], cwd: Path) -> subprocess.CompletedProcess[str]:
    """``lcchain argv`` in a fresh interpreter where ``modules`` cannot be imported, as on a machine without them
    (``sys.modules[name] = None`` makes ``import name`` raise ImportError)."""
    code = (f"import sys; sys.modules.update(dict.fromkeys({modules!r})); "
            f"from lcchain.cli.main import main; sys.exit(main({argv!r}))")
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=cwd)


def test_netlist_and_examples_write_to_stdout_for_dash(capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(["netlist", "--case", "two-mass", "--N", "4", "-o", "-"]) == 0
    out, _ = capsys.readouterr()
    assert out.startswith("lcchain two-mass chain N=4") and out.rstrip().endswith(".end")
    assert main(["examples", "cradle", "-o", "-"]) == 0
    out, _ = capsys.readouterr()
    assert "[chain]" in out and "wrote" not in out
    assert list(tmp_path.iterdir()) == []  # no file named "-"


@pytest.mark.ngspice
def test_simulate_waveforms_to_stdout_and_its_summary_to_stderr(capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(["simulate", "--case", "two-mass", "--N", "5", "--dt", "0.1", "--waveform-out", "-"]) == 0
    out, err = capsys.readouterr()
    header, *rows = out.splitlines()
    assert header == "t,first,last" and len(rows) > 10 and all(len(r.split(",")) == 3 for r in rows)
    assert "max |simulation - theory|" in err
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("argv, option", [
    (["simulate", "--case", "two-mass", "--N", "5", "--netlist-out", "-", "--waveform-out", "-"], "--waveform-out"),
    (["simulate", "--case", "two-mass", "--N", "5", "--waveform-out", "-", "--json"], "--waveform-out"),
    (["simulate", "--case", "two-mass", "--N", "5", "--plot", "-"], "--plot"),
])
def test_dash_is_refused_where_stdout_is_taken_or_no_text(capsys, tmp_path, monkeypatch, argv, option):
    monkeypatch.chdir(tmp_path)
    assert main(argv) == 2
    _, err = capsys.readouterr()
    assert err.count("\n") == 1 and f"{option} = '-' is not allowed" in err


def test_a_missing_extra_exits_4_naming_its_pip_command(tmp_path):
    proc = _without(["dask", "distributed"], ["sweep", "--case", "two-mass", "--N", "5", "--dt", "0.1",
                                              "--store", "s.sqlite", "--executor", "dask"], tmp_path)
    assert proc.returncode == 2, proc.stderr
    assert proc.stderr.count("\n") == 1 and "pip install 'lcchain[dask]'" in proc.stderr
    assert list(tmp_path.iterdir()) == []


def test_extra_missing_error_keeps_its_fields_through_pickle():
    error = ExtraMissingError("pandas", "data", "Store.to_dataframe")
    for protocol in range(pickle.HIGHEST_PROTOCOL + 1):
        back = pickle.loads(pickle.dumps(error, protocol))
        assert (back.module, back.extra, back.purpose, str(back)) == ("pandas", "data", "Store.to_dataframe",
                                                                       str(error))
    assert error.command == "pip install 'lcchain[data]'"


@pytest.mark.ngspice
def test_doctor_suggests_only_what_is_missing(tmp_path):
    """Without PySpice, the shared run's fix is PySpice's pip command, not the shared library just found."""
    code = ("import sys; sys.modules['PySpice'] = None; from lcchain.spice.doctor import doctor; "
            "import json; print(json.dumps({c.name: [c.ok, c.fix] for c in doctor()}))")
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    checks = json.loads(proc.stdout)
    assert checks["ngspice shared library"][0] is True
    assert checks["PySpice"][0] is False
    assert checks["shared run"] == [False, "pip install 'lcchain[shared]'"]


def _small_cradle(folder: Path) -> Path:
    """The bundled cradle scene at N = 10 with no [output] (nothing written beside the report)."""
    import tomllib

    from lcchain.scenes.bundled import example_text

    text = example_text("cradle").replace("N = 100", "N = 10")
    data = tomllib.loads(text)
    assert data["chain"]["N"] == 10 and "tolerance" not in data.get("effects", {})
    path = folder / "cradle.toml"
    path.write_text(text.split("[output]")[0])
    return path


@pytest.mark.ngspice
def test_a_monte_carlo_from_the_command_line_without_editing_the_scene(capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    scene = _small_cradle(tmp_path)
    before = scene.read_text()
    status = main(["run", str(scene), "--tolerance", "L=0.02,C=0.01", "--series", "E24", "--samples", "2",
                   "--seed", "7", "--json"])
    out, err = capsys.readouterr()
    assert status == 0, err
    report = json.loads(out)
    assert len(report["samples"]) == 2
    tolerance = report["scene"]["effects"]["tolerance"]
    assert {key: tolerance[key] for key in ("L", "C", "samples", "seed")} == {"L": 0.02, "C": 0.01, "samples": 2,
                                                                             "seed": 7}
    assert report["scene"]["effects"]["preferred_values"]["series"] == "E24"
    assert scene.read_text() == before  # the file is the user's: never edited


@pytest.mark.parametrize("argv, message", [
    (["--tolerance", "L=1.5"], "--tolerance L = 1.5 is not allowed: expected a relative tolerance, 0 <= L < 1"),
    (["--tolerance", "R=0.1"], "--tolerance = 'R=0.1' is not allowed: expected L=TOL,C=TOL"),
    (["--series", "E7"], "--series = 'E7' is not allowed: expected E12 | E24 | E96"),
    (["--samples", "0"], "--samples = 0 is not allowed: expected an integer from 1 to 10000"),
    (["--seed", "-1"], "--seed = -1 is not allowed"),
])
def test_monte_carlo_options_name_the_option_value_and_range(capsys, tmp_path, monkeypatch, argv, message):
    monkeypatch.chdir(tmp_path)
    scene = _small_cradle(tmp_path)
    assert main(["run", str(scene), *argv]) == 2
    _, err = capsys.readouterr()
    assert err.count("\n") == 1 and message in err, err
    assert main(["sweep", str(scene), *argv, "--store", "s.sqlite"]) == 2
    _, err = capsys.readouterr()
    assert message in err, err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["cradle.toml"]


def test_doctor_with_a_wrong_library_path_says_to_fix_the_variable_and_lists_only_usable_transports(tmp_path):
    """NGSPICE_LIBRARY_PATH names the one library looked for: the fix is the variable, not a package to install;
    and the engine's line no longer lists the shared transport as if it worked."""
    code = ("from lcchain.spice.doctor import doctor; import json; "
            "print(json.dumps({c.name: [c.ok, c.detail, c.fix] for c in doctor()}))")
    env = {**os.environ, "NGSPICE_LIBRARY_PATH": str(tmp_path / "missing.so")}
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=tmp_path, env=env)
    assert proc.returncode == 0, proc.stderr
    checks = json.loads(proc.stdout)
    assert checks["ngspice shared library"][0] is False
    assert checks["ngspice shared library"][2] == "unset NGSPICE_LIBRARY_PATH, or point it at libngspice.so.0"
    ok, detail, _ = checks["engine ngspice"]
    assert ok and "transports batch (shared: not usable here, see above)" in detail
