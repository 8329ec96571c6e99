"""What every command shares: argument types, progress on a terminal, outputs, chains, budgets."""

from __future__ import annotations

import argparse
import contextlib
import decimal
import json
import math
import re
import sys
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..circuit.effects import EFFECTS, Effect, effect_fields
from ..core.budget import (
    DEFAULT_MAX_MEMORY,
    DEFAULT_MAX_SECONDS,
    INTERPRETER_BYTES,
    INTERPRETER_SECONDS,
    Budget,
    perfect_estimate,
    show_bytes,
    show_seconds,
)
from ..core.errors import ParameterError
from ..core.limits import (
    COUPLED_MAX_N,
    MAX_BUDGET_BYTES,
    MAX_CHAIN_FILE_BYTES,
    MAX_CIRCUIT_N,
    MAX_COMMENT_LENGTH,
    MAX_PERFECT_N,
    MAX_SECONDS,
    MIN_N,
    MIN_TIMEOUT,
)
from ..core.types import E_SERIES_NAMES
from ..report.files import check_not_input, check_output, same_file, write_text
from ..theory.chain import Chain

__all__ = ["EXIT_OK", "EXIT_FAILED", "EXIT_USAGE", "EXIT_MISSING", "EXIT_SIGPIPE", "OPTION_NAMES", "NEGATIVE_NUMBER",
           "single_valued", "count", "list_entries", "int_list", "si_number", "SI_PREFIXES",
           "number_type", "size", "duration", "seconds", "budget_parent", "emit_json", "Outputs", "STDOUT",
           "EXIT_EXTRA", "chain_from_args", "budget_from_args", "load_chain_file", "check_perfect", "echoed_command",
           "CIRCUIT_EFFECTS", "add_effect_arguments", "effects_from_args", "tolerances", "add_parts_arguments"]

EXIT_OK, EXIT_FAILED, EXIT_USAGE, EXIT_MISSING = 0, 1, 2, 3
#: A missing optional extra (pandas, xarray, Dask, PySpice): ``pip install 'lcchain[EXTRA]'`` fixes it.
EXIT_EXTRA = 2  # a missing optional extra is an input the machine lacks: the usage status, naming the extra
#: The file name of every option that writes one text (``-o``, ``--netlist-out``, ``--waveform-out``) that
#: means standard output, as ``-`` does for most Unix tools.
STDOUT = "-"
#: A reader closed the pipe (``lcchain table --json | head -2``): the exit status of a process killed by SIGPIPE.
EXIT_SIGPIPE = 128 + 13

#: Names the package uses for what the user typed as an option.
OPTION_NAMES = {
    "N": "--N", "dt": "--dt", "accuracy": "--accuracy", "transits": "--transits", "L0": "--L0", "C0": "--C0",
    "title": "--title", "excitation": "--excitation", "method": "--method", "backend": "--backend",
    "engine": "--engine",
    "points": "--points", "Q": "--Q", "coupling": "--coupling",
    "case": "--case", "walls": "--walls", "max_memory": "--max-memory", "max_seconds": "--max-time",
    "timeout": "--timeout",
}


#: What argparse should read as a value, never as an option: a number with a minus sign (``--L0 -1e-5``,
#: ``--walls -1``, ``-inf``).  argparse's own pattern misses exponents, so ``-1e-5`` was "expected one argument".
NEGATIVE_NUMBER = re.compile(r"^-(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?$|^-(?:inf|infinity|nan)$", re.IGNORECASE)


class _StoreOnce(argparse._StoreAction):
    """argparse's ``store``, except that an option given twice is an error instead of silently the last."""

    def __call__(self, parser: argparse.ArgumentParser, namespace: argparse.Namespace, values: Any,
                 option_string: str | None = None) -> None:
        given: set[str] = namespace.__dict__.setdefault("_given_once", set())
        if self.dest in given:
            raise argparse.ArgumentError(self, f"given more than once: give {'/'.join(self.option_strings)} once "
                                         "(one value, or a comma-separated list where the option takes several)")
        given.add(self.dest)
        super().__call__(parser, namespace, values, option_string)


