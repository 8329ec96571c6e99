"""Child-process entry point of the ``"shared"`` backend (private).

Run as ``python -m lcchain.spice.ngspice.shared_worker`` by :mod:`lcchain.spice.ngspice.runner`
(under ``setpriv --pdeathsig KILL`` where available, in a session of its own,
with ``HOME`` pointing nowhere). It reads one JSON request
``{"netlist": str, "library": str}`` from stdin, runs the netlist once in the
ngspice shared library through PySpice's low-level ``NgSpiceShared`` and
writes one ``.npz`` to stdout: ``meta`` (UTF-8 JSON as uint8: ``names``,
``version``, ``wall_s``, ``errors``, ``complex``, ``lines``: the SHA-256 of
the lines handed to ``ngSpice_Circ``, split at LF alone as the allow-list split
them) and ``v0``, ``v1``, ...
(float64 vectors in the order of ``names``, ngspice's own plot names such as
``l1#branch``, ``n3``, ``time``).  Validation happens in the parent,
identically for both backends.  A request without ``"netlist"`` only reports
the library's version.

ngspice's output is written to stderr line by line as it comes (the parent
keeps it in a file, so it survives a kill on timeout); anything printed to
file descriptor 1 is redirected to stderr too, so the npz stream stays clean. PySpice is imported only
here; its "Unsupported Ngspice version" warning (a log record, emitted for
every ngspice newer than PySpice 1.5 knows) is the only thing silenced.
"""

from __future__ import annotations

import io
import json
import logging
import os
import sys
import time
from typing import TYPE_CHECKING, TypedDict

from lcchain.spice.text import circuit_lines, text_digest

if TYPE_CHECKING:
    import numpy as np


class WorkerRequest(TypedDict, total=False):
    """What the parent sends, as JSON: the library's path, and the netlist (without it: the version only)."""

    library: str
    netlist: str


class WorkerMeta(TypedDict, total=False):
    """What the worker answers, as JSON beside its arrays: the version (alone, for a version request), and for a
    run the vectors' names in the arrays' order, ngspice's wall seconds, its errors, whether the plot held complex
    vectors (not read), and the digest of the lines ngspice was given."""

    version: str
    names: list[str]
    wall_s: float
    errors: list[str]
    complex: bool
    lines: str


class _PySpiceLog(logging.Handler):
    """Passes PySpice's own log records to stderr, minus echoes of ngspice output."""

    def emit(self, record: logging.LogRecord) -> None:
        message = record.getMessage()
        # _send_char re-logs every ngspice stderr line, which the recorder already wrote.
        if record.funcName == "_send_char" or "Unsupported Ngspice version" in message:
            return
        _echo(f"PySpice {record.levelname.lower()}: {message}")


def _echo(line: str) -> None:
    # Written at once so that the parent keeps the output even when it kills us on timeout.
    stream = sys.__stderr__
    assert stream is not None  # the parent always gives the child a stderr
    stream.write(line + "\n")
    stream.flush()


