"""Every error one line, naming what the user typed (issue 29, item 4): the hostile families, not their examples.

Each case runs the real command line in this process, in a folder of its own (helpers.catalogue): a refusal
exits 2 with one line on stderr that names the option or scene key the user gave and its value, with no
traceback, nothing written and nothing left in the temporary folder.  The families:

* extreme numbers (1e-300, 1e300, inf, nan, 0, negative) in every option and scene key that reaches the
  theory: the losses' Q (--Q, effects.losses.Q, the AC fit's range), --walls (a cradle float64 cannot hold),
  --chain files and custom scenes far from bulk units, pulse widths, wall springs, timeouts and budgets;
* an empty entry in every comma-list option (--N, --case, --dt, --accuracy, --transits, --excitation,
  --engine, --vary, table and bench --N), and list entries out of range (named, not priced as a study);
* include cards with no file name in a batch netlist (``.include $HOME/x.inc``);
* scene titles that are not valid mathtext (drawn as plain text: the run is kept);
* cached figure rows that are malformed, stale or wrong (recomputed, never drawn);
* a Dask study's scratch space, gone from TMPDIR when the driver is killed outright.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from helpers.catalogue import Case, run_case
from helpers.processes import gone

from lcchain.cli import main
from lcchain.report.figure_data import DesignRows, _row_digest, cache_key
from lcchain.spice.scratch import MARKER, owner_pid, remove_stale, scratch_folder

SCENE = '[chain]\ncase = "two-mass"\nN = 6\n'
QUIET = "[output]\nplots = []\n"
SWEEP = ["sweep", "--case", "two-mass", "--N", "6", "--store", "s.sqlite", "--executor", "serial"]


def refused(argv: list[str], said: list[str], family: str, **kw: object) -> Case:
    return Case(argv, said, family=family, **kw)  # type: ignore[arg-type]


def scene(text: str) -> dict[str, str | bytes]:
    return {"s.toml": text}


CASES: dict[str, Case] = {}

# ------------------------------------------------------------------ the losses' Q: what the theory and the fit hold
for value, shown in (("1e-300", "1e-300"), ("1e300", "1e+300"), ("0.5", "0.5"), ("2e10", "20000000000.0"),
                     ("1e-30", "1e-30")):
    CASES[f"spectrum --Q {value}"] = refused(["spectrum", "--case", "two-mass", "--N", "10", "--Q", value],
                                            [f"--Q = {shown}", "1 <= Q <= 1e+10"], "Q")
    CASES[f"scene Q {value}"] = refused(["run", "s.toml"], ["s.toml", f"effects.losses.Q = {shown}", "1 <= Q"], "Q",
                                        files=scene(SCENE + f"[effects.losses]\nQ = {value}\n" + QUIET))
    CASES[f"AC scene Q {value}"] = refused(
        ["run", "s.toml"], ["s.toml", f"effects.losses.Q = {shown}"], "Q",
        files=scene(SCENE + f'[effects.losses]\nQ = {value}\n[analysis]\nkind = "ac"\n' + QUIET))
for value in ("1e6",):  # inside 1 .. 1e10, above what the AC fit places on this chain (below: merged modes, said)
    CASES[f"spectrum --Q {value} beyond the fit"] = refused(
        ["spectrum", "--case", "two-mass", "--N", "10", "--Q", value], ["--Q = ", "on this chain's AC analysis"], "Q")
# the lossy fit from theory's poles reaches every N an AC analysis takes (issue 32): what it refuses is a Q above
# the decay rates it can place on the chain
CASES["spectrum --Q above the lossy fit's range"] = refused(
    ["spectrum", "--case", "two-mass", "--N", "200", "--Q", "1e6"], ["--Q = 1000000.0", "Q <= 5e+04"], "Q")
CASES["sweep --vary effects.losses.Q"] = refused(
    ["sweep", "s.toml", "--vary", "effects.losses.Q=100,1e300", "--store", "s.sqlite", "--executor", "serial"],
    ["s.toml", "effects.losses.Q = 1e+300"], "Q", files=scene(SCENE + "[effects.losses]\nQ = 100\n" + QUIET))

# ------------------------------------------------------------------ --walls: a perfect cradle float64 holds
for command in ("design", "netlist", "simulate", "spectrum", "sensitivity"):
    CASES[f"{command} --walls 1e9"] = refused([command, "--case", "perfect", "--N", "100", "--walls", "1000000000"],
                                              ["--walls = 1000000000", "0 <= J <=", "N = 100"], "walls")
CASES["design --walls at N = 3"] = refused(["design", "--case", "perfect", "--N", "3", "--walls", "1000000000"],
                                           ["--walls = 1000000000", "0 <= J <="], "walls")
CASES["design --walls at N = 300"] = refused(["design", "--case", "perfect", "--N", "300", "--walls", "2000"],
                                             ["--walls = 2000", "0 <= J <=", "N = 300"], "walls")
CASES["spectrum --walls whose poles no sweep separates"] = refused(
    ["spectrum", "--case", "perfect", "--N", "6", "--walls", "1000000000"], ["--walls = 1000000000", "--N 6"],
    "walls")

# ------------------------------------------------------------------ --chain files and custom scenes far from bulk units
CHAINS = {"a huge spring": '{"masses": [1, 1, 1], "springs": [0, 1e300, 1, 0]}',
          "a tiny mass": '{"masses": [1e-300, 1, 1], "springs": [0, 1, 1, 0]}',
          "a huge wall": '{"masses": [1, 1, 1], "springs": [1e300, 1, 1, 0]}'}
for name, text in CHAINS.items():
    for command in ("simulate", "netlist", "spectrum", "sensitivity"):
        CASES[f"{command} --chain with {name}"] = refused([command, "--chain", "c.json"], ["--chain = 'c.json'"],
                                                          "chain files", files={"c.json": text})
    CASES[f"simulate --accuracy --chain with {name}"] = refused(
        ["simulate", "--chain", "c.json", "--accuracy", "1e-3"], ["--chain = 'c.json'"], "chain files",
        files={"c.json": text})
for key, value in (("springs", "[0, 1e300, 1, 0]"), ("masses", "[1e-300, 1, 1]")):
    other = "masses = [1, 1, 1]" if key == "springs" else "springs = [0, 1, 1, 0]"
    CASES[f"custom scene chain.{key} far from bulk units"] = refused(
        ["run", "s.toml"], ["s.toml", "chain.masses/chain.springs = "], "chain files",
        files=scene(f'[chain]\ncase = "custom"\n{key} = {value}\n{other}\n' + QUIET))

BIG = '{"masses": [' + ", ".join(["1"] * 2500) + '], "springs": [0, ' + ", ".join(["1"] * 2499) + ", 0]}"
for argv in (["simulate", "--chain", "c.json", "--coupling", "0.1"], ["spectrum", "--chain", "c.json"],
             ["sensitivity", "--chain", "c.json"]):
    CASES[f"{argv[0]} --chain too large"] = refused(argv, ["--chain = 'c.json'", "2000"], "chain files",
                                                     files={"c.json": BIG})

# ------------------------------------------------------------------ scene keys with extreme values
for value, shown in (("1e-300", "1e-300"), ("0", "0")):
    CASES[f"scene pulse width {value}"] = refused(
        ["run", "s.toml"], ["s.toml", f"excitation.width = {shown}", "0.001 <= width"], "scene keys",
        files=scene(SCENE + f'[excitation]\nkind = "pulse"\nshape = "gaussian"\nwidth = {value}\n' + QUIET))
for value, shown in (("1e300", "1e+300"), ("1e30", "1e+30"), ("inf", "inf")):
    CASES[f"scene wall spring {value}"] = refused(["run", "s.toml"], ["s.toml", f"effects.walls.K0 = {shown}"],
                                                  "scene keys", files=scene(SCENE + f"[effects.walls]\nK0 = {value}\n"))

for value, shown in (("1e300", "1e+300"), ("1e-300", "1e-300")):
    CASES[f"scene kick current {value}"] = refused(["run", "s.toml"], ["s.toml", f"excitation.I0 = {shown}"],
                                                   "scene keys", files=scene(SCENE + f"[excitation]\nI0 = {value}\n"))
for value, shown in (("1e300", "1e+300"), ("nan", "nan"), ("0", "0.0")):
    CASES[f"netlist --dt {value}"] = refused(["netlist", "--case", "two-mass", "--N", "6", "--dt", value],
                                             ["--dt", shown], "numeric options")

# ------------------------------------------------------------------ comma lists: no empty entry
LISTS = {"--N": "10,,20", "--case": "two-mass,,one-mass", "--dt": "0.05,,0.02", "--accuracy": "1e-3,,1e-4",
         "--transits": "1,,2", "--excitation": "kick,,displacement"}
for option, text in LISTS.items():
    first = text.split(",,")[0]
    for form in (text, f"{first},", f",{first}", text.replace(",,", ", ,"), ","):
        argv = [*SWEEP]
        if option in ("--case", "--N"):
            argv[argv.index(option) + 1] = form
        else:
            argv += [option, form]
        CASES[f"sweep {option} {form!r}"] = refused(argv, [option, repr(form), "none empty"], "empty list entries")
for form in ("10,,20", "10,", ",10"):
    CASES[f"table --N {form!r}"] = refused(["table", "--case", "two-mass", "--N", form], ["--N", repr(form)],
                                           "empty list entries")
    CASES[f"bench --N {form!r}"] = refused(["bench", "accuracy", "--quick", "--N", form, "--out", "b"],
                                           ["--N", repr(form)], "empty list entries")
for form in ("ngspice,", ",ngspice", "ngspice,,gnucap"):
    CASES[f"simulate --engine {form!r}"] = refused(["simulate", "--case", "two-mass", "--N", "6", "--engine", form],
                                                   ["--engine", repr(form)], "empty list entries")
for form in ("analysis.dt=0.05,,0.02", "analysis.dt=0.05,", "chain.N=,10"):
    CASES[f"sweep --vary {form}"] = refused(
        ["sweep", "s.toml", "--vary", form, "--store", "s.sqlite", "--executor", "serial"],
        ["--vary", repr(form), "no empty value"], "empty list entries", files=scene(SCENE))

# ------------------------------------------------------------------ list entries out of range: named, not priced
for option, text, shown in (("--dt", "nan,0.05", "nan"), ("--dt", "0,0.05", "0.0"), ("--dt", "0.05,inf", "inf"),
                            ("--dt", "1e-300,0.05", "1e-300"), ("--dt", "-0.05", "-0.05"),
                            ("--accuracy", "nan,1e-3", "nan"), ("--accuracy", "2", "2.0"),
                            ("--N", "10,2", "2"), ("--N", "10,1000000000", "1000000000"),
                            ("--transits", "0,1", "0"), ("--transits", "1,100000", "100000")):
    argv = [*SWEEP]
    if option == "--N":
        argv[argv.index("--N") + 1] = text
    else:
        argv += [option, text]
    CASES[f"sweep {option} {text}"] = refused(argv, [f"{option} = {shown}"], "list values")
CASES["sweep: one run beyond the budget, by its step"] = refused(
    ["sweep", "--case", "two-mass,one-mass", "--N", "100,200", "--dt", "0.002,0.001", "--store", "s.sqlite",
     "--max-time", "10"], ["--dt = 0.001", "a run at N = 200", "--max-time"], "list values")
CASES["sweep: the axes beyond the budget"] = refused(
    ["sweep", "--case", "two-mass,one-mass", "--N", "100,200", "--dt", "0.002,0.001", "--store", "s.sqlite",
     "--max-time", "20"], ["--case x --N x --dt = '8 points'", "--max-time"], "list values")

TOLERANCE = SCENE + "[effects.tolerance]\nL = 0.05\nsamples = 2\n" + QUIET
for option, value in (("--samples", "0"), ("--samples", "99999999999999999999"), ("--seed", "-1")):
    CASES[f"sweep SCENE {option} {value}"] = refused(
        ["sweep", "s.toml", option, value, "--store", "s.sqlite", "--executor", "serial"], [f"{option} = {value}"],
        "list values", files=scene(TOLERANCE))

# ------------------------------------------------------------------ timeouts and budgets
for value in ("nan", "inf", "0", "-1", "1e300", "1e-300"):
    CASES[f"sweep --timeout {value}"] = refused([*SWEEP, "--timeout", value], ["--timeout", repr(value)],
                                                "timeouts and budgets")
for option, value in (("--max-time", "1e-300"), ("--max-time", "1e300"), ("--max-memory", "1e300"),
                      ("--max-memory", "1k")):
    CASES[f"simulate {option} {value}"] = refused(["simulate", "--case", "two-mass", "--N", "6", option, value],
                                                  [option, repr(value)], "timeouts and budgets")

# ------------------------------------------------------------------ batch: include cards that name no file
for card in (".include $HOME/x.inc", ".inc $", ".include ;x", ".lib", ".include"):
    CASES[f"batch {card!r}"] = refused(
        ["batch", "n.cir", "--store", "s.sqlite"], ["n.cir: line 3", card.split()[0], "one file name"], "includes",
        files={"n.cir": f"title\nR1 1 0 1\n{card}\n.tran 1e-6 1e-5\n.end\n"})
CASES["batch: an include card with no name in an included file"] = refused(
    ["batch", "n.cir", "--store", "s.sqlite"], ["a.inc: line 1", "one file name"], "includes",
    files={"n.cir": "title\nR1 1 0 1\n.include a.inc\n.tran 1e-6 1e-5\n.end\n", "a.inc": ".include $HOME/x.inc\n"})


@pytest.mark.ngspice
@pytest.mark.parametrize("case", CASES.values(), ids=CASES.keys())
def test_every_refusal_is_one_line_naming_what_was_typed(case: Case, tmp_path: Path) -> None:
    case.env = {"XDG_CACHE_HOME": str(tmp_path / ".cache"), **case.env}
    outcome = run_case(case, tmp_path, main)
    assert outcome.kind == "clean", outcome.detail


# ------------------------------------------------------------------ mathtext titles: drawn as text, the run kept
@pytest.mark.ngspice
@pytest.mark.parametrize("title", ["$x", "$$", r"$\\frac{1}{$", r"$\\undefinedcommand$", r"$\\alpha$ stays math"])
def test_a_title_that_is_not_mathtext_is_drawn_as_text(title: str, tmp_path: Path) -> None:
    text = f'title = "{title}"\n' + SCENE + "[analysis]\ndt = 0.05\n"
    case = Case(["run", "s.toml"], [], status=0, files=scene(text), family="titles", leaves=("s-overlay.png",))
    outcome = run_case(case, tmp_path, main)
    assert outcome.kind == "clean", outcome.detail
    assert (tmp_path / "s-overlay.png").stat().st_size > 10_000


# ------------------------------------------------------------------ cached figure rows: checked, else recomputed
def _cache_file(folder: Path) -> Path:
    return folder / f"designs-{cache_key()}.json"


def _edit(folder: Path, change) -> None:  # type: ignore[no-untyped-def]
    path = _cache_file(folder)
    data = json.loads(path.read_text())
    change(data)
    path.write_text(json.dumps(data))


def _drop_key(data: dict) -> None:  # type: ignore[type-arg]
    del data["rows"]["two-mass:8"]["row"]["r"]


def _wrong_number(data: dict) -> None:  # type: ignore[type-arg]
    data["rows"]["two-mass:8"]["row"]["r"] *= 1.01


def _wrong_number_signed_again(data: dict) -> None:  # type: ignore[type-arg]
    row = data["rows"]["two-mass:8"]["row"]
    row["m1"] *= 2.0  # the fingerprint is made again: the row's own numbers no longer follow from its r and w
    data["rows"]["two-mass:8"]["sha256"] = _row_digest(cache_key(), "two-mass:8", row)


def _wrong_kind(data: dict) -> None:  # type: ignore[type-arg]
    data["rows"]["two-mass:8"]["row"]["delta"] = "0.1"


def _not_finite(data: dict) -> None:  # type: ignore[type-arg]
    data["rows"]["two-mass:8"]["row"]["delta"] = float("nan")


def _other_row(data: dict) -> None:  # type: ignore[type-arg]
    data["rows"]["two-mass:8"] = data["rows"]["one-mass:8"]


def _old_layout(data: dict) -> None:  # type: ignore[type-arg]
    rows = {name: entry["row"] for name, entry in data["rows"].items()}
    data.clear()
    data.update(rows)


def _other_code(data: dict) -> None:  # type: ignore[type-arg]
    data["key"] = "0123456789abcdef"


def _not_a_row(data: dict) -> None:  # type: ignore[type-arg]
    data["rows"]["two-mass:8"] = [1, 2, 3]


@pytest.fixture(scope="module")
def good_cache(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, dict[str, dict]]:  # type: ignore[type-arg]
    """A cache holding the rows (one-mass, 8) and (two-mass, 8), designed once for every case below."""
    folder = tmp_path_factory.mktemp("cache")
    rows = DesignRows(folder)
    return folder, {case: rows.row(case, 8) for case in ("two-mass", "one-mass")}


@pytest.mark.parametrize("change", [_drop_key, _wrong_number, _wrong_number_signed_again, _wrong_kind, _not_finite,
                                    _other_row, _old_layout, _other_code, _not_a_row],
                         ids=lambda change: change.__name__.strip("_"))
def test_a_cached_row_that_is_not_what_the_code_makes_is_recomputed(change, good_cache, tmp_path: Path) -> None:  # type: ignore[no-untyped-def]
    folder, right = good_cache
    _cache_file(tmp_path).write_bytes(_cache_file(folder).read_bytes())
    _edit(tmp_path, change)
    again = DesignRows(tmp_path)
    row = again.row("two-mass", 8)
    assert again.computed == 1
    assert {key: value for key, value in row.items() if key != "seconds"} == \
        {key: value for key, value in right["two-mass"].items() if key != "seconds"}
    assert DesignRows(tmp_path).computed == 0  # what was recomputed is stored again, with its fingerprint


def test_a_good_cache_is_read_back_untouched(good_cache) -> None:  # type: ignore[no-untyped-def]
    folder, right = good_cache
    again = DesignRows(folder)
    assert again.row("one-mass", 8) == right["one-mass"] and again.computed == 0 and again.refused == 0


@pytest.mark.slow
def test_lcchain_figures_redraws_from_recomputed_rows_not_from_a_bad_cache(tmp_path: Path,
                                                                          monkeypatch: pytest.MonkeyPatch) -> None:
    """The command itself (12 s cold, 7 s warm): rows of Fig. Pk20-100 (two-mass N = 20 and 100) damaged in the
    cache are designed again, and the cache ends as the first run left it."""
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    assert main(["figures", "--out", str(tmp_path / "a"), "--quick", "--format", "svg"]) == 0
    path = tmp_path / "cache" / "lcchain" / f"designs-{cache_key()}.json"
    good = json.loads(path.read_text())["rows"]
    data = json.loads(path.read_text())
    del data["rows"]["two-mass:20"]["row"]["r"]  # a KeyError before
    data["rows"]["two-mass:100"]["row"]["r"] *= 1.5  # drawn as it was, before
    path.write_text(json.dumps(data))
    assert main(["figures", "--out", str(tmp_path / "b"), "--quick", "--format", "svg"]) == 0
    rows = json.loads(path.read_text())["rows"]
    for name in ("two-mass:20", "two-mass:100"):
        assert {k: v for k, v in rows[name]["row"].items() if k != "seconds"} == \
            {k: v for k, v in good[name]["row"].items() if k != "seconds"}


# ------------------------------------------------------------------ scratch folders: nothing left by a dead owner
def _dead_pid() -> int:
    child = subprocess.Popen([sys.executable, "-c", "pass"])
    child.wait()
    return child.pid


def test_stale_scratch_folders_of_dead_owners_are_removed_and_nothing_else(tmp_path: Path) -> None:
    dead = _dead_pid()
    stale = [tmp_path / f"lcchain-dask-{dead}-abc123xy", tmp_path / f".lcchain-gnucap-{dead}-x_y_z_12"]
    for folder in stale:
        (folder / "dask-scratch-space").mkdir(parents=True)
        (folder / MARKER).write_text(str(dead))
    live = tmp_path / f"lcchain-dask-{os.getppid()}-live1234"
    live.mkdir()
    (live / MARKER).write_text(str(os.getppid()))
    kept = [live, tmp_path / f"lcchain-runs-{dead}-final123",  # a user's own, without the marker
            tmp_path / "lcchain-dask-notapid-abcdefgh", tmp_path / f"other-{dead}-abcdefgh"]
    for folder in kept[1:]:
        folder.mkdir()
    (tmp_path / f"lcchain-dask-{dead}-afile123").write_text("a file, not a scratch folder")
    assert sorted(remove_stale(tmp_path)) == sorted(folder.name for folder in stale)
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted([*(f.name for f in kept), f"lcchain-dask-{dead}-afile123"])
    with scratch_folder("dask", tmp_path, watch=True) as folder:
        assert owner_pid(folder.name) == os.getpid() and folder.parent == tmp_path
    assert not folder.exists()


_KILLED = r"""
import os, sys, time
from lcchain.spice.scratch import scratch_folder
with scratch_folder("dask", sys.argv[1], watch=True) as folder:
    (folder / "worker").mkdir()
    print(folder, flush=True)
    time.sleep(600)
