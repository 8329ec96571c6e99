"""One run record and one job per run (issue 34, item 4).

A transient and an AC analysis come back as the same record, :class:`lcchain.spice.result.RunResult`, with the
analysis's data as its ``data`` field; what a run is asked to do is a frozen job (:class:`RunJob`,
:class:`AcJob`) checked once when it is made, so that a mistake in one of its fields is one line naming the
field, its value and the allowed range.
"""

from __future__ import annotations

import pickle

import numpy as np
import pytest

import lcchain
from lcchain.circuit.ladder import Ladder
from lcchain.circuit.netlist import SimulationOptions, ac_netlist_text, netlist_text
from lcchain.core.errors import ParameterError
from lcchain.spice.ac import run_ac
from lcchain.spice.acdata import AcResult
from lcchain.spice.engines import find_engine, run_engine
from lcchain.spice.job import AcJob, RunJob, TransportJob
from lcchain.spice.result import AcData, RunResult, TransientData

LADDER = Ladder(lcchain.chain_for_case("two-mass", 8))
OPTIONS = SimulationOptions(dt=0.05, tstop=4.0)
TRANSIENT = netlist_text(LADDER, OPTIONS)
AC_TEXT = ac_netlist_text(LADDER, points=32, omega_max=2.1)
TSTOP = OPTIONS.tstop * LADDER.time_unit
#: The keys of a transient's metadata before the record was shared with AC runs (what a report reads).
TRANSIENT_METADATA = {"engine", "engine_version", "ngspice_version", "netlist_sha256", "options", "wall_s",
                      "backend", "points", "vectors", "t_end", "log"}


@pytest.mark.parametrize(("make", "field"), [
    (lambda: RunJob("", ["i(l1)"], 1.0), "netlist"),
    (lambda: RunJob(TRANSIENT, "i(l1)", 1.0), "vectors"),
    (lambda: RunJob(TRANSIENT, ["i(l1) i(l2)"], 1.0), "vectors"),
    (lambda: RunJob(TRANSIENT, ["i(l1)"], -1.0), "tstop"),
    (lambda: RunJob(TRANSIENT, ["i(l1)"], float("nan")), "tstop"),
    (lambda: RunJob(TRANSIENT, ["i(l1)"], 1.0, timeout=0), "timeout"),
    (lambda: RunJob(TRANSIENT, ["i(l1)"], 1.0, max_output_bytes=-5), "max_output_bytes"),
    (lambda: RunJob(TRANSIENT, ["i(l1)"], 1.0, max_resident_bytes="1G"), "max_resident_bytes"),
    (lambda: RunJob(TRANSIENT, ["i(l1)"], 1.0, foreign="no"), "foreign"),
    (lambda: RunJob(TRANSIENT, ["i(l1)"], 1.0, trusted=1), "trusted"),
    (lambda: RunJob(TRANSIENT, ["i(l1)"], 1.0, cwd=3), "cwd"),
    (lambda: AcJob(TRANSIENT, ["i(l1)"], 32), "netlist"),
    (lambda: AcJob(AC_TEXT, ["i(l1)"], 0), "points"),
    (lambda: AcJob(AC_TEXT, ["i(l1)"], 2.5), "points"),
    (lambda: AcJob(AC_TEXT, ["i(l1)"], 32, timeout=-1.0), "timeout"),
])
def test_a_job_refuses_a_bad_field_in_one_line_naming_it(make, field: str) -> None:
    with pytest.raises(ParameterError) as error:
        make()
    assert error.value.field == field and "\n" not in str(error.value)


def test_a_job_holds_canonical_vector_names_once_without_its_axis() -> None:
    job = RunJob(TRANSIENT, ["I(L1)", "l1#branch", "time", "n3"], TSTOP)
    assert job.vectors == ("i(l1)", "v(n3)") and job.analysis == "transient" and job.foreign
    ac = AcJob(AC_TEXT, ["frequency", "i(L1)"], 32)
    assert ac.vectors == ("i(l1)",) and ac.analysis == "ac" and not ac.foreign
    assert pickle.loads(pickle.dumps(job)) == job and pickle.loads(pickle.dumps(ac)) == ac
    with pytest.raises(AttributeError):
        job.tstop = 1.0  # type: ignore[misc]


