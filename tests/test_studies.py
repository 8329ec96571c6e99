"""Studies at scale, with real ngspice and a real Dask (issue 11).

Every executor gives the same digests; a killed driver loses no finished run
and a restarted one redoes none; a killed Dask worker costs nothing but time;
a run ngspice rejects becomes one failed record; an unsafe netlist is refused
before anything runs; a timeout leaves no ngspice running; the cluster path
works against a ``dask scheduler`` and ``dask worker`` started on 127.0.0.1.
"""

from __future__ import annotations

import json
import os
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from helpers.netlists import stored_records
from helpers.processes import alive, descendants
from helpers.tolerances import MAX_SWEEP_RUN_ERROR, RTOL_ARITHMETIC

from lcchain.cli import main
from lcchain.core.budget import Budget
from lcchain.studies.options import RunOptions
from lcchain.studies.plan import RealParts, SweepAxes, batch_plan, sweep_plan
from lcchain.studies.run import run_plan
from lcchain.studies.store import Store

ROOT = Path(__file__).resolve().parent.parent
DASK = Path(sys.executable).parent / "dask"
#: A small sweep: 2 cases x 3 sizes x 2 steps = 12 runs of a fraction of a second.
SMALL = dict(cases=["one-mass", "two-mass"], Ns=[20, 40, 60], dts=[0.05, 0.03])
#: The sweep a killed driver leaves half done: 16 runs of about half a second.
LONG = ["--case", "two-mass", "--N", "100,150,200,250", "--dt", "0.02,0.025,0.03,0.04"]

pytestmark = pytest.mark.ngspice


def _digests(path: Path) -> list[str]:
    with Store(path) as store:
        return [run.digest for run in store.runs()]


@pytest.fixture(scope="module")
def serial_store(tmp_path_factory: pytest.TempPathFactory) -> Path:
    path = tmp_path_factory.mktemp("serial") / "s.sqlite"
    summary = run_plan(sweep_plan(SweepAxes(**SMALL)), path, RunOptions(executor="serial"))
    assert (summary.total, summary.ran, summary.ok) == (12, 12, 12)
    return path


@pytest.mark.parametrize("executor", ["process", "dask"])
def test_every_executor_stores_the_same_digests(serial_store: Path, tmp_path: Path, executor: str) -> None:
    path = tmp_path / f"{executor}.sqlite"
    summary = run_plan(sweep_plan(SweepAxes(**SMALL)), path, RunOptions(executor=executor, workers=2))
    assert summary.to_dict() | {"wall_s": 0} == {"total": 12, "skipped": 0, "ran": 12, "ok": 12, "failed": 0,
                                                 "combined": 0, "combined_failed": 0, "pending": 0,
                                                 "refused": 0, "refusals": [], "store": str(path), "wall_s": 0}
    assert _digests(path) == _digests(serial_store) and all(len(d) == 64 for d in _digests(path))
    again = run_plan(sweep_plan(SweepAxes(**SMALL)), path, RunOptions(executor=executor, workers=2))
    assert (again.skipped, again.ran) == (12, 0)  # a finished study runs nothing


def test_a_sweep_planned_on_its_started_pool_is_the_serial_one(serial_store: Path, tmp_path: Path) -> None:
    """Issue 35: the pool's workers start first and design the chains while the driver plans, then run the
    study; the plan (its keys hold every netlist) and the stored digests are those of the serial study."""
    from lcchain.studies.pools import started_pool

    path = tmp_path / "started.sqlite"
    with started_pool(2) as pool:
        plan = sweep_plan(SweepAxes(**SMALL), pool=pool)
        summary = run_plan(plan, path, RunOptions(executor="process", workers=2, pool=pool))
    assert (summary.ran, summary.ok) == (12, 12)
    assert plan.fingerprint("39") == sweep_plan(SweepAxes(**SMALL)).fingerprint("39")
    assert _digests(path) == _digests(serial_store)


