"""``lcchain batch`` carries on past a refused netlist (issue 31, item 1), and counts ``.ac dec``/``oct`` sweeps.

A netlist lcchain will not run (the allow-list, the canonical text, its analysis, its price, an include) is a
stored run of status ``refused`` with its one-line reason; the others run, the summary lists every refusal and
the exit status is 1. ``--strict`` keeps the old behaviour: the first refusal, exit 2, nothing stored; so
does a batch whose every netlist is refused (nothing of it could run).

The frequency counts of logarithmic sweeps follow ngspice's ``ACan`` (``src/spicelib/analysis/acan.c``): from
FSTART multiply by delta while the frequency is at most FSTOP + delta * FSTOP * reltol, where delta is
10^(1/N) or 2^(1/N) (octaves; decades before ngspice 39 and, from ngspice 43, less than a decade apart) or
(FSTOP/FSTART)^(1/floor(log10(FSTOP/FSTART) N)) (decades from ngspice 39, commit 75c2a3c6).
"""

from __future__ import annotations

import json
import os
import sqlite3
from pathlib import Path

import pytest
from helpers.netlists import LADDER
from helpers.tolerances import RTOL_AC_SWEEP_STOP

from lcchain.cli.main import main
from lcchain.core.budget import Budget
from lcchain.core.errors import ParameterError
from lcchain.spice.engines import find_engine
from lcchain.spice.foreign import log_sweep_count
from lcchain.studies.options import RunOptions
from lcchain.studies.plan import batch_plan
from lcchain.studies.run import run_plan
from lcchain.studies.store import Store

#: One LC loop driven by an AC source: every sweep below runs in a few milliseconds.
AC_LOOP = "an LC loop\nV1 1 0 AC 1\nR1 1 2 10\nL1 2 3 1e-3\nC1 3 0 1e-6\n.save i(l1)\n{card}\n.end\n"


def _records(store: Path) -> dict[str, tuple[str, float]]:
    """key -> (status, when it was stored), read-only: a run stored again would change its time."""
    with sqlite3.connect(f"file:{store}?mode=ro", uri=True) as db:
        rows = db.execute("SELECT key, status, finished FROM records").fetchall()
    db.close()
    return {key: (status, finished) for key, status, finished in rows}


def _batch(folder: Path) -> tuple[list[str], dict[str, str], Path]:
    """Two good netlists and one of each kind of refusal: (paths in order, what each refusal names, the marker
    a shell escape would make)."""
    marker = folder.parent / "executed"
    (folder.parent / "outside.inc").write_text("* outside the batch's folder\nR9 n1 0 1\n")
    good = LADDER
    texts = {
        "a.cir": good,
        "control.cir": good.replace(".end\n", f".control\nshell touch {marker}\n.endc\n.end\n"),
        "shell.cir": good.replace(".end\n", f"shell touch {marker}\n.end\n"),
        "tab.cir": good.replace("C12 n1 0 1.0", "C12 n1 0\x0b1.0"),
        "outside.cir": good.replace(".end\n", ".include ../outside.inc\n.end\n"),
        "missing.cir": good.replace(".end\n", ".include nothere.inc\n.end\n"),
        "dear.cir": good.replace(".tran 0.001 7.7 0 0.001 uic", ".tran 1e-9 1e3 0 1e-9 uic"),
        "z.cir": good.replace(".tran 0.001 7.7", ".tran 0.001 7.8"),
    }
    for name, text in texts.items():
        (folder / name).write_text(text)
    names = {"control.cir": "line 12", "shell.cir": "line 12", "tab.cir": "line 3", "outside.cir": "line 12",
             "missing.cir": "line 12", "dear.cir": "would take about"}
    return [str(folder / name) for name in texts], names, marker


