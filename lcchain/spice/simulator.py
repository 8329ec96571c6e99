"""A circuit simulator that works on this machine, as lcchain passes it to every run: a frozen value.

An engine (:data:`lcchain.spice.engines.ENGINES`) finds its program once for a transport
(:meth:`lcchain.spice.engine.Engine.find`: ngspice's in :mod:`lcchain.spice.ngspice.find`), asks its version
once and returns a :class:`Simulator`; a run is then one process start, not two (``ngspice -v`` used to cost
14-25 ms of a 60-90 ms small run).
"""

from __future__ import annotations

import shutil
import sys
from dataclasses import dataclass

from ..core.errors import ParameterError
from ..core.types import TRANSPORTS, Transport
from .sandbox import Sandbox

__all__ = ["Simulator", "child_launcher"]


@dataclass(frozen=True)
class Simulator:
    """A circuit simulator that works on this machine: an engine (ngspice by default) and its transport.

    Attributes
    ----------
    backend : {"batch", "shared", "warm"}
        The transport: a child process per run (``ngspice -b``, ``gnucap -b``), ngspice's shared library in
        a child process per run, or (``"warm"``, chosen by studies) in long-lived workers.
    executable : str
        Path of the program (``ngspice``, ``gnucap``) or of ``libngspice.so.0`` (shared, warm).
    version : str
        The engine's version, e.g. ``"39"`` for ngspice.
    launcher : tuple of str
        Prefix of every child's command line: ``setpriv --pdeathsig KILL --``
        where util-linux has it (Linux), so that a child dies with lcchain
        even when lcchain is killed with SIGKILL; empty elsewhere.
    sandbox : Sandbox
        Where netlists lcchain did not write run (:mod:`lcchain.spice.sandbox`).
    engine : str
        The engine's name in :data:`lcchain.spice.engines.ENGINES`.
    """

    backend: Transport
    executable: str
    version: str
    launcher: tuple[str, ...] = ()
    sandbox: Sandbox = Sandbox(why_not="not looked for")
    engine: str = "ngspice"

    def __post_init__(self) -> None:
        if self.backend not in TRANSPORTS and not (isinstance(self.backend, str) and self.backend.isprintable()
                                                   and self.backend and " " not in self.backend):
            raise ParameterError("backend", self.backend, f"{' | '.join(TRANSPORTS)}, or a transport's name "
                                 "(its engine refuses one it does not have)")
        if not isinstance(self.engine, str) or not self.engine:
            raise ParameterError("engine", self.engine, "an engine's name, such as 'ngspice'")


def child_launcher() -> tuple[str, ...]:
    """The prefix of every child's command line: ``setpriv --pdeathsig KILL --`` on Linux (it dies with lcchain)."""
    setpriv = shutil.which("setpriv") if sys.platform.startswith("linux") else None
    return (setpriv, "--pdeathsig", "KILL", "--") if setpriv else ()
