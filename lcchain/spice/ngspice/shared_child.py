"""The shared-library child of ngspice's ``"shared"`` transport, seen from lcchain: start it, send it a request,
read its reply (``python -m lcchain.spice.ngspice.shared_worker``).

Separate from :mod:`~lcchain.spice.ngspice.shared` because finding the transport
(:func:`lcchain.spice.simulator.shared_library_version`) asks the same child for its version.
"""

from __future__ import annotations

import io
import json
import os
import subprocess
import sys
import tempfile
import time
from typing import TYPE_CHECKING

from ...core.errors import SimulationError
from ..log import useful_output
from ..processes import PACKAGE_ROOT, WATCH_INTERVAL, child_env, kill_group, outgrown, read_all

if TYPE_CHECKING:  # the worker's module is the child's: the parent names its messages' types only
    import numpy as np

    from .shared_worker import WorkerMeta, WorkerRequest

__all__ = ["call_shared_worker", "decode_worker_payload"]


def call_shared_worker(launcher: tuple[str, ...], request: WorkerRequest, timeout: float, cwd: str,
                       what: str, env: dict[str, str] | None = None, max_output_bytes: float | None = None,
                       max_resident_bytes: float | None = None) -> tuple[bytes, str, int]:
    """Start the shared-library child, send it a request, return (stdout, stderr text, exit status).

    ``launcher`` prefixes its command line (setpriv, a sandbox); ``env`` is its environment (default
    :func:`~lcchain.spice.processes.child_env`), to which the package's folder is added on ``PYTHONPATH``.
    While it runs it is watched as :func:`~lcchain.spice.processes.outgrown` says (its reply, the vectors,
    against ``max_output_bytes``; its memory against ``max_resident_bytes``), every
    :data:`~lcchain.spice.processes.WATCH_INTERVAL` seconds when a limit is given.
    """
    env = dict(env) if env is not None else child_env()
    env["PYTHONPATH"] = os.pathsep.join(p for p in (PACKAGE_ROOT, env.get("PYTHONPATH")) if p)
    watched = max_output_bytes is not None or max_resident_bytes is not None
    with tempfile.TemporaryFile() as source, tempfile.TemporaryFile() as out, tempfile.TemporaryFile() as err:
        source.write(json.dumps(request).encode("utf-8"))
        source.seek(0)
        # Files, not pipes: a child is never blocked on a full pipe while it is watched, and its output survives a kill.
        proc = subprocess.Popen([*launcher, sys.executable, "-P", "-m", "lcchain.spice.ngspice.shared_worker"], cwd=cwd,
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


def decode_worker_payload(payload: bytes) -> tuple[WorkerMeta, list[np.ndarray]]:
    import numpy as np

    with np.load(io.BytesIO(payload), allow_pickle=False) as npz:
        meta: WorkerMeta = json.loads(npz["meta"].tobytes().decode("utf-8"))
        arrays = [npz[f"v{i}"] for i in range(len(meta.get("names", [])))]
    return meta, arrays
