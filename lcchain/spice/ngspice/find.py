"""ngspice found on this machine, for a transport: found once, then passed to every run as a value.

:func:`find_simulator` locates the executable (``"batch"``) or the shared
library and PySpice (``"shared"``), asks for the version once, and returns a
frozen, picklable :class:`Simulator`; a run is then one process start, not
two (``ngspice -v`` used to cost 14-25 ms of a 60-90 ms small run).  How each
transport is found is its ``find`` (:mod:`lcchain.spice.ngspice.locate`).
"""

from __future__ import annotations

from ...core.errors import ParameterError
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
from .transports import TRANSPORT_RUNS, NgspiceTransport, is_named_transport, named_transports

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


def find_simulator(backend: str | NgspiceTransport = "batch") -> Simulator:
    """Locate ngspice for a backend and ask its version, once (and whether a sandbox works here).

    Parameters
    ----------
    backend : str or NgspiceTransport
        A transport's name (:func:`~lcchain.spice.ngspice.transports.named_transports`: ``"batch"``, ``"shared"``
        or a plugin's); a transport of one's own is used as given (registered under its ``name`` the first time); its
        ``find`` locates ngspice for it.

    Raises
    ------
    SimulatorMissingError
        ngspice, its shared library or (shared) PySpice is missing; the message
        says how to install it.
    """
    if isinstance(backend, str):  # a name: lcchain's own (no plugin's metadata read for it) or a plugin's
        if not is_named_transport(backend):
            raise ParameterError("backend", backend, " | ".join(named_transports()))
        transport = TRANSPORT_RUNS[backend]
    else:
        transport = TRANSPORT_RUNS.accept("backend", backend)
    if transport.find is None:  # the warm transport: a study starts it on a shared library it found
        raise ParameterError("backend", transport.name, f"a transport a user names: {' | '.join(named_transports())}")
    return transport.find(child_launcher())
