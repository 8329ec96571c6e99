"""The catalogue of bad and hostile inputs: one case, run the way a user would, classified.

Each case runs the command line in this process, in a folder of its own, and
gets one class:

``clean``
    The expected exit status, one line on stderr (for exit 2) naming what it
    must name, no traceback, nothing written, nothing left behind.
``traceback``
    A Python traceback reached the user.
``silent``
    A wrong exit status (0 for bad input), or a message that does not say
    what it must.
``unbounded``
    It ran past the case's time limit.
``orphan``
    A file or folder was left in the case's folder or in the temporary folder,
    or a simulator is still running.
``lost``
    A file the user had (an input, a store) was changed or removed.
``injection``
    The case's marker file appeared: a command or a file operation outside
    what lcchain allows took place.

``python tests/catalogue.py`` prints the counts per family and class.
"""

from __future__ import annotations

import contextlib
import hashlib
import io
import os
import signal
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path

from helpers.processes import children_named, temporary_entries

CLASSES = ("clean", "traceback", "silent", "unbounded", "orphan", "lost", "injection")
#: The file a hostile case tries to create (in its own folder or, by name, anywhere it can reach).
MARKER = "PWNED"


@dataclass
class Case:
    """One bad input: the command line, the files it needs, what it must say.

    ``files`` are written into the case's folder first (bytes or text), then
    ``make`` gets the folder and makes what else it wants (a FIFO, a symlink,
    a store). Every file there must come out unchanged; ``leaves`` names the
    outputs a case may make. ``{here}`` in an argument or a text file stands
    for the case's folder, so that a hostile case can aim its marker at an
    absolute path the test can see. ``family`` groups the cases in the
    counts of ``tests/catalogue.py``.
    """

    argv: list[str]
    said: list[str]
    status: int = 2
    files: dict[str, str | bytes] = field(default_factory=dict)
    env: dict[str, str] = field(default_factory=dict)
    one_line: bool = True
    family: str = "arguments"
    make: Callable[[Path], None] | None = None
    seconds: float = 60.0
    leaves: tuple[str, ...] = ()


def write_files(folder: Path, files: dict[str, str | bytes]) -> None:
    for name, content in files.items():
        path = folder / name
        path.parent.mkdir(parents=True, exist_ok=True)
        if isinstance(content, bytes):
            path.write_bytes(content)
        else:
            path.write_text(content.replace("{here}", str(folder)), encoding="utf-8")


def tree(folder: Path) -> dict[str, str]:
    """Every entry below ``folder``: a regular file by its content's hash, anything else by its kind."""
    found: dict[str, str] = {}
    for path in folder.rglob("*"):
        if path.is_symlink():
            found[str(path.relative_to(folder))] = "link:" + os.readlink(path)
        elif path.is_file():
            found[str(path.relative_to(folder))] = hashlib.sha256(path.read_bytes()).hexdigest()
        else:
            found[str(path.relative_to(folder))] = "dir" if path.is_dir() else "special"
    return found


class _Timeout(Exception):
    pass


@contextlib.contextmanager
def _alarm(seconds: float) -> Iterator[None]:
    def fire(signum: int, frame: object) -> None:
        raise _Timeout

    previous = signal.signal(signal.SIGALRM, fire)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)


@dataclass
class Outcome:
    kind: str
    detail: str
    status: int | None
    err: str


def run_case(case: Case, folder: Path, main: Callable[[list[str]], int]) -> Outcome:
    """Run one case in ``folder`` (which it changes into) and classify what happened."""
    write_files(folder, case.files)
    if case.make is not None:
        case.make(folder)
    before, temporary = tree(folder), temporary_entries()
    out, err = io.StringIO(), io.StringIO()
    old_cwd, old_env = os.getcwd(), dict(os.environ)
    os.chdir(folder)
    os.environ.update(case.env)
    status: int | None = None
    start = time.monotonic()
    try:
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err), _alarm(case.seconds):
            try:
                status = main([arg.replace("{here}", str(folder)) for arg in case.argv])
            except SystemExit as exit_:
                status = exit_.code if isinstance(exit_.code, int) else 1
    except _Timeout:
        return Outcome("unbounded", f"still running after {case.seconds:g} s", None, err.getvalue())
    except BaseException as error:  # noqa: BLE001 - an exception out of main() is a traceback to the user
        return Outcome("traceback", f"{type(error).__name__}: {error}", None, err.getvalue())
    finally:
        os.chdir(old_cwd)
        os.environ.clear()
        os.environ.update(old_env)
    elapsed = time.monotonic() - start
    text, output = err.getvalue(), out.getvalue()
    after = tree(folder)
    if (folder / MARKER).exists() or any(MARKER in name for name in after):
        return Outcome("injection", "the marker file appeared", status, text)
    if "Traceback" in text or "Traceback" in output:
        return Outcome("traceback", text[-400:], status, text)
    changed = [name for name, digest in before.items() if after.get(name) != digest]
    if changed:
        return Outcome("lost", f"changed or removed: {changed}", status, text)
    new = sorted(set(after) - set(before) - set(case.leaves))
    if new:
        return Outcome("orphan", f"left in its folder: {new}", status, text)
    if temporary_entries() - temporary:
        return Outcome("orphan", f"left in the temporary folder: {temporary_entries() - temporary}", status, text)
    if children_named(os.getpid(), "ngspice"):
        return Outcome("orphan", "a simulator is still running", status, text)
    if status != case.status:
        return Outcome("silent", f"exit {status}, expected {case.status} (after {elapsed:.1f} s): {text[-300:]}",
                       status, text)
    lines = [line for line in text.splitlines() if line.strip()]
    if case.status == 2 and case.one_line and (output or len(lines) != 1):
        return Outcome("silent", f"not one line on stderr and nothing on stdout: {text!r} {output[:200]!r}",
                       status, text)
    missing = [piece for piece in case.said if piece not in text]
    if missing:
        return Outcome("silent", f"{missing} not in {text!r}", status, text)
    return Outcome("clean", "", status, text)