def single_valued(parser: argparse.ArgumentParser) -> argparse.ArgumentParser:
    """Make every single-value option of ``parser`` refuse to be given twice, and read negative numbers as
    values: one rule for every option of every command (called before any argument is added)."""
    parser.register("action", None, _StoreOnce)
    parser.register("action", "store", _StoreOnce)
    parser._negative_number_matcher = NEGATIVE_NUMBER
    return parser


def count(option: str) -> Callable[[str], int]:
    """An argparse type: an integer >= 1 (a count of workers, say: 0 and -3 alike are refused)."""

    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            value = 0
        if value < 1:
            raise argparse.ArgumentTypeError(f"{option} = {text!r} is not allowed: expected an integer >= 1")
        return value

    return parse


def list_entries(option: str, text: str, what: str) -> list[str]:
    """The entries of a comma list, stripped; an empty one (``10,,20``, ``10,``, ``,10``) is refused, naming the
    option and its text: a silently dropped entry would run a study with one row fewer than the user wrote."""
    entries = [entry.strip() for entry in text.split(",")]
    empty = [k + 1 for k, entry in enumerate(entries) if not entry]
    if empty:
        where = f"entry {empty[0]} of {len(entries)} is empty" if len(entries) > 1 else "it is empty"
        raise argparse.ArgumentTypeError(f"{option} = {text!r} is not allowed: expected {what} separated by commas, "
                                         f"none empty ({where})")
    return entries


def int_list(option: str) -> Callable[[str], list[int]]:
    """An argparse type: integers separated by commas, none empty."""

    def parse(text: str) -> list[int]:
        entries = list_entries(option, text, "integers")
        try:
            return [int(v) for v in entries]
        except ValueError:
            raise argparse.ArgumentTypeError(
                f"{option} = {text!r} is not allowed: expected integers separated by commas") from None

    return parse


def number_type(option: str) -> Callable[[str], float]:
    """An argparse type: a finite number."""

    def parse(text: str) -> float:
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{option} = {text!r} is not allowed: expected a number") from None
        if not math.isfinite(value):
            raise argparse.ArgumentTypeError(f"{option} = {text!r} is not allowed: expected a finite number")
        return value

    return parse


#: SI prefixes (powers of ten) a component value may carry (``10u``, ``4.7n``, ``2.2k``); ``meg`` is SPICE's
#: mega, ``M`` too (a bare ``m`` is milli, as in SI: never SPICE's ``M`` = milli).
SI_PREFIXES = {"f": -15, "p": -12, "n": -9, "u": -6, "\u00b5": -6, "m": -3, "k": 3, "meg": 6, "M": 6, "G": 9}
_SI = re.compile(r"^\s*([-+]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][-+]?[0-9]+)?)\s*(meg|[fpnu\u00b5mkMG])?\s*"
                 r"(H|F|ohm|\u03a9)?\s*$")


def si_number(option: str, unit: str) -> Callable[[str], float]:
    """An argparse type: a finite number, plain (``1e-5``) or with an SI prefix and optionally its unit
    (``10u``, ``10uH``, ``4.7n``, ``4.7nF``), as :data:`SI_PREFIXES` lists; anything else is one line naming
    the option."""

    def parse(text: str) -> float:
        match = _SI.match(text)
        if match is None or (match.group(3) is not None and match.group(3) != unit):
            raise argparse.ArgumentTypeError(
                f"{option} = {text!r} is not allowed: expected a number in {unit}, plain or with an SI prefix "
                f"(f p n u m k meg G), such as 10u or 10u{unit}")
        # decimal: 10u is the float nearest 1e-5, as "1e-5" is (10 * 1e-6 is not)
        value = float(decimal.Decimal(match.group(1)).scaleb(SI_PREFIXES.get(match.group(2) or "", 0)))
        if not math.isfinite(value):
            raise argparse.ArgumentTypeError(f"{option} = {text!r} is not allowed: expected a finite number")
        return value

    return parse


