"""The first-arrival peak's sensitivities (lcchain.theory.sensitivity, lcchain.circuit.sensitivity) against central finite differences of
lcchain's own exact theory (first_arrival of the perturbed chain: an independent route, a peak search on new
modes, where the sensitivities perturb the nominal modes)."""

import numpy as np
import pytest
from helpers.tolerances import (
    ATOL_SAME_PEAK,
    RTOL_FIRST_ORDER_CORNER,
    RTOL_NETLIST_VALUE,
    RTOL_RELATIVE_SENSITIVITY,
    RTOL_SCALING_IDENTITY,
)

from lcchain.circuit.effects import Tolerance, cornered, with_walls
from lcchain.circuit.ladder import Ladder
from lcchain.circuit.netlist import SimulationOptions, netlist_text
from lcchain.circuit.sensitivity import corners, ladder_sensitivity
from lcchain.core.budget import Budget, sensitivity_estimate
from lcchain.core.errors import ParameterError
from lcchain.theory.arrivals import first_arrival
from lcchain.theory.cases import chain_for_case
from lcchain.theory.chain import Chain
from lcchain.theory.sensitivity import SENSITIVITY_MAX_N, peak_sensitivity

#: Relative step of the finite differences: truncation h^2 |p'''| / 6 ~ 1e-11 and rounding eps / h ~ 1e-11.
FD_STEP = 1e-5
#: What the finite differences justify on dp/d ln x: a hundred times their truncation and rounding (the
#: differences seen are 4e-11 to 2e-10).
FD_TOLERANCE = 1e-8


def _peak(masses, springs, coupling):
    return first_arrival(Chain(masses, springs, coupling=coupling)).peak


def _central(chain):
    """dp/d ln m_i and dp/d ln K_j by central differences of first_arrival (free ends: 0)."""
    h = FD_STEP
    relative_m, relative_k = [], []
    for i in range(chain.N):
        m_up, m_down = np.array(chain.masses), np.array(chain.masses)
        m_up[i] *= 1 + h
        m_down[i] *= 1 - h
        relative_m.append((_peak(m_up, chain.springs, chain.coupling)
                           - _peak(m_down, chain.springs, chain.coupling)) / (2 * h))
    for j in range(chain.N + 1):
        k_up, k_down = np.array(chain.springs), np.array(chain.springs)
        k_up[j] *= 1 + h
        k_down[j] *= 1 - h
        relative_k.append(0.0 if chain.springs[j] == 0 else (
            _peak(chain.masses, k_up, chain.coupling) - _peak(chain.masses, k_down, chain.coupling)) / (2 * h))
    return np.array(relative_m), np.array(relative_k)


CASES = {
    "two-mass N=12": lambda: chain_for_case("two-mass", 12),
    "one-mass N=9": lambda: chain_for_case("one-mass", 9),
    "perfect N=7": lambda: chain_for_case("perfect", 7),
    "perfect N=6 walls j=1": lambda: chain_for_case("perfect", 6, 1),
    "two-mass N=10, walls K0=0.3": lambda: with_walls(chain_for_case("two-mass", 10), 0.3),
    "two-mass N=10, coupled k=0.2": lambda: chain_for_case("two-mass", 10).with_coupling(0.2),
    "asymmetric N=8": lambda: Chain([1.3, 0.9, 1.1, 1.0, 1.0, 0.8, 1.2, 1.6], [0.0, 0.9, 1.1, 1.0, 1.0, 0.95, 1.2,
                                                                             0.7, 0.2]),
}


@pytest.mark.parametrize("make", CASES.values(), ids=CASES.keys())
def test_sensitivities_match_finite_differences_of_exact_theory(make):
    chain = make()
    sensitivity = peak_sensitivity(chain)
    assert sensitivity.peak == pytest.approx(first_arrival(chain).peak, abs=ATOL_SAME_PEAK)
    relative_m, relative_k = _central(chain)
    np.testing.assert_allclose(sensitivity.relative_masses, relative_m, rtol=0, atol=FD_TOLERANCE)
    np.testing.assert_allclose(sensitivity.relative_springs, relative_k, rtol=0, atol=FD_TOLERANCE)
    # the peak depends on them: a test of zeros would pass the comparison above
    assert np.max(np.abs(sensitivity.relative_masses)) > 0.1


