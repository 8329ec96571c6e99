"""lcchain's overhead in a simulation whose members run two at a time (issue 23): a wall-clock overhead, never
negative (the members' summed ngspice times once made it -45.9 s at N = 3000)."""

from __future__ import annotations

import os

import pytest

from lcchain.runs.simulate import ChainOptions, simulate_chain, simulator_wall_time
from lcchain.theory.cases import chain_for_case


def test_simulator_wall_time_is_the_union_of_the_runs() -> None:
    assert simulator_wall_time([]) == 0.0
    assert simulator_wall_time([(10.0, 2.0)]) == 2.0
    assert simulator_wall_time([(10.0, 4.0), (11.0, 1.0)]) == 4.0  # one inside the other
    assert simulator_wall_time([(11.0, 4.0), (10.0, 2.0)]) == 5.0  # overlapping, in any order
    assert simulator_wall_time([(10.0, 1.0), (20.0, 1.0), (20.5, 1.0)]) == 2.5  # a gap is nobody's
    runs = [(0.25 * i, 1.0 + 0.1 * i) for i in range(7)]
    assert max(w for _, w in runs) <= simulator_wall_time(runs) <= sum(w for _, w in runs)


@pytest.mark.ngspice
@pytest.mark.skipif(len(os.sched_getaffinity(0)) < 2, reason="the members run two at a time only on 2 cores")
def test_overhead_of_members_run_two_at_a_time_is_never_negative() -> None:
    # N = 300 at dt = 0.05 and 0.025: the two ngspice runs (1 s and 2 s) overlap by more than lcchain's own work,
    # so their summed times exceed the call's
    report = simulate_chain(chain_for_case("two-mass", 300), ChainOptions(dt=0.05, extrapolate=2))
    t = report.timings
    members = report.extrapolation.members
    walls = [m.wall_s for m in members]
    assert len(walls) == 2 and t["simulator_s"] == pytest.approx(sum(walls))
    rounding = 1e-9  # the union is summed from perf_counter readings
    assert max(walls) - rounding <= t["simulator_wall_s"] <= min(t["simulator_s"], t["execute_s"]) + rounding
    assert t["overhead_s"] == pytest.approx(t["total_s"] - t["simulator_wall_s"])
    assert t["overhead_s"] >= 0.0
    assert t["overhead_fraction"] >= 0.0
