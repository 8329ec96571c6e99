"""The command line's choices that come from a registry (cases, executors, transports), read when argparse lists or
checks them.  Apart from :mod:`lcchain.app.options` (effects, engines), which imports the circuit's effects and
their numerics: a command that only runs foreign netlists (``batch``) offers its executors from here and starts
without them."""

from __future__ import annotations

from collections.abc import Callable, Collection, Iterator, Mapping

from ..core.registry import entry_point_names
from ..core.types import EXECUTORS

__all__ = ["RegistryNames", "CASE_CHOICES", "EXECUTOR_CHOICES", "EXECUTORS_GROUP", "BACKEND_CHOICES"]


class RegistryNames:
    """A registry's names as a command line's choices, read when argparse first lists or checks them, not when
    the parser is built (by then a plugin's part given as itself is in the registry too), and imported only then.
    Give the option a ``metavar`` (argparse lists the choices in every usage line otherwise); where the
    registry's module is heavy (the executors' lives beside the runs' execution), check the value with
    ``lcchain.cli.common.registry_name`` instead of ``choices``, which ``--help`` lists."""

    def __init__(self, load: Callable[[], Collection[str]], listed: Callable[[], Collection[str]] | None = None,
                 own: Collection[str] = ()) -> None:
        self._load = load
        self._listed = listed or load  # what --help lists, when reading the registry itself costs a command's start
        self._own = own  # lcchain's own parts, always registered: a default checked without loading the registry

    def __contains__(self, name: object) -> bool:
        return name in self._own or name in self._load()

    def __iter__(self) -> Iterator[str]:
        return iter(self._listed())

    def __len__(self) -> int:
        return len(self._listed())


def _cases() -> Mapping[str, object]:
    from ..theory.cases import CHAIN_CASES

    return CHAIN_CASES


#: The named cases (``--case``), plugins included: :data:`lcchain.theory.cases.CHAIN_CASES`.
CASE_CHOICES = RegistryNames(_cases)


def _executors() -> Mapping[str, object]:
    from ..studies.executors import EXECUTOR_TRAITS

    return EXECUTOR_TRAITS


#: The executors' entry-point group (:data:`lcchain.studies.executors.EXECUTOR_TRAITS`' ``group``; tests/test_plugins.py
#: sees an installed executor listed by ``--help``).
EXECUTORS_GROUP = "lcchain.executors"


def _executors_listed() -> tuple[str, ...]:
    # lcchain's own (the ExecutorName literal, which a test holds to the registry's own) and the plugins' names,
    # read from their metadata: --help does not import the executors' module (25 to 60 modules, 0.1 to 0.3 s)
    return (*EXECUTORS, *entry_point_names(EXECUTORS_GROUP))


#: The executors (``--executor``), plugins included: :data:`lcchain.studies.executors.EXECUTOR_TRAITS`; listed
#: without importing it.
EXECUTOR_CHOICES = RegistryNames(_executors, _executors_listed, own=EXECUTORS)


def _backends() -> Collection[str]:
    from ..spice.ngspice.transports import named_transports

    return named_transports()


#: The transports a user names (``--backend``), plugins included: those of
#: :data:`lcchain.spice.ngspice.transports.TRANSPORT_RUNS` with a ``find``.
BACKEND_CHOICES = RegistryNames(_backends)
