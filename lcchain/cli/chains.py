"""What the commands about a chain share: the options that name it (``--case``, ``--N``, ``--chain``...), its
circuit and drive, the effects' options, the list of engines.  Apart from :mod:`lcchain.cli.common`, which every
command imports, so that a command about foreign netlists (``batch``) starts without the chain's theory (numpy)."""

from __future__ import annotations

import argparse

from ..app.inputs import ChainOptions
from ..app.netlist import DEFAULT_DT
from ..app.options import (
    CASE_CHOICES,
    COUPLING_HELP,
    COUPLING_OPTION,
    Effect,
    effect_options,
    effects_from_options,
    engine_names,
)
from ..core.errors import ParameterError
from ..core.types import DEFAULT_C0, DEFAULT_L0, EXCITATIONS
from .common import list_entries, number_type, si_number

__all__ = ["chain_options", "effect_values", "add_effect_arguments", "effects_from_args", "engine_list",
           "add_circuit_arguments", "add_chain_arguments"]


def chain_options(args: argparse.Namespace) -> ChainOptions:
    """How the command line named its chain: ``--chain FILE``, or ``--case``, ``--N`` and ``--walls``; with
    ``--coupling``."""
    return ChainOptions(case=getattr(args, "case", None), N=getattr(args, "N", None), walls=getattr(args, "walls", 0),
                        chain=getattr(args, "chain", None), coupling=getattr(args, "coupling", None))


def _dest(option: str) -> str:
    return option.lstrip("-").replace("-", "_")


def add_effect_arguments(p: argparse.ArgumentParser) -> None:
    """One option per registered effect that states one (``--Q``, ``--coil-capacitance``, a plugin's): its value
    is the effect's one field, checked by the effect (:func:`effects_from_args`)."""
    for effect in effect_options():
        try:
            p.add_argument(effect.option, type=number_type(effect.option), default=None, metavar=effect.metavar,
                           help=f"{effect.help}; as a scene's [effects.{effect.key}]")
        except argparse.ArgumentError as error:  # a plugin's option taken by another
            raise ParameterError(f"effects.{effect.key}", effect.option, f"an option no other has ({error})") from None


def effect_values(args: argparse.Namespace, but: tuple[str, ...] = ()) -> dict[str, float | None]:
    """What the effect options were given (option -> value; None: not given), except the options ``but`` names
    (a command that reads one itself: ``spectrum``'s ``--Q``)."""
    return {effect.option: getattr(args, _dest(effect.option), None) for effect in effect_options()
            if effect.option not in but}


def effects_from_args(args: argparse.Namespace, but: tuple[str, ...] = ()) -> tuple[Effect, ...]:
    """The effects the effect options ask for (except those ``but`` names), in the registry's order; a bad value
    is refused under its option's name (``--coil-capacitance = -1.0 is not allowed: ...``)."""
    return effects_from_options(effect_values(args, but))


def engine_list(text: str) -> tuple[str, ...]:
    """``--engine ngspice`` or ``--engine ngspice,gnucap``: registered engines, each once."""
    names = tuple(list_entries("--engine", text, "engine names"))
    known = engine_names()
    for name in names:
        if name not in known:
            raise argparse.ArgumentTypeError(f"unknown engine {name!r}: expected {' | '.join(known)}, or several "
                                             "separated by commas")
    if len(set(names)) != len(names):
        raise argparse.ArgumentTypeError(f"{text!r} names an engine twice")
    return names


def add_circuit_arguments(p: argparse.ArgumentParser) -> None:
    """The circuit: a chain (named, or a file), its coils' coupling and its bulk L0, C0."""
    p.add_argument("--case", choices=CASE_CHOICES, metavar="CASE",  # %(choices)s: read when --help prints
                   help="named chain: %(choices)s (one-mass/two-mass: the optimal design for N; perfect: the "
                        "perfect cradle)")
    p.add_argument("--N", type=int, help="number of masses (ladder cells)")
    p.add_argument("--walls", type=int, default=0, metavar="J",
                   help="--case perfect only: J >= 1 ties the perfect cradle to walls (frequencies n - 1 + 2J)")
    p.add_argument("--chain", metavar="FILE", help='JSON file {"masses": [...], "springs": [...]} in bulk units')
    p.add_argument(COUPLING_OPTION, type=number_type(COUPLING_OPTION), default=None, metavar="K", help=COUPLING_HELP)
    p.add_argument("--L0", type=si_number("--L0", "H"), default=DEFAULT_L0,
                   help=f"bulk inductance, henry: 1e-5, 10u or 10uH (default {DEFAULT_L0:g})")
    p.add_argument("--C0", type=si_number("--C0", "F"), default=DEFAULT_C0,
                   help=f"bulk capacitance, farad: 1e-8, 10n or 10nF (default {DEFAULT_C0:g})")


def add_chain_arguments(p: argparse.ArgumentParser) -> None:
    """The circuit and how a transient drives and watches it."""
    add_circuit_arguments(p)
    p.add_argument("--excitation", choices=EXCITATIONS, default="kick",
                   help="kick: initial current in L1; displacement: initial charge in loop 1")
    p.add_argument("--title", help="netlist title (one line)")
    p.add_argument("--transits", type=int, default=1, help="end-to-end transits to simulate (default 1)")
    p.add_argument("--dt", type=number_type("--dt"), default=None,
                   help=f"maximum time step in units of sqrt(L0*C0) (default {DEFAULT_DT})")
