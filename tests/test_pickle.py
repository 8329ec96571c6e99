"""Everything that crosses a process boundary pickles and comes back equal, and still read-only.

A study sends run specs to pool and Dask workers and gets records back; an
error raised on a worker must reach the user as itself, with its fields.  Every
public result and error type goes through every pickle protocol here.
"""

from __future__ import annotations

import dataclasses
import pickle
from collections.abc import Mapping

import numpy as np
import pytest

import lcchain
from lcchain.circuit.reference import REFERENCE_SET
from lcchain.compare.accuracy import AccuracyWarning, ErrorSplit
from lcchain.core.errors import Interrupted, LcchainError, ParameterError, SimulationError, SimulatorMissingError
from lcchain.core.frozen import FrozenMap
from lcchain.core.registry import PluginError
from lcchain.runs.execute import execute
from lcchain.runs.simulate import ChainOptions, simulation_spec
from lcchain.scenes.plan import scene_plan
from lcchain.spice.doctor import Check
from lcchain.spice.simulator import Simulator

PROTOCOLS = range(pickle.HIGHEST_PROTOCOL + 1)


def same(a: object, b: object, path: str = "") -> None:
    """Assert that two values are equal field by field (arrays bit for bit), and arrays read-only."""
    assert type(a) is type(b), f"{path}: {type(a)} != {type(b)}"
    if isinstance(a, np.ndarray):
        assert isinstance(b, np.ndarray)
        assert a.dtype == b.dtype and np.array_equal(a, b), path
        assert a.flags.writeable == b.flags.writeable, f"{path}: writeable {a.flags.writeable} -> {b.flags.writeable}"
    elif dataclasses.is_dataclass(a) and not isinstance(a, type):
        for field in dataclasses.fields(a):
            same(getattr(a, field.name), getattr(b, field.name), f"{path}.{field.name}")
    elif isinstance(a, Mapping):
        assert isinstance(b, Mapping) and list(a) == list(b), path
        for key in a:
            same(a[key], b[key], f"{path}[{key!r}]")
    elif isinstance(a, (list, tuple)):
        assert isinstance(b, (list, tuple)) and len(a) == len(b), path
        for i, (x, y) in enumerate(zip(a, b, strict=True)):
            same(x, y, f"{path}[{i}]")
    elif isinstance(a, BaseException):
        assert isinstance(b, BaseException)
        assert str(a) == str(b) and a.args == b.args, path
        assert vars(a) == vars(b), path
    elif isinstance(a, float) and np.isnan(a):
        assert isinstance(b, float) and np.isnan(b), path
    else:
        assert a == b, path


def round_trip(value: object) -> None:
    for protocol in PROTOCOLS:
        copy = pickle.loads(pickle.dumps(value, protocol=protocol))
        same(value, copy, f"{type(value).__name__} (protocol {protocol})")


def _theory_values() -> list[object]:
    chain = lcchain.Chain.from_rw(30, 0.7, 0.2)
    modes = lcchain.normal_modes(chain)
    scene = lcchain.parse_scene({"chain": {"case": "two-mass", "N": 12},
                                 "effects": {"tolerance": {"L": 0.01, "samples": 2}}})
    return [
        chain, lcchain.Chain.perfect(4), modes, lcchain.normal_modes(lcchain.chain_for_case("two-mass", 500)),
        lcchain.first_arrival(modes), lcchain.optimal_two_mass(20), lcchain.optimal_one_mass(20),
        lcchain.asymptotic_optimum("one-mass"), lcchain.Ladder(chain), lcchain.SimulationOptions(dt=0.05, tstop=40.0),
        scene, scene_plan(scene), REFERENCE_SET[-1], FrozenMap({"a": 1.0, "b": np.arange(3.0)}),
        ErrorSplit(1e-13, 1e-3, 1e-3), Simulator("batch", "/usr/bin/ngspice", "39"), Check("x", True, "ok"),
        simulation_spec(chain, ChainOptions(dt=0.05))[0],
    ]


@pytest.mark.parametrize("value", _theory_values(), ids=lambda v: type(v).__name__)
def test_results_and_descriptions_pickle(value: object) -> None:
    round_trip(value)


@pytest.mark.parametrize("error", [
    LcchainError("something"), ParameterError("N", 2, "an integer >= 3", where="scene.toml"),
    ParameterError("masses[1]", np.float64(-1.0), "a finite number > 0"),
    SimulationError("ngspice reported an error", "Error: unknown model", "failed"),
    SimulationError("ngspice timed out after 5 s and was killed", "", "timeout"),
    SimulatorMissingError("the ngspice executable is not on PATH"), Interrupted(15),
    AccuracyWarning("predicted error 0.2 > 0.1"),
    PluginError("entry point lcchain.effects leak", "leak:Leak", "an Effect (ModuleNotFoundError: leak)"),
], ids=lambda e: type(e).__name__)
def test_errors_pickle_with_their_fields(error: BaseException) -> None:
    round_trip(error)


def test_a_chain_stays_immutable_after_pickling() -> None:
    chain = pickle.loads(pickle.dumps(lcchain.Chain.uniform_free(5)))
    with pytest.raises(ValueError, match="read-only"):
        chain.masses[0] = 2.0
    modes = pickle.loads(pickle.dumps(lcchain.normal_modes(chain)))
    with pytest.raises(ValueError, match="read-only"):
        modes.omega[0] = 1.0


@pytest.mark.ngspice
def test_run_records_and_reports_pickle() -> None:
    chain = lcchain.chain_for_case("two-mass", 12)
    report = lcchain.simulate_chain(chain, lcchain.ChainOptions(dt=0.05, transits=2))
    round_trip(report)
    assert report.record is not None
    round_trip(report.record)
    spec = simulation_spec(chain, ChainOptions(dt=0.05))[0]
    failed = execute(dataclasses.replace(spec, netlist=spec.netlist.replace("L3 ", "Q3 "), trusted=True))
    assert failed.status == "failed"
    round_trip(failed)
    scene = lcchain.parse_scene({"chain": {"case": "two-mass", "N": 10},
                                 "effects": {"tolerance": {"C": 0.02, "samples": 2, "seed": 1}}})
    round_trip(lcchain.run_scene(scene, lcchain.SceneRun(write_outputs=False)))


def test_frozen_values_are_made_while_another_thread_imports_numpy(tmp_path) -> None:
    """A batch imports numpy in a thread of its own as its first run goes (a half-imported numpy is in
    ``sys.modules`` meanwhile, without ``ndarray``): frozen mappings made in the other threads then are made, and
    an array made once numpy is imported is still frozen."""
    import subprocess
    import sys

    code = (
        "import sys, threading\n"
        "sys.setswitchinterval(1e-5)\n"
        "from lcchain.core.frozen import FrozenMap\n"
        "loader = threading.Thread(target=__import__, args=('numpy',)); loader.start()\n"
        "made = 0\n"
        "while loader.is_alive():\n"
        "    FrozenMap({'a': 1.0}); made += 1\n"
        "import numpy as np\n"
        "assert not FrozenMap({'a': np.zeros(2)})['a'].flags.writeable\n"
        "print(made)\n")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    assert int(done.stdout) > 0
