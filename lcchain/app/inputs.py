"""What every command shares: the chain it is about, the files it writes, the command line a netlist echoes.

Moved from ``cli/common.py`` (issue 34): the command line parses options into a :class:`ChainOptions` and calls
these; a file that cannot be written is named in one line (:class:`Outputs`), never a traceback.

app/ prints nothing to stderr itself: what a command has to say beside its result (a file it could not write, a
target it missed) is a note, a line the command's result holds (``notes``, or :attr:`Outputs.notes`) and the
command line prints (``lcchain: <note>``).
"""

from __future__ import annotations

import json
import sys
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

from ..core.budget import Budget, perfect_estimate
from ..core.errors import ParameterError
from ..core.limits import COUPLED_MAX_N, MAX_CHAIN_FILE_BYTES, MAX_CIRCUIT_N, MAX_COMMENT_LENGTH, MAX_PERFECT_N, MIN_N
from ..core.types import Excitation
from ..report.files import check_not_input, check_output, same_file, write_text

if TYPE_CHECKING:
    from ..theory.chain import Chain

__all__ = ["STDOUT", "Outputs", "ChainOptions", "LadderRequest", "make_chain", "load_chain_file", "check_perfect",
           "echoed_command"]

#: The file name of every option that writes one text (``-o``, ``--netlist-out``, ``--waveform-out``) that
#: means standard output, as ``-`` does for most Unix tools.
STDOUT = "-"


@dataclass(frozen=True)
class ChainOptions:
    """How a command line names its chain: ``chain`` (a JSON file) or ``case`` and ``N`` (``walls`` for a walled
    perfect cradle), and ``coupling`` between neighbouring coils (None: as the chain says)."""

    case: str | None = None
    N: int | None = None
    walls: int = 0
    chain: str | None = None
    coupling: float | None = None


@dataclass(frozen=True)
class LadderRequest:
    """What a netlist and a simulation both start from: the chain and its units, how a transient drives it
    (``excitation``, ``transits``, ``dt``) and its title (:class:`lcchain.app.netlist.NetlistRequest` and
    :class:`lcchain.app.simulate.SimulateRequest` add what each does with it)."""

    chain: ChainOptions
    L0: float
    C0: float
    excitation: Excitation = "kick"
    title: str | None = None
    transits: int = 1
    dt: float | None = None


@dataclass
class Outputs:
    """The files a command writes: checked before any work, written after the results are shown.

    ``inputs`` names the files the command reads (option -> path): an output
    that is one of them is refused, so that no command destroys its own input.
    A file that cannot be written at the end (a full disk) is named in one
    note (:attr:`notes`, which the caller prints) and makes the command fail
    (exit 1), after everything else was written and printed.

    ``-`` (:data:`STDOUT`) names standard output for an option that writes
    one text (no ``formats``); one option at most may take it, and the
    command's own summary then goes to stderr (``lcchain.cli.common.summary_stream``).
    """

    inputs: dict[str, str] = field(default_factory=dict)
    checked: dict[str, Path] = field(default_factory=dict)
    failed: list[str] = field(default_factory=list)
    to_stdout: str | None = None
    notes: list[str] = field(default_factory=list)

    def take_notes(self) -> list[str]:
        """The notes said since the last call (a caller prints them as they come: before and after writing)."""
        taken = list(self.notes)
        self.notes.clear()
        return taken

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

    def write(self, option: str, writer: Callable[[Path], object]) -> None:
        """Run ``writer(path)`` for a checked output; report a failure by name instead of raising."""
        path = self.checked.get(option)
        if path is None:
            return
        try:
            writer(path)
        except OSError as error:
            self.failed.append(option)
            self.notes.append(f"could not write {path} ({option}): {error.strerror or error}")

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
    from ..theory.chain import Chain  # here: a command that names no chain (a batch) starts without its numerics

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


def make_chain(args: ChainOptions, budget: Budget, max_N: int = MAX_CIRCUIT_N) -> Chain:
    """The chain a command is about: ``--chain FILE`` or ``--case`` and ``--N`` (never both), with ``--coupling``."""
    chain = _chain_of_args(args, budget, max_N)
    coupling = args.coupling
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


def _chain_of_args(args: ChainOptions, budget: Budget, max_N: int) -> Chain:
    from ..theory.cases import CHAIN_CASES, chain_for_case

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
    named = CHAIN_CASES[args.case]  # a name the parser offered
    if args.N > named.max_N:  # a case's own limit (a plugin's may be below the circuit's), as a scene checks it
        raise ParameterError("--N", args.N, f"an integer from 3 to {named.max_N} for --case {args.case}")
    if args.walls and not named.walls:
        raise ParameterError("--walls", args.walls, "0 unless --case perfect (J >= 1: a perfect cradle tied to walls)")
    if named.walls:  # the case that takes walls, the perfect cradle, is designed from its spectrum: priced first
        check_perfect(args.N, args.walls, budget)
    return chain_for_case(args.case, args.N, args.walls)


def check_perfect(N: int, walls: int, budget: Budget) -> None:
    """Refuse a perfect cradle out of range or beyond the budget, naming the option."""
    if not MIN_N <= N <= MAX_PERFECT_N:
        raise ParameterError("--N", N, f"an integer from {MIN_N} to {MAX_PERFECT_N} for --case perfect")
    if walls < 0:
        raise ParameterError("--walls", walls, "an integer J >= 0 (0: free ends; J >= 1: tied to walls)")
    perfect_estimate(N, walls).check(budget, "--N", N)