"""


def test_a_watched_scratch_folder_goes_when_its_owner_is_killed(tmp_path: Path) -> None:
    owner = subprocess.Popen([sys.executable, "-c", _KILLED, str(tmp_path)], stdout=subprocess.PIPE, text=True)
    assert owner.stdout is not None
    with owner.stdout:
        folder = Path(owner.stdout.readline().strip())
    assert folder.is_dir()
    owner.send_signal(signal.SIGKILL)
    owner.wait()
    deadline = time.monotonic() + 30
    while folder.exists() and time.monotonic() < deadline:
        time.sleep(0.05)
    assert not folder.exists() and list(tmp_path.iterdir()) == []


@pytest.mark.slow
@pytest.mark.ngspice
def test_a_dask_sweep_killed_outright_leaves_nothing_in_the_temporary_folder(tmp_path: Path) -> None:
    pytest.importorskip("distributed")
    scratch = tmp_path / "tmp"
    scratch.mkdir()
    env = dict(os.environ, TMPDIR=str(scratch))
    command = [sys.executable, "-m", "lcchain", "sweep", "--case", "two-mass,one-mass", "--N", "20,30,40,50",
               "--dt", "0.01,0.005,0.002,0.001", "--executor", "dask", "--workers", "2", "--store", "s.sqlite"]
    log = tmp_path / "log"
    log.mkdir()
    with open(log / "out", "wb") as out, open(log / "err", "wb") as err:
        driver = subprocess.Popen(command, cwd=tmp_path, env=env, stdout=out, stderr=err, start_new_session=True)
    deadline = time.monotonic() + 120
    while not list(tmp_path.glob(".lcchain-dask-*/dask-scratch-space/worker-*")) and time.monotonic() < deadline:
        time.sleep(0.1)
    assert list(tmp_path.glob(".lcchain-dask-*")), "the cluster never started"
    assert os.listdir(scratch) == []  # the study's scratch space is beside its store, never in TMPDIR
    os.killpg(driver.pid, signal.SIGKILL)  # the driver and everything in its group, outright
    driver.wait()
    assert gone(driver.pid)
    deadline = time.monotonic() + 30
    while list(tmp_path.glob(".lcchain-dask-*")) and time.monotonic() < deadline:
        time.sleep(0.1)
    assert os.listdir(scratch) == []
    assert sorted(p.name for p in tmp_path.iterdir() if not p.name.startswith("s.sqlite")) == ["log", "tmp"]
