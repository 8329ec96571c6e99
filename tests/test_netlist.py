"""Netlist text: mapping, determinism, card_number format, injection safety, reference files."""

import re
from pathlib import Path

import numpy as np
import pytest
from helpers.tolerances import RTOL_NETLIST_TMAX

from lcchain.circuit.ladder import Ladder
from lcchain.circuit.netlist import (
    Drive,
    NetlistOutput,
    SimulationOptions,
    card_number,
    check_user_text,
    netlist_text,
    probe_names,
)
from lcchain.circuit.reference import REFERENCE_SET, reference_netlist
from lcchain.core.errors import ParameterError
from lcchain.theory.chain import Chain
from lcchain.theory.design import optimal_design

NETLISTS = Path(__file__).resolve().parent.parent / "netlists"
OPTIONS = SimulationOptions(dt=0.05, tstop=10.0)


def _elements(text):
    return [line.split() for line in text.splitlines()[1:] if line and line[0] in "LC"]


def test_mapping_masses_to_inductors_springs_to_capacitors():
    """Last section of the paper: L_i = m_i L0, C_{i,i+1} = C0 / K_{i,i+1}; walls are capacitors."""
    chain = Chain([2.0, 1.0, 0.5], [0.25, 4.0, 1.0, 0.0])
    text = netlist_text(Ladder(chain, L0=3e-6, C0=2e-9), OPTIONS)
    values = {e[0]: (e[1], e[2], float(e[3])) for e in _elements(text)}
    assert values["L1"] == ("n0", "n1", 6e-6)
    assert values["L2"] == ("n1", "n2", 3e-6)
    assert values["L3"] == ("n2", "0", 1.5e-6)  # free right end: a wire to ground
    assert values["C1_2"] == ("n1", "0", 2e-9 / 4.0)
    assert values["C2_3"] == ("n2", "0", 2e-9)
    assert values["C0_1"] == ("n0", "0", 2e-9 / 0.25)  # wall spring K01 = 0.25
    assert "C3_4" not in values


def test_free_ends_are_wires_and_bounded_ends_capacitors():
    free = netlist_text(Ladder(Chain.uniform_free(5)), OPTIONS)
    bounded = netlist_text(Ladder(Chain.uniform_bounded(5)), OPTIONS)
    assert re.search(r"^L1 0 n1 ", free, re.M) and re.search(r"^L5 n4 0 ", free, re.M)
    assert re.search(r"^C0_1 n0 0 ", bounded, re.M) and re.search(r"^C5_6 n5 0 ", bounded, re.M)


def test_excitations_set_initial_conditions():
    chain = Chain.uniform_bounded(4)
    kick = netlist_text(Ladder(chain, 1.0, 1.0), OPTIONS, Drive(kind="kick", I0=2.0))
    assert re.search(r"^L1 n0 n1 1.0 IC=2.0$", kick, re.M)
    disp = netlist_text(Ladder(chain, 1.0, 1.0), OPTIONS, Drive(kind="displacement", I0=2.0))
    # Q0 = I0 sqrt(L0 C0) = 2: V(n1) = Q0/C12 = 2, V(n0) = -Q0/C01 = -2
    assert re.search(r"^C1_2 n1 0 1.0 IC=2.0$", disp, re.M)
    assert re.search(r"^C0_1 n0 0 1.0 IC=-2.0$", disp, re.M)
    assert "IC=" not in "".join(line for line in disp.splitlines() if line.startswith("L"))


def test_deterministic_bytes_and_plain_floats():
    chain = Chain.from_rw(30, 0.6, np.float64(0.1))
    a = netlist_text(Ladder(chain, np.float64(10e-6), 10e-9), OPTIONS)
    b = netlist_text(Ladder(Chain.from_rw(30, 0.6, 0.1), 10e-6, 10e-9), OPTIONS)
    assert a == b
    assert "np." not in a and "float64" not in a
    for fields in _elements(a):
        value = fields[3]
        assert float(value) > 0
        assert re.fullmatch(r"[0-9.e+-]+", value), f"not a plain float: {value}"
        assert value == repr(float(value)), "full precision"
    # SPICE suffixes would be read as milli/femto: never emitted
    assert card_number(1e-3) == "0.001" and card_number(1e-15) == "1e-15"


def test_save_only_requested_probes_and_explicit_max_step():
    chain = Chain.uniform_free(6)
    text = netlist_text(Ladder(chain), OPTIONS)
    assert re.search(r"^\.save i\(l1\) i\(l6\)$", text, re.M)
    everything = netlist_text(Ladder(chain), OPTIONS, output=NetlistOutput(probes="all"))
    assert ".save " + " ".join(f"i(l{i})" for i in range(1, 7)) in everything
    tran = re.search(r"^\.tran (\S+) (\S+) 0 (\S+) uic$", text, re.M)
    assert tran and float(tran.group(3)) == pytest.approx(0.05 * np.sqrt(10e-6 * 10e-9), rel=RTOL_NETLIST_TMAX)
    options = re.search(r"^\.options (.*)$", text, re.M).group(1)
    for key in ("method=trap", "maxord=2", "reltol=", "abstol=", "vntol=", "chgtol="):
        assert key in options
    assert probe_names(6, "ends") == ["i(l1)", "i(l6)"]


