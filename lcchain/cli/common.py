"""What every command shares: argument types, progress on a terminal, outputs, chains, budgets."""

from __future__ import annotations

import argparse
import json
import math
import os
import re
import sys
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..core.budget import DEFAULT_MAX_MEMORY, DEFAULT_MAX_SECONDS, Budget, perfect_estimate
from ..core.errors import ParameterError
from ..core.limits import MAX_CHAIN_FILE_BYTES, MAX_CIRCUIT_N, MAX_PERFECT_N, MIN_N
from ..report.files import check_output, write_text
from ..theory.chain import Chain

__all__ = ["EXIT_OK", "EXIT_FAILED", "EXIT_USAGE", "EXIT_MISSING", "EXIT_SIGPIPE", "OPTION_NAMES", "int_list",
           "number", "size", "duration", "budget_parent", "progress_bar", "fraction_bar", "emit_json", "Outputs",
           "chain_from_args", "budget_from_args", "load_chain_file", "check_perfect"]

EXIT_OK, EXIT_FAILED, EXIT_USAGE, EXIT_MISSING = 0, 1, 2, 3
#: A reader closed the pipe (``lcchain table --json | head -2``): the exit status of a process killed by SIGPIPE.
EXIT_SIGPIPE = 128 + 13

#: Names the package uses for what the user typed as an option.
OPTION_NAMES = {
    "N": "--N", "dt": "--dt", "accuracy": "--accuracy", "transits": "--transits", "L0": "--L0", "C0": "--C0",
    "title": "--title", "excitation": "--excitation", "method": "--method", "backend": "--backend",
    "case": "--case", "walls": "--walls", "max_memory": "--max-memory", "max_seconds": "--max-time",
}


def int_list(option: str) -> Callable[[str], list[int]]:
    """An argparse type: integers separated by commas."""

    def parse(text: str) -> list[int]:
        try:
            values = [int(v) for v in text.split(",") if v.strip()]
        except ValueError:
            raise argparse.ArgumentTypeError(
                f"{option} = {text!r} is not allowed: expected integers separated by commas") from None
        if not values:
            raise argparse.ArgumentTypeError(f"{option} is empty: expected integers separated by commas")
        return values

    return parse


def number(option: str) -> Callable[[str], float]:
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


_SIZE = re.compile(r"^\s*([0-9.]+(?:[eE][-+]?[0-9]+)?)\s*([kKmMgGtT]?)(i?B)?\s*$")
_DURATION = re.compile(r"^\s*([0-9.]+(?:[eE][-+]?[0-9]+)?)\s*(s|min|h|d)?\s*$")


def size(text: str) -> float:
    """An argparse type: bytes, as 8G, 512M, 1.5T (binary units; a plain number is GiB)."""
    match = _SIZE.match(text)
    if not match or float(match.group(1)) <= 0:
        raise argparse.ArgumentTypeError(f"--max-memory = {text!r} is not allowed: expected a size such as 16G "
                                         "or 512M (a plain number is GiB)")
    scale = {"": 2**30, "k": 2**10, "m": 2**20, "g": 2**30, "t": 2**40}[match.group(2).lower()]
    return float(match.group(1)) * scale


def duration(text: str) -> float:
    """An argparse type: seconds, as 90, 90s, 30min, 2h, 1d."""
    match = _DURATION.match(text)
    if not match or float(match.group(1)) <= 0:
        raise argparse.ArgumentTypeError(f"--max-time = {text!r} is not allowed: expected a duration such as 90s, "
                                         "30min or 2h (a plain number is seconds)")
    return float(match.group(1)) * {None: 1, "s": 1, "min": 60, "h": 3600, "d": 86400}[match.group(2)]


def budget_parent() -> argparse.ArgumentParser:
    """The options every command that does real work takes: its budget."""
    parent = argparse.ArgumentParser(add_help=False)
    parent.add_argument("--max-memory", type=size, default=DEFAULT_MAX_MEMORY, metavar="SIZE",
                        help="most memory one request may use (default 8G)")
    parent.add_argument("--max-time", type=duration, default=DEFAULT_MAX_SECONDS, metavar="DURATION",
                        help="most time one request may take (default 1h)")
    return parent


