"""Effects that change the chain (walls, E-series, tolerances) and the netlist elements each effect adds."""

import dataclasses
import re
from typing import ClassVar

import numpy as np
import pytest
from helpers.tolerances import ATOL_ROUND_TRIP, RTOL_E_SERIES_VALUE, RTOL_TOLERANCE_BOUND

from lcchain.circuit.effects import (
    E_SERIES,
    CapacitorESR,
    Effect,
    Losses,
    Walls,
    preferred_value,
    realise,
    tolerance_samples,
    with_walls,
)
from lcchain.circuit.elements import ELEMENT_HOOKS, ladder_elements
from lcchain.circuit.exact import CircuitTheory
from lcchain.circuit.ladder import Ladder
from lcchain.circuit.netlist import Drive, NetlistOutput, SimulationOptions, netlist_text
from lcchain.core.errors import ParameterError
from lcchain.theory.cases import chain_for_case
from lcchain.theory.chain import Chain

OPTIONS = SimulationOptions(dt=0.05, tstop=30.0)


@pytest.mark.parametrize("series, value, expected", [
    ("E24", 4.2746e-5, 4.3e-5), ("E12", 2.4055e-8, 2.2e-8), ("E96", 9.99e-6, 1e-5), ("E24", 1e-5, 1e-5),
    ("E12", 9.6e-9, 1e-8), ("E96", 1.234e-7, 1.24e-7), ("E24", 0.95, 0.91),
])
def test_preferred_values_nearest_on_a_log_scale(series, value, expected):
    assert preferred_value(value, series) == expected


def test_every_series_value_is_a_fixed_point():
    for series, mantissas in E_SERIES.items():
        for m in mantissas:
            for scale in (1e-9, 1e-6, 1.0):
                value = float(f"{m * scale:.12g}")
                assert preferred_value(value, series) == value
    with pytest.raises(ParameterError, match="series"):
        preferred_value(1.0, "E48")


def test_walls_and_realised_chain():
    chain = Chain.from_rw(10, 0.8, 0.3)
    walled = with_walls(chain, 0.01)
    assert walled.springs[0] == walled.springs[-1] == 0.01 and not walled.is_free
    rounded = realise(chain, 10e-6, 10e-9, series="E12")
    assert rounded.springs[0] == 0 and rounded.springs[-1] == 0  # free ends stay wires
    for m in rounded.masses * 10e-6:
        assert preferred_value(m, "E12") == pytest.approx(m, rel=RTOL_E_SERIES_VALUE)
    with pytest.raises(ParameterError, match="K0"):
        with_walls(chain, -1.0)


def test_tolerance_samples_reproducible_bounded_and_asymmetric():
    chain = Chain.from_rw(20, 0.77, 0.25)
    tol_L, tol_C = 0.05, 0.02
    a = tolerance_samples(chain, 10e-6, 10e-9, samples=5, seed=7, tol_L=tol_L, tol_C=tol_C)
    b = tolerance_samples(chain, 10e-6, 10e-9, samples=8, seed=7, tol_L=tol_L, tol_C=tol_C)
    for x, y in zip(a, b, strict=False):  # sample k does not depend on how many are drawn
        assert x == y
    c = tolerance_samples(chain, 10e-6, 10e-9, samples=5, seed=8, tol_L=tol_L, tol_C=tol_C)
    assert a[0] != c[0]
    for s in a:
        ratio = s.masses / chain.masses
        assert np.all(np.abs(ratio - 1) <= tol_L) and np.std(ratio) > 0
        inner = chain.springs[1:-1]
        assert np.all(np.abs(inner / s.springs[1:-1] - 1) <= tol_C + RTOL_TOLERANCE_BOUND)  # C = C0/K within 2 %
        assert not s.is_symmetric


def _lines(text, prefix):
    return [line for line in text.splitlines() if line.startswith(prefix)]


def test_ideal_netlist_is_a_pure_lc_ladder():
    text = netlist_text(Ladder(Chain.from_rw(30, 0.6, 0.1)), OPTIONS)
    body = [line for line in text.splitlines()[1:] if line and line[0] not in "*."]
    assert {line[0] for line in body} == {"L", "C"}
    assert len(_lines(text, "L")) == 30 and len(_lines(text, "C")) == 29  # free ends: no wall capacitor
    assert re.search(r"^\.save i\(l1\) i\(l30\)$", text, re.M)


def test_each_effect_adds_only_its_own_elements():
    chain = Chain.from_rw(30, 0.6, 0.1)
    ideal = netlist_text(Ladder(chain), OPTIONS)
    lossy = netlist_text(Ladder(chain), OPTIONS, effects=(Losses(100),))
    assert len(_lines(lossy, "R")) == 30 and not _lines(ideal, "R")
    assert not _lines(lossy, "V") and not _lines(lossy, "B")
    for shape, prefix in (("gaussian", "B"), ("rect", "V")):
        pulsed = netlist_text(Ladder(chain), OPTIONS, Drive(kind="pulse", pulse=(shape, 0.2)))
        assert len(_lines(pulsed, prefix)) == 1 and not _lines(pulsed, "R")
        assert "IC=" not in pulsed
    walled = netlist_text(Ladder(with_walls(chain, 0.01)), OPTIONS)
    assert len(_lines(walled, "C")) == 31 and re.search(r"^C0_1 n0 0 1e-06$", walled, re.M)
    everything = netlist_text(Ladder(chain), OPTIONS, output=NetlistOutput(probes="all"))
    assert everything.count("i(l") == 30