@pytest.mark.parametrize("make", CASES.values(), ids=CASES.keys())
def test_relative_sensitivities_sum_to_zero(make):
    # scaling every mass (or every spring) only rescales time: the peak does not move
    sensitivity = peak_sensitivity(make())
    scale = np.max(np.abs(sensitivity.relative_masses))
    assert abs(sensitivity.relative_masses.sum()) < RTOL_SCALING_IDENTITY * max(1.0, scale) * sensitivity.chain.N
    assert abs(sensitivity.relative_springs.sum()) < RTOL_SCALING_IDENTITY * max(1.0, scale) * sensitivity.chain.N


def test_free_ends_have_no_relative_sensitivity_but_a_wall_spring_would_move_the_peak():
    sensitivity = peak_sensitivity(chain_for_case("two-mass", 10))
    assert sensitivity.springs[0] != 0.0  # a small wall spring would change the peak
    assert sensitivity.relative_springs[0] == sensitivity.relative_springs[-1] == 0.0


def test_refused_and_priced():
    with pytest.raises(ParameterError, match="N <= 2000"):
        peak_sensitivity(Chain.uniform_free(SENSITIVITY_MAX_N + 1))
    with pytest.raises(ParameterError, match="chain"):
        peak_sensitivity([1.0, 1.0])  # type: ignore[arg-type]
    assert sensitivity_estimate(2000).fits(Budget())
    assert not sensitivity_estimate(2000).fits(Budget(max_seconds=2.0))


# ------------------------------------------------------------------ the ladder's components and the corners


def test_components_are_named_valued_and_scaled_as_the_netlist_writes_them():
    ladder = Ladder(chain_for_case("perfect", 6, 1), L0=2e-6, C0=5e-9)
    sensitivity = ladder_sensitivity(ladder)
    netlist = netlist_text(ladder, SimulationOptions(dt=0.05, tstop=20.0))
    theory = peak_sensitivity(ladder.chain)
    assert len(sensitivity.components) == 2 * 6 + 1  # walls: C0_1 and C6_7 are parts too
    for part in sensitivity.components:
        line = next(line for line in netlist.splitlines() if line.split()[0] == part.name)
        assert float(line.split()[3]) == part.value
        assert part.derivative * part.value == pytest.approx(part.relative, rel=RTOL_RELATIVE_SENSITIVITY)
        if part.kind == "C":  # C = C0 / K: d ln C = -d ln K
            assert part.relative == -theory.relative_springs[part.slot - 6]
    ranked = [abs(part.relative) for part in sensitivity.components]
    assert ranked == sorted(ranked, reverse=True)


def test_corners_move_the_ranked_parts_at_their_tolerances():
    ladder = Ladder(chain_for_case("two-mass", 10))
    sensitivity = ladder_sensitivity(ladder)
    found = corners(sensitivity, components=2, tol_L=0.05, tol_C=0.02)
    assert [c.label for c in found][:1] == ["nominal"] and [c.label for c in found][-2:] == [
        "predicted max", "predicted min"]
    assert len(found) == 1 + 4 + 2 and len({c.signs for c in found}) == 7
    assert sum(map(abs, found[1].signs)) == 2 and sum(map(abs, found[-1].signs)) == 2 * 10 + 1 - 2  # free ends
    assert found[-2].predicted == -found[-1].predicted > 0
    corner = found[-1]
    chain = cornered(ladder.chain, ladder.L0, ladder.C0, signs=corner.signs, tol_L=0.05, tol_C=0.02)
    assert Tolerance(0.05, 0.02, corner=corner.signs).draw(ladder.chain, ladder.L0, ladder.C0)[0] == chain
    np.testing.assert_allclose(chain.masses / ladder.chain.masses, 1 + 0.05 * np.array(corner.signs[:10]))
    # to first order the corner moves the peak as predicted (second order: tol^2 terms)
    assert first_arrival(chain).peak - sensitivity.peak == pytest.approx(corner.predicted, rel=RTOL_FIRST_ORDER_CORNER)
    with pytest.raises(ParameterError, match="--components"):
        corners(sensitivity, components=0, tol_L=0.05, tol_C=0.02)


