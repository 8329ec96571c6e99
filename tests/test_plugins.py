"""Parts from a package installed apart from lcchain (issues 30 and 34): the ``lcchain.effects``,
``lcchain.engines``, ``lcchain.cases``, ``lcchain.mode_methods``, ``lcchain.executors`` and
``lcchain.ngspice_transports`` entry-point groups.  tests/plugin/ is such a package; each test installs it with pip into its own folder (no
network: the package's build backend is its own few lines) and uses it in a fresh interpreter whose PYTHONPATH
holds that folder, as a user's environment would."""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest
from helpers.tolerances import ATOL_EFFECT_RUN

PLUGIN = Path(__file__).parent / "plugin"


def _install(tmp_path: Path) -> dict[str, str]:
    """The plugin installed under tmp_path; the environment that sees it."""
    source, target = tmp_path / "plugin-source", tmp_path / "site"
    shutil.copytree(PLUGIN, source, ignore=shutil.ignore_patterns("__pycache__"))  # pip builds in the tree
    env = {**os.environ, "PYTHONPATH": str(target), "TMPDIR": str(tmp_path), "PYTHONDONTWRITEBYTECODE": "1",
           "PIP_CACHE_DIR": str(tmp_path / "pip-cache"), "PIP_DISABLE_PIP_VERSION_CHECK": "1"}
    subprocess.run([sys.executable, "-m", "pip", "install", "--quiet", "--no-deps", "--no-build-isolation",
                    "--no-index", "--target", str(target), str(source)], check=True, env=env, cwd=tmp_path,
                   capture_output=True, timeout=300)
    return env


def _python(env: dict[str, str], cwd: Path, code: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-c", textwrap.dedent(code)], env=env, cwd=cwd, capture_output=True,
                          text=True, timeout=600)


def _lcchain(env: dict[str, str], cwd: Path, *argv: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "lcchain", *argv], env=env, cwd=cwd, capture_output=True,
                          text=True, timeout=600)


def _help(env: dict[str, str], cwd: Path, command: str) -> str:
    """``lcchain COMMAND --help`` in one line, argparse's wrapping undone (it also breaks lines after a hyphen)."""
    helped = _lcchain(env, cwd, command, "--help")
    assert helped.returncode == 0, helped.stderr
    return re.sub(r"-\s+", "-", " ".join(helped.stdout.split()))


def test_an_installed_effect_is_in_the_registry_the_scene_schema_and_the_options(tmp_path):
    env = _install(tmp_path)
    done = _python(env, tmp_path, """
        import json

        from lcchain.circuit.effects import EFFECTS
        from lcchain.circuit.elements import ladder_elements
        from lcchain.circuit.ladder import Ladder
        from lcchain.scenes.load import parse_scene
        from lcchain.scenes.plan import scene_request
        from lcchain.spice.engines import ENGINES
        from lcchain.theory.cases import chain_for_case

        leak = EFFECTS["node_leakage"]
        assert list(EFFECTS)[-1] == "node_leakage" and "renamed-ngspice" in ENGINES
        scene = parse_scene({"chain": {"case": "two-mass", "N": 10}, "effects": {"node_leakage": {"R": 1000.0}}})
        assert scene.to_dict()["effects"] == {"node_leakage": {"R": 1000.0}}
        assert parse_scene(scene.to_dict()) == scene and scene_request(scene).effects == (leak(1000.0),)
        try:
            parse_scene({"chain": {"case": "two-mass", "N": 10}, "effects": {"node_leakage": {"R": -1}}})
        except Exception as error:
            print(error)
        cards = [e.card() for e in ladder_elements(Ladder(chain_for_case("two-mass", 10)), (leak(1000.0),))]
        print(json.dumps([c for c in cards if c.startswith("RG")]))
    """)
    assert done.returncode == 0, done.stderr
    error, cards = done.stdout.splitlines()
    assert error == "effects.node_leakage.R = -1 is not allowed: expected a finite number > 0 (resistance / " \
                    "sqrt(L0/C0))"
    # free ends: rail nodes n1..n9 (n0 and n10 are ground); sqrt(L0/C0) = sqrt(10e-6/10e-9) ohm
    assert json.loads(cards) == [f"RG{i} n{i} 0 {1000.0 * (10e-6 / 10e-9) ** 0.5!r}" for i in range(1, 10)]
    helped = _lcchain(env, tmp_path, "simulate", "--help")
    assert helped.returncode == 0 and "--node-leakage R" in helped.stdout
    assert "ngspice or gnucap or renamed-" in " ".join(helped.stdout.split())  # argparse wraps at the hyphen
    refused = _lcchain(env, tmp_path, "simulate", "--case", "two-mass", "--N", "10", "--node-leakage", "0")
    assert refused.returncode == 2 and refused.stdout == ""
    assert refused.stderr == ("lcchain: --node-leakage = 0.0 is not allowed: expected a finite number > 0 "
                              "(resistance / sqrt(L0/C0))\n")


