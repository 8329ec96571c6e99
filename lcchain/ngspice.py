"""The one module that talks to ngspice.

Two backends run a netlist and return the same :class:`RunResult`:

``"batch"`` (default)
    ``ngspice -b -r out.raw circuit.cir`` as a subprocess, in a fresh
    temporary directory that is also its ``HOME`` (so no user ``~/.spiceinit``
    can change the result); the binary raw file is read with numpy.
``"shared"``
    The ngspice shared library (``libngspice.so.0``) through PySpice's
    low-level ``NgSpiceShared``, in a child process
    (``python -m lcchain._shared_worker``) that is killed on timeout and
    exits after one run, so no simulator state survives between runs.
    PySpice is imported only in that child: ``import lcchain`` never loads it.

Both backends give bit-identical waveforms for the same netlist (tested).

Vector names
------------
The caller names vectors as the netlist ``.save``\\ s them; ngspice 39
accepts both ``.save i(l1)`` and ``.save l1#branch`` for an inductor current
and ``.save v(n3)`` (or ``n3``) for a node voltage. The raw file calls them
``i(l1)`` and ``v(n3)``, the shared library's plot ``l1#branch`` and ``n3``.
lcchain normalises every name, requested or found, to the raw-file form in
lower case (SPICE names are case-insensitive):

====================  ==============
written               key in result
====================  ==============
``i(L1)``             ``"i(l1)"``
``l1#branch``         ``"i(l1)"``
``v(N3)``, ``n3``     ``"v(n3)"``
====================  ==============

Other names (``@l1[i]``, ``v(a,b)``) are only lower-cased. The time vector is
``RunResult.time``, never a key of ``RunResult.vectors``.

Validation
----------
ngspice often exits 0 after an error, so every run is checked: exit status 0
(batch), no fatal line in ngspice's output (``Error...``, ``can't find
model``, ``singular matrix``, ``Timestep too small``, ``circuit not parsed``,
``simulation(s) aborted``), more than zero points, last time point equal to
``tstop`` (relative 1e-9), every requested vector present, all values finite.
A failure raises :class:`~lcchain.errors.SimulationError` whose message holds
the useful part of ngspice's output and the path of a kept directory
(``tempfile.mkdtemp(prefix="lcchain-failed-")``) with the netlist, ngspice's
stdout/stderr and the reason. Beware: ngspice 39 silently accepts an inductor
or capacitor line without a value (it uses a default) and a missing node;
only the netlist generator can prevent those.

Safety
------
A netlist with a ``.control``/``.endc`` line or a line starting with
``shell`` raises :class:`~lcchain.errors.ParameterError` (field
``"netlist"``) before anything runs: ngspice executes shell commands from
control blocks in batch mode and in the shared library alike.
"""

from __future__ import annotations

import hashlib
import json
import math
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType

import numpy as np

from .errors import ParameterError, SimulationError, SimulatorMissingError
from .types import BACKENDS, Backend

__all__ = [
    "Check",
    "RunResult",
    "canonical_vector_name",
    "doctor",
    "find_ngspice",
    "find_shared_library",
    "ngspice_version",
    "parse_options",
    "read_raw",
    "run",
]

#: How to install what this module needs on Debian/Ubuntu.
INSTALL_COMMAND = "sudo apt-get install ngspice libngspice0"
#: Relative tolerance on the last time point versus the requested ``tstop``.
TSTOP_RTOL = 1e-9
#: At most this many characters of ngspice's output are kept in ``RunResult.log``.
LOG_MAX_CHARS = 8000
#: At most this many lines of ngspice's output are quoted in an error message.
ERROR_MAX_LINES = 30

#: Seconds between progress reports of a batch run (when a progress callback is given).
PROGRESS_INTERVAL = 0.5
# Only complete lines (ngspice ends each with "\r"): a number cut by a partial write must not count.
_REFERENCE_VALUE = re.compile(r"Reference value\s*:\s*([-+0-9.eE]+)[ \t]*[\r\n]")
_NETLIST_FILE = "circuit.cir"
_RAW_FILE = "out.raw"
_STDOUT_FILE = "ngspice.stdout.txt"
_STDERR_FILE = "ngspice.stderr.txt"

