"""What a batch does once, not once a run, and no cost a run that grows with the batch (issue 35): guards for
what was made fast, with real ngspice.  Timings are in benchmarks/batch.md, never here."""

from __future__ import annotations

import gc
import sys
import threading
import weakref
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Any

import pytest

import lcchain
from lcchain.app.batch import BatchRequest, batch
from lcchain.app.studies import StudyOptions
from lcchain.runs.simulate import ChainOptions, simulation_spec
from lcchain.runs.spec import RunSpec
from lcchain.studies import executors, stream

pytestmark = pytest.mark.ngspice

#: Runs in the guarded batch: enough for the warm workers (WARM_MIN_RUNS_PER_WORKER a thread).
COUNT = 2 * executors.WARM_MIN_RUNS_PER_WORKER + 2


def _netlists(folder: Path) -> tuple[str, ...]:
    spec, _, _ = simulation_spec(lcchain.chain_for_case("two-mass", 10), ChainOptions(dt=0.05))
    paths = []
    for i in range(COUNT):  # distinct: each its own title
        path = folder / f"n{i:03d}.cir"
        path.write_text(spec.netlist.replace("\n", f" #{i}\n", 1))
        paths.append(str(path))
    return tuple(paths)


def _refused(folder: Path) -> str:
    """A netlist every batch refuses (a .control block), written in ``folder``."""
    bad = folder / "bad.cir"
    bad.write_text("bad\nV1 1 0 1\n.control\nshell true\n.endc\n.tran 1 2\n.end\n")
    return str(bad)


def test_a_run_is_keyed_once_by_the_plan_and_once_where_it_runs(tmp_path: Path,
                                                                monkeypatch: pytest.MonkeyPatch) -> None:
    """run_plan asks a plan for its keys, rows and fingerprint, and the pricing for its distinct runs: the plan
    makes each key once (per version), and the run's record makes its own."""
    calls: list[str] = []
    key = RunSpec.key

    def counted(self: RunSpec, engine_version: str) -> str:
        with lock:
            calls.append(engine_version)
        return key(self, engine_version)

    lock = threading.Lock()
    monkeypatch.setattr(RunSpec, "key", counted)
    result = batch(BatchRequest(_netlists(tmp_path), study=StudyOptions(store=str(tmp_path / "s.sqlite"))))
    assert result.summary.ok == COUNT
    assert len(calls) <= 3 * COUNT  # the pricing's (""), the plan's (the version) and the run's


