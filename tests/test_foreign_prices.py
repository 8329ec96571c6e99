"""Netlists lcchain did not write are priced from what they hold, and their runs are held to it (issue 29, item 2).

A netlist priced from its analysis card alone could cost anything: a PULSE with picosecond edges, thousands of K
lines, a huge title or B-source expression, a long PWL, a fast SIN.  Here a small hostile family runs in real
ngspice: each run stays within its own limits (a raw file and a resident memory a few times its price) and computes
at most twice the time points it was priced at.  Then every transport stops a run that outgrows its memory or its
output while it goes, and a batch stops starting runs once its --max-time is spent, leaving them pending.

No assert here is on a time: prices are checked against what ngspice computes (points, values), limits against the
status and reason of a stopped run.  The measured/priced ratios of time and memory are in benchmarks/pricing.md.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import pytest

from lcchain.core.budget import Budget
from lcchain.core.errors import ParameterError, SimulationError
from lcchain.runs.execute import execute
from lcchain.spice import processes
from lcchain.spice.foreign import analysis_of, foreign_estimate, foreign_price
from lcchain.spice.job import RunJob
from lcchain.spice.ngspice import warm
from lcchain.spice.ngspice.find import find_simulator
from lcchain.spice.ngspice.runner import run
from lcchain.spice.pricing import RUN_LIMIT_FACTOR, RUN_SECONDS_FLOOR, read_contents
from lcchain.spice.text import saved_vectors
from lcchain.studies.options import RunOptions
from lcchain.studies.plan import batch_plan
from lcchain.studies.run import run_plan
from lcchain.studies.store import Store

RC = "R1 in out 50\nC1 out 0 1p\n"


def _netlist(title: str, body: str, tran: str, save: str = ".save v(out)") -> str:
    return f"{title}\n{body}{tran}\n{save}\n.end\n"


def _ladder(cells: int, source: str, coupled: int = 0) -> str:
    """An LC ladder driven at its first node; the first ``coupled`` inductors all coupled pairwise."""
    lines = [source] + [f"L{i} n{i - 1} n{i} 1u\nC{i} n{i} 0 1p" for i in range(1, cells + 1)]
    pairs = [(i, j) for i in range(1, coupled + 1) for j in range(i + 1, coupled + 1)]
    lines += [f"K{k} L{i} L{j} {0.5 / (j - i + 1):.4f}" for k, (i, j) in enumerate(pairs, start=1)]
    return "\n".join(lines) + "\n"


#: Small members of each hostile family (benchmarks/bench_foreign_pricing.py runs them at full size).
FAMILY: dict[str, str] = {
    "a PULSE of 4 ps edges every 20 ps": _netlist("p", "V1 in 0 PULSE(0 1 0 4p 4p 5p 20p)\n" + RC, ".tran 1n 20n"),
    "a single PULSE of 1 fs edges": _netlist("p", "V1 in 0 PULSE(0 1 1n 1f 1f 1n)\n" + RC, ".tran 1n 100n"),
    "two PULSEs 1 fs apart": _netlist("p", "V1 in 0 PULSE(0 1 0 10p 10p 50p 100p)\nV2 in2 0 PULSE(0 1 1f 10p 10p 50p "
                                      "100p)\nR2 in2 out 50\n" + RC, ".tran 1n 10n"),
    "a PWL of 2000 points": _netlist("w", "V1 in 0 PWL(" + " ".join(f"{k * 5e-11:.6g} {k % 2}" for k in range(2000))
                                     + ")\n" + RC, ".tran 1n 100n"),
    "a PWL repeated every 30 ps": _netlist("w", "V1 in 0 PWL(0 0 10p 1 20p 0 r=0)\n" + RC, ".tran 1n 10n"),
    "a SIN at 10 GHz": _netlist("s", "V1 in 0 SIN(0 1 10g)\n" + RC, ".tran 1n 100n"),
    "an SFFM at 5 GHz": _netlist("s", "V1 in 0 SFFM(0 1 5g 2 1g)\n" + RC, ".tran 1n 100n"),
    "an EXP of 1 ps time constants": _netlist("e", "V1 in 0 EXP(0 1 1n 1p 50n 1p)\n" + RC, ".tran 1n 100n"),
    "TRNOISE every 10 ps": _netlist("n", "V1 in 0 TRNOISE(0.1 10p 0 0)\n" + RC, ".tran 1n 10n"),
    "30 inductors all coupled (435 K lines)": _netlist("k", _ladder(30, "V1 n0 0 PULSE(0 1 0 1n 1n 10n 100n)", 30),
                                                       ".tran 1n 50n", ".save v(n30)"),
    "an LC ladder of 300 cells ringing": _netlist("l", _ladder(300, "V1 n0 0 PULSE(0 1 0 1n 1n 10n 100n)"),
                                                  ".tran 1n 300n", ".save v(n300)"),
    "a 400-character title": _netlist("t" * 400, "V1 in 0 PULSE(0 1 0 1n 1n 10n 100n)\n" + RC, ".tran 1n 100n"),
    "a B expression of 2000 terms": _netlist("b", "V1 in 0 PULSE(0 1 0 1n 1n 10n 100n)\n" + RC + "B1 b 0 V="
                                             + "+".join(["v(in)"] * 2000) + "\nR2 b 0 1k\n", ".tran 1n 100n"),
    "5000 resistors": _netlist("r", "V1 in 0 SIN(0 1 100meg)\n" + RC + "".join(f"R{k} out 0 1meg\n"
                                                                               for k in range(2, 5002)),
                               ".tran 1n 100n"),
    "no .save: every vector": _netlist("a", "V1 in 0 PULSE(0 1 0 4p 4p 5p 20p)\n" + RC, ".tran 1n 10n", "* all"),
}


@pytest.mark.ngspice
@pytest.mark.parametrize("name", FAMILY)
def test_a_hostile_netlist_computes_what_it_was_priced_at(name: str, tmp_path: Path) -> None:
    """Within its own limits (raw file and memory from its price) it runs, and computes at most twice the time
    points priced (so at most twice the values lcchain reads back)."""
    path = tmp_path / "n.cir"
    path.write_text(FAMILY[name])
    plan = batch_plan([path])
    spec = plan.tasks[0].spec
    text = spec.netlist
    price = foreign_price(text, analysis_of(text, "n.cir"), len(saved_vectors(text)))
    record = execute(replace(spec, timeout=600.0))  # limits on memory and output only: no timed assert
    assert record.ok, record.reason
    assert record.points is not None and record.points <= 2 * price.points, (record.points, price.points)


def test_the_issues_examples_are_not_priced_at_milliseconds() -> None:
    """A 4 ps PULSE, 19,900 K lines, a 20 MB title, a 300 kB B expression and a 100,000-point PWL take 2 to 430 s
    (measured, benchmarks/pricing.md): priced from the analysis card alone they cost milliseconds."""
    tran = ".tran 1n 1u"
    title = _netlist("t" * 20_000_000, "V1 in 0 DC 1\n" + RC, tran)
    cases = {
        "pulse": (_netlist("p", "V1 in 0 PULSE(0 1 0 4p 4p 5p 20p)\n" + RC, tran), 2.0),
        "K lines": (_netlist("k", _ladder(200, "V1 n0 0 PULSE(0 1 0 1n 1n 10n 100n)", 200), tran, ".save v(n200)"),
                    100.0),
        "title": (title, 2.0),
        "expression": (_netlist("b", "V1 in 0 DC 1\n" + RC + "B1 b 0 V=" + "+".join(["v(in)"] * 50_000) + "\n", tran),
                       1.0),
        "PWL": (_netlist("w", "V1 in 0 PWL(" + " ".join(f"{k * 1e-11:.6g} {k % 2}" for k in range(100_000)) + ")\n"
                         + RC, tran), 100.0),
    }
    for name, (text, seconds) in cases.items():
        estimate = foreign_estimate(text, analysis_of(text, name), len(saved_vectors(text)))
        assert estimate.seconds > seconds, (name, estimate.what, estimate.seconds)
    assert foreign_estimate(title, analysis_of(title, "t"), 1).memory > 200 * 2**20  # lcchain's copies, ngspice's


@pytest.mark.parametrize("line", ["V1 in 0 FOO(1 2 3)", "V1 in 0 PULSE(0 1 0 {tr} 1p 1n 2n)", "I1 in 0 external",
                                  "V1 in 0 SIN(0 1 fast)"])
def test_a_source_lcchain_cannot_price_is_refused_naming_its_line(line: str) -> None:
    text = _netlist("x", line + "\n" + RC, ".tran 1n 1u")
    with pytest.raises(ParameterError) as caught:
        foreign_estimate(text, analysis_of(text, "n.cir"), 1, "n.cir")
    assert caught.value.field == "n.cir: line 2" and "PULSE" in caught.value.allowed


def test_a_source_with_values_from_parameters_is_read() -> None:
    contents = read_contents(_netlist("x", ".param vdd=1 c=1p\nV1 in 0 DC {vdd} AC 1\nR1 in out 1\nL1 out m 1n\n"
                                      "C1 m 0 {c}\n", ".tran 1n 1u"))
    assert contents.ringing > 1e9 and contents.unknowns == 5  # in, out, m; the branches of V1 and L1


def test_a_batch_run_gets_its_limits_from_its_own_price(tmp_path: Path) -> None:
    """Not the whole --timeout or --max-time: a few times its price, within both."""
    path = tmp_path / "n.cir"
    path.write_text(FAMILY["a SIN at 10 GHz"])
    budget = Budget(max_memory=2**30, max_seconds=600.0)
    (task,) = batch_plan([path], timeout=3600.0, budget=budget).tasks
    assert task.spec.timeout == pytest.approx(RUN_LIMIT_FACTOR * task.seconds + RUN_SECONDS_FLOOR)
    assert task.spec.timeout < 10.0 and task.spec.max_resident_bytes is not None
    assert task.spec.max_resident_bytes < budget.max_memory and task.spec.max_output_bytes is not None
    small = batch_plan([path], timeout=0.5, budget=budget).tasks[0].spec
    assert small.timeout == 0.5  # the user's --timeout still bounds it


# --------------------------------------------------------------------------- watched while they run

#: 60,000 resistors: ngspice holds about 60 MB before its first time point.
MANY = _netlist("many", "V1 n0 0 DC 1\n" + "".join(f"R{k} n0 0 1meg\n" for k in range(60_000)), ".tran 1n 10n",
                ".save v(n0)")
LIMIT = 40 * 2**20


@pytest.fixture(autouse=True)
def _no_worker_outlives_a_test():
    yield
    warm.close_workers(kill=True)


@pytest.mark.ngspice
@pytest.mark.parametrize("backend", ["batch", "warm", "shared"])
def test_every_transport_stops_a_run_past_its_memory(backend: str) -> None:
    """The warm worker checked its memory only after a run (2.6 GiB under --max-memory 600M); now every transport
    watches the resident memory of its child while it runs."""
    simulator = find_simulator("shared" if backend == "shared" else "batch")
    if backend == "warm":
        simulator = warm.warm_simulator(simulator)
    with pytest.raises(SimulationError) as caught:
        run(RunJob(MANY, ["v(n0)"], 1e-8, max_resident_bytes=LIMIT), simulator)
    assert caught.value.status == "failed"
    assert "memory grew past 40 MiB resident" in caught.value.reason and "was stopped" in caught.value.reason
    assert run(RunJob(MANY, ["v(n0)"], 1e-8, max_resident_bytes=512 * 2**20), simulator).points > 1


@pytest.mark.ngspice
def test_a_warm_run_that_prints_past_its_limit_is_stopped(monkeypatch: pytest.MonkeyPatch) -> None:
    """What the warm worker's ngspice prints streams to a file the parent watches, as a ngspice -b run's does."""
    simulator = warm.warm_simulator(find_simulator("batch"))
    long = _netlist("t" * 200, "V1 in 0 SIN(0 1 1meg)\n" + RC, ".tran 1p 1u 0 1p")  # a million points
    monkeypatch.setattr(processes, "MAX_LOG_BYTES", 100)
    with pytest.raises(SimulationError, match="printed more than 100 B"):
        run(RunJob(long, ["v(out)"], 1e-6, max_output_bytes=1e9), simulator)
    assert not [w for w in warm._workers if w.alive]  # the worker went with the run


@pytest.mark.ngspice
def test_a_warm_worker_keeps_its_log_per_run() -> None:
    simulator = warm.warm_simulator(find_simulator("batch"))
    first = run(RunJob(_netlist("first title", "V1 in 0 DC 1\n" + RC, ".tran 1n 10n"), ["v(out)"], 1e-8), simulator)
    second = run(RunJob(_netlist("second title", "V1 in 0 DC 1\n" + RC, ".tran 1n 10n"), ["v(out)"], 1e-8), simulator)
    assert "first title" in first.log and "first title" not in second.log and "second title" in second.log


# --------------------------------------------------------------------------- a batch's whole budget


def _batch(folder: Path, count: int, tran: str = ".tran 1n 100n") -> list[Path]:
    paths = []
    for k in range(count):
        path = folder / f"n{k}.cir"
        path.write_text(_netlist(f"n{k}", "V1 in 0 SIN(0 1 1g)\n" + RC, tran))
        paths.append(path)
    return paths


@pytest.mark.ngspice
def test_a_spent_budget_leaves_the_runs_pending_for_the_same_command(tmp_path: Path) -> None:
    plan = batch_plan(_batch(tmp_path, 3))
    store = tmp_path / "s.sqlite"
    summary = run_plan(plan, store, RunOptions(executor="serial", max_seconds=0.0))
    assert (summary.ran, summary.pending, summary.ok, summary.failed) == (0, 3, 0, 0) and not summary.complete
    again = run_plan(plan, store, RunOptions(executor="serial"))
    assert (again.skipped, again.ran, again.ok, again.pending) == (0, 3, 3, 0) and again.complete


@pytest.mark.ngspice
@pytest.mark.parametrize("executor", ["serial", "process"])
def test_a_run_going_when_the_budget_ends_is_stopped_and_stays_pending(tmp_path: Path, executor: str) -> None:
    """Ten million time points run for many seconds on any machine: the budget of one second stops them, and the
    runs are neither stored as timed out nor lost."""
    plan = batch_plan(_batch(tmp_path, 2, ".tran 1p 10u 0 1p"))
    store = tmp_path / "s.sqlite"
    summary = run_plan(plan, store, RunOptions(executor=executor, workers=2, max_seconds=1.0))
    assert (summary.ran, summary.pending, summary.failed) == (0, 2, 0)
    assert not [w for w in warm._workers if w.alive]
    with Store(store, "read") as stored:
        assert stored.finished() == set()  # nothing stored as timed out: the same command runs both