@pytest.mark.ngspice
def test_a_batch_runs_its_good_netlists_and_stores_each_refusal_with_its_reason(tmp_path: Path, capsys) -> None:
    folder = tmp_path / "batch"
    folder.mkdir()
    paths, names, marker = _batch(folder)
    store = tmp_path / "s.sqlite"
    command = ["batch", *paths, "--store", str(store), "--executor", "serial", "--max-time", "600"]
    assert main(command) == 1
    out = capsys.readouterr().out
    assert "8 runs" in out and "2 ok, 0 failed, 6 refused" in out
    listed = [line for line in out.splitlines() if line.startswith("refused ")]
    assert len(listed) == 6
    for line, (name, said) in zip(listed, names.items(), strict=True):
        assert line.startswith(f"refused {folder / name}: ") and said in line
    assert not marker.exists()
    with Store(store, "read") as results:
        runs = results.runs()
    assert [run.status for run in runs] == ["ok", "refused", "refused", "refused", "refused", "refused", "refused",
                                            "ok"]
    for run in runs[1:-1]:
        said = names[Path(run.params["netlist"]).name]
        assert said in run.reason and run.params["netlist"] in run.reason and "\n" not in run.reason
    assert "'.control'" in runs[1].reason and "'shell touch" in runs[2].reason and "U+000B" in runs[3].reason
    assert "inside the netlist's folder" in runs[4].reason and "a readable file" in runs[5].reason
    before = _records(store)

    # the same command again: nothing runs, nothing is stored twice, every refusal is reported again
    assert main([*command, "--json"]) == 1
    summary = json.loads(capsys.readouterr().out)
    assert (summary["total"], summary["ran"], summary["skipped"]) == (8, 0, 8)
    assert (summary["ok"], summary["failed"], summary["refused"]) == (2, 0, 6)
    assert [Path(r["netlist"]).name for r in summary["refusals"]] == list(names)
    assert [r["reason"] for r in summary["refusals"]] == [run.reason for run in runs[1:-1]]
    assert _records(store) == before
    # --retry-failed runs failed runs again, not refusals: nothing of them could run
    assert main([*command, "--retry-failed"]) == 1
    capsys.readouterr()
    assert _records(store) == before

    assert main(["results", str(store), "--json"]) == 0
    shown = json.loads(capsys.readouterr().out)
    assert [run["status"] for run in shown].count("refused") == 6
    assert all(run["error"] == stored.reason for run, stored in zip(shown, runs, strict=True)
               if run["status"] == "refused")
    assert main(["results", str(store), "--csv"]) == 0
    csv = capsys.readouterr().out.splitlines()
    assert sum(",refused," in line for line in csv) == 6
    assert main(["results", str(store)]) == 0
    assert "8 runs: 2 ok, 6 refused" in capsys.readouterr().out