# Lines of ngspice output that mean the run failed even when it exits 0.
_FATAL = re.compile(
    r"^\s*error\b|can't find model|could not find a valid modelname|singular matrix"
    r"|timestep too small|circuit not parsed|simulation\(s\) aborted|simulation interrupted",
    re.IGNORECASE,
)
# Resource-usage chatter ngspice prints after every batch run.
_BOILERPLATE = re.compile(
    r"^\s*(DRAM|Total DRAM|Maximum ngspice|Current ngspice|Shared ngspice|Text \(code\)"
    r"|Stack =|Library pages|Total elapsed|Note: No compatibility mode)",
    re.IGNORECASE,
)
_FORBIDDEN = re.compile(r"^\s*(\.control\b|\.endc\b|shell\b)", re.IGNORECASE)
_VERSION = re.compile(r"ngspice-(\d+(?:\.\d+)*)", re.IGNORECASE)
_OPTIONS_LINE = re.compile(r"^\s*\.opt(ion|ions)?\b(.*)$", re.IGNORECASE)


# --------------------------------------------------------------------------- results


@dataclass(frozen=True, eq=False)
class RunResult:
    """Waveforms and metadata of one ngspice transient run.

    Attributes
    ----------
    time : numpy.ndarray
        Time points in seconds (read-only), ending at ``tstop``.
    vectors : Mapping[str, numpy.ndarray]
        Requested vectors (read-only arrays, amperes or volts) keyed by their
        normalised name (see the module docstring), e.g. ``"i(l1)"``.
    ngspice_version : str
        ngspice version, e.g. ``"39"``.
    netlist_sha256 : str
        SHA-256 (hex) of the netlist text encoded as UTF-8.
    options : Mapping[str, str]
        The ``.options`` the netlist sets (see :func:`parse_options`).
    wall_s : float
        Wall time of the simulator run in seconds: the ``ngspice -b``
        process for ``"batch"``, loading and running the circuit inside the
        child process for ``"shared"`` (child start-up excluded).
    backend : str
        ``"batch"`` or ``"shared"``.
    points : int
        Number of time points.
    log : str
        ngspice's output without blank lines and resource chatter, trimmed to
        :data:`LOG_MAX_CHARS` characters.
    """

    time: np.ndarray
    vectors: Mapping[str, np.ndarray]
    ngspice_version: str
    netlist_sha256: str
    options: Mapping[str, str]
    wall_s: float
    backend: str
    points: int
    log: str = field(repr=False)

    def metadata(self) -> dict[str, object]:
        """Everything but the arrays, as a JSON-serialisable dict.

        Returns
        -------
        dict
            Keys ``ngspice_version``, ``netlist_sha256``, ``options``,
            ``wall_s``, ``backend``, ``points``, ``vectors`` (the names),
            ``t_end`` (last time point, s) and ``log``.
        """
        return {
            "ngspice_version": self.ngspice_version,
            "netlist_sha256": self.netlist_sha256,
            "options": dict(self.options),
            "wall_s": float(self.wall_s),
            "backend": self.backend,
            "points": int(self.points),
            "vectors": list(self.vectors),
            "t_end": float(self.time[-1]),
            "log": self.log,
        }


@dataclass(frozen=True)
class Check:
    """One line of :func:`doctor`'s report.

    Attributes
    ----------
    name : str
        What was checked.
    ok : bool
        Whether it works.
    detail : str
        What was found (a version, a path, an error).
    fix : str
        How to fix it; empty when ``ok``.
    """

    name: str
    ok: bool
    detail: str
    fix: str = ""


# --------------------------------------------------------------------------- netlist helpers


