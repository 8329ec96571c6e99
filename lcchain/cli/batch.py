"""``lcchain batch``: netlists lcchain did not write, checked, priced and run in a sandbox, into a store
(:func:`lcchain.app.batch.batch`)."""

from __future__ import annotations

import argparse
import codecs
import contextlib
import os
import sys
import tempfile
from collections.abc import Iterator

from ..core.errors import ParameterError
from .common import Parser, Subcommands, budget_from_args
from .studies import add_study_arguments, show_study, study_hooks, study_options

__all__ = ["add_parser", "cmd_batch"]


def add_parser(sub: Subcommands, budget: list[Parser]) -> None:
    p = sub.add_parser("batch", parents=budget, help="netlists lcchain did not write, checked, priced and run in a "
                       "sandbox, into a store")
    p.add_argument("netlist", nargs="*", metavar="NETLIST",
                   help="netlist files: comments, R L C K V I E F G H B D Q M J S W X elements, .tran .ac .options "
                        ".save .ic .param .meas .subckt/.ends .model .func .global .temp .op .dc .end and "
                        ".include/.lib of files in the netlist's folder; any other line is refused")
    p.add_argument("--from", dest="from_list", metavar="LIST",
                   help="also the netlists LIST names, one file name a line (blank lines skipped; - reads the names "
                        "from standard input): more netlists than a command line holds, e.g. find runs -name "
                        "'*.cir' | lcchain batch --from - --store runs.sqlite")
    p.add_argument("--allow-control", action="store_true",
                   help="run a netlist as it is (.control blocks, any include), still in the sandbox")
    p.add_argument("--check", action="store_true",
                   help="also compare each run's saved vectors with the netlist's exact response (lcchain check): "
                        "the largest error, in the vectors' own units, is stored as the measurement "
                        "check_max_abs_error (empty, with the reason, for a netlist that is not linear)")
    p.add_argument("--strict", action="store_true",
                   help="stop at the first netlist lcchain will not run, with its reason, before anything runs "
                        "(exit 2); by default each is stored as refused, with its reason, the others run, and "
                        "the exit status is 1")
    add_study_arguments(p)
    p.set_defaults(func=cmd_batch)


def cmd_batch(args: argparse.Namespace) -> int:
    """A batch's --max-time is its whole budget: each run's own limits come from its price, and no run starts once
    the budget is spent (the runs left stay pending in the store). A netlist lcchain will not run is stored as
    refused and the others run (exit 1); with --strict the first refusal stops the batch (exit 2).  A list's names
    (--from) are read as the batch is planned, none of them kept: standard input is copied to a temporary
    file first (unnamed on Linux)."""
    from ..app.batch import BatchRequest, batch

    if not args.netlist and args.from_list is None:
        raise ParameterError("NETLIST", "none", "at least one netlist file, given or listed (--from LIST)")
    with contextlib.ExitStack() as stack:
        listed = args.from_list
        if listed == "-":
            listed = stack.enter_context(_stdin_list())
        request = BatchRequest(tuple(args.netlist), allow_control=args.allow_control, strict=args.strict,
                               check=getattr(args, "check", False), study=study_options(args),
                               budget=budget_from_args(args), listed=listed)
        return show_study(args, batch(request, study_hooks(args)))


@contextlib.contextmanager
def _stdin_list() -> Iterator[str]:
    """The names piped to ``--from -``, copied to a temporary file (removed after) a chunk at a time: at most as
    much as a list file may hold (``< /dev/zero`` is refused, not read without end), UTF-8."""
    from ..core.limits import MAX_NETLIST_LIST_BYTES

    decoder = codecs.getincrementaldecoder("utf-8")()
    # Without a name where /proc shows it again (Linux): even a batch killed outright leaves no file behind.
    unnamed = os.path.isdir("/proc/self/fd")
    with tempfile.TemporaryFile() if unnamed else tempfile.NamedTemporaryFile(prefix="lcchain-names-") as copy:
        size = 0
        try:
            while chunk := sys.stdin.buffer.read(min(1 << 16, MAX_NETLIST_LIST_BYTES + 1 - size)):
                size += len(chunk)
                if size > MAX_NETLIST_LIST_BYTES:
                    raise ParameterError("--from", "-", f"at most {MAX_NETLIST_LIST_BYTES} bytes of netlist names on "
                                         "standard input")
                decoder.decode(chunk)
                copy.write(chunk)
            decoder.decode(b"", final=True)
        except UnicodeDecodeError:
            raise ParameterError("--from", "-", "netlist names in UTF-8 on standard input") from None
        copy.flush()
        yield f"/proc/self/fd/{copy.fileno()}" if unnamed else copy.name
