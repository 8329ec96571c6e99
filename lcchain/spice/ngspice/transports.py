"""ngspice's transports, by name: one registry, :data:`TRANSPORT_RUNS`.

A transport is how a netlist reaches ngspice and its columns come back: ``ngspice -b`` (``batch``), the shared
library in a child per run (``shared``), or in long-lived workers (``warm``).  Each is an
:class:`NgspiceTransport`: its run, and how it is found when a user names it (``--backend``); the warm transport
is not named by users, a study starts it.  Adding one is a module and one line here, or, from a package of its
own, an entry point in the ``lcchain.ngspice_transports`` group.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, TypeAlias

from ...core.registry import Registry
from ..job import Progress, TransportJob
from ..simulator import Simulator
from .batch import run_batch
from .locate import find_batch, find_shared
from .place import Place
from .shared import run_shared
from .warm import run_warm

if TYPE_CHECKING:
    import numpy as np

__all__ = ["NgspiceTransport", "TransportRun", "TRANSPORT_RUNS", "named_transports", "is_named_transport"]

#: How a transport runs a checked text: (job, simulator, place, progress) -> (columns, log, wall seconds).  The
#: job (:class:`lcchain.spice.job.TransportJob`) carries the text its check returned, the digest of its lines, the
#: plot to read and the limits; the transport runs ``job.text`` as it is.
TransportRun: TypeAlias = (  # a string: read by the type checker, so that importing this module loads no numpy
    "Callable[[TransportJob, Simulator, Place, Progress | None], tuple[dict[str, np.ndarray], str, float]]")


@dataclass(frozen=True)
class NgspiceTransport:
    """One of ngspice's transports.

    Attributes
    ----------
    name : str
        The simulator's ``backend`` that selects it.
    run : callable
        A :data:`TransportRun`.
    find : callable, optional
        ``find(launcher) -> Simulator``: ngspice located for it and its version asked; None for a transport a
        user does not name (the warm one, which a study starts on a shared library it found).
    """

    name: str
    run: TransportRun
    find: Callable[[tuple[str, ...]], Simulator] | None = None


def _admit(name: str, loaded: object) -> NgspiceTransport:
    """An ``lcchain.ngspice_transports`` entry point's object (or a transport given as itself)."""
    if not isinstance(loaded, NgspiceTransport) or loaded.name != name or not name:
        raise TypeError(f"{loaded!r} is not an NgspiceTransport named {name!r}")
    return loaded


#: ngspice's transports, by name, the default first; then those of the ``lcchain.ngspice_transports`` entry
#: points.  Its names are :data:`lcchain.core.types.Transport`, and those with a ``find`` are
#: :data:`lcchain.core.types.Backend` (a test checks both).
TRANSPORT_RUNS: Registry[NgspiceTransport] = Registry(
    "lcchain.ngspice_transports",
    {"batch": NgspiceTransport("batch", run_batch, find_batch),
     "shared": NgspiceTransport("shared", run_shared, find_shared),
     "warm": NgspiceTransport("warm", run_warm)},
    _admit, "an lcchain.spice.ngspice.transports.NgspiceTransport, named as the entry point",
    name_of=lambda part: str(getattr(part, "name", "")))


def named_transports() -> tuple[str, ...]:
    """The transports a user names (``--backend``, a scene's ``analysis.backend``): those with a ``find``, the
    default first, plugins included (:data:`lcchain.core.types.Backend` holds lcchain's own, a test checks)."""
    return tuple(name for name, transport in TRANSPORT_RUNS.items() if transport.find is not None)


def is_named_transport(name: str) -> bool:
    """Whether ``name`` is one of :func:`named_transports`, by a lookup: a name the registry holds reads no entry
    point (``importlib.metadata`` and every installed package's metadata, on a batch's start)."""
    return name in TRANSPORT_RUNS and TRANSPORT_RUNS[name].find is not None