def canonical_vector_name(name: str) -> str:
    """Normalise an ngspice vector name to lcchain's key convention.

    Parameters
    ----------
    name : str
        ``i(l1)``, ``l1#branch``, ``v(n3)``, ``n3``, ... in any case.

    Returns
    -------
    str
        ``"i(l1)"`` for a branch current, ``"v(n3)"`` for a node voltage,
        ``"time"`` for time, otherwise the lower-cased name.
    """
    text = name.strip().lower()
    if text.endswith("#branch"):
        return f"i({text[: -len('#branch')]})"
    if text == "time" or "(" in text or "@" in text or "#" in text or "[" in text:
        return text
    return f"v({text})"


def parse_options(netlist: str) -> dict[str, str]:
    """The ``.options`` a netlist sets, read from its text.

    Parameters
    ----------
    netlist : str
        Netlist text. ``.option``, ``.options`` and ``.opt`` lines count, with
        ``+`` continuation lines; later settings override earlier ones.

    Returns
    -------
    dict[str, str]
        Lower-cased option name -> value as written (``"1e-6"``, ``"trap"``);
        a bare flag such as ``noinit`` maps to ``"true"``.
    """
    options: dict[str, str] = {}
    for line in _logical_lines(netlist):
        match = _OPTIONS_LINE.match(line)
        if not match:
            continue
        body = re.sub(r"\s*=\s*", "=", match.group(2).strip())
        for token in body.split():
            key, sep, value = token.partition("=")
            options[key.lower()] = value if sep else "true"
    return options


def _logical_lines(netlist: str) -> list[str]:
    lines: list[str] = []
    for raw in netlist.splitlines():
        if raw.startswith("+") and lines:
            lines[-1] += " " + raw[1:]
        else:
            lines.append(raw)
    return lines


def _refuse_unsafe(netlist: str) -> None:
    for line in netlist.splitlines():
        if _FORBIDDEN.match(line):
            raise ParameterError(
                "netlist",
                line.strip(),
                "a netlist without .control/.endc blocks or shell lines "
                "(ngspice would execute them)",
            )


def _check_arguments(netlist: str, vectors: Sequence[str], tstop: float, backend: str, timeout: float) -> list[str]:
    if not isinstance(netlist, str) or not netlist.strip():
        raise ParameterError("netlist", netlist, "non-empty netlist text")
    if backend not in BACKENDS:
        raise ParameterError("backend", backend, f"one of {', '.join(BACKENDS)}")
    if not (isinstance(tstop, (int, float)) and math.isfinite(tstop) and tstop > 0):
        raise ParameterError("tstop", tstop, "a finite time > 0 in seconds")
    if not (isinstance(timeout, (int, float)) and timeout > 0):
        raise ParameterError("timeout", timeout, "a time > 0 in seconds")
    if isinstance(vectors, str):
        raise ParameterError("vectors", vectors, "a sequence of vector names, not one string")
    names: list[str] = []
    for name in vectors:
        if not isinstance(name, str) or not name.strip() or re.search(r"\s", name.strip()):
            raise ParameterError("vectors", name, "an ngspice vector name such as 'i(l1)' or 'v(n3)'")
        key = canonical_vector_name(name)
        if key == "time":
            continue
        if key not in names:
            names.append(key)
    _refuse_unsafe(netlist)
    return names


# --------------------------------------------------------------------------- locating ngspice


def find_ngspice() -> str:
    """Path of the ngspice executable.

    Returns
    -------
    str
        Absolute path found on ``PATH``.

    Raises
    ------
    SimulatorMissingError
        If ngspice is not installed; the message says how to install it.
    """
    path = shutil.which("ngspice")
    if path is None:
        raise SimulatorMissingError(f"the ngspice executable is not on PATH; install it with: {INSTALL_COMMAND}")
    return path