@pytest.mark.ngspice
def test_strict_stops_at_the_first_refusal_and_stores_nothing(tmp_path: Path, capsys) -> None:
    folder = tmp_path / "batch"
    folder.mkdir()
    paths, _, marker = _batch(folder)
    store = tmp_path / "s.sqlite"
    assert main(["batch", *paths, "--store", str(store), "--strict", "--max-time", "600"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "control.cir: line 12" in err and "'.control'" in err
    assert not store.exists() and not marker.exists()


def test_a_refusal_costs_no_run_and_the_others_keep_their_price(tmp_path: Path) -> None:
    """The over-budget netlist is refused by the same budget the others are priced against, and the plan's price
    is that of the netlists that run."""
    folder = tmp_path / "batch"
    folder.mkdir()
    paths, names, _ = _batch(folder)
    budget = Budget(max_memory=4e9, max_seconds=600.0)
    plan = batch_plan(paths, budget=budget)
    good = batch_plan([paths[0], paths[-1]], budget=budget)
    assert [task.params["netlist"] for task in plan.tasks] == [paths[0], paths[-1]]
    assert [Path(r.params["netlist"]).name for r in plan.refusals] == list(names)
    assert plan.price(2).seconds == good.price(2).seconds and plan.price(2).memory == good.price(2).memory
    assert plan.estimate() == good.estimate()
    assert "would take about" in plan.refusals[-1].reason
    with pytest.raises(ParameterError, match="control.cir: line 12"):
        batch_plan(paths, budget=budget, strict=True)
    # a refusal's key is its netlist's path and text: the same batch planned again has the same rows
    assert batch_plan(paths, budget=budget).keys("39") == plan.keys("39")


def test_a_batch_of_refusals_alone_is_bad_input(tmp_path: Path) -> None:
    """Nothing of it could run: the first refusal, as with --strict (exit 2 from the command, no store)."""
    folder = tmp_path / "batch"
    folder.mkdir()
    paths, _, _ = _batch(folder)
    with pytest.raises(ParameterError, match="control.cir: line 12"):
        batch_plan(paths[1:-1], budget=Budget(max_memory=4e9, max_seconds=600.0))


@pytest.mark.ngspice
def test_refused_runs_read_back_as_a_dataframe(tmp_path: Path) -> None:
    pd = pytest.importorskip("pandas")
    folder = tmp_path / "batch"
    folder.mkdir()
    paths, _, _ = _batch(folder)
    plan = batch_plan(paths[:2], budget=Budget(max_memory=4e9, max_seconds=600.0))
    summary = run_plan(plan, tmp_path / "r.sqlite", RunOptions(executor="serial"))
    assert (summary.total, summary.ran, summary.refused, summary.ok) == (2, 1, 1, 1) and not summary.complete
    with Store(tmp_path / "r.sqlite", "read") as store:
        frame = store.to_dataframe()
    assert isinstance(frame, pd.DataFrame) and list(frame["status"]) == ["ok", "refused"]


@pytest.mark.parametrize(("spacing", "per", "start", "stop", "reltol", "version", "count"), [
    # a whole number of decades: 3 decades x 10 + FSTART, in every version (acan.c, before and after 75c2a3c6)
    ("dec", 10, 1.0, 1000.0, 1e-3, 38, 31),
    ("dec", 10, 1.0, 1000.0, 1e-3, 39, 31),
    ("dec", 10, 1.0, 1000.0, 1e-3, 43, 31),
    # a wide reltol lets one frequency past FSTOP: 1000 * 10^0.1 <= 1000 + 1000 * 10^0.1 * 0.3
    ("dec", 10, 1.0, 1000.0, 0.3, 39, 32),
    # less than a decade: ngspice 39 spreads floor(3 * log10 9.99) = 2 steps from 1 to 9.99; before 39 and from
    # 43 it steps by 10^(1/3): 1, 2.15, 4.64, 10.0 <= 9.99 + 2.15 * 9.99e-3
    ("dec", 3, 1.0, 9.99, 1e-3, 38, 4),
    ("dec", 3, 1.0, 9.99, 1e-3, 39, 3),
    ("dec", 3, 1.0, 9.99, 1e-3, 43, 4),
    # log10(100000 / 3) * 7 = 31.66: 31 steps, 32 frequencies, from ngspice 39
    ("dec", 7, 3.0, 1e5, 1e-3, 39, 32),
    # octaves never changed: log2(100) * 5 = 33.2, 34 frequencies; 1000 * 2^0.2 > 1000 (1 + 2^0.2 * 1e-3)
    ("oct", 5, 10.0, 1000.0, 1e-3, 39, 34),
    ("oct", 12, 100.0, 101.0, 1e-3, 39, 1),
])
def test_a_log_sweep_is_counted_as_ngspice_counts_it(spacing, per, start, stop, reltol, version, count) -> None:
    assert log_sweep_count(spacing, per, start, stop, reltol=reltol, version=version) == count


def test_a_dec_sweep_ngspice_39_would_never_end_is_refused(tmp_path: Path) -> None:
    """ngspice 39 computes floor(3 log10 1.5) = 0 steps, divides by them and sweeps inf Hz until killed."""
    with pytest.raises(ParameterError, match="never ends"):
        log_sweep_count("dec", 3, 1.0, 1.5, version=39)
    assert log_sweep_count("dec", 3, 1.0, 1.5, version=43) == 1  # 1.5 < 10^(1/3) (1 + 1e-3)
    path = tmp_path / "short.cir"
    path.write_text(AC_LOOP.format(card=".ac dec 3 1 1.5"))
    with pytest.raises(ParameterError, match="short.cir: line 7.*never ends"):
        batch_plan([path], engine_version=lambda: "39")


@pytest.mark.ngspice
@pytest.mark.parametrize("card", [".ac dec 10 1e3 1e6", ".ac dec 7 3e3 1e6", ".ac oct 5 1e3 1e5",
                                  ".ac dec 3 1e3 9.99e3", ".options reltol=0.3\n.ac oct 12 1e3 1.01e3"])
def test_a_foreign_log_sweep_runs_and_stores_as_many_frequencies_as_ngspice_makes(tmp_path: Path, card: str) -> None:
    """The count is the planner's (from the card and the installed ngspice's version); the run reads back
    ngspice's own frequency vector, whose length must be that count (:func:`lcchain.spice.acdata.ac_result`
    refuses any other), and stores it."""
    path = tmp_path / "sweep.cir"
    path.write_text(AC_LOOP.format(card=card))
    (task,) = batch_plan([path]).tasks
    assert main(["batch", str(path), "--store", str(tmp_path / "s.sqlite"), "--executor", "serial"]) == 0
    with Store(tmp_path / "s.sqlite", "read") as store:
        (run,) = store.runs()
        arrays = store.waveforms(run.key)
    assert run.status == "ok" and arrays is not None
    assert run.points == task.spec.points == arrays["frequency"].size
    words = card.split()
    assert arrays["frequency"][0] == float(words[-2])
    decades = float(words[-1]) / float(words[-2]) >= 10.0
    if card.startswith(".ac dec") and decades and int(find_engine().version.split(".")[0]) >= 39:
        assert arrays["frequency"][-1] == pytest.approx(float(words[-1]), rel=RTOL_AC_SWEEP_STOP)  # FSTOP, exactly included


@pytest.mark.ngspice
def test_names_that_are_no_utf_8_or_hold_a_newline_run_or_are_refused_on_one_line(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """A name of Latin-1 bytes (a legal Linux name) runs, shown and stored with that byte escaped; a refused name
    holding a newline is still one line of the summary; the JSON counts one refusal per refused run."""
    folder = os.fsencode(tmp_path)
    latin = os.fsdecode(folder + b"/caf\xe9.cir")
    Path(latin).write_text(LADDER)
    broken = tmp_path / "two\nlines.cir"
    broken.write_text(LADDER.replace(".end\n", ".control\n.endc\n.end\n"))
    store = tmp_path / "s.sqlite"
    assert main(["batch", latin, str(broken), str(broken), "--store", str(store)]) == 1
    said = capsys.readouterr().out.splitlines()
    assert said[0].startswith("2 runs in") and "1 ok" in said[0] and "1 refused" in said[0]
    assert len(said) == 2 and said[1].startswith(f"refused {tmp_path}/two\\nlines.cir: ")
    assert main(["results", str(store), "--json"]) == 0
    rows = json.loads(capsys.readouterr().out)
    assert [row["label"] for row in rows] == ["caf\\xe9.cir", "two\\nlines.cir", "two\\nlines.cir"]
    store.unlink()
    assert main(["batch", latin, str(broken), str(broken), "--store", str(store), "--json"]) == 1
    summary = json.loads(capsys.readouterr().out)
    assert summary["refused"] == len(summary["refusals"]) == 1


@pytest.mark.ngspice
def test_a_plan_held_in_memory_names_and_counts_its_refusals_as_the_streamed_one(tmp_path: Path) -> None:
    """The plan a Dask batch holds (``batch_plan``): the same shown names, one refusal per refused run."""
    latin = os.fsdecode(os.fsencode(tmp_path) + b"/caf\xe9.cir")
    Path(latin).write_text(LADDER)
    broken = tmp_path / "two\nlines.cir"
    broken.write_text(LADDER.replace(".end\n", ".control\n.endc\n.end\n"))
    plan = batch_plan([latin, str(broken), str(broken)])
    assert [task.params["netlist"] for task in plan.tasks] == [f"{tmp_path}/caf\\xe9.cir"]
    assert [task.spec.label for task in plan.tasks] == ["caf\\xe9.cir"]
    assert [r.params["netlist"] for r in plan.refusals] == [f"{tmp_path}/two\\nlines.cir"] * 2
    summary = run_plan(plan, tmp_path / "s.sqlite", RunOptions(executor="serial"))
    assert summary.ok == summary.refused == len(summary.refusals) == 1


@pytest.mark.ngspice
def test_a_store_of_another_batch_says_what_differs(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """The same netlist resumed with --check, then with one more netlist: the refusal names what changed."""
    (tmp_path / "a.cir").write_text(LADDER)
    (tmp_path / "b.cir").write_text(LADDER.replace(".tran 0.001 7.7", ".tran 0.001 7.8"))
    store = str(tmp_path / "s.sqlite")
    assert main(["batch", str(tmp_path / "a.cir"), "--store", store]) == 0
    capsys.readouterr()
    assert main(["batch", str(tmp_path / "a.cir"), "--store", store, "--check"]) == 2
    assert "; this one differs in check: true, the store's none)" in capsys.readouterr().err
    assert main(["batch", str(tmp_path / "a.cir"), str(tmp_path / "b.cir"), "--store", store]) == 2
    said = capsys.readouterr().err  # each list clipped at 80 characters, the message one line
    assert "; this one differs in netlists: [" in said and "the store's [" in said and said.count("\n") == 1
    many = [str(tmp_path / "a.cir")] * 200  # one run, a long description: the message stays a line to read
    assert main(["batch", *many, "--store", str(tmp_path / "many.sqlite")]) == 0
    capsys.readouterr()
    assert main(["batch", *many, "--store", str(tmp_path / "many.sqlite"), "--check"]) == 2
    said = capsys.readouterr().err
    assert "differs in check" in said and len(said) < 200 + 2 * len(str(tmp_path)) + 400


@pytest.mark.ngspice
def test_a_summary_of_runs_that_all_failed_says_so_not_to_resume(tmp_path: Path,
                                                                  capsys: pytest.CaptureFixture[str]) -> None:
    """Two voltage sources in parallel fail in ngspice; a .control is refused: both finished, neither ok, and the
    same command would not run them again."""
    (tmp_path / "loop.cir").write_text("two sources in parallel\nV1 a 0 1\nV2 a 0 2\nR1 a 0 1k\n.tran 1u 10u\n.end\n")
    (tmp_path / "control.cir").write_text(LADDER.replace(".end\n", ".control\n.endc\n.end\n"))
    store = str(tmp_path / "s.sqlite")
    assert main(["batch", str(tmp_path / "loop.cir"), str(tmp_path / "control.cir"), "--store", store]) == 1
    capsys.readouterr()
    assert main(["results", store, "--summary", "--metric", "peak"]) == 2
    said = capsys.readouterr().err
    assert "none did: 1 failed, 1 refused" in said and "--retry-failed" in said and "resume" not in said
    assert main(["results", store, "--json"]) == 0
    engines = {row["status"]: (row["engine"], row["engine_version"]) for row in json.loads(capsys.readouterr().out)}
    assert engines["refused"] == ("ngspice", "") and engines["failed"][0] == "ngspice" and engines["failed"][1]
