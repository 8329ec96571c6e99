"""Command line: ``lcchain <command> ...`` (a thin layer over the package).

Exit status: 0 ok, 1 simulation or comparison failed (or an output could not
be written), 2 bad usage or bad input, 3 simulator missing, 128 + n after
signal n (130 for Ctrl-C), 141 when the reader of the output went away.
"""

from __future__ import annotations

import argparse
import contextlib
import importlib
import logging
import os
import signal
import sys
import threading
import warnings
from collections.abc import Iterator, Sequence
from types import ModuleType
from typing import TextIO

from ..core import __version__
from ..core.blas import BLAS_THREADS
from ..core.errors import (
    ExtraMissingError,
    Interrupted,
    LcchainError,
    ParameterError,
    SimulationError,
    SimulatorMissingError,
)
from .common import (
    EXIT_EXTRA,
    EXIT_FAILED,
    EXIT_MISSING,
    EXIT_SIGPIPE,
    EXIT_USAGE,
    OPTION_NAMES,
    Parser,
    UsageError,
    budget_parent,
)
from .progress import lines_ended

__all__ = ["main", "build_parser", "COMMANDS"]

#: The commands, in the order ``lcchain --help`` lists them: name -> (its module of cli/, holding its parser,
#: ``add_parser(sub, budget)``, and its ``cmd_*``, which calls the command's function in app/; its one-line help).
#: Only the command asked for is imported and given its whole parser (its options, the plugin groups read for them):
#: the others are listed by this help alone, so that a command's start pays for no other command's modules.
#: tests/test_cli.py checks that each help here is the one its module's parser gives.
COMMANDS: dict[str, tuple[str, str]] = {
    'design': ('design',
                'optimal one-mass or two-mass chain for N (a row of Table I or II), or a perfect cradle'),
    'table': ('table',
               'Table I (one-mass) or II (two-mass) for a list of N'),
    'asymptotic': ('asymptotic',
                    'N -> infinity: maximum of alpha_inf(tau, sigma) and the scaling laws'),
    'netlist': ('netlist',
                 'SPICE netlist of the equivalent LC ladder'),
    'examples': ('examples',
                  'the example scenes that ship with lcchain: list them, or write one here'),
    'reference-netlists': ('reference_netlists',
                            'regenerate the reference netlists of netlists/'),
    'spectrum': ('spectrum',
                  "the ladder's normal frequencies and mode weights from an AC analysis in ngspice (or gnucap), "
                  'beside theory'),
    'bom': ('bom',
             "bill of materials: the ladder's distinct inductors and capacitors (rounded to a preferred-number series"
             ' with --series) with their counts, as a table or --csv'),
    'sensitivity': ('sensitivity',
                     'which components move the first-arrival peak: dp/dL_i and dp/dC_j from exact theory, ranked '
                     '(--check M: against ngspice finite differences)'),
    'requirements': ('requirements',
                      "how good must the parts be: the first arrival's energy against a coil's self-capacitance and "
                      "resistance, a capacitor's ESR and ESL, and coupling, from the circuit's exact theory, with "
                      'ngspice points'),
    'simulate': ('simulate',
                  'run the ladder in ngspice (or gnucap) and compare with alpha_N(t)'),
    'run': ('run',
             'run a scene (TOML experiment description)'),
    'sweep': ('sweep',
               'many runs: the product of comma-list axes, or a scene or a netlist varied'),
    'batch': ('batch',
               'netlists lcchain did not write, checked, priced and run in a sandbox, into a store'),
    'check': ('check',
               'a linear netlist (R L C K, V/I with DC PULSE SIN PWL EXP) run in a simulator and compared with its '
               'exact response: the error of every saved vector, the error the step predicts, the step an accuracy '
               'needs'),
    'results': ('results',
                 "a store's runs: a table, --json, --csv, or a --plot of the study"),
    'figures': ('figures',
                 "the paper's figures, recomputed: one file per figure, named by its label"),
    'report': ('report',
                'the validation report: the paper reproduced and the circuit validated, in DIR/index.html and '
                'DIR/report.json (exit 1 when a check fails)'),
    'bench': ('bench',
               'benchmarks (accuracy: what each digit costs per method and N)'),
    'doctor': ('doctor',
                'check ngspice, its shared library and PySpice'),
}