@pytest.mark.parametrize(
    "title",
    ["two\nlines", "cr\rreturn", ".control", ".endc", ".include /etc/passwd", "  .lib /etc/passwd x",
     ".param a=1", ".title x", "tab\tchar", "nul\x00", "next\u2028line", "x" * 201, 42],
)
def test_user_text_cannot_add_lines_or_commands(title):
    with pytest.raises(ParameterError, match="title"):
        netlist_text(Ladder(Chain.uniform_free(3)), OPTIONS, output=NetlistOutput(title=title))


#: Titles ngspice 39 reads as plain text (measured: it executes none of them); refusing them would be wrong.
HARMLESS_TITLES = ["shell model of a spring chain", ".5 uH ladder", "x .control", "*.include /etc/passwd",
                   "L1 n0 n1 1.0", "Newton's cradle: N = 100 (two-mass)"]


@pytest.mark.parametrize("title", HARMLESS_TITLES)
def test_titles_that_ngspice_reads_as_text_are_accepted(title):
    text = netlist_text(Ladder(Chain.uniform_free(3)), OPTIONS, output=NetlistOutput(title=title))
    assert text.splitlines()[0] == title


@pytest.mark.ngspice
def test_a_shell_title_executes_nothing_in_ngspice(tmp_path):
    from lcchain.spice.job import RunJob
    from lcchain.spice.ngspice.runner import run

    marker = tmp_path / "executed"
    text = netlist_text(Ladder(Chain.uniform_free(3)), OPTIONS, output=NetlistOutput(title=f"shell touch {marker}"))
    run(RunJob(text, ["i(l1)"], OPTIONS.tstop * Ladder(Chain.uniform_free(3)).time_unit))
    assert not marker.exists()


def test_no_generated_netlist_contains_a_control_block():
    text = netlist_text(Ladder(Chain.uniform_free(3)), OPTIONS, output=NetlistOutput(title="safe title: N=3 (ok)"))
    lowered = text.lower()
    assert ".control" not in lowered and "shell" not in lowered
    assert text.splitlines()[0] == "safe title: N=3 (ok)"
    assert check_user_text("title", "Bench cradle, 50 cells") == "Bench cradle, 50 cells"


@pytest.mark.parametrize(
    "kwargs, field",
    [({"dt": 0}, "dt"), ({"dt": -1}, "dt"), ({"dt": float("nan")}, "dt"), ({"dt": 2.0}, "dt"),
     ({"tstop": 0.01}, "tstop"), ({"method": "euler"}, "method")],
)
def test_bad_simulation_options(kwargs, field):
    arguments = {"dt": 0.05, "tstop": 10.0} | kwargs
    with pytest.raises(ParameterError, match=field):
        SimulationOptions(**arguments)


@pytest.mark.parametrize("name, value", [("L0", 0.0), ("C0", -1e-9), ("L0", float("inf"))])
def test_bad_component_scale(name, value):
    with pytest.raises(ParameterError, match=name):
        Ladder(Chain.uniform_free(3), **{name: value})


@pytest.mark.parametrize("reference", REFERENCE_SET, ids=[r.name for r in REFERENCE_SET])
def test_reference_netlists_match_the_generator(reference):
    """netlists/ is regenerated by `lcchain reference-netlists --out netlists`; drift fails here.

    The generator starts from golden literals (no optimiser runs), so the text
    does not depend on the BLAS/LAPACK build.
    """
    path = NETLISTS / reference.name
    assert path.exists(), f"{path} missing: run lcchain reference-netlists --out netlists"
    assert path.read_text(encoding="utf-8") == reference_netlist(reference), (
        f"{reference.name} drifted from the generator: run lcchain reference-netlists --out netlists")
    assert "made by: lcchain reference-netlists" in path.read_text(encoding="utf-8")


#: The golden parameters are six significant digits of the optimum: half a unit of the
#: sixth digit (5e-6 relative at most), plus the optimiser's own tolerance (~1e-7).
RTOL_GOLDEN = 1e-5


@pytest.mark.parametrize("reference", [r for r in REFERENCE_SET if r.params], ids=lambda r: r.name)
def test_the_optimiser_still_lands_on_the_golden_parameters(reference):
    design = optimal_design(reference.case, reference.N)
    for key, golden in reference.params:
        assert getattr(design, key) == pytest.approx(golden, rel=RTOL_GOLDEN), key
