"""ngspice found on this machine, for a transport: found once, then passed to every run as a value.

:func:`find_simulator` locates the executable (``"batch"``) or the shared
library and PySpice (``"shared"``), asks for the version once, and returns a
frozen, picklable :class:`Simulator`; a run is then one process start, not
two (``ngspice -v`` used to cost 14-25 ms of a 60-90 ms small run).  How each
transport is found is its ``find`` (:mod:`lcchain.spice.ngspice.locate`).
"""

from __future__ import annotations

from ...core.checks import choice
from ...core.errors import ParameterError
from ...core.types import BACKENDS, Backend
from ..simulator import Simulator, child_launcher
from .locate import (
    INSTALL_COMMAND,
    PYSPICE_INSTALL_COMMAND,
    find_ngspice,
    find_shared_library,
    ngspice_version,
    require_pyspice,
    shared_library_version,
)
from .transports import TRANSPORT_RUNS, NgspiceTransport

__all__ = [
    "find_simulator",
    "find_ngspice",
    "find_shared_library",
    "ngspice_version",
    "INSTALL_COMMAND",
    "PYSPICE_INSTALL_COMMAND",
    "shared_library_version",
    "require_pyspice",
]


def find_simulator(backend: Backend | NgspiceTransport = "batch") -> Simulator:
    """Locate ngspice for a backend and ask its version, once (and whether a sandbox works here).

    Parameters
    ----------
    backend : {"batch", "shared"} or NgspiceTransport
        A transport of one's own is used as given (registered under its ``name`` the first time); its
        ``find`` locates ngspice for it.

    Raises
    ------
    SimulatorMissingError
        ngspice, its shared library or (shared) PySpice is missing; the message
        says how to install it.
    """
    transport = TRANSPORT_RUNS[choice("backend", backend, BACKENDS)] if isinstance(backend, str) else \
        TRANSPORT_RUNS.accept("backend", backend)
    if transport.find is None:  # the warm transport: a study starts it on a shared library it found
        raise ParameterError("backend", transport.name, f"a transport a user names: {' | '.join(BACKENDS)}")
    return transport.find(child_launcher())