def test_a_transport_job_is_made_of_checked_text_only() -> None:
    job = RunJob(TRANSIENT, ["i(l1)"], TSTOP)
    checked = TransportJob.checked(TRANSIENT, job)
    assert (checked.text, checked.tstop, checked.timeout, checked.plot, checked.joined) == \
        (TRANSIENT, TSTOP, job.timeout, "transient", False)
    assert TransportJob.checked(AC_TEXT, AcJob(AC_TEXT, (), 32), "ac").joined  # every .ac card's plot
    with pytest.raises(ParameterError, match="line 2"):
        TransportJob.checked(TRANSIENT.replace("\n", "\n\x0c", 1), job)


@pytest.mark.ngspice
def test_a_transient_and_an_ac_run_are_one_record() -> None:
    simulator = find_engine("ngspice")
    transient = run_engine(RunJob(TRANSIENT, ["i(l1)", "i(l8)"], TSTOP, foreign=False), simulator)
    ac = run_ac(AcJob(AC_TEXT, ["i(l1)", "i(l8)"], 32), simulator)
    assert type(transient) is type(ac) is RunResult and AcResult is RunResult
    assert isinstance(transient.data, TransientData) and isinstance(ac.data, AcData)
    assert (transient.analysis, ac.analysis) == ("transient", "ac")
    assert transient.time is transient.data.time and ac.frequency is ac.data.frequency
    assert transient.points == transient.time.size and ac.points == ac.frequency.size == 32
    assert list(transient.vectors) == list(ac.vectors) == ["i(l1)", "i(l8)"]
    assert transient.vectors["i(l1)"].dtype == np.float64 and ac.vectors["i(l1)"].dtype == np.complex128
    for one in (transient, ac):  # the fields every run records, the same for both analyses
        assert (one.engine, one.engine_version, one.backend) == ("ngspice", simulator.version, "batch")
        assert one.wall_s > 0 and len(one.netlist_sha256) == 64
    with pytest.raises(AttributeError, match="no time points"):
        _ = ac.time
    with pytest.raises(AttributeError, match="no frequencies"):
        _ = transient.frequency
    assert set(transient.metadata()) == TRANSIENT_METADATA
    assert set(ac.metadata()) == TRANSIENT_METADATA - {"t_end"} | {"f_end"}
    for one in (transient, ac):  # a record pickles (a Dask worker sends it) and its arrays stay read-only
        back = pickle.loads(pickle.dumps(one))
        assert type(back.data) is type(one.data) and not back.data.axis.flags.writeable
        assert all(np.array_equal(back.vectors[k], one.vectors[k]) and not back.vectors[k].flags.writeable
                   for k in one.vectors)


@pytest.mark.ngspice
def test_a_transient_and_an_ac_run_are_one_record_with_the_engine_run_as_one_field() -> None:
    from dataclasses import fields

    from lcchain.runs.execute import RunRecord, execute
    from lcchain.runs.spec import RunSpec

    assert {"result", "ac"}.isdisjoint(field.name for field in fields(RunRecord))
    transient = execute(RunSpec(TRANSIENT, ("i(l1)", "i(l8)"), TSTOP, foreign=False))
    ac = execute(RunSpec(AC_TEXT, ("i(l1)", "i(l8)"), 0.0, foreign=False, analysis="ac", points=32))
    for record, data, kind in ((transient, TransientData, "transient"), (ac, AcData, "ac")):
        assert record.ok and record.run is not None, record.reason
        assert isinstance(record.run.data, data) and record.analysis == kind
        assert record.points == record.run.points == record.run.data.axis.size
        assert record.summary()["netlist_sha256"] == record.run.netlist_sha256
        again = pickle.loads(pickle.dumps(record))
        assert again.run is not None and again.digest == record.digest
        np.testing.assert_array_equal(again.run.vectors["i(l8)"], record.run.vectors["i(l8)"])
    assert ac.run is not None and ac.points == 32 and np.iscomplexobj(ac.run.vectors["i(l1)"])
