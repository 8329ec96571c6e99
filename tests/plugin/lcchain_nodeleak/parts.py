"""Test-only lcchain plugin's case, mode method, executor and ngspice transport (each found through its entry
point).  Each says on stderr that it was used, so that a test sees the installed part ran, not lcchain's own."""

from __future__ import annotations

import contextlib
import dataclasses
import sys
from collections.abc import Callable, Iterator
from typing import Any

from lcchain.spice.ngspice.batch import run_batch
from lcchain.spice.ngspice.locate import find_batch
from lcchain.spice.ngspice.transports import NgspiceTransport
from lcchain.spice.simulator import Simulator
from lcchain.studies.executors import Executor, execute_group
from lcchain.theory.cases import ChainCase
from lcchain.theory.chain import Chain
from lcchain.theory.exact import exact_modes
from lcchain.theory.modes import Modes


def _said(what: str) -> None:
    print(f"lcchain_nodeleak: {what}", file=sys.stderr, flush=True)


def _uniform(N: int, walls: int) -> Chain:
    _said(f"case nodeleak-uniform N = {N}")
    return Chain.uniform_free(N)


#: ``lcchain.cases``: the uniform free chain under a name of its own.
UNIFORM = ChainCase("nodeleak-uniform", _uniform, max_N=40)


def nodeleak_exact(chain: Chain) -> Modes:
    """``lcchain.mode_methods``: exact diagonalisation, counted."""
    _said("mode method nodeleak_exact")
    return exact_modes(chain)


@contextlib.contextmanager
def _counting_runner(simulator: Simulator, workers: int, scheduler: str | None, keep_signals: bool, verbose: bool,
                     scratch: str | None, pool: Any) -> Iterator[Callable[..., Iterator[Any]]]:
    def run(groups: Any, transports: Any) -> Iterator[Any]:
        for group in groups:
            _said(f"executor nodeleak-serial ran a group of {len(group)}")
            yield execute_group(group, simulator, keep_signals, transports)

    yield run


#: ``lcchain.executors``: the driver runs each group itself, one after the other.
SERIAL = Executor(parallel=False, remote=False, name="nodeleak-serial", runner=_counting_runner)


def _counted_batch(job: Any, simulator: Simulator, place: Any, progress: Any = None) -> Any:
    _said(f"transport counted-batch ran on {simulator.backend}")
    return run_batch(job, simulator, place, progress)


def _find(launcher: tuple[str, ...]) -> Simulator:
    return dataclasses.replace(find_batch(launcher), backend="counted-batch")


#: ``lcchain.ngspice_transports``: ``ngspice -b``, counted.
COUNTED_BATCH = NgspiceTransport("counted-batch", _counted_batch, _find)
