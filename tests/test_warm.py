"""The warm transport (issue 23): ngspice's shared library loaded once per worker, with real ngspice.

Its runs must be those of ``ngspice -b`` to the bit (so that keys and digests do not depend on the transport),
one netlist must not change the next, a failure or a crash must fail that run only, a timeout must kill the
worker, and nothing may outlive a study.
"""

from __future__ import annotations

import json
import os
import signal
import sqlite3
import subprocess
import sys
import threading
import time
from dataclasses import replace
from pathlib import Path
from typing import Any

import pytest
from helpers.processes import alive, as_from_a_terminal, descendants, gone, reaped
from helpers.tolerances import RTOL_WORKER_RESIDENT

import lcchain
from lcchain.core.errors import ParameterError, SimulationError, SimulatorMissingError
from lcchain.runs.simulate import ChainOptions, simulation_spec
from lcchain.spice.job import RunJob
from lcchain.spice.ngspice import warm
from lcchain.spice.ngspice.find import find_simulator
from lcchain.spice.ngspice.runner import run
from lcchain.spice.result import RunResult
from lcchain.spice.simulator import Simulator
from lcchain.studies.executors import Transports, choose_transports
from lcchain.studies.options import RunOptions
from lcchain.studies.plan import batch_plan
from lcchain.studies.run import run_plan

pytestmark = pytest.mark.ngspice


@pytest.fixture(scope="module")
def simulators() -> tuple[Simulator, Simulator]:
    batch = find_simulator("batch")
    try:
        return batch, warm.warm_simulator(batch)
    except SimulatorMissingError as error:
        pytest.fail(f"the warm transport needs ngspice's shared library of the same version: {error}")


@pytest.fixture(autouse=True)
def _no_worker_outlives_a_test():
    yield
    warm.close_workers(kill=True)


def _netlist(N: int, dt: float = 0.05, transits: int = 1) -> tuple[str, tuple[str, ...], float]:
    spec, _, _ = simulation_spec(lcchain.chain_for_case("two-mass", N), ChainOptions(dt=dt, transits=transits))
    return spec.netlist, spec.vectors, spec.tstop


def _same(a: RunResult, b: RunResult) -> bool:
    return (a.time.tobytes() == b.time.tobytes() and set(a.vectors) == set(b.vectors)
            and all(a.vectors[k].tobytes() == b.vectors[k].tobytes() for k in a.vectors))


def _workers() -> list[warm.WarmWorker]:
    with warm._lock:
        return [w for w in warm._workers if w.alive]


@pytest.mark.parametrize("foreign", [False, True], ids=["lcchain's", "foreign"])
@pytest.mark.parametrize("N", [10, 40])
def test_a_warm_run_is_ngspice_b_to_the_bit(simulators, N: int, foreign: bool) -> None:
    batch, hot = simulators
    netlist, vectors, tstop = _netlist(N)
    job = RunJob(netlist, vectors, tstop, trusted=not foreign, foreign=foreign)
    expected = run(job, batch)
    first = run(job, hot)
    again = run(job, hot)  # the same worker, a second time
    assert (expected.backend, first.backend) == ("batch", "warm")
    assert _same(expected, first) and _same(expected, again)
    assert first.points == expected.points > 100


def test_a_netlist_leaves_nothing_to_the_next(simulators) -> None:
    batch, hot = simulators
    netlist, vectors, tstop = _netlist(10)
    odd = netlist.replace(".tran", ".options reltol=1e-2 method=gear maxord=2 abstol=1e-6\n.tran", 1)
    plain, other = (run(RunJob(text, vectors, tstop), batch) for text in (netlist, odd))
    assert not _same(plain, other)  # the options matter, so the check below can fail
    assert _same(run(RunJob(odd, vectors, tstop), hot), other)
    assert _same(run(RunJob(netlist, vectors, tstop), hot), plain)
    assert len(_workers()) == 1  # both in one worker


