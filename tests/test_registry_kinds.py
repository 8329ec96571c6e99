"""Every kind of part in an open registry (issue 34, item 1): cases, mode methods, executors and ngspice's
transports.

Each registry maps a name to a part and, as ``solve_ivp(method=MyOdeSolver)`` does, also takes the part itself:
a part written here, outside the package, is given as an object to the public function that takes its kind,
and it works (the executor's runs go through real ngspice).  The ``Literal`` option sets mypy reads stay
static, and a test checks that each one is its registry's names, so that the two cannot drift apart.
"""

from __future__ import annotations

import contextlib
import dataclasses
from collections.abc import Iterator
from typing import Any, get_args

import pytest
from helpers.netlists import RC_NETLIST

from lcchain.app.options import BACKEND_CHOICES, CASE_CHOICES, EXECUTOR_CHOICES
from lcchain.cli.main import build_parser
from lcchain.core.errors import ParameterError
from lcchain.core.registry import Registry
from lcchain.core.types import Backend, Case, ExecutorName, ModeMethod, Transport
from lcchain.runs.request import Request, Transient, plan_request
from lcchain.scenes.schema import ChainSpec
from lcchain.spice.engines import ENGINES
from lcchain.spice.foreign import allowed_netlist
from lcchain.spice.job import RunJob
from lcchain.spice.ngspice.batch import run_batch
from lcchain.spice.ngspice.find import find_simulator
from lcchain.spice.ngspice.locate import find_batch
from lcchain.spice.ngspice.runner import run
from lcchain.spice.ngspice.transports import TRANSPORT_RUNS, NgspiceTransport, named_transports
from lcchain.spice.result import read_include
from lcchain.studies.executors import EXECUTOR_TRAITS, Executor, execute_group
from lcchain.studies.options import RunOptions
from lcchain.studies.run import run_specs
from lcchain.theory.cases import CHAIN_CASES, ChainCase, chain_for_case
from lcchain.theory.chain import Chain
from lcchain.theory.exact import exact_modes
from lcchain.theory.modes import Modes
from lcchain.theory.spectrum import MODE_SOLVERS, normal_modes


@pytest.fixture
def forget() -> Iterator[list[tuple[Registry[Any], str]]]:
    """Parts a test registers, taken out again after it: the registries are the process's."""
    added: list[tuple[Registry[Any], str]] = []
    yield added
    for registry, name in added:
        registry.pop(name, None)


@pytest.mark.parametrize("literal, registry, outside", [
    (ModeMethod, MODE_SOLVERS, ()),
    (Case, CHAIN_CASES, ("custom",)),  # a scene's own masses and springs: no case makes them
    (ExecutorName, EXECUTOR_TRAITS, ()),
    (Transport, TRANSPORT_RUNS, ()),
], ids=["mode method", "case", "executor", "transport"])
def test_each_literal_option_set_is_its_registrys_names(literal, registry, outside):
    assert tuple(name for name in get_args(literal) if name not in outside) == tuple(registry)


def test_the_backends_are_the_transports_a_user_names():
    assert get_args(Backend) == tuple(name for name, part in TRANSPORT_RUNS.items() if part.find is not None)
    assert tuple(BACKEND_CHOICES) == named_transports() == get_args(Backend)  # --backend's choices


def test_a_transport_of_ones_own_is_a_backend_choice(forget):
    """Registered (as itself, or by an entry point), a transport is ``--backend``'s choice and ngspice's."""
    mine = NgspiceTransport("test-choice", run_batch, find_batch)
    forget.append((TRANSPORT_RUNS, mine.name))
    assert "test-choice" not in BACKEND_CHOICES
    TRANSPORT_RUNS.accept("backend", mine)
    assert "test-choice" in BACKEND_CHOICES and "test-choice" in ENGINES["ngspice"].user_transports()
    assert build_parser().parse_args(["simulate", "--case", "perfect", "--N", "4", "--backend", "test-choice"]
                                     ).backend == "test-choice"
    assert "test-choice" not in ENGINES["gnucap"].user_transports()  # ngspice's transports, not gnucap's


def test_the_command_lines_case_and_executor_choices_are_the_registries(forget):
    assert tuple(CASE_CHOICES) == tuple(CHAIN_CASES) and tuple(EXECUTOR_CHOICES) == tuple(EXECUTOR_TRAITS)
    case = ChainCase("test-uniform", lambda N, walls: Chain.uniform_free(N))
    forget.append((CHAIN_CASES, case.name))
    assert "test-uniform" not in CASE_CHOICES
    CHAIN_CASES.accept("case", case)
    assert "test-uniform" in CASE_CHOICES  # read when argparse checks the value, not when the parser was built
    args = build_parser().parse_args(["simulate", "--case", "test-uniform", "--N", "5"])
    assert args.case == "test-uniform"