def test_a_threaded_batch_never_waits_on_every_pending_run(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """concurrent.futures.wait locks and scans every pending run at each finished one: the threads' results come
    off a queue instead."""

    def refused(*args: Any, **kwargs: Any) -> Any:
        raise AssertionError("concurrent.futures.wait on the pending runs")

    monkeypatch.setattr(executors, "wait", refused)
    result = batch(BatchRequest(_netlists(tmp_path), study=StudyOptions(workers=2,
                                                                       store=str(tmp_path / "s.sqlite"))))
    assert (result.summary.ok, result.summary.failed) == (COUNT, 0)


def test_a_threaded_batch_holds_a_few_runs_a_thread_not_the_whole_batch(tmp_path: Path,
                                                                        monkeypatch: pytest.MonkeyPatch) -> None:
    """A submitted run holds about 2 KB until it is done (200 MB for 100,000 runs): at most RUNS_AHEAD runs a
    thread wait beside the ones running, the rest are handed over as runs finish."""
    most = [0]
    outstanding = [0]
    lock = threading.Lock()

    class Counted(ThreadPoolExecutor):
        def submit(self, *args: Any, **kwargs: Any) -> Any:
            future = super().submit(*args, **kwargs)
            with lock:
                outstanding[0] += 1
                most[0] = max(most[0], outstanding[0])
            future.add_done_callback(finished)
            return future

    def finished(future: Any) -> None:
        with lock:
            outstanding[0] -= 1

    monkeypatch.setattr(executors, "ThreadPoolExecutor", Counted)
    monkeypatch.setattr(executors, "RUNS_AHEAD", 1)
    result = batch(BatchRequest(_netlists(tmp_path), study=StudyOptions(workers=2,
                                                                       store=str(tmp_path / "s.sqlite"))))
    assert (result.summary.ok, result.summary.failed) == (COUNT, 0)
    assert 0 < most[0] <= (1 + 1) * 2 < COUNT


def test_a_batch_holds_a_window_of_its_runs_not_every_run(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A batch's runs are read back from disk as the threads ask for them (lcchain.studies.stream): the runs alive
    in the driver while it runs are those started or queued (RUNS_AHEAD a thread), whatever the batch's size (a
    plan that held them all held 2 KB a run, 400 MB at 100,000 runs)."""
    count, workers = 6 * COUNT, 2
    paths = [*_netlists(tmp_path)]
    spec, _, _ = simulation_spec(lcchain.chain_for_case("one-mass", 10), ChainOptions(dt=0.05))
    for i in range(count - len(paths)):
        path = tmp_path / f"m{i:03d}.cir"
        path.write_text(spec.netlist.replace("\n", f" #{i}\n", 1))
        paths.append(str(path))
    alive: list[int] = []
    # Every RunSpec made, by its __init__ (the plan) or unpickled (the spool), is in `made` while it lives. Not
    # gc.get_objects(): its list takes a reference to a tuple another thread is still building from a generator,
    # whose final resize then fails (CPython's SystemError "bad argument to internal function", seen in CI).
    made: weakref.WeakSet[RunSpec] = weakref.WeakSet()
    init = RunSpec.__init__

    def made_by_init(self: RunSpec, *args: Any, **kwargs: Any) -> None:
        init(self, *args, **kwargs)
        made.add(self)

    unpickle = getattr(RunSpec, "__setstate__", None)  # none today: pickle then updates the instance's dict

    def made_by_unpickling(self: RunSpec, state: dict[str, Any]) -> None:
        if unpickle is not None:
            unpickle(self, state)
        else:
            vars(self).update(state)
        made.add(self)

    execute_group = executors.execute_group

    def counted(group: Any, *args: Any, **kwargs: Any) -> Any:
        if len(alive) < 20 or group[0][0] % 10 == 0:
            gc.collect()  # a run let go of in a reference cycle is not held
            alive.append(len(made))
        return execute_group(group, *args, **kwargs)

    monkeypatch.setattr(RunSpec, "__init__", made_by_init)
    monkeypatch.setattr(RunSpec, "__setstate__", made_by_unpickling, raising=False)
    monkeypatch.setattr(executors, "execute_group", counted)
    monkeypatch.setattr(stream, "HELD", 0)  # every run spooled (a batch holds its first HELD, ~5 MB)
    result = batch(BatchRequest(tuple(paths), study=StudyOptions(workers=workers, store=str(tmp_path / "s.sqlite"))))
    assert (result.summary.ok, result.summary.failed) == (count, 0)
    # each thread's queued and running runs (a running one twice: cut to the batch's deadline), the one each thread
    # has just finished (its work item lets it go right after the done callback that wakes the driver, which a
    # 0.1 ms switch interval lets run first), and the one being read back from the spool
    assert 0 < max(alive) <= 2 * (executors.RUNS_AHEAD + 1) * workers + workers + 1 < count


def test_a_streamed_batch_stores_the_rows_and_keys_of_the_whole_plan(tmp_path: Path,
                                                                     monkeypatch: pytest.MonkeyPatch) -> None:
    """Runs held and runs spooled, a refusal, a netlist given twice and one named the long way round
    (``folder//./n001.cir``): the store holds the rows, keys and fingerprint batch_plan makes (what a resume, or
    another executor, finds: each netlist's name as a path says it), and the summary counts each run once; a second
    call runs nothing."""
    from lcchain.studies.plan import batch_plan
    from lcchain.studies.store import Store

    paths = [*_netlists(tmp_path)]
    bad = _refused(tmp_path)
    paths[3:3] = [bad, paths[5]]  # a refusal, and a netlist given twice
    paths[1] = str(tmp_path) + "//./" + Path(paths[1]).name
    monkeypatch.setattr(stream, "HELD", 4)
    store = tmp_path / "s.sqlite"
    first = batch(BatchRequest(tuple(paths), study=StudyOptions(workers=2, store=str(store)))).summary
    assert (first.total, first.ran, first.ok, first.refused, first.skipped) == (COUNT + 1, COUNT, COUNT, 1, 0)
    assert first.refusals[0][0] == bad
    with Store(store, "read") as stored:
        version = stored.meta()["engine"].split()[-1]
        plan = batch_plan(paths, engine_version=lambda: version)
        assert stored.meta()["plan"] == plan.fingerprint(version)
        assert [(run.key, run.params, run.label) for run in stored.light_runs()] == plan.rows(version)
    again = batch(BatchRequest(tuple(paths), study=StudyOptions(workers=2, store=str(store)))).summary
    assert (again.total, again.ran, again.skipped, again.ok, again.refused) == (COUNT + 1, 0, COUNT + 1, COUNT, 1)


def test_a_batch_hands_its_threads_the_gil_promptly(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """While the engine starts and while the runs go, the thread switch interval is at most SWITCH_SECONDS (a
    thread woken by a worker's answer gets the GIL within it, not within Python's 5 ms), and the caller's
    interval is back after the batch."""
    from lcchain.spice.ngspice import warm

    seen: dict[str, list[float]] = {"finding": [], "running": []}
    find, run = executors.EngineStart._find, warm.WarmWorker.run

    def finding(self: executors.EngineStart) -> None:
        seen["finding"].append(sys.getswitchinterval())
        find(self)

    def running(self: warm.WarmWorker, job: Any) -> Any:
        seen["running"].append(sys.getswitchinterval())
        return run(self, job)

    monkeypatch.setattr(executors.EngineStart, "_find", finding)
    monkeypatch.setattr(warm.WarmWorker, "run", running)
    before = sys.getswitchinterval()
    result = batch(BatchRequest(_netlists(tmp_path), study=StudyOptions(workers=2,
                                                                       store=str(tmp_path / "s.sqlite"))))
    assert (result.summary.ok, result.summary.failed) == (COUNT, 0)
    assert seen["finding"] and seen["running"]  # the engine started here, and the runs went warm
    assert max(seen["finding"] + seen["running"]) <= executors.SWITCH_SECONDS
    assert sys.getswitchinterval() == before


def test_the_switch_interval_is_restored_when_the_last_of_overlapping_blocks_ends() -> None:
    """Two studies in two threads of one program (a library caller): their blocks overlap and the first in ends
    first; the interval stays short while the second runs and is the caller's again after both."""
    before = sys.getswitchinterval()
    a_in, b_in, a_out = threading.Event(), threading.Event(), threading.Event()
    seen: list[float] = []

    def first() -> None:
        with executors.prompt_handoffs():
            a_in.set()
            b_in.wait(10)
        a_out.set()

    def second() -> None:
        a_in.wait(10)
        with executors.prompt_handoffs():
            b_in.set()
            a_out.wait(10)
            seen.append(sys.getswitchinterval())

    threads = [threading.Thread(target=first), threading.Thread(target=second)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join(10)
    assert seen and seen[0] <= executors.SWITCH_SECONDS
    assert sys.getswitchinterval() == before


def test_the_plan_waits_for_the_engine_doing_what_comes_next(monkeypatch: pytest.MonkeyPatch) -> None:
    """EngineStart.simulator(while_waiting) calls it when the engine is not found yet (a batch loads its runs'
    modules while its workers start), and not once the engine is found."""
    release = threading.Event()
    find = executors.EngineStart._find

    def slow(self: executors.EngineStart) -> None:
        release.wait(10)
        find(self)

    monkeypatch.setattr(executors.EngineStart, "_find", slow)
    calls: list[str] = []
    with executors.EngineStart("ngspice", "batch", runs=0, workers=1, executor="serial",
                               transport="process") as engine:
        found = engine.simulator(lambda: (calls.append("waiting"), release.set()))
        engine.simulator(lambda: calls.append("found"))
    assert calls == ["waiting"] and found.engine == "ngspice"


def test_a_batch_loads_what_runs_it_while_its_engine_starts(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A streamed batch's plan asks for the engine with work to do meanwhile: loading the runs' modules."""
    asked: list[Any] = []
    simulator = executors.EngineStart.simulator

    def asking(self: executors.EngineStart, while_waiting: Any = None) -> Any:
        asked.append(while_waiting)
        return simulator(self, while_waiting)

    monkeypatch.setattr(executors.EngineStart, "simulator", asking)
    result = batch(BatchRequest(_netlists(tmp_path), study=StudyOptions(workers=2,
                                                                       store=str(tmp_path / "s.sqlite"))))
    assert result.summary.ok == COUNT
    loaders = [given for given in asked if given is not None]
    assert loaders and all(loader.__module__ == "lcchain.app.batch" for loader in loaders)
    loaders[0]()  # loads the store's and the records' modules (here already loaded): nothing else


@pytest.mark.parametrize("streamed", [True, False], ids=["streamed", "held"])
def test_a_batch_plan_says_how_many_netlists_it_has_planned(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                                            streamed: bool) -> None:
    """Both plans of a batch tell ``progress(done)`` as they go, every few netlists (WINDOW, PLANNED_EVERY) and
    once all are, refusals counted: 100,000 netlists are planned for about 30 s before the first run."""
    from lcchain.studies import plan as plans

    paths = [*_netlists(tmp_path)]
    paths.insert(3, _refused(tmp_path))
    told: list[int] = []
    monkeypatch.setattr(stream, "WINDOW", 4)
    monkeypatch.setattr(plans, "PLANNED_EVERY", 4)

    def refusals(names: list[str]) -> int:
        """The plan's refusals, its progress told to ``told``."""
        if not streamed:
            return len(plans.batch_plan(names, engine_version=lambda: "39", progress=told.append).refusals)
        spooled = stream.streamed_batch_plan(names, lambda: "39", engine_version=lambda: "39", folder=str(tmp_path),
                                             progress=told.append)
        spooled.spool.close()
        return len(spooled.refusals)

    count = len(paths)
    assert refusals(paths) == 1
    assert count % 4 and told == [*range(4, count, 4), count]
    told.clear()  # a count the window divides: told once at the end, not twice
    del paths[count - count % 4:]
    refusals(paths)
    assert told == [*range(4, len(paths) + 1, 4)]


def test_a_batch_tells_its_plan_of_every_netlist_given_and_listed(tmp_path: Path,
                                                                  monkeypatch: pytest.MonkeyPatch) -> None:
    """lcchain batch's ``planning(done, total)`` hook: the total counts the netlists given and those of --from's
    list, and the last call has planned them all; a list that shrank after it was counted still ends with all
    told (done == total: a progress line finished)."""
    from lcchain.app.studies import StudyHooks

    paths = _netlists(tmp_path)
    listed = tmp_path / "list.txt"
    listed.write_text("\n".join(paths[2:]) + "\n")
    told: list[tuple[int, int]] = []
    request = BatchRequest(paths[:2], listed=str(listed), study=StudyOptions(store=str(tmp_path / "s.sqlite")))
    hooks = StudyHooks(planning=lambda done, total: told.append((done, total)))
    assert batch(request, hooks).summary.ok == COUNT
    assert told and told[-1] == (COUNT, COUNT) and all(total == COUNT for _, total in told)
    told.clear()
    monkeypatch.setattr(stream, "WINDOW", 4)
    monkeypatch.setattr(BatchRequest, "count", lambda self: COUNT + 5)  # five names gone once counted
    assert batch(request, hooks).summary.skipped == COUNT  # resumed: planned again, nothing run
    assert told[:-1] == [(done, COUNT + 5) for done in range(4, COUNT + 1, 4)] + [(COUNT, COUNT + 5)]
    assert told[-1] == (COUNT, COUNT)