def test_a_failing_netlist_fails_alone(simulators) -> None:
    batch, hot = simulators
    netlist, vectors, tstop = _netlist(10)
    # two sources that disagree across the same nodes: ngspice cannot solve it, in either transport
    broken = netlist.replace(".tran", "Va nx 0 1\nVb nx 0 2\n.tran", 1)
    reasons = []
    for simulator in (batch, hot):
        with pytest.raises(SimulationError) as caught:
            run(RunJob(broken, vectors, tstop), simulator)
        reasons.append(caught.value.reason)
    assert all("singular" in reason.lower() for reason in reasons), reasons
    assert _same(run(RunJob(netlist, vectors, tstop), hot), run(RunJob(netlist, vectors, tstop), batch))


def test_a_crash_fails_that_run_only(simulators) -> None:
    batch, hot = simulators
    long_netlist, long_vectors, long_tstop = _netlist(300, dt=0.01, transits=3)
    netlist, vectors, tstop = _netlist(10)
    run(RunJob(netlist, vectors, tstop), hot)
    (worker,) = _workers()
    killer = threading.Timer(0.3, lambda: os.kill(worker.proc.pid, signal.SIGKILL))
    killer.start()
    try:
        with pytest.raises(SimulationError) as caught:
            run(RunJob(long_netlist, long_vectors, long_tstop), hot)
    finally:
        killer.cancel()
    assert "SIGKILL" in caught.value.reason and caught.value.status == "failed"
    assert not alive(worker.proc.pid)
    assert _same(run(RunJob(netlist, vectors, tstop), hot), run(RunJob(netlist, vectors, tstop), batch))
    (replacement,) = _workers()
    assert replacement is not worker


def test_a_run_past_its_timeout_kills_its_worker(simulators) -> None:
    _, hot = simulators
    netlist, vectors, tstop = _netlist(300, dt=0.01, transits=3)
    with pytest.raises(SimulationError) as caught:
        run(RunJob(netlist, vectors, tstop, timeout=0.2), hot)
    assert caught.value.status == "timeout"
    assert _workers() == []


def test_a_spent_worker_is_replaced(simulators, monkeypatch: pytest.MonkeyPatch) -> None:
    _, hot = simulators
    monkeypatch.setattr(warm, "MAX_WORKER_RUNS", 2)
    netlist, vectors, tstop = _netlist(10)
    pids = []
    for _ in range(5):
        run(RunJob(netlist, vectors, tstop), hot)
        pids.append(_workers()[0].proc.pid)
    assert pids[0] == pids[1] != pids[2] == pids[3] != pids[4]


def _netlists(folder: Path, count: int, N: int = 10) -> list[Path]:
    netlist, _, _ = _netlist(N)
    paths = []
    for i in range(count):  # distinct netlists: each its own title
        path = folder / f"n{i:03d}.cir"
        path.write_text(netlist.replace("\n", f" #{i}\n", 1))
        paths.append(path)
    return paths


def test_choose_transports(simulators, tmp_path: Path) -> None:
    batch, _ = simulators
    plan = batch_plan(_netlists(tmp_path, 25))
    items = [(task.index, task.spec, task.seconds) for task in plan.tasks]
    assert all(seconds < warm.WARM_BELOW_SECONDS for *_, seconds in items)
    assert choose_transports(items, batch, 2, "auto").runs == frozenset(range(25))
    assert choose_transports(items, batch, 3, "auto") == Transports()  # too few runs to pay 3 workers' start
    assert choose_transports(items, batch, 2, "process") == Transports()
    assert choose_transports(items[:3], batch, 2, "warm").runs == frozenset(range(3))
    slow = [(index, spec, warm.WARM_BELOW_SECONDS * 2) for index, spec, _ in items]
    assert choose_transports(slow, batch, 1, "auto") == Transports()
    trusted = [(index, replace(spec, trusted=True), seconds) for index, spec, seconds in items]
    assert choose_transports(trusted, batch, 1, "warm") == Transports()
    with pytest.raises(ParameterError, match="--transport"):
        choose_transports(items, batch, 1, "fast")


def _started_by(monkeypatch: pytest.MonkeyPatch) -> list[str]:
    """The names of the threads that start warm workers from now on (a spy on the constructor: the workers are
    real)."""
    names: list[str] = []
    start = warm.WarmWorker.__init__

    def spied(self: warm.WarmWorker, *args: Any, **kwargs: Any) -> None:
        names.append(threading.current_thread().name)
        start(self, *args, **kwargs)

    monkeypatch.setattr(warm.WarmWorker, "__init__", spied)
    return names