@pytest.mark.ngspice
def test_an_installed_effect_and_engine_run_through_ngspice(tmp_path):
    env = _install(tmp_path)
    ran = _lcchain(env, tmp_path, "simulate", "--case", "two-mass", "--N", "10", "--dt", "0.02", "--node-leakage",
                   "100", "--engine", "renamed-ngspice", "--netlist-out", "run.cir", "--json")
    assert "RG1 n1 0 " in (tmp_path / "run.cir").read_text()
    assert ran.returncode == 0, ran.stderr
    data = json.loads(ran.stdout)
    assert data["engine"] == "renamed-ngspice" and data["max_abs_error"] < ATOL_EFFECT_RUN


def test_an_installed_case_executor_transport_and_mode_method_are_offered(tmp_path):
    """Each is in the registry of its kind and the command line's choices (``--help`` lists them, read from the
    registries, not from the ``Literal`` sets), and the mode method computes modes; no simulator runs."""
    env = _install(tmp_path)
    done = _python(env, tmp_path, """
        from lcchain.studies.executors import EXECUTOR_TRAITS
        from lcchain.spice.ngspice.transports import TRANSPORT_RUNS, named_transports
        from lcchain.theory.cases import CHAIN_CASES, chain_for_case
        from lcchain.theory.spectrum import MODE_SOLVERS, normal_modes

        print(list(CHAIN_CASES)[-1], list(EXECUTOR_TRAITS)[-1], list(TRANSPORT_RUNS)[-1], named_transports()[-1],
              list(MODE_SOLVERS)[-1])
        chain = chain_for_case("nodeleak-uniform", 6)
        print(len(normal_modes(chain, method="nodeleak_exact").omega))
    """)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == ["nodeleak-uniform", "nodeleak-serial", "counted-batch", "counted-batch",
                                   "nodeleak_exact", "6"]
    assert "mode method nodeleak_exact" in done.stderr  # the plugin's function computed them
    simulate = _help(env, tmp_path, "simulate")
    assert "perfect, nodeleak-uniform (" in simulate  # --case
    assert "how ngspice runs: batch, shared, counted-batch (default batch)" in simulate  # --backend
    sweep = _help(env, tmp_path, "sweep")
    assert "serial, process, dask, nodeleak-serial (default process)" in sweep  # --executor
    assert "perfect, nodeleak-uniform)" in sweep and "batch, shared, counted-batch" in sweep  # --case, --backend
    refused = _lcchain(env, tmp_path, "simulate", "--case", "nodeleak-uniform", "--N", "41")
    assert refused.returncode == 2 and refused.stderr.count("\n") == 1 and "41" in refused.stderr  # its max_N