def ngspice_version(executable: str | None = None) -> str:
    """Version of an ngspice executable.

    Parameters
    ----------
    executable : str, optional
        Path of ngspice; found with :func:`find_ngspice` when omitted.

    Returns
    -------
    str
        The version number, e.g. ``"39"``.

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

    Returns
    -------
    str
        A path (or, from ``find_library`` only, a soname ``dlopen`` resolves).

    Raises
    ------
    SimulatorMissingError
        If no library is found; the message says how to install it.
    """
    explicit = os.environ.get("NGSPICE_LIBRARY_PATH")
    if explicit and "{" not in explicit and Path(explicit).is_file():
        return explicit
    dirs = [Path(sys.prefix) / "lib", Path("/usr/local/lib"), Path("/usr/lib64"), Path("/usr/lib"),
            Path("/opt/homebrew/lib")]
    dirs[3:3] = sorted(Path("/usr/lib").glob("*-linux-gnu*"))
    for directory in dirs:
        for pattern in ("libngspice.so", "libngspice.so.0", "libngspice.so.*", "libngspice.dylib"):
            hits = sorted(p for p in directory.glob(pattern) if p.is_file())
            if hits:
                return str(hits[0])
    import ctypes.util  # only needed for this fallback

    name = ctypes.util.find_library("ngspice")
    if name:
        return name
    raise SimulatorMissingError(
        f"the ngspice shared library (libngspice.so.0) was not found; install it with: {INSTALL_COMMAND}"
    )


# --------------------------------------------------------------------------- running


def run(
    netlist: str,
    vectors: Sequence[str],
    tstop: float,
    *,
    backend: Backend = "batch",
    timeout: float = 600.0,
    progress: Callable[[float], None] | None = None,
) -> RunResult:
    """Run a transient netlist in ngspice and return validated waveforms.

    Parameters
    ----------
    netlist : str
        Complete netlist text with one ``.tran`` analysis ending at ``tstop``
        and ``.save`` lines for the wanted vectors. ``.control`` blocks and
        ``shell`` lines are refused.
    vectors : Sequence[str]
        Vector names as saved, e.g. ``["i(l1)", "v(n3)"]`` or ``["l1#branch"]``.
    tstop : float
        End time of the ``.tran`` analysis in seconds; the last time point
        must equal it.
    backend : {"batch", "shared"}
        ``ngspice -b`` subprocess or the shared library in a child process.
    timeout : float
        Seconds after which the simulator process is killed.
    progress : callable, optional
        Called with the fraction of ``tstop`` simulated: 0.0 before, then
        (batch backend) about every :data:`PROGRESS_INTERVAL` seconds from
        ngspice's ``Reference value`` lines, and 1.0 after a successful run.

    Returns
    -------
    RunResult
        Time, the requested vectors (keys normalised, see the module
        docstring) and run metadata.

    Raises
    ------
    ParameterError
        Bad arguments, or an unsafe netlist (``.control``, ``shell``).
    SimulatorMissingError
        ngspice (or its shared library) is not installed.
    SimulationError
        ngspice failed, timed out, or its output failed validation.
    """
    names = _check_arguments(netlist, vectors, tstop, backend, timeout)
    if progress is not None:
        progress(0.0)
    workdir = tempfile.mkdtemp(prefix="lcchain-run-")
    try:
        Path(workdir, _NETLIST_FILE).write_text(netlist, encoding="utf-8")
        if backend == "batch":
            raw = _run_batch(workdir, timeout, float(tstop), progress)
        else:
            raw = _run_shared(workdir, netlist, timeout)
        try:
            time_s, found = _validate(raw, names, float(tstop))
        except SimulationError as exc:
            _fail(workdir, str(exc), raw["log"])
    finally:
        shutil.rmtree(workdir, ignore_errors=True)
    if progress is not None:
        progress(1.0)
    return RunResult(
        time=time_s,
        vectors=MappingProxyType(found),
        ngspice_version=raw["version"],
        netlist_sha256=hashlib.sha256(netlist.encode("utf-8")).hexdigest(),
        options=MappingProxyType(parse_options(netlist)),
        wall_s=raw["wall_s"],
        backend=backend,
        points=int(time_s.size),
        log=_trim_log(raw["log"]),
    )