def test_a_store_of_another_plan_is_refused(serial_store: Path, capsys: pytest.CaptureFixture[str]) -> None:
    status = main(["sweep", "--case", "two-mass", "--N", "20", "--store", str(serial_store)])
    err = capsys.readouterr().err
    assert status == 2 and "holds another" in err and "never mixes" in err


def test_results_json_lists_every_run_in_task_order(serial_store: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["results", str(serial_store), "--json"]) == 0
    runs = json.loads(capsys.readouterr().out)
    assert [r["index"] for r in runs] == list(range(12))
    for run in runs:
        assert {"index", "key", "status", "params", "digest", "max_abs_error", "arrivals", "wall_s"} <= run.keys()
        assert run["status"] == "ok" and run["max_abs_error"] < MAX_SWEEP_RUN_ERROR
    assert runs[0]["params"] == {"case": "one-mass", "N": 20, "dt": 0.05, "transits": 1, "excitation": "kick"}
    assert main(["results", str(serial_store), "--csv"]) == 0
    header = capsys.readouterr().out.splitlines()[0].split(",")
    assert {"index", "status", "case", "N", "dt", "digest", "peak_sim"} <= set(header)


@pytest.mark.slow  # 22 s: a long sweep killed mid-way and resumed (test_boundary_stores kills one run in 5 s)
def test_a_killed_driver_loses_no_finished_run_and_redoes_none(tmp_path: Path) -> None:
    store = tmp_path / "long.sqlite"
    command = [sys.executable, "-m", "lcchain", "sweep", *LONG, "--store", str(store), "--workers", "2"]
    env = dict(os.environ, TMPDIR=str(tmp_path))
    driver = subprocess.Popen(command, cwd=tmp_path, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    deadline = time.monotonic() + 120
    while stored_records(store) < 4 and time.monotonic() < deadline and driver.poll() is None:
        time.sleep(0.1)
    family = descendants(driver.pid)
    driver.send_signal(signal.SIGKILL)
    driver.wait(timeout=30)
    kept = stored_records(store)
    assert 4 <= kept < 16, "the sweep was not caught half way"
    time.sleep(1.0)  # the kernel's parent-death signals arrive
    assert [pid for pid in family if alive(pid)] == [], f"workers or ngspice outlived the driver: {family}"
    resumed = subprocess.run([*command, "--json"], cwd=tmp_path, env=env, capture_output=True, text=True,
                             timeout=600)
    summary = json.loads(resumed.stdout)
    assert resumed.returncode == 0, resumed.stderr
    assert (summary["skipped"], summary["ran"], summary["ok"]) == (kept, 16 - kept, 16)
    assert f"{kept} of 16 runs are stored, {16 - kept} to run" in resumed.stderr
    reference = tmp_path / "reference.sqlite"
    assert main(["sweep", *LONG, "--store", str(reference), "--executor", "serial"]) == 0
    assert _digests(store) == _digests(reference)
    assert [p.name for p in tmp_path.iterdir() if not p.name.endswith((".sqlite", "-wal", "-shm"))] == []


def test_a_rejected_netlist_is_one_failed_record(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    good = (ROOT / "netlists" / "perfect-N4.cir").read_text()
    (tmp_path / "good.cir").write_text(good)
    (tmp_path / "bad.cir").write_text(good.replace("C2_3 n2 0 1e-08", "C2_3 n2 0 1.0.0"))  # allowed, yet wrong
    (tmp_path / "also.cir").write_text((ROOT / "netlists" / "perfect-N3.cir").read_text())
    names = [str(tmp_path / n) for n in ("good.cir", "bad.cir", "also.cir")]
    status = main(["batch", *names, "--store", str(tmp_path / "b.sqlite"), "--executor", "serial", "--json"])
    summary = json.loads(capsys.readouterr().out)
    assert status == 1 and (summary["ok"], summary["failed"]) == (2, 1)
    with Store(tmp_path / "b.sqlite") as store:
        runs = store.runs()
        assert [r.status for r in runs] == ["ok", "failed", "ok"]
        assert "can't find model" in runs[1].reason + runs[1].log_tail
        waveforms = store.waveforms(runs[0].key)
    assert waveforms is not None and {"time", "i(l1)", "i(l4)"} <= waveforms.keys()


@pytest.mark.parametrize("line", [".control\nshell touch {marker}\n.endc", ".include /etc/passwd"])
def test_an_unsafe_netlist_is_refused_before_anything_runs(tmp_path: Path, line: str,
                                                          capsys: pytest.CaptureFixture[str]) -> None:
    marker = tmp_path / "executed"
    good = (ROOT / "netlists" / "perfect-N3.cir").read_text()
    (tmp_path / "a.cir").write_text(good)
    (tmp_path / "z.cir").write_text(good.replace(".end\n", line.format(marker=marker) + "\n.end\n"))
    batch = ["batch", str(tmp_path / "a.cir"), str(tmp_path / "z.cir"), "--executor", "serial"]
    status = main([*batch, "--store", str(tmp_path / "u.sqlite"), "--strict"])
    err = capsys.readouterr().err
    assert status == 2 and "z.cir: line" in err and "--allow-control" in err
    assert not (tmp_path / "u.sqlite").exists() and not marker.exists()
    # without --strict: a.cir runs, z.cir is stored as refused, and still nothing of it runs
    assert main([*batch, "--store", str(tmp_path / "c.sqlite")]) == 1
    assert "z.cir: line" in capsys.readouterr().out and not marker.exists()
    with Store(tmp_path / "c.sqlite") as store:
        assert [run.status for run in store.runs()] == ["ok", "refused"]


def test_a_spiceinit_beside_a_netlist_is_never_read(tmp_path: Path) -> None:
    """ngspice runs a foreign netlist in an empty scratch folder with -n: an init file beside it does nothing."""
    (tmp_path / "a.cir").write_text((ROOT / "netlists" / "perfect-N3.cir").read_text())
    (tmp_path / ".spiceinit").write_text(f"shell touch {tmp_path / 'executed'}\n")
    summary = run_plan(batch_plan([tmp_path / "a.cir"], allow_control=True), tmp_path / "s.sqlite")
    assert summary.ok == 1 and not (tmp_path / "executed").exists()


def test_a_timeout_is_a_record_and_leaves_no_ngspice(tmp_path: Path) -> None:
    endless = (ROOT / "netlists" / "perfect-N3.cir").read_text()
    endless = "\n".join(line if not line.startswith(".tran") else ".tran 1e-10 1.0 0 1e-10 uic"
                        for line in endless.splitlines()) + "\n"
    (tmp_path / "endless.cir").write_text(endless)
    plan = batch_plan([tmp_path / "endless.cir"], timeout=1.0, budget=Budget(1e15, 1e7))  # priced far beyond 1 s
    before = set(descendants(os.getpid()))
    summary = run_plan(plan, tmp_path / "t.sqlite", RunOptions(executor="process", workers=1))
    assert (summary.failed, summary.ok) == (1, 0)
    with Store(tmp_path / "t.sqlite") as store:
        (run,) = store.runs()
    assert run.status == "timeout" and "timed out after 1 s" in run.reason
    assert run.wall_s is not None and run.wall_s >= 1.0  # the time it took (it said 0.0: a cost of nothing)
    assert [p for p, name in descendants(os.getpid()).items() if p not in before and name == "ngspice"] == []


def test_run_workers_gives_the_serial_result(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                             capsys: pytest.CaptureFixture[str]) -> None:
    monkeypatch.chdir(tmp_path)
    (tmp_path / "mc.toml").write_text('[chain]\ncase = "two-mass"\nN = 12\n[effects.tolerance]\nL = 0.02\nC = 0.02\n'
                                      'samples = 6\nseed = 5\n[output]\nplots = []\n')
    assert main(["run", "mc.toml", "--json"]) == 0
    serial = json.loads(capsys.readouterr().out)
    assert main(["run", "mc.toml", "--json", "--workers", "2"]) == 0
    parallel = json.loads(capsys.readouterr().out)
    assert [s["digest"] for s in parallel["samples"]] == [s["digest"] for s in serial["samples"]]
    assert parallel["transmitted_peak"] == serial["transmitted_peak"]


def test_a_scene_sweep_varies_keys_and_makes_each_sample_a_task(tmp_path: Path,
                                                                capsys: pytest.CaptureFixture[str]) -> None:
    scene = tmp_path / "bench.toml"
    scene.write_text('[chain]\ncase = "two-mass"\nN = 10\n[effects.losses]\nQ = 50\n[effects.tolerance]\nL = 0.01\n'
                     '[output]\nplots = []\n')
    store = tmp_path / "v.sqlite"
    status = main(["sweep", str(scene), "--vary", "chain.N=10,14", "--vary", "effects.losses.Q=50,100",
                   "--samples", "3", "--seed", "2", "--store", str(store), "--executor", "serial", "--json"])
    assert status == 0 and json.loads(capsys.readouterr().out)["total"] == 12
    with Store(store) as results:
        params = [run.params for run in results.runs()]
    assert params[0] == {"chain.N": 10, "effects.losses.Q": 50, "sample": 1}
    assert params[-1] == {"chain.N": 14, "effects.losses.Q": 100, "sample": 3}
    assert main(["results", str(store), "--plot", str(tmp_path / "h.png")]) == 0
    assert (tmp_path / "h.png").stat().st_size > 10_000


def test_joined_keys_vary_together() -> None:
    from lcchain.studies.plan import parse_vary, scene_sweep_plan

    key, values = parse_vary(" effects.tolerance.L + effects.tolerance.C = 0.0, 0.05")
    assert (key, values) == ("effects.tolerance.L+effects.tolerance.C", [0.0, 0.05])
    plan = scene_sweep_plan(ROOT / "examples" / "scenes" / "real-parts.toml", [(key, values)], RealParts(samples=2))
    netlists = {(t.params[key], t.params["sample"]): t.spec.netlist for t in plan.tasks}

    def values_of(text: str, kind: str) -> list[str]:
        return [line.split()[3] for line in text.splitlines() if line.startswith(kind)]

    for kind in ("L", "C"):  # with 5 % both the inductors and the capacitors change between samples; with 0 neither
        assert values_of(netlists[0.0, 1], kind) == values_of(netlists[0.0, 2], kind)
        assert values_of(netlists[0.05, 1], kind) != values_of(netlists[0.05, 2], kind)


def test_two_designs_under_real_parts_side_by_side(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """The issue-13 study in small: perfect against two-mass, N = 20, E24, 1 % and 5 %, 6 samples each."""
    store = tmp_path / "parts.sqlite"
    status = main(["sweep", str(ROOT / "examples" / "scenes" / "real-parts.toml"), "--vary", "chain.N=20",
                   "--vary", "chain.case=perfect,two-mass", "--vary", "effects.tolerance.L+effects.tolerance.C=0.01,0.05",
                   "--samples", "6", "--store", str(store), "--executor", "serial", "--json"])
    assert status == 0 and json.loads(capsys.readouterr().out)["ok"] == 24
    assert main(["results", str(store), "--summary", "--metric", "energy", "--json"]) == 0
    groups = json.loads(capsys.readouterr().out)
    assert [g["n"] for g in groups] == [6, 6, 6, 6]
    energy = {(g["params"]["chain.case"], g["params"]["effects.tolerance.L+effects.tolerance.C"]): g for g in groups}
    for group in groups:  # a lossless chain never gives its last inductor more than the kick's energy
        assert 0.9 < group["min"] <= group["max"] <= 1.0
    for tolerance in (0.01, 0.05):  # perfect keeps more than the optimum's 1 - delta*^2 ~ 0.97 at N = 20
        assert energy["perfect", tolerance]["mean"] > energy["two-mass", tolerance]["mean"]
    assert energy["two-mass", 0.05]["std"] > energy["two-mass", 0.01]["std"]
    assert main(["results", str(store), "--summary", "--csv"]) == 0
    header = capsys.readouterr().out.splitlines()[0]
    assert header.startswith("chain.case,effects.tolerance.L+effects.tolerance.C,n,failed,mean")  # N: one value
    assert main(["results", str(store), "--summary"]) == 0
    title, columns = capsys.readouterr().out.splitlines()[:2]
    assert "N = 20 throughout" in title and columns.split() == ["case", "L+C", "n", "failed", "mean", "std", "min",
                                                                "p05", "median", "max"]
    assert main(["results", str(store), "--metric", "energy", "--plot", str(tmp_path / "parts.png")]) == 0
    assert (tmp_path / "parts.png").stat().st_size > 20_000


def test_a_sweep_over_N_draws_fig_delta(serial_store: Path, tmp_path: Path) -> None:
    assert main(["results", str(serial_store), "--plot", str(tmp_path / "delta.svg")]) == 0
    assert "Fig. delta" in (tmp_path / "delta.svg").read_text() or (tmp_path / "delta.svg").stat().st_size > 10_000


# ------------------------------------------------------------------ a real cluster on 127.0.0.1


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def _start(command: list[str], log: Path) -> subprocess.Popen[bytes]:
    with log.open("wb") as output:  # the child keeps its own copy of the descriptor
        return subprocess.Popen(command, stdout=output, stderr=subprocess.STDOUT, cwd=log.parent,
                                start_new_session=True)


def _stop(processes: list[subprocess.Popen[bytes]]) -> None:
    for proc in processes:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGTERM)
    for proc in processes:
        try:
            proc.wait(timeout=20)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()


@pytest.mark.slow  # 40 s: a cluster of its own, and a worker killed and replaced
def test_an_existing_cluster_runs_the_study_and_survives_a_killed_worker(serial_store: Path, tmp_path: Path) -> None:
    port = _free_port()
    address = f"tcp://127.0.0.1:{port}"
    scheduler = _start([str(DASK), "scheduler", "--host", "127.0.0.1", "--port", str(port),
                        "--dashboard-address", ":0", "--no-show"], tmp_path / "scheduler.log")
    processes = [scheduler]
    try:
        for n in range(2):
            processes.append(_start([str(DASK), "worker", address, "--nthreads", "1", "--nworkers", "1",
                                     "--host", "127.0.0.1", "--no-nanny", "--name", f"w{n}",
                                     "--dashboard-address", ":0"], tmp_path / f"worker{n}.log"))
        from distributed import Client

        with Client(address, timeout=60) as client:
            client.wait_for_workers(2, timeout=60)
        store = tmp_path / "cluster.sqlite"
        command = [sys.executable, "-m", "lcchain", "sweep", *LONG, "--store", str(store), "--executor", "dask",
                   "--scheduler", address, "--json"]
        driver = subprocess.Popen(command, cwd=tmp_path, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
        deadline = time.monotonic() + 120
        while stored_records(store) < 3 and time.monotonic() < deadline and driver.poll() is None:
            time.sleep(0.1)
        os.killpg(processes[1].pid, signal.SIGKILL)  # one worker dies mid-study
        out, err = driver.communicate(timeout=600)
        summary = json.loads(out)
        assert driver.returncode == 0, err.decode()
        assert (summary["ran"], summary["ok"], summary["failed"]) == (16, 16, 0)
        reference = tmp_path / "reference.sqlite"
        assert main(["sweep", *LONG, "--store", str(reference), "--executor", "serial"]) == 0
        assert _digests(store) == _digests(reference)
    finally:
        _stop(processes)


def test_a_store_reads_back_as_a_dataframe_and_a_dataset(serial_store: Path) -> None:
    """The Python API beside the CLI; pandas and xarray are optional (the test extra has them)."""
    with Store(serial_store) as store:
        frame = store.to_dataframe()
        dataset = store.to_xarray()
    assert len(frame) == 12 and {"case", "N", "dt", "status", "digest", "peak_sim"} <= set(frame.columns)
    assert set(frame["status"]) == {"ok"} and sorted(set(frame["N"])) == [20, 40, 60]
    # the study's axes are the dataset's dimensions; a constant parameter is an attribute
    assert dict(dataset.sizes) == {"case": 2, "N": 3, "dt": 2} and dataset.attrs["transits"] == "1"
    for _, row in frame.iterrows():
        cell = dataset.sel(case=row["case"], N=row["N"], dt=row["dt"])
        assert cell["key"].item() == row["key"] and cell["max_abs_error"].item() == row["max_abs_error"]


def test_a_study_goes_to_netcdf_on_its_axes_with_its_waveforms(serial_store: Path, tmp_path: Path,
                                                               capsys: pytest.CaptureFixture[str]) -> None:
    xarray = pytest.importorskip("xarray")  # the data extra; the test extra has it
    target = tmp_path / "s.nc"
    assert main(["results", str(serial_store), "--netcdf", str(target), "--waveforms"]) == 0
    assert capsys.readouterr().out.count("\n") == 1  # one line: what was written, not every run
    with Store(serial_store, "read") as store, xarray.open_dataset(target) as dataset, \
            xarray.open_dataset(target, group="transient") as waves:
        assert dict(dataset.sizes) == {"case": 2, "N": 3, "dt": 2}  # the waveforms are in their own group
        assert dataset.attrs["Conventions"] == "CF-1.10" and {"title", "history"} <= set(dataset.attrs)
        runs = store.runs()
        # issue 33: one run after another (CF's contiguous ragged array), nothing padded to the longest run
        assert dict(waves.sizes) == {"run": len(runs), "obs": sum(r.points for r in runs)}
        assert waves["time"].attrs["units"] == "s" and waves["i_l1"].attrs["units"] == "A"
        assert waves["row_size"].attrs["sample_dimension"] == "obs"
        # CF 9: a discrete sampling geometry, each run's time series named by its key; CF 5: no coordinate has a
        # fill value (xarray gives a float one by default)
        assert waves.attrs["featureType"] == "timeSeries" and waves["key"].attrs["cf_role"] == "timeseries_id"
        assert all("_FillValue" not in dataset[name].encoding for name in dataset.coords)
        assert "references" not in dataset.attrs  # CF's is for published references: the note is a comment
        starts = np.concatenate(([0], np.cumsum(waves["row_size"].values)[:-1]))
        by_index = {int(i): (int(start), int(size)) for i, start, size in
                    zip(waves["index"].values, starts, waves["row_size"].values, strict=True)}
        for run in runs:
            cell = dataset.sel(case=run.params["case"], N=run.params["N"], dt=run.params["dt"])
            arrays = store.waveforms(run.key)
            assert cell["digest"].item() == run.digest and cell["points"].item() == run.points
            assert cell["engine"].item() == "ngspice" and cell["engine_version"].item() == run.engine_version
            start, size = by_index[run.index]
            for name, values in arrays.items():
                saved = waves[name.replace("(", "_").replace(")", "")].values[start:start + size]
                assert np.array_equal(saved, values)
    assert main(["results", str(serial_store), "--waveforms"]) == 2
    assert "--waveforms" in capsys.readouterr().err


@pytest.mark.ngspice
def test_a_metric_the_store_cannot_give_is_refused_before_anything_prints(tmp_path: Path,
                                                                          capsys: pytest.CaptureFixture[str]) -> None:
    """Issue 22: `results --summary --metric energy` on a pulse study printed an empty table and exited 0."""
    scene = tmp_path / "pulse.toml"
    scene.write_text('[chain]\ncase = "two-mass"\nN = 10\n[excitation]\nkind = "pulse"\nshape = "rect"\n'
                     'width = 0.5\n[analysis]\ndt = 0.05\n')
    store = tmp_path / "pulse.sqlite"
    assert main(["sweep", str(scene), "--vary", "chain.N=10,12", "--store", str(store)]) == 0
    capsys.readouterr()
    for metric in ("energy", "loss"):
        for extra in (["--summary"], ["--plot", str(tmp_path / "p.png")]):
            assert main(["results", str(store), "--metric", metric, *extra]) == 2
            captured = capsys.readouterr()
            assert captured.out == "" and "--metric" in captured.err and "peak" in captured.err
    assert not (tmp_path / "p.png").exists()
    assert main(["results", str(store), "--summary", "--metric", "peak"]) == 0
    assert "first-arrival peak" in capsys.readouterr().out


def test_results_json_gives_each_arrival_in_seconds_too(serial_store: Path, capsys) -> None:
    """Issue 33: a sweep states its L0 and C0, so its arrivals' times are also in seconds, beside the bulk ones."""
    assert main(["results", str(serial_store), "--json"]) == 0
    runs = json.loads(capsys.readouterr().out)
    tau = (1e-5 * 1e-8) ** 0.5  # the sweep's default L0 and C0
    for run in runs:
        for arrival in run["arrivals"]:
            assert arrival["t_sim_s"] == pytest.approx(arrival["t_sim"] * tau, rel=RTOL_ARITHMETIC)


@pytest.mark.parametrize("scene_from", ["file", "options"])
def test_a_scene_sweep_takes_the_timeout_given(scene_from: str) -> None:
    """``sweep SCENE --timeout S`` (and a scene made from the options) limits every run to S seconds: each run keeps
    the smaller of its own limit and S, and its key is the same, so a study resumes under another timeout."""
    from lcchain.app.studies import StudyOptions
    from lcchain.app.sweep import SweepRequest, plan_sweep

    asked: dict[str, Any]
    if scene_from == "file":
        asked = {"scene": str(ROOT / "examples" / "scenes" / "real-parts.toml"), "vary": ["chain.N=10,12"],
                 "samples": 2}
    else:
        asked = {"case": ["two-mass"], "N": [10, 12], "tolerance": {"L": 0.01, "C": 0.01}, "samples": 2}
    free = plan_sweep(SweepRequest(**asked)).plan
    limited = plan_sweep(SweepRequest(**asked, study=StudyOptions(timeout=0.5))).plan
    assert len(limited.tasks) == len(free.tasks) >= 4
    assert all(task.spec.timeout > 0.5 for task in free.tasks)
    assert all(task.spec.timeout == 0.5 for task in limited.tasks)
    assert [task.spec.key("39") for task in limited.tasks] == [task.spec.key("39") for task in free.tasks]


def test_a_summary_group_of_one_run_has_no_spread(serial_store: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """Every group of a plain sweep holds one run: its ddof-1 standard deviation is undefined (null, a blank
    cell), not 0, which would read as no spread at all."""
    capsys.readouterr()
    assert main(["results", str(serial_store), "--summary", "--json"]) == 0
    groups = json.loads(capsys.readouterr().out)
    assert len(groups) == 12 and all(g["n"] == 1 and g["std"] is None and g["mean"] is not None for g in groups)
    assert main(["results", str(serial_store), "--summary", "--csv"]) == 0
    rows = capsys.readouterr().out.splitlines()
    std = rows[0].split(",").index("std")
    assert all(row.split(",")[std] == "" for row in rows[1:])