@pytest.mark.ngspice
def test_an_installed_case_transport_and_executor_run_a_sweep_through_ngspice(tmp_path):
    """``sweep`` over the plugin's case and one of lcchain's, on the plugin's executor and ngspice transport: every
    run goes through both (each says so on stderr) and passes; the store holds the transport's name."""
    env = _install(tmp_path)
    ran = _lcchain(env, tmp_path, "sweep", "--case", "nodeleak-uniform,two-mass", "--N", "4,5", "--dt", "0.05",
                   "--executor", "nodeleak-serial", "--backend", "counted-batch", "--store", "s.sqlite", "--json")
    assert ran.returncode == 0, ran.stderr
    summary = json.loads(ran.stdout)
    assert (summary["total"], summary["ok"], summary["failed"]) == (4, 4, 0)
    said = ran.stderr.splitlines()
    assert said.count("lcchain_nodeleak: executor nodeleak-serial ran a group of 1") == 4
    assert said.count("lcchain_nodeleak: transport counted-batch ran on counted-batch") == 4
    assert {"lcchain_nodeleak: case nodeleak-uniform N = 4", "lcchain_nodeleak: case nodeleak-uniform N = 5"} <= \
        set(said)
    simulated = _lcchain(env, tmp_path, "simulate", "--case", "nodeleak-uniform", "--N", "6", "--dt", "0.02",
                         "--backend", "counted-batch", "--node-leakage", "1000", "--json")
    assert simulated.returncode == 0, simulated.stderr
    data = json.loads(simulated.stdout)
    assert data["backend"] == "counted-batch" and data["max_abs_error"] < ATOL_EFFECT_RUN
    assert "transport counted-batch ran on counted-batch" in simulated.stderr


def test_a_broken_plugin_is_one_line_naming_its_entry_point(tmp_path):
    env = _install(tmp_path)
    broken = tmp_path / "site" / "lcchain_broken-0.1.dist-info"
    broken.mkdir()
    (broken / "METADATA").write_text("Metadata-Version: 2.1\nName: lcchain-broken\nVersion: 0.1\n")
    (broken / "entry_points.txt").write_text("[lcchain.effects]\nbroken = lcchain_nowhere:Broken\n")
    said = _lcchain(env, tmp_path, "simulate", "--help")
    assert said.returncode == 2 and said.stdout == ""
    assert said.stderr.startswith("lcchain: entry point lcchain.effects broken = 'lcchain_nowhere:Broken' is not "
                                  "allowed: expected a frozen dataclass subclass of lcchain.circuit.effects.Effect")
    assert "ModuleNotFoundError: No module named 'lcchain_nowhere'" in said.stderr
    assert said.stderr.count("\n") == 1 and "Traceback" not in said.stderr
    (broken / "entry_points.txt").write_text("[lcchain.engines]\nngspice = lcchain_nodeleak:RenamedNgspice\n")
    said = _lcchain(env, tmp_path, "doctor")
    assert said.returncode == 2 and "entry point lcchain.engines ngspice" in said.stderr and "is taken" in said.stderr
    assert said.stderr.count("\n") == 1


def test_importing_lcchain_reads_no_entry_points(tmp_path):
    """The groups are read the first time a registry is asked for a name it does not hold or listed, not when
    lcchain (its runs, scenes, studies) loads, nor for lcchain's own parts (which no plugin can take)."""
    env = {**os.environ, "TMPDIR": str(tmp_path), "PYTHONDONTWRITEBYTECODE": "1"}
    done = _python(env, tmp_path, """
        import lcchain.runs.simulate, lcchain.scenes.load, lcchain.studies.plan
        from lcchain.circuit.effects import EFFECTS
        from lcchain.spice.engines import ENGINES

        print(repr(EFFECTS).endswith("plugins not read yet)"), repr(ENGINES).endswith("plugins not read yet)"))
        print("losses" in EFFECTS, ENGINES["ngspice"].name, repr(EFFECTS).endswith("plugins not read yet)"),
              repr(ENGINES).endswith("plugins not read yet)"))
        print("no-such-effect" in EFFECTS, repr(EFFECTS).endswith("plugins not read yet)"))
    """)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == ["True", "True", "True", "ngspice", "True", "True", "False", "False"]
