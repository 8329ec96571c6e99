"""``lcchain bom``: the ladder's distinct parts and their counts (issue 33, item 2)."""

from __future__ import annotations

import csv
import io

import numpy as np
import pytest
from helpers.tolerances import RTOL_BOM_VALUE

from lcchain.circuit.bom import bill_of_materials
from lcchain.circuit.effects import E_SERIES, CapacitorESL, CoilCapacitance, Losses
from lcchain.cli.main import main
from lcchain.theory.cases import chain_for_case


def test_a_bom_counts_every_coil_and_capacitor_of_the_ladder_in_preferred_values(capsys) -> None:
    assert main(["bom", "--case", "two-mass", "--N", "20", "--series", "E24", "--L0", "10u", "--C0", "10n",
                 "--tolerance", "1%", "--csv"]) == 0
    rows = list(csv.DictReader(io.StringIO(capsys.readouterr().out)))
    kinds = {kind: [r for r in rows if r["kind"] == kind] for kind in ("inductor", "capacitor")}
    # N coils and N - 1 inner capacitors (a free chain's ends are wires), each named once
    assert sum(int(r["count"]) for r in kinds["inductor"]) == 20
    assert sum(int(r["count"]) for r in kinds["capacitor"]) == 19
    assert sum(len(r["parts"].split()) for r in rows) == 39 and all(r["tolerance"] == "1%" for r in rows)
    mantissas = {round(float(r["value"]) / 10.0 ** np.floor(np.log10(float(r["value"]))), 9) for r in rows}
    assert mantissas <= {round(m, 9) for m in E_SERIES["E24"]}
    # the two-mass chain's bulk coils and springs are L0 and C0 themselves (Table II's chain: m = K = 1 inside)
    bulk = {(r["kind"], float(r["value"])) for r in rows if int(r["count"]) > 2}
    assert bulk == {("inductor", 1e-5), ("capacitor", 1e-8)}


def test_the_exact_bom_holds_the_chain_and_what_the_effects_add(capsys) -> None:
    chain = chain_for_case("two-mass", 6)
    parts = bill_of_materials(chain, 2e-6, 3e-9)
    values = sorted(v for p in parts if p.kind == "inductor" for v in [p.value] * p.count)
    np.testing.assert_allclose(values, sorted(np.asarray(chain.masses) * 2e-6), rtol=RTOL_BOM_VALUE)
    assert main(["bom", "--case", "two-mass", "--N", "6", "--coupling", "0.1", "--Q", "100"]) == 0
    out = capsys.readouterr().out
    assert "coils coupled k = 0.1" in out and "resistor" in out and "coupling" in out


def test_a_parts_own_properties_are_listed_apart_as_nothing_to_buy(capsys) -> None:
    """A coil's self-capacitance, a capacitor's ESL and the coils' coupling are elements of the circuit, not parts
    (they were listed as capacitors, inductors and a coupling to buy, with the tolerance of the parts)."""
    parts = bill_of_materials(chain_for_case("two-mass", 4), 1e-5, 1e-8, series="E24",
                              effects=(CoilCapacitance(0.0123), CapacitorESL(0.0317), Losses(100.0)))
    bought = {name for part in parts if part.bought for name in part.names}
    own = {name for part in parts if not part.bought for name in part.names}
    assert {"L1", "L4", "C1_2", "R1"} <= bought and {"CP1", "CP4", "LS1_2"} <= own and not bought & own
    assert main(["bom", "--case", "two-mass", "--N", "4", "--coil-capacitance", "0.0123", "--coupling", "0.1",
                 "--tolerance", "5%", "--csv"]) == 0
    rows = list(csv.DictReader(io.StringIO(capsys.readouterr().out)))
    for row in rows:
        parasitic = row["parts"].startswith(("CP", "K"))
        assert (row["bought"] == "yes") != parasitic and (row["tolerance"] == "") == parasitic


@pytest.mark.parametrize("argv, option", [
    (["--L0", "10x"], "--L0"), (["--C0", "10uH"], "--C0"), (["--L0", "0"], "--L0"),
    (["--C0", "10M"], "--C0 = '10M' is not allowed: expected meg for mega or m for milli"),
    (["--tolerance", "150%"], "--tolerance"), (["--series", "E7"], "--series")])
def test_bad_bom_values_are_one_line_naming_the_option(argv: list[str], option: str, capsys) -> None:
    assert main(["bom", "--case", "two-mass", "--N", "6", *argv]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and option in err
