"""What every command's parser shares: argument types, the chain's and the effects' options, budgets, JSON out."""

from __future__ import annotations

import argparse
import contextlib
import math
import re
import sys
from collections.abc import Callable, Iterable
from typing import TYPE_CHECKING, Any, NoReturn, TypeAlias

from ..core.budget import (
    DEFAULT_MAX_MEMORY,
    DEFAULT_MAX_SECONDS,
    INTERPRETER_BYTES,
    INTERPRETER_SECONDS,
    Budget,
    show_bytes,
    show_seconds,
)
from ..core.json import json_text
from ..core.limits import (
    MAX_BUDGET_BYTES,
    MAX_SECONDS,
    MIN_TIMEOUT,
)
from ..core.types import E_SERIES_NAMES

if TYPE_CHECKING:
    from ..app.choices import RegistryNames
    from ..app.inputs import Outputs

__all__ = ["Parser", "UsageError", "Subcommands", "EXIT_OK", "EXIT_FAILED", "EXIT_USAGE", "EXIT_MISSING",
           "EXIT_SIGPIPE", "EXIT_EXTRA", "OPTION_NAMES",
           "NEGATIVE_NUMBER", "single_valued", "count", "list_entries", "int_list", "si_number", "SI_PREFIXES",
           "number_type", "size", "duration", "seconds", "budget_parent", "emit_json", "budget_from_args",
           "print_notes", "summary_stream", "tolerances", "add_parts_arguments", "registry_name", "plural"]

EXIT_OK, EXIT_FAILED, EXIT_USAGE, EXIT_MISSING = 0, 1, 2, 3
#: A missing optional extra (pandas, xarray, Dask, PySpice): ``pip install 'lcchain[EXTRA]'`` fixes it.
EXIT_EXTRA = 2  # a missing optional extra is an input the machine lacks: the usage status, naming the extra
#: A reader closed the pipe (``lcchain table --json | head -2``): the exit status of a process killed by SIGPIPE.
EXIT_SIGPIPE = 128 + 13

#: Names the package uses for what the user typed as an option.
OPTION_NAMES = {
    "N": "--N", "dt": "--dt", "accuracy": "--accuracy", "transits": "--transits", "L0": "--L0", "C0": "--C0",
    "title": "--title", "excitation": "--excitation", "method": "--method", "backend": "--backend",
    "engine": "--engine",
    "points": "--points", "Q": "--Q", "coupling": "--coupling",
    "case": "--case", "walls": "--walls", "max_memory": "--max-memory", "max_seconds": "--max-time",
    "timeout": "--timeout", "extrapolate": "--extrapolate",
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


class UsageError(Exception):
    """Bad usage, in the one line :meth:`Parser.error` made of it (exit 2)."""


class Parser(argparse.ArgumentParser):
    """argparse that reports bad usage as one line (exit 2), never a traceback; a single-value option given twice
    is bad usage, and ``-1e-5`` is a value, not an option (:func:`single_valued`).  Every command's parser is one,
    and so are the parents they share (:func:`budget_parent`), as typeshed wants of a subparser's parents."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:  # argparse's own arguments, passed on as they are
        super().__init__(*args, **kwargs)
        single_valued(self)

    def error(self, message: str) -> NoReturn:
        raise UsageError(f"{self.prog}: {message} (see '{self.prog} --help')")


#: What ``lcchain``'s parser hands each command's ``add_parser(sub, budget)``: the subcommands to add its parser
#: to, and the parents it may take (its budget's options).
Subcommands: TypeAlias = "argparse._SubParsersAction[Parser]"  # generic in typeshed only: a string at run time


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
SI_PREFIXES = {"f": -15, "p": -12, "n": -9, "u": -6, "\u00b5": -6, "m": -3, "k": 3, "meg": 6, "G": 9}
_SI = re.compile(r"^\s*([-+]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][-+]?[0-9]+)?)\s*(meg|[fpnu\u00b5mkMG])?\s*"
                 r"(H|F|ohm|\u03a9)?\s*$")


def si_number(option: str, unit: str) -> Callable[[str], float]:
    """An argparse type: a finite number, plain (``1e-5``) or with an SI prefix and optionally its unit
    (``10u``, ``10uH``, ``4.7n``, ``4.7nF``), as :data:`SI_PREFIXES` lists; anything else is one line naming
    the option."""

    def parse(text: str) -> float:
        match = _SI.match(text)
        if match is not None and match.group(2) == "M":  # SI's mega, SPICE's milli: neither is guessed
            raise argparse.ArgumentTypeError(
                f"{option} = {text!r} is not allowed: expected meg for mega or m for milli (M is mega in SI but "
                f"milli in SPICE, which reads 10M{unit} as 10 m{unit})")
        if match is None or (match.group(3) is not None and match.group(3) != unit):
            raise argparse.ArgumentTypeError(
                f"{option} = {text!r} is not allowed: expected a number in {unit}, plain or with an SI prefix "
                f"(f p n u m k meg G), such as 10u or 10u{unit}")
        # decimal: 10u is the float nearest 1e-5, as "1e-5" is (10 * 1e-6 is not)
        import decimal  # here alone: its C module costs every command's start 1.5 ms

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


def budget_parent() -> Parser:
    """The options every command that does real work takes: its budget."""
    parent = Parser(add_help=False)
    parent.add_argument("--max-memory", type=size, default=DEFAULT_MAX_MEMORY, metavar="SIZE",
                        help="most memory one request may use (default 8G)")
    parent.add_argument("--max-time", type=duration, default=DEFAULT_MAX_SECONDS, metavar="DURATION",
                        help="most time one request may take (default 1h)")
    return parent


def budget_from_args(args: argparse.Namespace) -> Budget:
    """--max-memory and --max-time, or the defaults for a command without them."""
    return Budget(getattr(args, "max_memory", DEFAULT_MAX_MEMORY), getattr(args, "max_time", DEFAULT_MAX_SECONDS))


def plural(count: int, noun: str) -> str:
    """``count`` and ``noun``, in the plural but for one: ``1 run``, ``2 runs``."""
    return f"{count} {noun}{'' if count == 1 else 's'}"


def emit_json(data: object) -> None:
    """Print a JSON document (what ``json.dumps`` takes), indented: valid JSON, so a number that is not finite (a
    mean of values near the largest float, which overflows) is ``null`` (:func:`lcchain.core.json.json_text`)."""
    print(json_text(data))


def summary_stream(outputs: Outputs) -> contextlib.AbstractContextManager[object]:
    """Where a command's own lines go: stdout, or stderr when one of its outputs writes its text to stdout (``-``)."""
    if outputs.to_stdout is None:
        return contextlib.nullcontext()
    return contextlib.redirect_stdout(sys.stderr)


def print_notes(notes: Iterable[str]) -> None:
    """What a command's result says beside it (a file it could not write, a target it missed): app/ prints
    nothing itself; each note is one line on stderr."""
    for note in notes:
        print(f"lcchain: {note}", file=sys.stderr)


def registry_name(option: str, names: RegistryNames) -> Callable[[str], str]:
    """An argparse type: a name the registry holds, looked up when a value is given (so that ``--help`` imports
    no registry whose module is heavy, as the executors' is), in the line every refused option has."""

    def parse(text: str) -> str:
        if text not in names:
            raise argparse.ArgumentTypeError(f"{option} = {text!r} is not allowed: expected {' | '.join(names)}")
        return text

    return parse