@pytest.mark.parametrize("kwargs, field", [
    ({"corner": (1, 2)}, "effects.tolerance.corner"),
    ({"corner": "+-"}, "effects.tolerance.corner"),
    ({"corner": (True, 0)}, "effects.tolerance.corner"),
    ({"corner": (1, 0), "samples": 3}, "effects.tolerance.samples"),
])
def test_bad_corners_are_refused(kwargs, field):
    with pytest.raises(ParameterError) as raised:
        Tolerance(0.05, 0.05, **kwargs)
    assert raised.value.field == field


def test_a_corner_of_the_wrong_length_is_refused():
    with pytest.raises(ParameterError, match="2N\\+1 = 21 signs"):
        Tolerance(0.05, 0.05, corner=(1, 0, -1)).draw(chain_for_case("two-mass", 10), 1e-5, 1e-8)


def test_energy_sensitivities_match_finite_differences_of_the_energy_fraction():
    chain = with_walls(chain_for_case("two-mass", 9), 0.2)
    sensitivity = peak_sensitivity(chain)
    h = FD_STEP

    def energy(masses, springs):
        return first_arrival(Chain(masses, springs)).peak ** 2 * masses[-1] / masses[0]

    for i in (0, 4, chain.N - 1):
        up, down = np.array(chain.masses), np.array(chain.masses)
        up[i] *= 1 + h
        down[i] *= 1 - h
        fd = (energy(up, chain.springs) - energy(down, chain.springs)) / (2 * h)
        assert sensitivity.energy_relative_masses[i] == pytest.approx(fd, abs=FD_TOLERANCE)
    up, down = np.array(chain.springs), np.array(chain.springs)
    up[0] *= 1 + h
    down[0] *= 1 - h
    fd = (energy(chain.masses, up) - energy(chain.masses, down)) / (2 * h)
    assert sensitivity.energy_relative_springs[0] == pytest.approx(fd, abs=FD_TOLERANCE)
    assert abs(sensitivity.energy_relative_masses.sum()) < RTOL_SCALING_IDENTITY  # the scaling identity holds for e too


def test_a_scene_corner_is_realised_by_the_planner_and_round_trips():
    from lcchain.scenes.load import parse_scene
    from lcchain.scenes.plan import scene_plan

    signs = [1, 0, -1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1]
    data = {"chain": {"case": "two-mass", "N": 10}, "excitation": {"kind": "kick"},
            "effects": {"tolerance": {"L": 0.05, "C": 0.02, "corner": signs}}, "analysis": {"dt": 0.05}}
    scene = parse_scene(data, source="corner.toml")
    assert parse_scene(scene.to_dict()) == scene
    plan = scene_plan(scene)
    assert len(plan.chains) == 1 and len(plan.specs) == 1
    expected = cornered(plan.nominal, 1e-5, 1e-8, signs=tuple(signs), tol_L=0.05, tol_C=0.02)
    assert plan.chains[0] == expected
    assert plan.specs[0].theory.chain == expected  # the netlist and the theory of one realised chain
    values = {line.split()[0]: float(line.split()[3]) for line in plan.specs[0].netlist.splitlines()
              if line[:1] in "LC" and not line.startswith(".")}
    assert values["L1"] == pytest.approx(1.05 * 1e-5 * plan.nominal.masses[0], rel=RTOL_NETLIST_VALUE)
    assert values["L3"] == pytest.approx(0.95 * 1e-5 * plan.nominal.masses[2], rel=RTOL_NETLIST_VALUE)
    assert values["L2"] == pytest.approx(1e-5 * plan.nominal.masses[1], rel=RTOL_NETLIST_VALUE)
