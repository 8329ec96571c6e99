"""What a run may leave behind: files in the temporary folder, processes in the process table."""

from __future__ import annotations

import contextlib
import os
import signal
import subprocess
import tempfile
import time
from collections.abc import Iterator
from pathlib import Path


def temporary_entries() -> set[str]:
    """Names in the temporary folder (the session's own, see conftest.py)."""
    return set(os.listdir(tempfile.gettempdir()))


def alive(pid: int) -> bool:
    """Whether a process exists and is not a zombie."""
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except (FileNotFoundError, ProcessLookupError, IndexError):
        return False
    return state != "Z"


def gone(pid: int, seconds: float = 10.0) -> bool:
    """Whether a process is gone (or a zombie) within ``seconds``, looking every 50 ms."""
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        if not alive(pid):
            return True
        time.sleep(0.05)
    return not alive(pid)


def _process_table() -> dict[int, tuple[int, str]]:
    """pid -> (parent pid, command name) of every process in /proc."""
    table = {}
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            stat = (entry / "stat").read_text()
        except OSError:
            continue
        table[int(entry.name)] = (int(stat.rsplit(")", 1)[1].split()[1]), stat[stat.index("(") + 1 : stat.rindex(")")])
    return table


def children_named(parent: int, name: str) -> list[int]:
    """PIDs of the live processes whose parent is ``parent`` and whose command is ``name``."""
    return [pid for pid, (ppid, comm) in _process_table().items() if ppid == parent and comm == name and alive(pid)]


def descendants(root: int) -> dict[int, str]:
    """pid -> command name of every live process below ``root`` in the process tree."""
    table = _process_table()
    found: dict[int, str] = {}
    frontier = [root]
    while frontier:
        parent = frontier.pop()
        for pid, (ppid, name) in table.items():
            if ppid == parent and pid not in found and alive(pid):
                found[pid] = name
                frontier.append(pid)
    return found


def dies_unless_in(pid: int, value: object) -> object:
    """A task that kills the process it runs in unless that is ``pid`` (a pool worker killed, as by the kernel)."""
    if os.getpid() != pid:
        os.kill(os.getpid(), 9)
    return value


def as_from_a_terminal() -> None:
    """``preexec_fn``: default Ctrl-C in the child, as a shell gives it (a disposition inherited from the test
    process, a library that ignores SIGINT, would make Python ignore it too)."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


@contextlib.contextmanager
def reaped(proc: subprocess.Popen[bytes]) -> Iterator[subprocess.Popen[bytes]]:
    """The block's process, killed if it is still running when the block ends (an assertion failed first)."""
    try:
        yield proc
    finally:
        if proc.poll() is None:
            proc.kill()
