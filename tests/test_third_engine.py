"""A third engine written outside lcchain, with no edit to it (issue 34, item 2): ngspice under another name.

The engine is a subclass of lcchain's ngspice engine that changes only its name; it is given to the public API as
itself (``engine=RenamedNgspice()``, as scipy's ``solve_ivp(method=MyOdeSolver)`` takes a solver), and runs a
transient and an AC analysis.  Nothing in lcchain asks an engine's name to decide what it may do: the runner,
the transports and the AC analysis read the engine's attributes, so the renamed engine gets the same waveforms
and the same spectrum as ngspice itself, under its own name.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import ClassVar

import numpy as np
import pytest

import lcchain
from lcchain.core.errors import ParameterError
from lcchain.spice.engines import ENGINES
from lcchain.spice.ngspice.engine import Ngspice


class RenamedNgspice(Ngspice):
    """ngspice under another name: everything else is ngspice's."""

    name: ClassVar[str] = "renamed-ngspice-test"


@pytest.fixture
def renamed() -> Iterator[RenamedNgspice]:
    """The engine, and the registry as it was once the test is done (giving an engine registers it)."""
    engine = RenamedNgspice()
    yield engine
    ENGINES.pop(engine.name, None)


def test_an_engine_given_as_itself_is_registered_under_its_name(renamed: RenamedNgspice) -> None:
    assert renamed.name not in ENGINES
    request = lcchain.Request(lcchain.chain_for_case("two-mass", 8), lcchain.Transient(dt=0.05), engine=renamed)
    assert request.engine == renamed.name and ENGINES[renamed.name] is renamed
    assert lcchain.Request(request.chain, request.analysis, engine=RenamedNgspice()).engine == renamed.name


def test_an_object_that_is_no_engine_is_refused_in_one_line() -> None:
    with pytest.raises(ParameterError, match="engine") as error:
        lcchain.Request(lcchain.chain_for_case("two-mass", 8), lcchain.Transient(dt=0.05), engine=object())
    assert error.value.field == "engine" and "\n" not in str(error.value)


@pytest.mark.ngspice
def test_a_renamed_ngspice_runs_a_transient_through_the_public_api(renamed: RenamedNgspice) -> None:
    chain = lcchain.chain_for_case("perfect", 12)
    ours = lcchain.simulate_chain(chain, lcchain.ChainOptions(dt=0.05, engine=renamed))
    plain = lcchain.simulate_chain(chain, lcchain.ChainOptions(dt=0.05))
    assert ours.run.engine == renamed.name and ours.record.engine == renamed.name
    assert ours.run.netlist_sha256 == plain.run.netlist_sha256  # the same text (ngspice's dialect) ...
    assert np.array_equal(ours.waveforms.last, plain.waveforms.last)  # ... gives ngspice's own bits
    assert ours.record.key != plain.record.key  # a record of another engine is never another's


@pytest.mark.ngspice
def test_a_renamed_ngspice_runs_an_ac_analysis_through_the_public_api(renamed: RenamedNgspice) -> None:
    chain = lcchain.chain_for_case("two-mass", 8)
    ours = lcchain.spectrum(lcchain.Request(chain, lcchain.AC(), engine=renamed))
    plain = lcchain.spectrum(lcchain.Request(chain, lcchain.AC()))
    assert ours.engine == renamed.name and plain.engine == "ngspice"
    assert ours.netlist_sha256 == plain.netlist_sha256
    assert np.array_equal(ours.fit.omega, plain.fit.omega) and np.array_equal(ours.fitted, plain.fitted)