def test_a_batch_runs_on_the_workers_started_while_it_planned(tmp_path: Path,
                                                                monkeypatch: pytest.MonkeyPatch) -> None:
    """lcchain batch finds ngspice and starts one warm worker per thread while it plans (EngineStart); the run
    threads take them over, and they live on after the thread that started them is done with them (a worker
    dies with the *thread* that started it: setpriv --pdeathsig)."""
    from lcchain.app.batch import BatchRequest, batch
    from lcchain.app.studies import StudyOptions

    started = _started_by(monkeypatch)
    paths = _netlists(tmp_path, 25)
    result = batch(BatchRequest(tuple(map(str, paths)), study=StudyOptions(workers=2,
                                                                          store=str(tmp_path / "s.sqlite"))))
    assert (result.summary.ok, result.summary.failed) == (25, 0)
    assert started == ["lcchain-engine-start"] * 2  # none by the run threads
    assert _workers() == []  # ended with the study


def test_the_workers_started_while_planning_end_with_a_refused_plan(tmp_path: Path,
                                                                    monkeypatch: pytest.MonkeyPatch) -> None:
    from lcchain.app.batch import BatchRequest, batch
    from lcchain.app.studies import StudyOptions

    started = _started_by(monkeypatch)
    paths = _netlists(tmp_path, 25)
    paths[-1].write_text(paths[-1].read_text() + ".control\nshell true\n.endc\n")
    with pytest.raises(ParameterError):
        batch(BatchRequest(tuple(map(str, paths)), strict=True,
                           study=StudyOptions(workers=2, store=str(tmp_path / "s.sqlite"))))
    assert started == ["lcchain-engine-start"] * 2
    assert _workers() == []
    assert not (tmp_path / "s.sqlite").exists()


def test_workers_started_before_the_engine_is_found_are_adopted_where_it_runs_them() -> None:
    """EngineStart starts its workers beside ``ngspice -v`` and the sandbox's trial (prestart_workers, a guess of
    the placement): warm_simulator adopts them, greeted and version-checked, where the found engine runs foreign
    netlists, and starts no other."""
    batch = find_simulator("batch")
    if not batch.sandbox.available:
        pytest.skip(f"no sandbox here: {batch.sandbox.why_not}")
    warm.prestart_workers(2)
    guessed = [worker for workers in warm._guessed.values() for worker in workers]
    assert len(guessed) == 2 and not any(worker.version for worker in guessed)  # started, not yet greeted
    warm.warm_simulator(batch, 2)
    spares = [worker for workers in warm._spare.values() for worker in workers]
    assert {id(worker) for worker in spares} == {id(worker) for worker in guessed}
    assert all(worker.version == batch.version for worker in spares)
    assert warm._guessed == {}


def test_workers_started_on_a_wrong_guess_are_ended() -> None:
    """Where the found engine has no sandbox (its trial failed), the workers started in bubblewrap on the guess are
    ended, not used: a foreign netlist runs where the found engine says."""
    from lcchain.spice.sandbox import Sandbox

    batch = find_simulator("batch")
    warm.prestart_workers(2)
    guessed = [worker for workers in warm._guessed.values() for worker in workers]
    if not guessed:
        pytest.skip("no bubblewrap here: nothing is started on a guess")
    warm.warm_simulator(replace(batch, sandbox=Sandbox(why_not="its trial run failed")), 1)
    assert not any(worker.alive for worker in guessed)
    assert warm._guessed == {}


ENGINE_MISSING = """\
from lcchain.core.errors import SimulatorMissingError
from lcchain.spice.ngspice import warm
from lcchain.studies.executors import EngineStart

started = []
start = warm.WarmWorker.__init__


def spied(self, *args, **kwargs):
    started.append(self)
    start(self, *args, **kwargs)


warm.WarmWorker.__init__ = spied
try:
    with EngineStart("ngspice", "batch", runs=100, workers=2, executor="process", transport="auto") as engine:
        engine.simulator()
except SimulatorMissingError:
    print(len(started), sum(worker.proc.poll() is None for worker in started), len(warm._workers))
"""


