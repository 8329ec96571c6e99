"""Child processes: started in a session of their own, killed as a group, dead with lcchain."""

from __future__ import annotations

import io
import json
import os
import signal
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import IO, Any

import numpy as np

from ..core.errors import SimulationError
from .log import useful_output

__all__ = ["PACKAGE_ROOT", "CHILD_HOME", "child_env", "kill_group", "read_all", "call_shared_worker",
           "decode_worker_payload"]

#: The folder lcchain is imported from: the shared-library child imports it there.
PACKAGE_ROOT = str(Path(__file__).resolve().parents[2])
#: HOME of every ngspice child: a folder that does not exist, so no ~/.spiceinit is read.
CHILD_HOME = "/nonexistent/lcchain"


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


def read_all(handle: IO[bytes]) -> bytes:
    handle.seek(0)
    return handle.read()


def call_shared_worker(launcher: tuple[str, ...], request: dict[str, Any], timeout: float, cwd: str,
                       what: str, env: dict[str, str] | None = None) -> tuple[bytes, str, int]:
    """Start the shared-library child, send it a request, return (stdout, stderr text, exit status).

    ``launcher`` prefixes its command line (setpriv, a sandbox); ``env`` is its environment (default
    :func:`child_env`), to which the package's folder is added on ``PYTHONPATH``.
    """
    env = dict(env) if env is not None else child_env()
    env["PYTHONPATH"] = os.pathsep.join(p for p in (PACKAGE_ROOT, env.get("PYTHONPATH")) if p)
    payload = json.dumps(request).encode("utf-8")
    with tempfile.TemporaryFile() as err, subprocess.Popen(
            [*launcher, sys.executable, "-P", "-m", "lcchain.spice.shared_worker"], cwd=cwd, env=env,
            stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=err, start_new_session=True) as proc:
        try:
            stdout, _ = proc.communicate(payload, timeout=timeout)
        except subprocess.TimeoutExpired:
            kill_group(proc)
            log = read_all(err).decode("utf-8", "replace")
            raise SimulationError(f"the ngspice shared-library child ({what}) timed out after {timeout:g} s "
                                  "and was killed", useful_output(log), "timeout") from None
        finally:
            if proc.poll() is None:  # interrupted: the whole group goes
                kill_group(proc)
        return stdout, read_all(err).decode("utf-8", "replace"), proc.returncode


def decode_worker_payload(payload: bytes) -> tuple[dict[str, Any], list[np.ndarray]]:
    with np.load(io.BytesIO(payload), allow_pickle=False) as npz:
        meta = json.loads(npz["meta"].tobytes().decode("utf-8"))
        arrays = [npz[f"v{i}"] for i in range(len(meta.get("names", [])))]
    return meta, arrays
