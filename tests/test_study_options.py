"""The frozen options that carry what the study, scene and report functions used to take as a dozen keywords
(issue 34 item 4): each refuses a bad value when it is made, in one line naming the field (the option a user
typed, where there is one), the value and what is allowed; sequences are kept as tuples, so a plan cannot change
after it was checked.  No simulator runs here (the functions that take them are tested with ngspice in
test_studies.py, test_scenes.py, test_netlist_sweep.py and test_report*.py)."""

from __future__ import annotations

import pickle

import numpy as np
import pytest

from lcchain.app.scenes import SceneRun
from lcchain.core.errors import ParameterError
from lcchain.report.plots import OverlayCurves
from lcchain.report.validation import ValidationRuns
from lcchain.studies.options import RunHooks, RunOptions
from lcchain.studies.plan import NetlistSweep, Planning, RealParts, SpectrumAxes, SweepAxes

BAD = {
    "steps and accuracies": (lambda: SweepAxes(["two-mass"], [10], dts=[0.05], accuracies=[1e-3]),
                             r"--dt/--accuracy = .* steps or accuracies, not both"),
    "neither steps nor accuracies": (lambda: SweepAxes(["two-mass"], [10]), r"--dt/--accuracy"),
    "a size below the least": (lambda: SweepAxes(["two-mass"], [0], dts=[0.05]), r"^N = 0 is not allowed"),
    "a NaN step": (lambda: SweepAxes(["two-mass"], [10], dts=[float("nan")]), r"^dt = nan is not allowed"),
    "no transit": (lambda: SweepAxes(["two-mass"], [10], dts=[0.05], transits=[0]), r"^transits = 0"),
    "a case as one string": (lambda: SweepAxes("two-mass", [10], dts=[0.05]), r"^cases = 'two-mass'"),
    "an AC size below the least": (lambda: SpectrumAxes(["two-mass"], [0]), r"^N = 0 is not allowed"),
    "no worker": (lambda: Planning(workers=0), r"^workers = 0 is not allowed"),
    "a budget that is none": (lambda: Planning(budget="1 s"), r"^budget = "),
    "no sample": (lambda: RealParts(samples=0), r"^--samples = 0 is not allowed"),
    "a tolerance of one": (lambda: RealParts(tolerance={"L": 1.0}), r"^--tolerance L = 1\.0 is not allowed"),
    "a tolerance of another part": (lambda: RealParts(tolerance={"R": 0.1}), r"^--tolerance = "),
    "a netlist sweep without time": (lambda: NetlistSweep(timeout=0.0), r"^timeout = 0\.0 is not allowed"),
    "an unknown executor": (lambda: RunOptions(executor="cluster"), r"^--executor = 'cluster' is not allowed"),
    "no run worker": (lambda: RunOptions(workers=0), r"^--workers = 0 is not allowed"),
    "a scheduler without Dask": (lambda: RunOptions(executor="serial", scheduler="tcp://127.0.0.1:1"),
                                 r"^--scheduler = "),
    "an unknown transport": (lambda: RunOptions(transport="pigeon"), r"^--transport = 'pigeon' is not allowed"),
    "a negative time budget": (lambda: RunOptions(max_seconds=-1.0), r"^--max-time = -1\.0 is not allowed"),
    "a progress that is no function": (lambda: RunHooks(progress="dots"), r"^progress = "),
    "outputs that are no flag": (lambda: SceneRun(write_outputs="yes"), r"^write_outputs = 'yes' is not allowed"),
    "a bytes file name": (lambda: SceneRun(netlist_out=b"x.cir"), r"^netlist_out = "),
    "a check that is none": (lambda: ValidationRuns([object()], {"ngspice": "45"}), r"^circuit\[0\] = "),
    "a negative time": (lambda: ValidationRuns([], {}, seconds=-1.0), r"^seconds = -1\.0 is not allowed"),
    "curves of two lengths": (lambda: OverlayCurves(np.arange(5.0), np.arange(4.0), np.arange(3.0), np.arange(3.0)),
                              r"^y_sim\.shape = \(4,\) is not allowed"),
    "loop 1 half given": (lambda: OverlayCurves(np.arange(3.0), np.arange(3.0), np.arange(3.0), np.arange(3.0),
                                                first_sim=np.arange(3.0)), r"^first_sim, first_theory = "),
}


@pytest.mark.parametrize("make, message", BAD.values(), ids=BAD.keys())
def test_a_bad_option_is_refused_when_made_in_one_line_naming_its_field(make, message):
    with pytest.raises(ParameterError, match=message) as caught:
        make()
    assert "\n" not in str(caught.value)


def test_the_axes_are_kept_as_tuples_and_the_options_pickle():
    given = ["two-mass"]
    axes = SweepAxes(given, [10, 20], dts=[0.05])
    given.append("one-mass")  # the caller's list changes: the axes do not
    assert axes.cases == ("two-mass",) and axes.Ns == (10, 20) and axes.dts == (0.05,)
    assert pickle.loads(pickle.dumps(axes)) == axes
    parts = RealParts(samples=3, tolerance={"L": 0.05})
    assert pickle.loads(pickle.dumps(parts)) == parts
    assert RunOptions(executor="serial", workers=2) == RunOptions("serial", 2)


def test_real_parts_set_a_scene_as_the_options_do():
    tables = RealParts(samples=4, seed=7, tolerance={"C": 0.02}, series="E24").applied({"title": "t"})
    assert tables["title"] == "t"
    assert tables["effects"]["tolerance"] == {"C": 0.02, "samples": 4, "seed": 7}
    assert tables["effects"]["preferred_values"] == {"series": "E24"}
    assert RealParts().applied({})["effects"] == {}