def command_module(name: str) -> ModuleType:
    """The module of cli/ that holds command ``name``'s parser and its ``cmd_*`` (imported now)."""
    return importlib.import_module(f"{__package__}.{COMMANDS[name][0]}")


log = logging.getLogger("lcchain")


def build_parser(only: str | None = None) -> argparse.ArgumentParser:
    """The whole parser, or with ``only`` (a command's name, or ``""`` for none) that command's parser alone,
    the other commands listed by their help (:data:`COMMANDS`)."""
    parser = Parser(prog="lcchain", description="Quasi-uniform spring-mass chains and their LC ladders in ngspice.")
    parser.add_argument("-v", "--verbose", action="store_true", help="log every ngspice run to stderr")
    parser.add_argument("--version", action="version", version=f"lcchain {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=Parser)
    sub.required = True
    budget = [budget_parent()]  # argparse parents, of the subparsers' class as typeshed wants

    for name, (_, help_) in COMMANDS.items():
        if only is None or name == only:
            command_module(name).add_parser(sub, budget)
        else:
            sub.add_parser(name, help=help_)
    return parser


def _raise_interrupted(signum: int, frame: object) -> None:
    raise Interrupted(signum)


@contextlib.contextmanager
def _signals_interrupt() -> Iterator[None]:
    """SIGTERM and SIGHUP raise Interrupted while a command runs, so that every cleanup runs."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = {sig: signal.signal(sig, _raise_interrupted) for sig in (signal.SIGTERM, signal.SIGHUP)}
    try:
        yield
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)


def _as_typed(error: ParameterError, args: argparse.Namespace) -> ParameterError:
    """The error under the option the user typed (``--dt``, not ``dt``) when it came from the command line.

    A refusal of the chain itself (``chain``: its time scale, its poles; ``N``: its size) names how the user gave
    the chain: ``--chain FILE`` (with a file, --N was not typed), else ``--walls`` for a walled cradle, else ``--N``.
    So does a refusal of a step the user did not type (the default --dt): the chain makes the run long.
    """
    if error.where is not None:
        return error
    allowed = error.allowed
    if error.field == "dt" and "dt" in args and args.dt is None:  # the default step: what the user gave is the chain
        allowed = f"{allowed} (at the default step --dt {error.value!r})"
        if isinstance(getattr(args, "N", None), list):  # a sweep: its sizes
            return ParameterError("--N", ",".join(str(N) for N in args.N), allowed)
        error = ParameterError("chain", error.value, allowed)
    chain_file = getattr(args, "chain", None)
    if error.field in ("chain", "N") and isinstance(chain_file, str):
        return ParameterError("--chain", chain_file, allowed)
    if error.field == "chain":
        walls, N = getattr(args, "walls", 0), getattr(args, "N", None)
        if walls:
            return ParameterError("--walls", walls, f"{allowed} (with --N {N})")
        if isinstance(N, int):
            return ParameterError("--N", N, allowed)
    if error.field in OPTION_NAMES:
        return error.renamed(OPTION_NAMES[error.field])
    return error


def _quiet_stdout() -> None:
    """The reader of our output went away: send what is left nowhere, say nothing."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
    except (OSError, ValueError):
        pass


def _show_warning(message: Warning | str, category: type[Warning], filename: str, lineno: int,
                  file: TextIO | None = None, line: str | None = None) -> None:
    print(f"lcchain: warning: {message}", file=sys.stderr)


def _command_asked(argv: Sequence[str]) -> str:
    """The command argv names, or "" when it names none of :data:`COMMANDS` (``--help``, ``--version``, a typo):
    the first word that is not an option, since no option of lcchain's own takes a value."""
    word = next((arg for arg in argv if not arg.startswith("-")), "")
    return word if word in COMMANDS else ""


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit status."""
    try:
        return _command_line(argv)
    except Exception as error:  # Ctrl-C while a module loads: Python may hand it on inside another error
        if not _from_ctrl_c(error):
            raise
        print("lcchain: interrupted", file=sys.stderr)
        return 130
    except KeyboardInterrupt:  # Ctrl-C while the command's parser and modules load: as within the command
        print("lcchain: interrupted", file=sys.stderr)
        return 130


def _from_ctrl_c(error: BaseException) -> bool:
    """Whether ``error`` was caused by a Ctrl-C (its ``__cause__`` chain): a class body interrupted while a module
    loads ends as ``RuntimeError: Error calling __set_name__``, raised from the KeyboardInterrupt.  An error merely
    raised while one was handled (its ``__context__``) is an error of its own, shown as such."""
    seen: set[int] = set()
    current: BaseException | None = error
    while current is not None and id(current) not in seen:
        if isinstance(current, KeyboardInterrupt):
            return True
        seen.add(id(current))
        current = current.__cause__
    return False


def _blas_limited() -> contextlib.AbstractContextManager[object]:
    """BLAS_THREADS for the BLAS already loaded (a caller's numpy, when main is called in its process); none is
    loaded when the command line starts a process, whose BLAS starts with OPENBLAS_NUM_THREADS, so threadpoolctl
    (2 ms, and a walk of the loaded libraries) is not imported there."""
    if "numpy" not in sys.modules:
        return contextlib.nullcontext()
    from threadpoolctl import threadpool_limits

    limited: contextlib.AbstractContextManager[object] = threadpool_limits(limits=BLAS_THREADS, user_api="blas")
    return limited


def _command_line(argv: Sequence[str] | None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    if "numpy" not in sys.modules:
        # numpy's OpenBLAS starts its threads when numpy loads, and they spin: 0.06 to 0.08 s of CPU at every start
        # on this 2-core machine, taken from the runs of a batch.  Every command computes under a limit of
        # BLAS_THREADS (below): its BLAS starts with that many, and so do the workers it spawns.
        os.environ.setdefault("OPENBLAS_NUM_THREADS", str(BLAS_THREADS))
    try:
        parser = build_parser(_command_asked(argv))  # reads the registries: a broken plugin is bad input, one line
    except ParameterError as error:
        print(f"lcchain: {error}", file=sys.stderr)
        return EXIT_USAGE
    try:
        args = parser.parse_args(argv)
    except UsageError as error:
        print(str(error), file=sys.stderr)
        return EXIT_USAGE
    except SystemExit as exit_:  # --help, --version
        return int(exit_.code or 0)
    args.argv_echo = argv[1:]
    logging.basicConfig(level=logging.INFO if args.verbose else logging.WARNING, format="lcchain: %(message)s")
    try:
        with _signals_interrupt(), _blas_limited(), warnings.catch_warnings(), lines_ended():
            warnings.showwarning = _show_warning  # one line a person reads, not a source location
            status = int(args.func(args))
        sys.stdout.flush()
        return status
    except SimulatorMissingError as error:
        print(f"lcchain: {error}", file=sys.stderr)
        return EXIT_MISSING
    except ExtraMissingError as error:
        print(f"lcchain: {error}", file=sys.stderr)
        return EXIT_EXTRA
    except ParameterError as error:
        print(f"lcchain: {_as_typed(error, args)}", file=sys.stderr)
        return EXIT_USAGE
    except SimulationError as error:
        print(f"lcchain: simulation failed: {error}", file=sys.stderr)
        return EXIT_FAILED
    except LcchainError as error:
        print(f"lcchain: {error}", file=sys.stderr)
        return EXIT_FAILED
    except BrokenPipeError:
        _quiet_stdout()
        return EXIT_SIGPIPE
    except OSError as error:  # e.g. a disk full or a folder removed while running
        where = f"{error.filename}: " if error.filename else ""
        print(f"lcchain: {where}{error.strerror or error}", file=sys.stderr)
        return EXIT_FAILED
    except KeyboardInterrupt:
        print("lcchain: interrupted", file=sys.stderr)
        return 130
    except Interrupted as interrupt:
        print(f"lcchain: interrupted by signal {interrupt.signum}", file=sys.stderr)
        return 128 + interrupt.signum


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
