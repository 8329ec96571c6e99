"""What a command line may offer, read from the registries: engines, effects and their options, preferred-number
series, figure formats.

The parser (``cli/``) builds its choices from these, so a plugin's engine or effect is offered without an edit to
the command line.  Light to import: ``lcchain --help`` builds every parser from this module alone (no run, no
study, no scipy submodule).
"""

from __future__ import annotations

from collections.abc import Callable, Collection, Iterator, Mapping

from ..circuit.effects import E_SERIES, EFFECTS, Coupling, Effect, effect_fields
from ..core.errors import ParameterError
from ..core.registry import entry_point_names
from ..core.types import EXECUTORS
from ..report.files import FIGURE_FORMATS
from ..spice.engines import DEFAULT_ENGINE, ENGINES
from ..theory.chain import Chain

__all__ = ["Chain", "Effect", "CASE_CHOICES", "EXECUTOR_CHOICES", "BACKEND_CHOICES", "RegistryNames",
           "DEFAULT_ENGINE",
           "FIGURE_FORMATS", "E_SERIES_NAMES", "COUPLING_OPTION", "COUPLING_HELP",
           "CIRCUIT_EFFECTS", "EffectOption", "effect_options", "effects_from_options", "engine_names"]

#: The preferred-number series a part may be rounded to (``--series``).
E_SERIES_NAMES = tuple(E_SERIES)
#: The chain's own coupling option (every command with a circuit takes it) and its help.
COUPLING_OPTION: str = Coupling.option or "--coupling"
COUPLING_HELP: str = Coupling.option_help
#: Effects every command with a circuit takes in its chain (``--coupling``), not as an effect option.
CIRCUIT_EFFECTS = ("coupling",)


def engine_names() -> tuple[str, ...]:
    """The registered engines' names (plugins included), in the registry's order."""
    return tuple(ENGINES)


class RegistryNames:
    """A registry's names as a command line's choices, read when argparse first lists or checks them, not when
    the parser is built (by then a plugin's part given as itself is in the registry too), and imported only then.
    Give the option a ``metavar`` (argparse lists the choices in every usage line otherwise); where the
    registry's module is heavy (the executors' lives beside the runs' execution), check the value with
    ``lcchain.cli.common.registry_name`` instead of ``choices``, which ``--help`` lists."""

    def __init__(self, load: Callable[[], Collection[str]], listed: Callable[[], Collection[str]] | None = None
                 ) -> None:
        self._load = load
        self._listed = listed or load  # what --help lists, when reading the registry itself costs a command's start

    def __contains__(self, name: object) -> bool:
        return name in self._load()

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
EXECUTOR_CHOICES = RegistryNames(_executors, _executors_listed)


def _backends() -> Collection[str]:
    from ..spice.ngspice.transports import named_transports

    return named_transports()


#: The transports a user names (``--backend``), plugins included: those of
#: :data:`lcchain.spice.ngspice.transports.TRANSPORT_RUNS` with a ``find``.
BACKEND_CHOICES = RegistryNames(_backends)


class EffectOption:
    """One effect a command line asks for by an option of its own (``--Q``, ``--coil-capacitance``, a plugin's):
    the option, its help, the name of the effect's one field (the option's metavar) and its scene key."""

    def __init__(self, cls: type[Effect]) -> None:
        assert cls.option is not None
        self._cls = cls
        self.option: str = cls.option
        self.help: str = cls.option_help
        self.key: str = cls.key
        self.metavar: str = effect_fields(cls)[0].name

    def make(self, value: float) -> Effect:
        """The effect with this value, refused under the option's name (``--coil-capacitance = -1.0 is not
        allowed: ...``)."""
        try:
            return self._cls.from_option(value)
        except ParameterError as error:
            raise error.renamed(self.option) from None


def effect_options() -> list[EffectOption]:
    """The registered effects a command line can ask for by an option of theirs (``Effect.option``)."""
    return [EffectOption(cls) for key, cls in EFFECTS.items() if cls.option is not None and key not in CIRCUIT_EFFECTS]


def effects_from_options(values: Mapping[str, float | None]) -> tuple[Effect, ...]:
    """The effects the effect options ask for (option -> value, None: not given), in the registry's order."""
    return tuple(option.make(value) for option in effect_options()
                 if (value := values.get(option.option)) is not None)