_SIZE = re.compile(r"^\s*([0-9.]+(?:[eE][-+]?[0-9]+)?)\s*([kKmMgGtT]?)(i?B)?\s*$")
_DURATION = re.compile(r"^\s*([0-9.]+(?:[eE][-+]?[0-9]+)?)\s*(s|min|h|d)?\s*$")


def size(text: str) -> float:
    """An argparse type: bytes, as 8G, 512M, 1.5T (binary units; a plain number is GiB), at least what the
    interpreter alone takes (:data:`lcchain.core.budget.INTERPRETER_BYTES`: a smaller budget fits no request)."""
    match = _SIZE.match(text)
    allowed = (f"a size such as 16G or 512M (a plain number is GiB), from {show_bytes(INTERPRETER_BYTES)} (the "
               f"interpreter's own memory) to {show_bytes(MAX_BUDGET_BYTES)}")
    if not match:
        raise argparse.ArgumentTypeError(f"--max-memory = {text!r} is not allowed: expected {allowed}")
    scale = {"": 2**30, "k": 2**10, "m": 2**20, "g": 2**30, "t": 2**40}[match.group(2).lower()]
    value = float(match.group(1)) * scale
    if not INTERPRETER_BYTES <= value <= MAX_BUDGET_BYTES:
        raise argparse.ArgumentTypeError(f"--max-memory = {text!r} is not allowed: expected {allowed}")
    return value


def duration(text: str) -> float:
    """An argparse type: seconds, as 90, 90s, 30min, 2h, 1d, at least the interpreter's own start
    (:data:`lcchain.core.budget.INTERPRETER_SECONDS`: a shorter budget fits no request)."""
    match = _DURATION.match(text)
    allowed = (f"a duration such as 90s, 30min or 2h (a plain number is seconds), from "
               f"{show_seconds(INTERPRETER_SECONDS)} (the interpreter's own start) to {show_seconds(MAX_SECONDS)}")
    if not match:
        raise argparse.ArgumentTypeError(f"--max-time = {text!r} is not allowed: expected {allowed}")
    value = float(match.group(1)) * {None: 1, "s": 1, "min": 60, "h": 3600, "d": 86400}[match.group(2)]
    if not INTERPRETER_SECONDS <= value <= MAX_SECONDS:
        raise argparse.ArgumentTypeError(f"--max-time = {text!r} is not allowed: expected {allowed}")
    return value


def seconds(option: str) -> Callable[[str], float]:
    """An argparse type: a timeout in seconds, from :data:`lcchain.core.limits.MIN_TIMEOUT` (a run's start) to
    :data:`lcchain.core.limits.MAX_SECONDS` (a larger one overflowed the clock's deadline arithmetic)."""

    def parse(text: str) -> float:
        allowed = f"seconds, {MIN_TIMEOUT:g} <= {option.lstrip('-')} <= {MAX_SECONDS:g}"
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{option} = {text!r} is not allowed: expected {allowed}") from None
        if not MIN_TIMEOUT <= value <= MAX_SECONDS:  # NaN fails both
            raise argparse.ArgumentTypeError(f"{option} = {text!r} is not allowed: expected {allowed}")
        return value

    return parse