def _child_env(workdir: str) -> dict[str, str]:
    # A copy: HOME -> workdir hides any ~/.spiceinit; an ASCII raw file request would break the reader.
    env = dict(os.environ)
    env["HOME"] = workdir
    env.pop("SPICE_ASCIIRAWFILE", None)
    return env


def _kill_group(proc: subprocess.Popen) -> None:
    try:
        os.killpg(proc.pid, signal.SIGKILL)
    except ProcessLookupError:
        pass
    proc.wait()


def _simulated_time(err_path: Path) -> float | None:
    """The last ``Reference value : t`` ngspice wrote to stderr (its progress, in seconds)."""
    try:
        with open(err_path, "rb") as f:
            f.seek(0, os.SEEK_END)
            f.seek(max(0, f.tell() - 256))
            tail = f.read().decode("ascii", "replace")
    except OSError:
        return None
    found = _REFERENCE_VALUE.findall(tail)
    return float(found[-1]) if found else None


def _wait(proc: subprocess.Popen, timeout: float, tstop: float, err_path: Path,
          progress: Callable[[float], None] | None) -> int | None:
    """Exit status of ngspice, or None after the timeout; reports progress meanwhile."""
    deadline = time.monotonic() + timeout
    while True:
        left = deadline - time.monotonic()
        try:
            return proc.wait(timeout=max(0.0, min(PROGRESS_INTERVAL, left)) if progress else max(0.0, left))
        except subprocess.TimeoutExpired:
            if time.monotonic() >= deadline:
                return None
            t = _simulated_time(err_path)
            if t is not None and progress is not None:
                progress(min(max(t / tstop, 0.0), 1.0))


def _run_batch(workdir: str, timeout: float, tstop: float,
               progress: Callable[[float], None] | None = None) -> dict:
    exe = find_ngspice()
    version = ngspice_version(exe)
    out_path, err_path = Path(workdir, _STDOUT_FILE), Path(workdir, _STDERR_FILE)
    with open(out_path, "wb") as out, open(err_path, "wb") as err:
        start = time.perf_counter()
        with subprocess.Popen(
            [exe, "-b", "-r", _RAW_FILE, _NETLIST_FILE],
            cwd=workdir, env=_child_env(workdir), stdin=subprocess.DEVNULL, stdout=out, stderr=err,
            start_new_session=True,
        ) as proc:
            status = _wait(proc, timeout, tstop, err_path, progress)
            if status is None:
                _kill_group(proc)
        wall = time.perf_counter() - start
    log = _read_logs(workdir)
    if status is None:
        _fail(workdir, f"ngspice timed out after {timeout:g} s and was killed", log)
    if status != 0:
        _fail(workdir, _failure_reason(log, f"ngspice exited with status {status}"), log)
    raw_path = Path(workdir, _RAW_FILE)
    if not raw_path.is_file():
        _fail(workdir, "ngspice wrote no raw file", log)
    try:
        columns = read_raw(raw_path)
    except SimulationError as exc:
        _fail(workdir, str(exc), log)
    return {"columns": columns, "log": log, "version": version, "wall_s": wall}