def simulate(netlist: str, library: str) -> tuple[WorkerMeta, list[np.ndarray]]:
    """Run a netlist once in the ngspice shared library.

    ngspice's output goes to stderr line by line as it comes.

    Parameters
    ----------
    netlist : str
        Netlist text (already checked by the parent).
    library : str
        Path of ``libngspice.so.0``.

    Returns
    -------
    meta : dict
        JSON-serialisable run description (see the module docstring).
    arrays : list of numpy.ndarray
        The vectors of the last transient plot, in the order of ``meta["names"]``.
    """
    import numpy as np

    errors: list[str] = []
    pyspice_logger = logging.getLogger("PySpice")
    pyspice_logger.addHandler(_PySpiceLog(level=logging.WARNING))
    pyspice_logger.propagate = False

    from PySpice.Spice.NgSpice.Shared import NgSpiceShared, ffi

    class Recorder(NgSpiceShared):  # type: ignore[misc]  # PySpice is untyped (NgSpiceShared is Any)
        """NgSpiceShared that echoes every line ngspice prints."""

        def send_char(self, message: str, ngspice_id: int) -> int:
            _, _, content = message.partition(" ")
            if not content.startswith("**"):  # the banner of PySpice's "version -f"
                _echo(content)
            return 0

    Recorder.LIBRARY_PATH = library
    ng = Recorder.new_instance()
    version = str(ng.ngspice_version)

    given = circuit_lines(netlist)  # split at LF alone, as the allow-list split it (PySpice's load splits more)

    def load() -> None:
        # PySpice's load_circuit, less its str.splitlines: the lines handed to ngSpice_Circ are ``given``.
        keep = [ffi.new("char[]", line.encode("utf-8")) for line in given] + [ffi.NULL]
        ng.clear_output()
        status = ng._ngspice_shared.ngSpice_Circ(ffi.new("char *[]", keep))
        if status:
            raise NameError(f"ngSpice_Circ returned {status}")

    start = time.perf_counter()
    for step, action in (("load", load), ("run", ng.run)):
        try:
            action()
        except Exception as exc:  # noqa: BLE001
            if type(exc) is NameError:  # PySpice's report of a non-zero ngspice return code
                errors.append(f"{step}: {exc}")
                break
            # NgSpiceCircuitError/NgSpiceCommandError flag any stderr line; the parent validates the output.
            _echo(f"PySpice {step}: {type(exc).__name__}: {exc}")
    wall = time.perf_counter() - start

    names: list[str] = []
    arrays: list[np.ndarray] = []
    is_complex = False
    plot = next((name for name in ng.plot_names if name.startswith("tran")), None)
    if plot is not None and not errors:
        library_handle = ng._ngspice_shared  # PySpice exposes the raw API only here
        for name in NgSpiceShared._convert_string_array(library_handle.ngSpice_AllVecs(plot.encode("utf-8"))):
            info = library_handle.ngGet_Vec_Info(f"{plot}.{name}".encode())
            if info.v_compdata != ffi.NULL:
                is_complex = True
                continue
            buffer = ffi.buffer(info.v_realdata, info.v_length * 8)
            names.append(name)
            arrays.append(np.frombuffer(buffer, dtype=np.float64).copy())

    for command in ("destroy all", "remcirc"):
        try:
            ng.exec_command(command)
        except Exception as exc:  # noqa: BLE001 - cleanup must not hide the result
            _echo(f"PySpice {command}: {type(exc).__name__}: {exc}")

    meta: WorkerMeta = {"names": names, "version": version, "wall_s": wall, "errors": errors,
                        "complex": is_complex, "lines": text_digest(given)}
    return meta, arrays


def version(library: str) -> str:
    """ngspice's version as the shared library reports it (the library is loaded, nothing runs)."""
    from PySpice.Spice.NgSpice.Shared import NgSpiceShared

    logging.getLogger("PySpice").addHandler(_PySpiceLog(level=logging.WARNING))
    logging.getLogger("PySpice").propagate = False
    NgSpiceShared.LIBRARY_PATH = library
    return str(NgSpiceShared.new_instance().ngspice_version)


def main() -> int:
    """Read a request from stdin, simulate (or only report the version), write the npz to stdout.

    A request without ``"netlist"`` asks for the library's version only.
    """
    import numpy as np

    request: WorkerRequest = json.loads(sys.stdin.buffer.read().decode("utf-8"))
    protocol = os.fdopen(os.dup(1), "wb")
    os.dup2(2, 1)
    sys.stdout = sys.stderr
    if "netlist" not in request:
        meta: WorkerMeta = {"version": version(request["library"])}
        arrays: list[np.ndarray] = []
    else:
        meta, arrays = simulate(request["netlist"], request["library"])
    buffer = io.BytesIO()
    payload = {f"v{i}": array for i, array in enumerate(arrays)}
    np.savez(buffer, meta=np.frombuffer(json.dumps(meta).encode("utf-8"), dtype=np.uint8), **payload)  # type: ignore[arg-type]
    protocol.write(buffer.getvalue())
    protocol.flush()
    return 0


if __name__ == "__main__":
    sys.exit(main())