def tolerances(text: str) -> dict[str, float]:
    """An argparse type: ``--tolerance L=0.05,C=0.02`` (either or both), or ``--tolerance 0.05`` for both;
    each relative, 0 <= tol < 1 (checked by :func:`lcchain.scenes.load.override_parts`)."""
    allowed = "L=TOL,C=TOL (either or both) or one TOL for both, each a relative tolerance 0 <= TOL < 1 (0.01 or 1%)"
    entries = list_entries("--tolerance", text, "L=TOL and C=TOL")
    if len(entries) == 1 and "=" not in entries[0]:
        value = _relative("--tolerance", entries[0], allowed)
        return {"L": value, "C": value}
    out: dict[str, float] = {}
    for entry in entries:
        name, sep, given = (part.strip() for part in entry.partition("="))
        if not sep or name not in ("L", "C") or name in out:
            raise argparse.ArgumentTypeError(f"--tolerance = {text!r} is not allowed: expected {allowed}")
        out[name] = _relative(f"--tolerance {name}", given, allowed)
    return out


def _relative(option: str, text: str, allowed: str) -> float:
    """A relative tolerance as a fraction (``0.01``) or a percentage (``1%``)."""
    if text.endswith("%"):
        return number_type(option)(text[:-1].strip()) / 100.0
    return number_type(option)(text)


def add_parts_arguments(p: argparse.ArgumentParser, samples: bool = True, netlist: bool = False) -> None:
    """A scene's real parts from the command line (a Monte Carlo without editing the file): ``--tolerance``,
    ``--series`` and (``samples``) ``--samples``, ``--seed``; each sets the scene's own key (``netlist``: their
    help also says what they do with ``sweep --netlist``)."""
    draws = (" (with --netlist: draws of its --vary distributions)", " (with --netlist: the seed of its draws, "
             "default 0)") if netlist else ("", "")
    p.add_argument("--tolerance", type=tolerances, metavar="L=TOL,C=TOL",
                   help="relative tolerances of the inductors and capacitors, e.g. L=5%%,C=0.02 or 1%% for both "
                        "(a scene's effects.tolerance.L, .C)")
    p.add_argument("--series", metavar="|".join(E_SERIES_NAMES),
                   help="round every part to this IEC 60063 series (a scene's effects.preferred_values.series)")
    if samples:
        p.add_argument("--samples", type=int,
                       help="tolerance samples (a scene's effects.tolerance.samples)" + draws[0])
        p.add_argument("--seed", type=int, help="the tolerance seed (a scene's effects.tolerance.seed)" + draws[1])


def budget_parent() -> argparse.ArgumentParser:
    """The options every command that does real work takes: its budget."""
    parent = single_valued(argparse.ArgumentParser(add_help=False))
    parent.add_argument("--max-memory", type=size, default=DEFAULT_MAX_MEMORY, metavar="SIZE",
                        help="most memory one request may use (default 8G)")
    parent.add_argument("--max-time", type=duration, default=DEFAULT_MAX_SECONDS, metavar="DURATION",
                        help="most time one request may take (default 1h)")
    return parent


def budget_from_args(args: argparse.Namespace) -> Budget:
    """--max-memory and --max-time, or the defaults for a command without them."""
    return Budget(getattr(args, "max_memory", DEFAULT_MAX_MEMORY), getattr(args, "max_time", DEFAULT_MAX_SECONDS))


def emit_json(data: Any) -> None:
    print(json.dumps(data, indent=2))