def _run_shared(workdir: str, netlist: str, timeout: float) -> dict:
    library = find_shared_library()
    env = _child_env(workdir)
    package_root = str(Path(__file__).resolve().parent.parent)
    env["PYTHONPATH"] = os.pathsep.join(p for p in (package_root, env.get("PYTHONPATH")) if p)
    request = json.dumps({"netlist": netlist, "library": library}).encode("utf-8")
    err_path = Path(workdir, _STDERR_FILE)
    with open(err_path, "wb") as err:
        with subprocess.Popen(
            [sys.executable, "-P", "-m", "lcchain._shared_worker"],
            cwd=workdir, env=env, stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=err,
            start_new_session=True,
        ) as proc:
            try:
                payload, _ = proc.communicate(request, timeout=timeout)
            except subprocess.TimeoutExpired:
                _kill_group(proc)
                payload = None
    if payload is None:
        _fail(workdir, f"the ngspice shared-library child timed out after {timeout:g} s and was killed",
              _read_logs(workdir))
    try:
        meta, arrays = _decode_worker_payload(payload)
    except Exception as exc:  # noqa: BLE001 - a crashed child leaves empty or partial bytes
        _fail(workdir, f"the shared-library child (exit status {proc.returncode}) returned no result ({exc})",
              _read_logs(workdir))
    log = _read_logs(workdir)
    if meta["errors"]:
        _fail(workdir, _failure_reason(log, "the ngspice shared library failed: " + "; ".join(meta["errors"])), log)
    if proc.returncode != 0:
        _fail(workdir, _failure_reason(log, f"the shared-library child exited with status {proc.returncode}"), log)
    if meta["complex"]:
        _fail(workdir, "the transient plot holds complex vectors; lcchain reads real data only", log)
    columns = {canonical_vector_name(name): arr for name, arr in zip(meta["names"], arrays)}
    return {"columns": columns, "log": log, "version": meta["version"], "wall_s": meta["wall_s"]}


def _decode_worker_payload(payload: bytes) -> tuple[dict, list[np.ndarray]]:
    import io

    with np.load(io.BytesIO(payload), allow_pickle=False) as npz:
        meta = json.loads(npz["meta"].tobytes().decode("utf-8"))
        arrays = [npz[f"v{i}"] for i in range(len(meta["names"]))]
    return meta, arrays


def _read_logs(workdir: str) -> str:
    parts = []
    for name in (_STDOUT_FILE, _STDERR_FILE):
        path = Path(workdir, name)
        if path.is_file():
            parts.append(path.read_text(encoding="utf-8", errors="replace"))
    return "\n".join(parts)


def _fatal_lines(log: str) -> list[str]:
    return list(dict.fromkeys(line.strip() for line in log.splitlines() if _FATAL.search(line)))


def _failure_reason(log: str, fallback: str) -> str:
    fatal = _fatal_lines(log)
    return "ngspice reported an error: " + " | ".join(fatal) if fatal else fallback


def _validate(raw: dict, names: list[str], tstop: float) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    if _fatal_lines(raw["log"]):
        raise SimulationError(_failure_reason(raw["log"], ""))
    columns = raw["columns"]
    if "time" not in columns:
        raise SimulationError("ngspice returned no time vector (is there a .tran analysis?)")
    time_s = columns["time"]
    if time_s.size == 0:
        raise SimulationError("ngspice returned zero time points")
    if not math.isclose(float(time_s[-1]), tstop, rel_tol=TSTOP_RTOL, abs_tol=0.0):
        raise SimulationError(f"the last time point is {float(time_s[-1])!r} s, not tstop = {tstop!r} s")
    missing = [name for name in names if name not in columns]
    if missing:
        available = ", ".join(sorted(k for k in columns if k != "time")) or "none"
        raise SimulationError(
            f"requested vector(s) {', '.join(missing)} not in ngspice's output (saved: {available}); "
            "add them to the netlist's .save line"
        )
    found: dict[str, np.ndarray] = {}
    for name in ["time", *names]:
        arr = np.ascontiguousarray(columns[name], dtype=np.float64)
        if arr.shape != time_s.shape:
            raise SimulationError(f"vector {name} has {arr.size} points, time has {time_s.size}")
        if not np.all(np.isfinite(arr)):
            raise SimulationError(f"vector {name} holds non-finite values")
        arr.flags.writeable = False
        found[name] = arr
    return found.pop("time"), found


def _fail(workdir: str, reason: str, log: str) -> None:
    """Keep the run's files in a new directory and raise SimulationError."""
    kept = tempfile.mkdtemp(prefix="lcchain-failed-")
    for name in (_NETLIST_FILE, _STDOUT_FILE, _STDERR_FILE):
        source = Path(workdir, name)
        if source.is_file():
            shutil.copyfile(source, Path(kept, name))
    Path(kept, "reason.txt").write_text(reason + "\n", encoding="utf-8")
    useful = _useful_output(log)
    quoted = f"\nngspice said:\n{useful}" if useful else "\nngspice printed nothing useful"
    raise SimulationError(f"{reason}{quoted}\nnetlist and ngspice output kept in {kept}")


