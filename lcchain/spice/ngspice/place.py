"""Where an ngspice child runs: its command line's prefix, its working folder and its environment."""

from __future__ import annotations

import contextlib
import functools
import sys
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

from ..processes import PACKAGE_ROOT, child_env
from ..sandbox import SCRATCH, scratch_env
from ..scratch import scratch_folder
from ..simulator import Simulator

__all__ = ["Place", "placement"]


@dataclass(frozen=True)
class Place:
    """Where a child runs: its command-line prefix, working folder and environment."""

    prefix: tuple[str, ...]
    cwd: str
    env: dict[str, str]


@functools.cache
def _installed_in_tmp() -> tuple[str, ...]:
    """The interpreter's and lcchain's folders that lie in the host's /tmp (resolved once: every run of a batch
    is placed, and resolving them was four ``realpath`` walks a run)."""
    return tuple(p for p in dict.fromkeys((sys.prefix, PACKAGE_ROOT)) if Path(p).resolve().is_relative_to("/tmp"))


@contextlib.contextmanager
def placement(simulator: Simulator, foreign: bool, own_folder: str | None) -> Iterator[Place]:
    """lcchain's own netlists run in ``/`` with a HOME that does not exist; a foreign one in a scratch folder,
    in the sandbox where there is one (``own_folder``: a trusted netlist's folder, read-only there)."""
    if not foreign:
        yield Place(simulator.launcher, own_folder or "/", child_env())
    elif simulator.sandbox.available:
        # What the run reads from the host's /tmp (the netlist's folder; an interpreter and lcchain installed
        # there, for the shared backend's child) is shown in the sandbox, whose /tmp is its own.
        shown = [own_folder] if own_folder else []
        shown += _installed_in_tmp()
        prefix = (*simulator.launcher, *simulator.sandbox.command([], own_folder or SCRATCH, shown))
        yield Place(prefix, "/", scratch_env(SCRATCH))
    else:
        with scratch_folder("scratch") as folder:
            scratch = str(folder)
            yield Place(simulator.launcher, own_folder or scratch, scratch_env(scratch))