@dataclass
class Outputs:
    """The files a command writes: checked before any work, written after the results are shown.

    ``inputs`` names the files the command reads (option -> path): an output
    that is one of them is refused, so that no command destroys its own input.
    A file that cannot be written at the end (a full disk) is named in one
    line and makes the command fail (exit 1), after everything else was
    written and printed.

    ``-`` (:data:`STDOUT`) names standard output for an option that writes
    one text (no ``formats``); one option at most may take it, and the
    command's own summary then goes to stderr (:meth:`summary`).
    """

    inputs: dict[str, str] = field(default_factory=dict)
    checked: dict[str, Path] = field(default_factory=dict)
    failed: list[str] = field(default_factory=list)
    to_stdout: str | None = None

    def check(self, option: str, path: str | None, formats: tuple[str, ...] | None = None, *,
              make_folder: bool = False) -> None:
        """Refuse ``path`` now if it could not be written later (``make_folder``: the caller makes its folder)."""
        if path is None:
            return
        if path == STDOUT:
            self.claim_stdout(option, formats)
            return
        target = check_output(option, path, formats, make_folder=make_folder)
        check_not_input(option, path, [(named, source) for named, source in self.inputs.items() if source])
        for other, seen in self.checked.items():
            if same_file(seen, target):
                raise ParameterError(option, path, f"a file no other option writes ({other} writes it too)")
        self.checked[option] = target

    def claim_stdout(self, option: str, formats: tuple[str, ...] | None = None) -> None:
        """Let ``option`` write its text to stdout (``-``): refused for a figure or a store, or a second option."""
        if formats is not None:
            raise ParameterError(option, STDOUT, f"a file name ending in .{', .'.join(formats)} (- means stdout, "
                                 "which takes only a text)")
        if self.to_stdout is not None and self.to_stdout != option:
            raise ParameterError(option, STDOUT, f"a file name: {self.to_stdout} writes to stdout (-) already")
        self.to_stdout = option

    def summary(self) -> contextlib.AbstractContextManager[object]:
        """Where the command's own lines go: stdout, or stderr when an output writes its text to stdout."""
        if self.to_stdout is None:
            return contextlib.nullcontext()
        return contextlib.redirect_stdout(sys.stderr)

    def write(self, option: str, writer: Callable[[Path], object]) -> None:
        """Run ``writer(path)`` for a checked output; report a failure by name instead of raising."""
        path = self.checked.get(option)
        if path is None:
            return
        try:
            writer(path)
        except OSError as error:
            self.failed.append(option)
            print(f"lcchain: could not write {path} ({option}): {error.strerror or error}", file=sys.stderr)

    def text(self, option: str, text: str) -> None:
        """Write a checked output's text: to its file, atomically, or to stdout for ``-``."""
        if option == self.to_stdout:
            sys.stdout.write(text)
            sys.stdout.flush()
            return
        self.write(option, lambda path: write_text(path, text))


def echoed_command(command: str, argv: list[str]) -> str:
    """The command line as a netlist's comment shows it: one printable line, cut short to fit.

    A file name may hold any character and be long; the comment only
    reminds the reader how the file was made, so it is shortened (and what
    is not printable, a control character or undecodable byte, shown as ``?``), never a reason to refuse the command.
    """
    text = " ".join([command, *argv])
    text = "".join(ch if ch.isprintable() else "?" for ch in text)
    room = MAX_COMMENT_LENGTH - len("made by: ")
    return text if len(text) <= room else text[:room - 5] + " ..."


def load_chain_file(path: str, max_N: int = MAX_CIRCUIT_N) -> Chain:
    """A chain from a JSON file ``{"masses": [...], "springs": [...]}``: a regular file, size-checked before it is
    read (a FIFO or a device is refused, never read)."""
    from ..spice.inputs import read_input

    text = read_input(path, "--chain", MAX_CHAIN_FILE_BYTES)
    try:
        data = json.loads(text)
    except json.JSONDecodeError as error:
        raise ParameterError("--chain", path, f"valid JSON (line {error.lineno}: {error.msg})") from None
    except RecursionError:
        raise ParameterError("--chain", path, "JSON nested a few levels deep (lists inside an object); this "
                             "one nests too deeply to read") from None
    chain = Chain.from_dict(data, where=path)
    if chain.N > max_N:
        raise ParameterError("--chain", path, f"a chain of at most {max_N} masses (it has {chain.N})")
    return chain


