"""Where ngspice is on this machine and what version: the executable, the shared library and PySpice.

:func:`find_batch` and :func:`find_shared` locate ngspice for a transport (its ``find`` in
:data:`lcchain.spice.ngspice.transports.TRANSPORT_RUNS`), ask its version once and return a frozen, picklable
:class:`Simulator` (:func:`lcchain.spice.ngspice.find.find_simulator` chooses the transport).
"""

from __future__ import annotations

import importlib.util
import os
import re
import shutil
import subprocess
import sys
import threading
from pathlib import Path

from ...core.errors import ExtraMissingError, SimulatorMissingError
from ..log import useful_output
from ..sandbox import Sandbox, find_sandbox
from ..simulator import Simulator
from .shared_child import call_shared_worker, decode_worker_payload

__all__ = [
    "find_batch",
    "find_shared",
    "find_ngspice",
    "find_shared_library",
    "ngspice_version",
    "INSTALL_COMMAND",
    "PYSPICE_INSTALL_COMMAND",
    "shared_library_version",
    "require_pyspice",
]

#: How to install ngspice and its shared library on Debian/Ubuntu.
INSTALL_COMMAND = "sudo apt-get install ngspice libngspice0"
#: How to install what the shared backend needs from PyPI (PySpice is an optional extra).
PYSPICE_INSTALL_COMMAND = "pip install 'lcchain[shared]'"

_VERSION = re.compile(r"ngspice-(\d+(?:\.\d+)*)", re.IGNORECASE)



def find_ngspice() -> str:
    """Path of the ngspice executable.

    Raises
    ------
    SimulatorMissingError
        If ngspice is not on ``PATH``; the message says how to install it.
    """
    path = shutil.which("ngspice")
    if path is None:
        raise SimulatorMissingError(f"the ngspice executable is not on PATH; install it with: {INSTALL_COMMAND}")
    return path


def ngspice_version(executable: str | None = None) -> str:
    """Version of an ngspice executable (``ngspice -v``), e.g. ``"39"``.

    Raises
    ------
    SimulatorMissingError
        If ngspice is missing or does not report a version.
    """
    exe = executable or find_ngspice()
    try:
        proc = subprocess.run([exe, "-v"], capture_output=True, text=True, timeout=30, stdin=subprocess.DEVNULL)
    except (OSError, subprocess.TimeoutExpired) as exc:
        raise SimulatorMissingError(f"cannot run {exe} -v: {exc}; install ngspice with: {INSTALL_COMMAND}") from exc
    match = _VERSION.search(proc.stdout + proc.stderr)
    if match is None:
        output = (proc.stdout + proc.stderr)[:200]
        raise SimulatorMissingError(f"{exe} -v did not report an ngspice version: {output!r}")
    return match.group(1)


def find_shared_library() -> str:
    """Path of the ngspice shared library.

    Looks at ``$NGSPICE_LIBRARY_PATH`` (read, never written), the usual
    library directories (Debian installs ``/usr/lib/<triplet>/libngspice.so.0``
    without the unversioned ``.so`` unless ``libngspice0-dev`` is installed),
    then ``ctypes.util.find_library("ngspice")``.

    Raises
    ------
    SimulatorMissingError
        If no library is found, or ``$NGSPICE_LIBRARY_PATH`` names no readable
        file; the message says how to fix it.
    """
    explicit = os.environ.get("NGSPICE_LIBRARY_PATH")
    if explicit:
        if not (Path(explicit).is_file() and os.access(explicit, os.R_OK)):
            raise SimulatorMissingError(
                f"NGSPICE_LIBRARY_PATH = {explicit!r} is not a readable file; unset it, or point it at "
                f"libngspice.so.0 (install with: {INSTALL_COMMAND})")
        return explicit
    # /usr/lib/<triplet> after /usr/lib64, before /usr/lib; each folder's exact names asked of the file system first
    # (Debian's libngspice.so.0: the triplet's folder, thousands of names, is not listed), then its other versions
    triplets = sorted(name for name in _names("/usr/lib") or () if "-linux-gnu" in name)
    folders = [os.path.join(sys.prefix, "lib"), "/usr/local/lib", "/usr/lib64",
               *(f"/usr/lib/{name}" for name in triplets), "/usr/lib", "/opt/homebrew/lib"]
    for folder in folders:
        for name in (_SHARED_NAMES[0], _SHARED_NAMES[1]):
            if os.path.isfile(os.path.join(folder, name)):
                return os.path.join(folder, name)
        if not os.path.isdir(folder):
            continue
        names = _names(folder)
        versions = sorted(name for name in names if name.startswith(_SHARED_NAMES[2])) if names is not None else \
            sorted(path.name for path in Path(folder).glob(_SHARED_NAMES[2] + "*"))  # searched, not listed (711)
        for name in (*versions, _SHARED_NAMES[3]):
            if os.path.isfile(os.path.join(folder, name)):
                return os.path.join(folder, name)
    import ctypes.util  # only needed for this fallback

    library = ctypes.util.find_library("ngspice")
    if library:
        return library
    raise SimulatorMissingError(
        f"the ngspice shared library (libngspice.so.0) was not found; install it with: {INSTALL_COMMAND}"
    )




#: The shared library's names, in the order each folder is searched: ``libngspice.so``, ``libngspice.so.0``, any
#: other ``libngspice.so.*`` (sorted), ``libngspice.dylib``.
_SHARED_NAMES = ("libngspice.so", "libngspice.so.0", "libngspice.so.", "libngspice.dylib")


def _names(folder: str) -> list[str] | None:
    """The names in ``folder``, or None when it cannot be listed (missing, not a folder, or searched only)."""
    try:
        return os.listdir(folder)
    except OSError:
        return None


def require_pyspice() -> None:
    """Raise :class:`~lcchain.core.errors.ExtraMissingError` unless PySpice is installed (without importing it)."""
    if importlib.util.find_spec("PySpice") is None:
        raise ExtraMissingError("PySpice", "shared", "the shared backend")


def find_batch(launcher: tuple[str, ...]) -> Simulator:
    exe = find_ngspice()
    sandbox: list[Sandbox] = []  # the sandbox's trial run beside ngspice -v: two processes waited for at once
    trial = threading.Thread(target=lambda: sandbox.append(find_sandbox()), name="lcchain-sandbox-trial")
    trial.start()
    try:
        version = ngspice_version(exe)
    finally:
        trial.join()
    return Simulator("batch", exe, version, launcher, sandbox[0] if sandbox else find_sandbox())


def find_shared(launcher: tuple[str, ...]) -> Simulator:
    library = find_shared_library()
    require_pyspice()
    return Simulator("shared", library, shared_library_version(library, launcher), launcher, find_sandbox())


def shared_library_version(library: str, launcher: tuple[str, ...] = ()) -> str:
    """ngspice's version as the shared library reports it (loads it once, in a child)."""
    stdout, log, status = call_shared_worker(launcher, {"library": library}, 120.0, "/", "version")
    try:
        meta, _ = decode_worker_payload(stdout)
    except Exception as exc:  # noqa: BLE001 - a crashed child leaves empty or partial bytes
        raise SimulatorMissingError(f"the ngspice shared library {library} could not be loaded (exit status "
                                    f"{status}: {exc}); {useful_output(log) or 'no output'}") from None
    return str(meta["version"])