def test_workers_started_for_an_engine_not_found_end_with_the_block(tmp_path: Path) -> None:
    """Where the shared library and bubblewrap are found but the ngspice program is not, the workers EngineStart
    started on its guess end when the study's block ends with the missing engine's error, not at the
    interpreter's exit."""
    import shutil

    programs = tmp_path / "bin"
    programs.mkdir()
    for name in ("bwrap", "setpriv", "true"):
        found = shutil.which(name)
        if found is None:
            pytest.skip(f"{name} is not installed")
        (programs / name).symlink_to(found)
    done = subprocess.run([sys.executable, "-c", ENGINE_MISSING], capture_output=True, text=True, cwd=tmp_path,
                          env={**os.environ, "PATH": str(programs)})
    assert done.returncode == 0, done.stderr[-2000:]
    assert done.stdout.split() == ["2", "0", "0"], done.stdout + done.stderr[-2000:]


def test_few_runs_start_no_worker_while_planning(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Under WARM_MIN_RUNS_PER_WORKER runs a worker, every run starts its own process: no worker is started."""
    from lcchain.studies.executors import WARM_MIN_RUNS_PER_WORKER, EngineStart

    started = _started_by(monkeypatch)
    with EngineStart("ngspice", "batch", runs=2 * WARM_MIN_RUNS_PER_WORKER - 1, workers=2, executor="process",
                     transport="auto") as engine:
        assert engine.simulator().version
    with EngineStart("ngspice", "batch", runs=100, workers=2, executor="process", transport="process") as engine:
        assert engine.simulator().version
    assert started == []


def _stored(path: Path) -> list[tuple[str, str, str, int]]:
    with sqlite3.connect(path) as db:
        rows = db.execute("SELECT key, status, digest, points FROM records ORDER BY key").fetchall()
    db.close()
    return rows


@pytest.mark.parametrize("executor", ["serial", "process"])
def test_a_batch_is_the_same_whichever_transport(simulators, tmp_path: Path, executor: str) -> None:
    batch, _ = simulators
    plan = batch_plan(_netlists(tmp_path, 24))
    stores = {}
    for transport in ("process", "warm", "auto"):
        stores[transport] = tmp_path / f"{transport}.sqlite"
        summary = run_plan(plan, stores[transport], RunOptions(executor=executor, workers=2, simulator=batch, transport=transport))
        assert summary.ok == 24 and summary.failed == 0
        assert _workers() == []  # every warm worker ended with its study
    rows = {transport: _stored(path) for transport, path in stores.items()}
    assert len(rows["process"]) == 24 and all(status == "ok" for _, status, _, _ in rows["process"])
    assert rows["process"] == rows["warm"] == rows["auto"]


SAVES = """saves ngspice names its own way
V1 in 0 PULSE(0 1 0 1u 1u 1m 2m)
R1 in a 100
L1 a b 1m
C1 b 0 1u
R2 b 0 1k
.save v(b) i(L1) @R2[i] @C1[i] v(in,a) v(b,0) i(v1)
.tran 2u 2m
.end
"""


def test_a_device_vector_and_a_difference_saved_are_the_same_on_both_transports(simulators) -> None:
    """ngspice -b's raw file writes @r2[i] as i(@r2[i]), the shared library as @r2[i]; .save v(in,a) saves v(in) and
    v(a): a batch failed such a run ("add them to the .save line", where they were) on the process transport."""
    batch, warm_simulator = simulators
    job = RunJob(SAVES, ["v(b)", "i(L1)", "@R2[i]", "@C1[i]", "v(in,a)", "v(b,0)", "i(v1)"], 2e-3)
    results = [run(job, simulator) for simulator in (batch, warm_simulator)]
    for result in results:
        assert set(result.vectors) == {"v(b)", "i(l1)", "@r2[i]", "@c1[i]", "v(in)", "v(a)", "i(v1)"}
    assert all((results[0].vectors[name] == results[1].vectors[name]).all() for name in results[0].vectors)
    with pytest.raises(SimulationError, match=r"v\(nosuch\) not in ngspice's output .*no node or device"):
        run(RunJob(SAVES.replace("i(v1)", "v(nosuch)"), ["v(b)", "v(nosuch)"], 2e-3), batch)


def _long_netlists(folder: Path) -> list[Path]:
    netlist, _, _ = _netlist(2000, dt=0.01)
    paths = []
    for i in range(2):
        path = folder / f"long{i}.cir"
        path.write_text(netlist.replace("\n", f" #{i}\n", 1))
        paths.append(path)
    return paths


@pytest.mark.parametrize("transport", ["process", "warm"])
def test_nothing_outlives_an_interrupted_batch(tmp_path: Path, transport: str) -> None:
    # Two long runs at once, from threads (process) or in two warm workers: Ctrl-C must end them all.
    paths = _long_netlists(tmp_path)
    marker = "ngspice" if transport == "process" else "python"
    proc = subprocess.Popen([sys.executable, "-m", "lcchain", "batch", *map(str, paths), "--store",
                             str(tmp_path / "s.sqlite"), "--workers", "2", "--transport", transport],
                            cwd=tmp_path, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            preexec_fn=as_from_a_terminal)
    with reaped(proc):
        deadline = time.monotonic() + 120
        running: dict[int, str] = {}
        while time.monotonic() < deadline:
            assert proc.poll() is None, proc.communicate()
            running = {pid: name for pid, name in descendants(proc.pid).items() if marker in name}
            if len(running) >= 2:
                break
            time.sleep(0.1)
        assert len(running) >= 2, f"the two runs did not start together: {descendants(proc.pid)}"
        time.sleep(0.5)
        everything = descendants(proc.pid)
        proc.send_signal(signal.SIGINT)
        _, err = proc.communicate(timeout=60)
    assert proc.returncode == 130 and b"Traceback" not in err, err.decode()
    assert all(gone(pid) for pid in everything), f"outlived lcchain: {everything}"


def test_a_scene_run_on_workers_takes_the_transport(tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                                    monkeypatch: pytest.MonkeyPatch) -> None:
    from lcchain.cli.main import main

    monkeypatch.chdir(tmp_path)  # the scene's default plot is written here
    scene = tmp_path / "s.toml"
    scene.write_text('[chain]\ncase = "two-mass"\nN = 10\n[effects.tolerance]\nL = 0.05\nC = 0.05\nsamples = 4\n'
                     'seed = 3\n[analysis]\ndt = 0.05\n')
    digests = {}
    for transport in ("process", "warm"):
        capsys.readouterr()
        assert main(["run", str(scene), "--workers", "2", "--transport", transport, "--json"]) == 0
        digests[transport] = [sample["digest"] for sample in json.loads(capsys.readouterr().out)["samples"]]
    assert len(digests["process"]) == 4 and digests["process"] == digests["warm"]
    assert _workers() == []


def test_a_worker_s_resident_memory_between_runs_is_its_tree_s(simulators) -> None:
    """Between runs a worker's resident memory is what it said after its last run plus its launcher's and
    sandbox's (read from /proc once): what walking its whole tree in /proc finds, within RTOL_WORKER_RESIDENT (the
    pages the reply's write touched after the worker measured itself); a worker holding more than RESTART_SHARE of
    a run's limit is replaced.  The worker is placed where a foreign netlist's run places it (the sandbox)."""
    from lcchain.spice.job import TransportJob
    from lcchain.spice.ngspice.place import placement
    from lcchain.spice.processes import resident_bytes

    _, hot = simulators
    netlist, _, tstop = _netlist(10)
    with placement(hot, True, None) as place:
        where = (hot.executable, place.prefix, place.cwd, place.env)
        worker = warm.worker_for(*where)
        for _ in range(3):
            worker.run(TransportJob(netlist, tstop, 60.0, None, None))
            walked = resident_bytes(worker.proc.pid)
            assert worker.rss <= worker.resident()
            assert abs(worker.resident() - walked) <= RTOL_WORKER_RESIDENT * walked
        assert warm.worker_for(*where, resident=1e12) is worker
        replaced = warm.worker_for(*where, resident=worker.resident())
        assert replaced is not worker and not worker.alive


def test_the_shared_library_is_found_in_a_folder_that_cannot_be_listed(monkeypatch: pytest.MonkeyPatch) -> None:
    """find_shared_library asks for the library's usual names before it lists a folder: Debian's libngspice.so.0 is
    found without a listing of its folder (thousands of names); a folder that may be searched but not listed (mode
    711) gives the same library."""
    from lcchain.spice.ngspice import locate

    found = locate.find_shared_library()
    listdir = os.listdir
    listed: list[str] = []

    def refused(path: Any) -> list[str]:
        listed.append(os.fspath(path))
        if os.fspath(path) == os.path.dirname(found):
            raise PermissionError(13, "Permission denied", os.fspath(path))
        return listdir(path)

    monkeypatch.setattr(os, "listdir", refused)
    assert locate.find_shared_library() == found
    if os.path.basename(found) in ("libngspice.so", "libngspice.so.0"):
        assert os.path.dirname(found) not in listed


@pytest.mark.parametrize("names, wanted", [
    (["libngspice.so.0.0.6"], "libngspice.so.0.0.6"),
    (["libngspice.so.0.0.6", "libngspice.so.0"], "libngspice.so.0"),
    (["libngspice.so.0", "libngspice.so"], "libngspice.so"),
    (["libngspice.so.1", "libngspice.so.0.9", "libngspice.dylib"], "libngspice.so.0.9"),
    (["libngspice.dylib", "libngspice.a"], "libngspice.dylib"),
])
def test_the_shared_library_is_chosen_by_its_name_in_a_folder(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch, names: list[str], wanted: str) -> None:
    """The environment's own lib folder comes first; in a folder, libngspice.so, then libngspice.so.0, then the
    first other libngspice.so.* by name (a folder of such a name is none), then libngspice.dylib."""
    from lcchain.spice.ngspice import locate

    monkeypatch.delenv("NGSPICE_LIBRARY_PATH", raising=False)
    (tmp_path / "lib").mkdir()
    (tmp_path / "lib" / "libngspice.so.0.0.1").mkdir()
    for name in names:
        (tmp_path / "lib" / name).write_bytes(b"")
    monkeypatch.setattr(sys, "prefix", str(tmp_path))
    assert locate.find_shared_library() == str(tmp_path / "lib" / wanted)


@pytest.mark.parametrize("libraries, wanted", [
    (["/usr/lib64/libngspice.so.0", "/usr/lib/x86_64-linux-gnu/libngspice.so.0"], "/usr/lib64/libngspice.so.0"),
    (["/usr/lib/x86_64-linux-gnu/libngspice.so.0", "/usr/lib/libngspice.so"], "/usr/lib/x86_64-linux-gnu/libngspice.so.0"),
    (["/usr/lib/aarch64-linux-gnu/libngspice.so.0.0.6", "/usr/lib/x86_64-linux-gnu/libngspice.so.0"],
     "/usr/lib/aarch64-linux-gnu/libngspice.so.0.0.6"),
    (["/usr/lib/libngspice.so.0", "/opt/homebrew/lib/libngspice.dylib"], "/usr/lib/libngspice.so.0"),
    (["/usr/local/lib/libngspice.so.0.0.9", "/usr/lib64/libngspice.so"], "/usr/local/lib/libngspice.so.0.0.9"),
])
def test_the_shared_library_is_looked_for_in_the_folders_order(
        monkeypatch: pytest.MonkeyPatch, libraries: list[str], wanted: str) -> None:
    """The folders, in order: the environment's lib, /usr/local/lib, /usr/lib64, each /usr/lib/*-linux-gnu* by
    name, /usr/lib, /opt/homebrew/lib (a file system of these libraries alone, faked)."""
    from lcchain.spice.ngspice import locate

    monkeypatch.delenv("NGSPICE_LIBRARY_PATH", raising=False)
    monkeypatch.setattr(sys, "prefix", "/nowhere-lcchain-test")
    files = set(libraries)
    folders = {os.path.dirname(path) for path in files} | {"/usr/lib"}

    def names(folder: Any) -> list[str]:
        folder = os.fspath(folder)
        if folder not in folders:
            raise FileNotFoundError(2, "No such file or directory", folder)
        below = {path[len(folder) + 1:].split("/")[0] for path in files | folders if path.startswith(folder + "/")}
        return sorted(below)

    monkeypatch.setattr(os, "listdir", names)
    monkeypatch.setattr(os.path, "isfile", lambda path: os.fspath(path) in files)
    monkeypatch.setattr(os.path, "isdir", lambda path: os.fspath(path) in folders)
    assert locate.find_shared_library() == wanted