def _clean_lines(log: str) -> list[str]:
    lines: list[str] = []
    for line in log.splitlines():
        text = line.rstrip()
        if not text.strip() or _BOILERPLATE.match(text):
            continue
        if lines and lines[-1] == text:  # ngspice repeats e.g. "singular matrix" many times
            continue
        if lines and text.lstrip().startswith("Reference value") and lines[-1].lstrip().startswith("Reference value"):
            lines[-1] = text  # progress lines: the last one says how far the run got
            continue
        lines.append(text)
    return lines


def _useful_output(log: str) -> str:
    lines = _clean_lines(log)
    if len(lines) > ERROR_MAX_LINES:
        fatal = [i for i, line in enumerate(lines) if _FATAL.search(line)]
        start = max(0, (fatal[0] if fatal else len(lines)) - 5)
        start = min(start, len(lines) - ERROR_MAX_LINES)
        lines = ["..."] * (start > 0) + lines[start : start + ERROR_MAX_LINES] + ["..."] * (
            start + ERROR_MAX_LINES < len(lines)
        )
    return "\n".join(lines)


def _trim_log(log: str) -> str:
    text = "\n".join(_clean_lines(log))
    if len(text) > LOG_MAX_CHARS:
        half = LOG_MAX_CHARS // 2
        text = text[:half] + "\n...\n" + text[-half:]
    return text


# --------------------------------------------------------------------------- raw file


def read_raw(path: str | os.PathLike[str]) -> dict[str, np.ndarray]:
    """Read the transient plot of an ngspice binary raw file.

    Parameters
    ----------
    path : path-like
        Raw file written by ``ngspice -b -r``.

    Returns
    -------
    dict[str, numpy.ndarray]
        Normalised vector name (``"time"``, ``"i(l1)"``, ``"v(n3)"``) ->
        read-only float64 column. When the file holds several plots, the
        last transient one is returned.

    Raises
    ------
    SimulationError
        Not a binary real raw file, truncated, or without a transient plot.
    """
    data = Path(path).read_bytes()
    offset = 0
    chosen: dict[str, np.ndarray] | None = None
    while offset < len(data):
        header_end = data.find(b"Binary:\n", offset)
        if header_end < 0:
            if b"Values:" in data[offset:]:
                raise SimulationError("the raw file is ASCII; lcchain reads binary raw files only")
            raise SimulationError("the raw file has no 'Binary:' section")
        header = data[offset:header_end].decode("latin-1")
        plotname, flags, nvars, npoints, names = _parse_raw_header(header)
        if "complex" in flags:
            raise SimulationError(f"the raw plot {plotname!r} is complex; lcchain reads real data only")
        start = header_end + len(b"Binary:\n")
        nbytes = nvars * npoints * 8
        if start + nbytes > len(data):
            raise SimulationError(
                f"the raw file is truncated: {npoints} points x {nvars} variables announced, "
                f"{(len(data) - start) // 8} values present"
            )
        block = np.frombuffer(data, dtype=np.float64, count=nvars * npoints, offset=start).reshape(npoints, nvars)
        if plotname.lower().startswith("transient"):
            chosen = {canonical_vector_name(name): block[:, i] for i, name in enumerate(names)}
        offset = start + nbytes
    if chosen is None:
        raise SimulationError("the raw file holds no transient analysis")
    return chosen