def budget_from_args(args: argparse.Namespace) -> Budget:
    """--max-memory and --max-time, or the defaults for a command without them."""
    return Budget(getattr(args, "max_memory", DEFAULT_MAX_MEMORY), getattr(args, "max_time", DEFAULT_MAX_SECONDS))


def _draw_bar(fraction: float, text: str) -> None:
    width = 30
    filled = int(width * min(max(fraction, 0.0), 1.0))
    end = "\n" if fraction >= 1 else ""
    # "\033[K" clears what a longer previous label left on the line (drawn on terminals only)
    sys.stderr.write(f"\r[{'#' * filled}{'.' * (width - filled)}] {text}\033[K{end}")
    sys.stderr.flush()


def progress_bar(done: int, total: int, label: str) -> None:
    """A one-line progress indicator on a terminal (nothing when piped)."""
    if sys.stderr.isatty():
        _draw_bar(done / max(total, 1), f"{done}/{total} {label}")


def fraction_bar(label: str) -> Callable[[float], None] | None:
    """A progress callback for long work: a bar on a terminal, None when piped."""
    if not sys.stderr.isatty():
        return None
    shown: list[int] = []

    def show(fraction: float) -> None:
        percent = int(100 * fraction)
        if not shown or percent != shown[-1]:  # once per percent, and 100% once
            shown.append(percent)
            _draw_bar(fraction, f"{percent:3d}% {label}")

    return show


def emit_json(data: Any) -> None:
    print(json.dumps(data, indent=2))


@dataclass
class Outputs:
    """The files a command writes: checked before any work, written after the results are shown.

    A file that cannot be written at the end (a full disk) is named in one
    line and makes the command fail (exit 1), after everything else was
    written and printed.
    """

    checked: dict[str, Path] = field(default_factory=dict)
    failed: list[str] = field(default_factory=list)

    def check(self, option: str, path: str | None, formats: tuple[str, ...] | None = None) -> None:
        if not path:
            return
        target = check_output(option, path, formats)
        for other, seen in self.checked.items():
            if seen.resolve() == target.resolve():
                raise ParameterError(option, path, f"a file no other option writes ({other} writes it too)")
        self.checked[option] = target

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
        self.write(option, lambda path: write_text(path, text))


def load_chain_file(path: str, max_N: int = MAX_CIRCUIT_N) -> Chain:
    """A chain from a JSON file ``{"masses": [...], "springs": [...]}``, size-checked before it is read."""
    try:
        bytes_ = os.stat(path).st_size
    except OSError as error:
        raise ParameterError("--chain", path, f"a readable JSON file ({error.strerror})") from None
    if bytes_ > MAX_CHAIN_FILE_BYTES:
        raise ParameterError("--chain", path, f"a chain file of at most {MAX_CHAIN_FILE_BYTES // 2**20} MiB "
                             f"(this one has {bytes_ / 2**20:.0f} MiB; a chain of {MAX_CIRCUIT_N} masses takes "
                             "about 5 MiB)")
    try:
        text = Path(path).read_text(encoding="utf-8")
    except OSError as error:
        raise ParameterError("--chain", path, f"a readable JSON file ({error.strerror})") from None
    except UnicodeDecodeError as error:
        raise ParameterError("--chain", path, f"UTF-8 text ({error.reason} at byte {error.start})") from None
    try:
        data = json.loads(text)
    except json.JSONDecodeError as error:
        raise ParameterError("--chain", path, f"valid JSON (line {error.lineno}: {error.msg})") from None
    chain = Chain.from_dict(data, where=path)
    if chain.N > max_N:
        raise ParameterError("--chain", path, f"a chain of at most {max_N} masses (it has {chain.N})")
    return chain


def chain_from_args(args: argparse.Namespace, max_N: int = MAX_CIRCUIT_N) -> Chain:
    """The chain a command is about: ``--chain FILE`` or ``--case`` and ``--N`` (never both)."""
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

