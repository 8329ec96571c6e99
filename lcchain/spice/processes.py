"""Child processes of every engine: started in a session of their own, killed as a group, dead with lcchain.

Engine-neutral: ngspice's transports (:mod:`lcchain.spice.ngspice`) and gnucap (:mod:`lcchain.spice.gnucap`)
both start their children with :func:`child_env`, wait for them with :func:`wait_watching` (a pidfd wakes the
wait the moment a child exits), stop one that :func:`outgrown` its limits and kill its whole group with
:func:`kill_group`.
"""

from __future__ import annotations

import contextlib
import os
import select
import signal
import subprocess
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import IO

from ..core.budget import show_bytes

__all__ = ["PACKAGE_ROOT", "CHILD_HOME", "child_env", "kill_group", "read_all", "resident_bytes", "outgrown",
           "exited", "wait_watching", "progress_reporter", "MAX_LOG_BYTES", "WATCH_INTERVAL", "PROGRESS_INTERVAL"]

#: The folder lcchain is imported from: a Python child (ngspice's shared-library workers) imports it there.
PACKAGE_ROOT = str(Path(__file__).resolve().parents[2])
#: HOME of every simulator child: a folder that does not exist, so no ~/.spiceinit is read.
CHILD_HOME = "/nonexistent/lcchain"
#: What a watched run (a foreign netlist) may print on stdout and stderr before it is stopped.
MAX_LOG_BYTES = 16 * 2**20
#: Seconds between two looks at a running child whose memory or output is watched: ngspice grows by tens of MB a
#: second at most, so a child is stopped within a few MB of its limit.
WATCH_INTERVAL = 0.1
#: Seconds between two looks at a running batch run, when there is something to look at (a progress callback,
#: a raw-file limit); its exit is seen at once.
PROGRESS_INTERVAL = 0.5


def child_env() -> dict[str, str]:
    # A copy: HOME -> nowhere hides any ~/.spiceinit; an ASCII raw file request would break the reader.
    env = dict(os.environ)
    env["HOME"] = CHILD_HOME
    env.pop("SPICE_ASCIIRAWFILE", None)
    return env


def kill_group(proc: subprocess.Popen[bytes]) -> None:
    try:
        os.killpg(proc.pid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):
        pass
    proc.wait()


def resident_bytes(pid: int, leaves: bool = True) -> int:
    """The resident memory of a process and of all its descendants, bytes (what ``/proc`` says; 0 where it says
    nothing).  A child runs under setpriv and bubblewrap, so the simulator is a grandchild of ``pid``.
    ``leaves=False``: of those that have children only (the launcher and the sandbox above a worker)."""
    page = os.sysconf("SC_PAGE_SIZE")
    total = 0
    todo = [pid]
    seen: set[int] = set()
    while todo:
        current = todo.pop()
        if current in seen:
            continue
        seen.add(current)
        try:
            with open(f"/proc/{current}/statm", "rb") as statm:
                own = int(statm.read().split()[1]) * page
        except (OSError, ValueError, IndexError):  # gone meanwhile, or not Linux
            continue
        found: list[int] = []
        try:
            for task in os.listdir(f"/proc/{current}/task"):
                with open(f"/proc/{current}/task/{task}/children", "rb") as children:
                    found += [int(child) for child in children.read().split()]
        except (OSError, ValueError):  # gone meanwhile: its memory counted, the children read so far walked
            pass
        total += own if leaves or found else 0
        todo += found
    return total


def outgrown(pid: int, who: str, *, printed: Sequence[IO[bytes]] = (), output: IO[bytes] | None = None,
             output_name: str = "raw file", max_output_bytes: float | None = None,
             max_resident_bytes: float | None = None) -> str | None:
    """Why a running child must be stopped, or None: what it ``printed`` (files) past :data:`MAX_LOG_BYTES` (when
    it is watched at all: a limit is given), its ``output`` file past ``max_output_bytes``, or the resident memory of
    its process tree past ``max_resident_bytes``.  ``who`` names it in the reason (``"ngspice"``)."""
    if max_output_bytes is not None and output is not None and os.fstat(output.fileno()).st_size > max_output_bytes:
        return (f"{who}'s {output_name} grew past {show_bytes(max_output_bytes)}, the most this run may write (its "
                "price, within --max-memory), and the run was stopped")
    if (max_output_bytes is not None or max_resident_bytes is not None) and \
            sum(os.fstat(f.fileno()).st_size for f in printed) > MAX_LOG_BYTES:
        return f"{who} printed more than {show_bytes(MAX_LOG_BYTES)} and the run was stopped"
    if max_resident_bytes is not None:
        resident = resident_bytes(pid)
        if resident > max_resident_bytes:
            return (f"{who}'s memory grew past {show_bytes(max_resident_bytes)} resident ({show_bytes(resident)}), "
                    "the most this run may hold (its price, within --max-memory), and the run was stopped")
    return None


def read_all(handle: IO[bytes]) -> bytes:
    handle.seek(0)
    return handle.read()


def exited(proc: subprocess.Popen[bytes], pidfd: int | None, seconds: float) -> int | None:
    """A child's exit status as soon as it exits within ``seconds``, else None.

    A pidfd (Linux) wakes this the moment the child exits; Popen.wait with a timeout would sleep-poll it
    (1, 3, 7 ... 50 ms late), a delay that every short run paid in full.
    """
    if pidfd is None:
        try:
            return proc.wait(timeout=seconds)
        except subprocess.TimeoutExpired:
            return None
    ready, _, _ = select.select([pidfd], [], [], seconds)
    return proc.wait() if ready else None


def wait_watching(proc: subprocess.Popen[bytes], timeout: float, look: Callable[[], None] | None,
                  interval: float = PROGRESS_INTERVAL) -> int | None:
    """A child's exit status, or None after ``timeout`` seconds; ``look`` (which may raise to stop the run) is
    called every ``interval`` seconds while it runs, and without it the wait sleeps to the exit at once."""
    deadline = time.monotonic() + timeout
    try:
        pidfd: int | None = os.pidfd_open(proc.pid)
    except (AttributeError, OSError):  # not Linux, or an old kernel
        pidfd = None
    try:
        while True:
            left = deadline - time.monotonic()
            if left <= 0:
                return None
            status = exited(proc, pidfd, min(interval, left) if look is not None else left)
            if status is not None:
                return status
            if look is not None:
                look()
    finally:
        if pidfd is not None:
            with contextlib.suppress(OSError):
                os.close(pidfd)


def progress_reporter(progress: Callable[[float], None], tstop: float,
                      simulated: Callable[[], float | None]) -> Callable[[], None]:
    """A look that reports the fraction of ``tstop`` simulated so far (never going back)."""
    fraction = 0.0

    def report() -> None:
        nonlocal fraction
        t = simulated()
        fraction = max(fraction, min(max(t / tstop, 0.0), 1.0)) if t is not None else fraction
        progress(fraction)

    return report