@pytest.mark.parametrize("kwargs, field", [
    ({"excitation": "pulse"}, "pulse"),
    ({"excitation": "kick", "pulse": ("gaussian", 0.2)}, "pulse"),
    ({"excitation": "pulse", "pulse": ("triangle", 0.2)}, "shape"),
    ({"excitation": "pulse", "pulse": ("rect", 0.0)}, "width"),
    ({"effects": (100,)}, "effects"),  # losses are an effect, Losses(Q): no Q= of their own
])
def test_bad_effect_arguments(kwargs, field):
    with pytest.raises(ParameterError, match=field):
        effects = kwargs.pop("effects", ())
        drive = Drive(kwargs["excitation"], pulse=kwargs.get("pulse")) if kwargs else None
        netlist_text(Ladder(Chain.uniform_free(5)), OPTIONS, drive, effects=effects)


# ------------------------------------------------------ the element hooks (issue 30)
@dataclasses.dataclass(frozen=True)
class _Everywhere(Effect):
    """Test-only: one element in every new place (a leak across each capacitor, a resistor from each rail node to
    ground, a capacitor spanning each pair of neighbouring coils)."""

    key: ClassVar[str] = "everywhere"

    def across_capacitor(self, ladder, spring):
        return (("R", 1e3),)

    def to_ground(self, ladder, node):
        return (("R", 2e3),)

    def between_coils(self, ladder, loop):
        return (("C", 1e-12),)


@dataclasses.dataclass(frozen=True)
class _CouplingByElements(Effect):
    """Test-only: coupled coils said as ``K`` elements between neighbouring coils, not as a chain change."""

    key: ClassVar[str] = "coupling_by_elements"
    k: float

    def between_coils(self, ladder, loop):
        return (("K", self.k),)


def test_every_hook_is_asked_for_elements():
    assert set(ELEMENT_HOOKS) == {name for name in vars(Effect) if callable(getattr(Effect, name))
                                  and name not in ("realise", "response", "from_option")}


def test_the_new_places_put_their_elements_where_they_say():
    ladder = Ladder(chain_for_case("two-mass", 5), 10e-6, 10e-9)
    walled = Ladder(with_walls(chain_for_case("two-mass", 5), 0.5), 10e-6, 10e-9)
    cards = {e.name: (e.a, e.b, e.value) for e in ladder_elements(ladder, (_Everywhere(),))}
    # free ends: C1_2..C4_5 only, nodes n1..n4; n0 and n5 are ground
    assert [name for name in cards if name.startswith("RA")] == ["RA1_2", "RA2_3", "RA3_4", "RA4_5"]
    assert cards["RA2_3"] == ("n2", "0", 1e3)
    assert [name for name in cards if name.startswith("RG")] == ["RG1", "RG2", "RG3", "RG4"]
    assert cards["RG4"] == ("n4", "0", 2e3)
    assert [name for name in cards if name.startswith("CB")] == ["CB1_2", "CB2_3", "CB3_4", "CB4_5"]
    assert cards["CB1_2"] == ("0", "n2", 1e-12) and cards["CB4_5"] == ("n3", "0", 1e-12)
    walls = {e.name: (e.a, e.b) for e in ladder_elements(walled, (_Everywhere(), CapacitorESR(0.01)))}
    assert walls["RA0_1"] == ("c0", "0") and walls["RS0_1"] == ("n0", "c0")  # across the capacitor alone
    assert walls["RG0"] == ("n0", "0") and walls["RG5"] == ("n5", "0")
    plain = ladder_elements(ladder)
    assert ladder_elements(ladder, (Walls(1.0),)) == plain  # no element hook: no element


def test_coupling_as_elements_is_the_coupled_chains_exact_theory():
    """The same circuit said two ways, a chain with coupled coils or K elements between coils, has the same
    exact theory (lcchain.circuit.exact), to rounding."""
    chain = chain_for_case("two-mass", 8)
    t = np.linspace(0.0, 5e-4, 50)
    I0 = 1e-3
    by_chain = CircuitTheory(ladder_elements(Ladder(chain.with_coupling(0.2), 10e-6, 10e-9), kick=I0))
    by_elements = CircuitTheory(ladder_elements(Ladder(chain, 10e-6, 10e-9), (_CouplingByElements(0.2),),
                                                kick=I0))
    probes = ["L1", "L8"]
    assert np.allclose(by_elements.currents(t, probes), by_chain.currents(t, probes), rtol=0.0,
                       atol=ATOL_ROUND_TRIP * I0)
