"""The package a user installs (issue 22): ``python -m build`` makes a wheel and an sdist, and the wheel, installed
on its own, works from an empty folder: its example scenes, ``py.typed``, and a scene run in real ngspice."""

from __future__ import annotations

import json
import os
import re
import shlex
import subprocess
import sys
import tarfile
import zipfile
from pathlib import Path

import pytest

from lcchain.scenes.bundled import example_names

ROOT = Path(__file__).resolve().parent.parent


@pytest.fixture(scope="module")
def built(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    out = tmp_path_factory.mktemp("dist")
    done = subprocess.run([sys.executable, "-m", "build", "--outdir", str(out), str(ROOT)], capture_output=True,
                          text=True, timeout=600)
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    wheels, sdists = sorted(out.glob("*.whl")), sorted(out.glob("*.tar.gz"))
    assert len(wheels) == len(sdists) == 1, sorted(p.name for p in out.iterdir())
    return {"wheel": wheels[0], "sdist": sdists[0]}


def test_the_wheel_ships_the_example_scenes_and_its_types(built: dict[str, Path]) -> None:
    names = set(zipfile.ZipFile(built["wheel"]).namelist())
    scenes = {Path(n).stem for n in names if n.startswith("lcchain/scenes/examples/") and n.endswith(".toml")}
    assert scenes == set(example_names()) == {p.stem for p in (ROOT / "examples" / "scenes").glob("*.toml")}
    assert len(scenes) >= 8
    assert "lcchain/py.typed" in names


def test_the_sdist_builds_the_same_package_without_tests(built: dict[str, Path]) -> None:
    with tarfile.open(built["sdist"]) as sdist:
        names = [name.split("/", 1)[1] for name in sdist.getnames() if "/" in name]
    assert "pyproject.toml" in names and "lcchain/py.typed" in names
    assert {Path(n).stem for n in names if n.startswith("lcchain/scenes/examples/")} == set(example_names())
    # they stay in the repository; the package page is the long description the wheel is built with
    assert not [n for n in names if n.startswith(("tests/", "benchmarks/", "docs/")) and n != "docs/package.md"]
    assert "docs/package.md" in names


@pytest.fixture(scope="module")
def installed(built: dict[str, Path], tmp_path_factory: pytest.TempPathFactory) -> dict[str, str]:
    """The wheel installed alone into a folder of its own: the environment that imports it, not the repository."""
    site = tmp_path_factory.mktemp("site")
    done = subprocess.run([sys.executable, "-m", "pip", "install", "-q", "--no-deps", "--no-index", "--target",
                           str(site), str(built["wheel"])], capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    env = dict(os.environ, PYTHONPATH=str(site))
    where = subprocess.run([sys.executable, "-P", "-c", "import lcchain; print(lcchain.__file__)"], cwd=site,
                           env=env, capture_output=True, text=True)
    assert Path(where.stdout.strip()).is_relative_to(site), where  # the wheel, not the repository
    return env


def _lcchain(env: dict[str, str], here: Path, *argv: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-P", "-m", "lcchain", *argv], cwd=here, env=env, capture_output=True,
                          text=True, timeout=300)


@pytest.mark.ngspice
def test_the_installed_wheel_runs_an_example_from_an_empty_folder(installed: dict[str, str], tmp_path: Path) -> None:
    here = tmp_path

    def lcchain(*argv: str) -> subprocess.CompletedProcess[str]:
        return _lcchain(installed, here, *argv)

    listed = lcchain("examples")
    assert listed.returncode == 0 and all(name in listed.stdout for name in example_names()), listed
    assert lcchain("examples", "cradle").returncode == 0
    assert (here / "cradle.toml").read_text() == (ROOT / "examples" / "scenes" / "cradle.toml").read_text()
    again = lcchain("examples", "cradle")  # the same example again (a README followed twice): nothing to do
    assert again.returncode == 0 and "here already, unchanged" in again.stdout, again
    (here / "cradle.toml").write_text((here / "cradle.toml").read_text() + "# my own edit\n")
    edited = lcchain("examples", "cradle")  # the user's own copy is never overwritten
    assert edited.returncode == 2 and "cradle.toml exists" in edited.stderr and "Traceback" not in edited.stderr
    assert (here / "cradle.toml").read_text().endswith("# my own edit\n")
    (here / "cradle.toml").write_text((ROOT / "examples" / "scenes" / "cradle.toml").read_text())
    ran = lcchain("run", "cradle.toml", "--json")
    assert ran.returncode == 0, ran.stderr
    report = json.loads(ran.stdout)
    assert report["source"] == "cradle.toml" and report["N"] == 100 and report["accuracy_met"] is True


def _page_commands(text: str) -> list[list[str]]:
    """The ``lcchain`` commands of the package page's shell blocks, each ``&&`` part on its own, comments cut."""
    commands = []
    for block in re.findall(r"```sh\n(.*?)```", text, flags=re.S):
        for line in block.splitlines():
            line = line.split("#", 1)[0].strip()
            for part in filter(None, (p.strip() for p in line.split("&&"))):
                if part.startswith("lcchain "):
                    commands.append(shlex.split(part)[1:])
    return commands


def test_the_package_page_has_no_link_a_package_index_cannot_resolve(built: dict[str, Path]) -> None:
    with zipfile.ZipFile(built["wheel"]) as wheel:
        metadata = next(wheel.read(n).decode() for n in wheel.namelist() if n.endswith(".dist-info/METADATA"))
    page = (ROOT / "docs" / "package.md").read_text()
    assert "Description-Content-Type: text/markdown" in metadata and page.strip() in metadata
    targets = re.findall(r"\]\(([^)]*)\)", page) + re.findall(r"<(?:img|a)\b[^>]*>", page)
    assert [t for t in targets if not t.startswith(("https://", "#"))] == []
    assert len(_page_commands(page)) >= 6


@pytest.mark.ngspice
def test_every_command_of_the_package_page_works_from_the_installed_wheel(installed: dict[str, str],
                                                                         tmp_path: Path) -> None:
    for argv in _page_commands((ROOT / "docs" / "package.md").read_text()):
        done = _lcchain(installed, tmp_path, *argv)
        assert done.returncode == 0, (argv, done.stdout[-2000:], done.stderr[-2000:])
    assert (tmp_path / "cradle.png").stat().st_size > 0 and (tmp_path / "cradle.toml").is_file()


def test_examples_refuses_what_it_cannot_write(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                               capsys: pytest.CaptureFixture[str]) -> None:
    from lcchain.cli.main import main

    monkeypatch.chdir(tmp_path)
    assert main(["examples", "nope"]) == 2
    err = capsys.readouterr().err
    assert "NAME = 'nope'" in err and all(name in err for name in example_names())
    assert main(["examples", "walls", "-o", str(tmp_path / "missing" / "w.toml")]) == 2
    assert "-o" in capsys.readouterr().err
    (tmp_path / "walls.toml").write_text("# my own walls\n")
    assert main(["examples", "walls"]) == 2
    assert (tmp_path / "walls.toml").read_text() == "# my own walls\n"
    assert main(["examples", "walls", "-o", "mine.toml"]) == 0
    assert (tmp_path / "mine.toml").read_text() == (ROOT / "examples" / "scenes" / "walls.toml").read_text()
    assert list(tmp_path.iterdir()) and not any(p.name.startswith(".") for p in tmp_path.iterdir())