def _parse_raw_header(header: str) -> tuple[str, str, int, int, list[str]]:
    fields: dict[str, str] = {}
    names: list[str] = []
    in_variables = False
    for line in header.splitlines():
        if in_variables and line[:1] in ("\t", " ") and line.strip():
            parts = line.split()
            names.append(parts[1])
            continue
        key, sep, value = line.partition(":")
        if sep:
            fields[key.strip().lower()] = value.strip()
            in_variables = key.strip().lower() == "variables"
    try:
        nvars = int(fields["no. variables"])
        npoints = int(fields["no. points"])
    except (KeyError, ValueError) as exc:
        raise SimulationError(f"unreadable raw file header ({exc})") from exc
    if len(names) != nvars:
        raise SimulationError(f"raw file header lists {len(names)} variables, announces {nvars}")
    return fields.get("plotname", ""), fields.get("flags", "").lower(), nvars, npoints, names


# --------------------------------------------------------------------------- doctor

_DOCTOR_NETLIST = """\
* lcchain doctor: one LC loop, i(l1) = cos(t)
L1 n0 n1 1.0 IC=1.0
C1 n1 0 1.0
V0 n0 0 0
.options method=trap reltol=1e-6
.tran 0.001 1.0 0 0.001 uic
.save i(l1)
.end
"""
#: Tolerance of the doctor's check i(l1)(t=1 s) = cos(1) for the unit LC loop.
_DOCTOR_ATOL = 1e-4


def _doctor_run(backend: Backend) -> str:
    result = run(_DOCTOR_NETLIST, ["i(l1)"], 1.0, backend=backend, timeout=60.0)
    error = abs(float(result.vectors["i(l1)"][-1]) - math.cos(1.0))
    if error > _DOCTOR_ATOL:
        raise SimulationError(f"i(l1)(1 s) differs from cos(1) by {error:.3g}")
    return f"{result.points} points in {result.wall_s:.3f} s, |i - cos t| = {error:.1e}"


def doctor() -> list[Check]:
    """Check that ngspice, its shared library and PySpice work here.

    Never raises: every failure becomes a :class:`Check` with ``ok=False``
    that says what is missing and how to fix it.

    Returns
    -------
    list[Check]
        ngspice executable, batch run, shared library, PySpice, shared run.
    """
    checks: list[Check] = []

    def attempt(name: str, fix: str, action: Callable[[], str]) -> bool:
        try:
            detail = action()
        except Exception as exc:  # noqa: BLE001 - the doctor reports, never raises
            checks.append(Check(name, False, f"{type(exc).__name__}: {exc}", fix))
            return False
        checks.append(Check(name, True, detail, ""))
        return True

    have_exe = attempt("ngspice executable", f"install ngspice: {INSTALL_COMMAND}",
                       lambda: f"{find_ngspice()} (ngspice {ngspice_version()})")
    if have_exe:
        attempt("batch run", "run `ngspice -b` on the netlist in the kept directory to see why it fails",
                lambda: _doctor_run("batch"))
    else:
        checks.append(
            Check("batch run", False, "skipped: no ngspice executable", f"install ngspice: {INSTALL_COMMAND}")
        )
    have_lib = attempt("ngspice shared library", f"install the library: {INSTALL_COMMAND}", find_shared_library)
    have_pyspice = attempt("PySpice", "pip install 'PySpice>=1.5'", _pyspice_version)
    if have_lib and have_pyspice:
        attempt("shared run", "see the error; try `python -m lcchain._shared_worker` by hand",
                lambda: _doctor_run("shared"))
    else:
        checks.append(Check("shared run", False, "skipped: shared library or PySpice missing",
                            f"{INSTALL_COMMAND}; pip install 'PySpice>=1.5'"))
    return checks


def _pyspice_version() -> str:
    # Imported in a child so that lcchain itself never loads PySpice.
    proc = subprocess.run(
        [sys.executable, "-c", "import PySpice.Spice.NgSpice.Shared, PySpice; print(PySpice.__version__)"],
        capture_output=True, text=True, timeout=120, stdin=subprocess.DEVNULL,
    )
    if proc.returncode != 0:
        raise ImportError(proc.stderr.strip().splitlines()[-1] if proc.stderr.strip() else "import failed")
    return f"PySpice {proc.stdout.strip()}"

