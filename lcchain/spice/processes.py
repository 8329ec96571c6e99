"""Child processes: started in a session of their own, killed as a group, dead with lcchain."""

from __future__ import annotations

import io
import json
import os
import signal
import subprocess
import sys
import tempfile
import time
from collections.abc import Sequence
from pathlib import Path
from typing import IO, Any

import numpy as np

from ..core.budget import show_bytes
from ..core.errors import SimulationError
from .log import useful_output

__all__ = ["PACKAGE_ROOT", "CHILD_HOME", "child_env", "kill_group", "read_all", "call_shared_worker",
           "decode_worker_payload", "resident_bytes", "outgrown", "MAX_LOG_BYTES", "WATCH_INTERVAL"]

#: The folder lcchain is imported from: the shared-library child imports it there.
PACKAGE_ROOT = str(Path(__file__).resolve().parents[2])
#: HOME of every ngspice child: a folder that does not exist, so no ~/.spiceinit is read.
CHILD_HOME = "/nonexistent/lcchain"
#: What a watched run (a foreign netlist) may print on stdout and stderr before it is stopped.
MAX_LOG_BYTES = 16 * 2**20
#: Seconds between two looks at a running child whose memory or output is watched: ngspice grows by tens of MB a
#: second at most, so a child is stopped within a few MB of its limit.
WATCH_INTERVAL = 0.1


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


def resident_bytes(pid: int) -> int:
    """The resident memory of a process and of all its descendants, bytes (what ``/proc`` says; 0 where it says
    nothing).  A child runs under setpriv and bubblewrap, so the simulator is a grandchild of ``pid``."""
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
                total += int(statm.read().split()[1]) * page
            for task in os.listdir(f"/proc/{current}/task"):
                with open(f"/proc/{current}/task/{task}/children", "rb") as children:
                    todo += [int(child) for child in children.read().split()]
        except (OSError, ValueError, IndexError):  # gone meanwhile, or not Linux
            continue
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


def call_shared_worker(launcher: tuple[str, ...], request: dict[str, Any], timeout: float, cwd: str,
                       what: str, env: dict[str, str] | None = None, max_output_bytes: float | None = None,
                       max_resident_bytes: float | None = None) -> tuple[bytes, str, int]:
    """Start the shared-library child, send it a request, return (stdout, stderr text, exit status).

    ``launcher`` prefixes its command line (setpriv, a sandbox); ``env`` is its environment (default
    :func:`child_env`), to which the package's folder is added on ``PYTHONPATH``.  While it runs it is watched as
    :func:`outgrown` says (its reply, the vectors, against ``max_output_bytes``; its memory against
    ``max_resident_bytes``), every :data:`WATCH_INTERVAL` seconds when a limit is given.
    """
    env = dict(env) if env is not None else child_env()
    env["PYTHONPATH"] = os.pathsep.join(p for p in (PACKAGE_ROOT, env.get("PYTHONPATH")) if p)
    watched = max_output_bytes is not None or max_resident_bytes is not None
    with tempfile.TemporaryFile() as source, tempfile.TemporaryFile() as out, tempfile.TemporaryFile() as err:
        source.write(json.dumps(request).encode("utf-8"))
        source.seek(0)
        # Files, not pipes: a child is never blocked on a full pipe while it is watched, and its output survives a kill.
        proc = subprocess.Popen([*launcher, sys.executable, "-P", "-m", "lcchain.spice.shared_worker"], cwd=cwd,
                                env=env, stdin=source, stdout=out, stderr=err, start_new_session=True)
        deadline = time.monotonic() + timeout
        try:
            while True:
                left = deadline - time.monotonic()
                if left <= 0:
                    kill_group(proc)
                    log = read_all(err).decode("utf-8", "replace")
                    raise SimulationError(f"the ngspice shared-library child ({what}) timed out after {timeout:g} s "
                                          "and was killed", useful_output(log), "timeout")
                try:
                    proc.wait(min(WATCH_INTERVAL, left) if watched else left)
                    break
                except subprocess.TimeoutExpired:
                    pass
                why = outgrown(proc.pid, "ngspice's shared-library child", printed=(err,), output=out,
                               output_name="vectors", max_output_bytes=max_output_bytes,
                               max_resident_bytes=max_resident_bytes)
                if why is not None:
                    kill_group(proc)
                    raise SimulationError(why, useful_output(read_all(err).decode("utf-8", "replace")))
        finally:
            if proc.poll() is None:  # interrupted: the whole group goes
                kill_group(proc)
        return read_all(out), read_all(err).decode("utf-8", "replace"), proc.returncode


def decode_worker_payload(payload: bytes) -> tuple[dict[str, Any], list[np.ndarray]]:
    with np.load(io.BytesIO(payload), allow_pickle=False) as npz:
        meta = json.loads(npz["meta"].tobytes().decode("utf-8"))
        arrays = [npz[f"v{i}"] for i in range(len(meta.get("names", [])))]
    return meta, arrays
