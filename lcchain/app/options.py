"""What a command line may offer, read from the registries: engines, effects and their options, preferred-number
series, figure formats.

The parser (``cli/``) builds its choices from these, so a plugin's engine or effect is offered without an edit to
the command line.  Light to import: ``lcchain --help`` builds every parser from this module alone (no run, no
study, no scipy submodule).
"""

from __future__ import annotations

from collections.abc import Mapping

from ..circuit.effects import E_SERIES, EFFECTS, Coupling, Effect, effect_fields
from ..core.errors import ParameterError
from ..report.files import FIGURE_FORMATS
from ..spice.engines import DEFAULT_ENGINE, ENGINES
from ..theory.chain import Chain
from .choices import BACKEND_CHOICES, CASE_CHOICES, EXECUTOR_CHOICES, RegistryNames

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
