"""Parts added from outside lcchain (issue 20, docs/extending.md): an effect defined here, in the tests folder,
runs through simulate and a study without any edit to lcchain."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np
import pytest
from helpers.tolerances import PREDICTION_FACTOR

import lcchain
from lcchain.circuit.effects import Effect
from lcchain.circuit.ladder import Ladder
from lcchain.runs.request import Request, Transient, plan_request
from lcchain.studies.plan import request_plan
from lcchain.studies.run import run_plan
from lcchain.theory.cases import chain_for_case
from lcchain.theory.chain import Chain


@dataclass(frozen=True)
class HeavyEnds(Effect):
    """Test-only effect: both end coils ``factor`` times their design value (a chain change, so the netlist and
    the exact theory both follow from the realised chain)."""

    key: ClassVar[str] = "heavy_ends"
    factor: float

    def realise(self, chain: Chain, L0: float, C0: float) -> Chain:
        masses = np.array(chain.masses)
        masses[[0, -1]] *= self.factor
        return Chain(masses, chain.springs, name=chain.name, coupling=chain.coupling)


@dataclass(frozen=True)
class SeriesProbe(Effect):
    """Test-only effect: a 1 uohm resistor after every inductor (an element in series; the theory neglects it)."""

    key: ClassVar[str] = "series_probe"

    def in_series(self, ladder: Ladder, loop: int) -> tuple[tuple[str, float], ...]:
        return (("R", 1e-6),)


def test_an_outside_effect_changes_netlist_and_theory_together():
    chain = chain_for_case("two-mass", 12)
    plain, heavy = (plan_request(Request(chain, Transient(dt=0.05), effects=effects)).specs[0]
                    for effects in ((), (HeavyEnds(1.25),)))
    assert heavy.theory.chain.masses[0] == 1.25 * chain.masses[0]
    assert f"L1 0 n1 {float(1.25 * chain.masses[0]) * 10e-6!r} IC=" in heavy.netlist
    assert plain.netlist != heavy.netlist
    probed = plan_request(Request(chain, Transient(dt=0.05), effects=(SeriesProbe(),))).specs[0]
    assert "R1 m1 n1 1e-06" in probed.netlist and probed.netlist.count("\nR") == chain.N


@pytest.mark.ngspice
def test_an_outside_effect_runs_in_simulate_and_in_a_study(tmp_path):
    chain = chain_for_case("two-mass", 20)
    report = lcchain.simulate(Request(chain, Transient(dt=0.02, transits=2), effects=(HeavyEnds(1.1),)))
    assert report.chain.masses[-1] == 1.1 * chain.masses[-1]
    assert report.predicted_error is not None
    assert report.comparison.max_abs_error <= PREDICTION_FACTOR * report.predicted_error
    points = [({"factor": f}, Request(chain, Transient(dt=0.05), effects=(HeavyEnds(f),))) for f in (1.0, 1.2)]
    plan = request_plan(points)
    assert plan.axes == ("factor",) and len(plan.tasks) == 2
    summary = run_plan(plan, tmp_path / "heavy.sqlite", executor="process", workers=2)
    assert summary.ok == 2 and summary.failed == 0