def chain_from_args(args: argparse.Namespace, max_N: int = MAX_CIRCUIT_N) -> Chain:
    """The chain a command is about: ``--chain FILE`` or ``--case`` and ``--N`` (never both), with ``--coupling``."""
    chain = _chain_of_args(args, max_N)
    coupling = getattr(args, "coupling", None)
    if coupling is None:
        return chain
    if chain.coupled:
        raise ParameterError("--coupling", coupling,
                             f"nothing when the --chain file sets the coupling ({chain.coupling})")
    try:
        chain = chain.with_coupling(coupling)
    except ParameterError as error:
        raise error.renamed("--coupling") from None
    if chain.coupled and chain.N > COUPLED_MAX_N:
        raise ParameterError("N", chain.N, f"at most {COUPLED_MAX_N} masses with --coupling (the coupled modes are "
                             "a dense generalised eigenproblem)")
    return chain


def _chain_of_args(args: argparse.Namespace, max_N: int) -> Chain:
    from ..theory.cases import chain_for_case

    if args.chain:
        given = [option for option, value in (("--case", args.case), ("--N", args.N), ("--walls", args.walls or None))
                 if value is not None]
        if given:
            raise ParameterError(given[0], getattr(args, given[0].lstrip("-")),
                                 "nothing with --chain FILE (the file says the whole chain)")
        return load_chain_file(args.chain, max_N)
    if args.case is None or args.N is None:
        missing = "--case" if args.case is None else "--N"
        raise ParameterError(missing, None, "--case and --N, or --chain FILE")
    if not 3 <= args.N <= max_N:
        raise ParameterError("--N", args.N, f"an integer from 3 to {max_N} (masses of a circuit)")
    if args.walls and args.case != "perfect":
        raise ParameterError("--walls", args.walls, "0 unless --case perfect (J >= 1: a perfect cradle tied to walls)")
    if args.case == "perfect":
        check_perfect(args.N, args.walls, budget_from_args(args))
    return chain_for_case(args.case, args.N, args.walls)


def check_perfect(N: int, walls: int, budget: Budget) -> None:
    """Refuse a perfect cradle out of range or beyond the budget, naming the option."""
    if not MIN_N <= N <= MAX_PERFECT_N:
        raise ParameterError("--N", N, f"an integer from {MIN_N} to {MAX_PERFECT_N} for --case perfect")
    if walls < 0:
        raise ParameterError("--walls", walls, "an integer J >= 0 (0: free ends; J >= 1: tied to walls)")
    perfect_estimate(N, walls).check(budget, "--N", N)


#: Effects every command with a circuit takes in its chain (``--coupling``), not as an effect option.
CIRCUIT_EFFECTS = ("coupling",)


def _effect_options() -> list[type[Effect]]:
    """The registered effects a command line can ask for by an option of theirs (``Effect.option``)."""
    return [cls for key, cls in EFFECTS.items() if cls.option is not None and key not in CIRCUIT_EFFECTS]


def _dest(option: str) -> str:
    return option.lstrip("-").replace("-", "_")


def add_effect_arguments(p: argparse.ArgumentParser) -> None:
    """One option per registered effect that states one (``--Q``, ``--coil-capacitance``, a plugin's): its value
    is the effect's one field, checked by the effect (:func:`effects_from_args`)."""
    for cls in _effect_options():
        assert cls.option is not None
        try:
            p.add_argument(cls.option, type=number_type(cls.option), default=None,
                           metavar=effect_fields(cls)[0].name,
                           help=f"{cls.option_help}; as a scene's [effects.{cls.key}]")
        except argparse.ArgumentError as error:  # a plugin's option taken by another
            raise ParameterError(f"effects.{cls.key}", cls.option, f"an option no other has ({error})") from None


def effects_from_args(args: argparse.Namespace) -> tuple[Effect, ...]:
    """The effects the effect options ask for, in the registry's order; a bad value is refused under its
    option's name (``--coil-capacitance = -1.0 is not allowed: ...``)."""
    effects: list[Effect] = []
    for cls in _effect_options():
        assert cls.option is not None
        value = getattr(args, _dest(cls.option), None)
        if value is None:
            continue
        try:
            effects.append(cls.from_option(value))
        except ParameterError as error:
            raise error.renamed(cls.option) from None
    return tuple(effects)