def test_a_mode_method_of_ones_own_is_taken_as_itself(forget):
    calls: list[int] = []

    def counted_exact(chain: Chain) -> Modes:
        calls.append(chain.N)
        return exact_modes(chain)

    forget.append((MODE_SOLVERS, "counted_exact"))
    chain = Chain.uniform_free(6)
    modes = normal_modes(chain, method=counted_exact)
    assert calls == [6] and len(modes.omega) == 6
    assert normal_modes(chain, method="counted_exact").omega.shape == (6,)  # registered under its name
    assert calls == [6, 6]

    def counted_exact_2(chain: Chain) -> Modes:
        return exact_modes(chain)

    counted_exact_2.__name__ = "counted_exact"  # another function under a name already taken: refused
    with pytest.raises(ParameterError, match="'counted_exact' is taken"):
        normal_modes(chain, method=counted_exact_2)
    with pytest.raises(ParameterError, match="method"):
        normal_modes(chain, method=lambda c: exact_modes(c))  # no name to register it under


def test_a_case_of_ones_own_is_taken_as_itself(forget):
    case = ChainCase("test-uniform", lambda N, walls: Chain.uniform_free(N), max_N=50)
    forget.append((CHAIN_CASES, case.name))
    made = chain_for_case(case, 7)
    assert made.N == 7 and list(made.masses) == list(Chain.uniform_free(7).masses)
    assert chain_for_case("test-uniform", 5).N == 5  # by name, once given
    assert ChainSpec(case="test-uniform", N=9).case == "test-uniform"  # a scene may name it
    with pytest.raises(ParameterError, match="chain.N"):
        ChainSpec(case="test-uniform", N=60)  # beyond its max_N
    with pytest.raises(ParameterError, match="walls"):
        chain_for_case(case, 7, walls=1)  # it does not take walls
    with pytest.raises(ParameterError, match="'test-uniform' is taken"):
        chain_for_case(ChainCase("test-uniform", lambda N, walls: Chain.uniform_bounded(N)), 7)
    with pytest.raises(ParameterError, match="case"):
        chain_for_case(object(), 7)


@pytest.mark.ngspice
def test_an_executor_of_ones_own_runs_a_tiny_study_through_ngspice(forget):
    groups_seen: list[int] = []

    @contextlib.contextmanager
    def counting_runner(simulator, workers, scheduler, keep_signals, verbose, scratch, pool):
        def run(groups, transports):
            for group in groups:
                groups_seen.append(len(group))
                yield execute_group(group, simulator, keep_signals, transports)

        yield run

    mine = Executor(parallel=False, remote=False, name="test-counting", runner=counting_runner)
    forget.append((EXECUTOR_TRAITS, mine.name))
    specs = [plan_request(Request(Chain.uniform_free(N), Transient(dt=0.05))).specs[0] for N in (4, 5)]
    records = run_specs(specs, RunOptions(executor=mine, workers=1, transport="process"))
    assert [record.status for record in records] == ["ok", "ok"]
    assert groups_seen == [1, 1]  # a serial executor: one run per group, both through this runner
    assert "test-counting" in EXECUTOR_TRAITS and "test-counting" in EXECUTOR_CHOICES
    with pytest.raises(ParameterError, match="--executor"):
        run_specs(specs, RunOptions(executor=object(), workers=1))


@pytest.mark.ngspice
def test_a_transport_of_ones_own_runs_a_netlist_through_ngspice(forget):
    runs: list[str] = []
    texts: list[str] = []

    def counted_batch(job, simulator, place, progress=None):
        runs.append(simulator.backend)
        texts.append(job.text)
        return run_batch(job, simulator, place, progress)

    def find(launcher):
        return dataclasses.replace(find_batch(launcher), backend="test-counted")

    mine = NgspiceTransport("test-counted", counted_batch, find)
    forget.append((TRANSPORT_RUNS, mine.name))
    simulator = find_simulator(mine)
    assert simulator.backend == "test-counted" and find_simulator("batch").version == simulator.version
    result = run(RunJob(RC_NETLIST, ["v(out)"], 2e-6, foreign=True), simulator)
    assert runs == ["test-counted"] and result.points > 10
    # the transport is handed the text the allow-list returned, and nothing else
    assert texts == [allowed_netlist(RC_NETLIST, "netlist", None, read_include)]
    with pytest.raises(ParameterError, match="backend = 'warm'"):
        find_simulator(TRANSPORT_RUNS["warm"])  # a study starts it: no user names it
