"""Child-process entry point of the ``"warm"`` transport (private): ngspice's shared library, loaded once.

Run as ``python -P -m lcchain.spice.ngspice.warm_worker LIBRARY`` by
:mod:`lcchain.spice.ngspice.warm` (under ``setpriv --pdeathsig KILL``, in a session of
its own, with ``HOME`` pointing nowhere, and in the sandbox for netlists lcchain
did not write).  It loads ``libngspice.so.0`` through :mod:`ctypes` (no PySpice,
no numpy: it starts in tens of milliseconds) and then serves one netlist after
the other, so that a run of a small circuit costs what ngspice computes, not
what a new process costs to start.

Protocol, on file descriptors 0 (requests) and 1 (replies); each frame is an
8-byte little-endian length and that many bytes:

* first, unasked, a JSON hello: ``{"version": "39"}`` (``"error"`` instead
  when the library does not load);
* per request (UTF-8 netlist text, already checked by the parent, split at
  LF alone by :func:`lcchain.spice.text.circuit_lines`, as the check split
  it): a JSON header ``{"names", "lengths", "complex", "errors", "wall_s",
  "rss", "exit", "lines"}`` frame (``lines``: the SHA-256 of the lines
  handed to ``ngSpice_Circ``, which the parent compares with the text it
  checked), then one frame of the vectors' float64 values (native
  byte order), concatenated in the order of ``names``.

What ngspice prints goes to stderr (a file of the parent's) line by line as it
comes, so that the parent can watch its size while the run goes and keeps it
if the run is killed.

After each run the circuit and its plots are destroyed (``destroy all``,
``remcirc``), so nothing of a run but memory the library keeps survives it;
``rss`` (bytes) lets the parent recycle a worker whose memory grew.  When
ngspice asks to exit (its controlled exit after a fatal error) the reply says
so and the worker exits: the library cannot be trusted after it.  Anything
the library prints on file descriptor 1 goes to stderr, so the frames stay clean.
"""

from __future__ import annotations

import ctypes
import os
import struct
import sys
import time

#: The worker's hello comes before anything it does not need for it: no ``typing`` (its frames' types are the type
#: checker's alone), no ``json`` (which loads ``re``, ``enum`` and more), and :mod:`lcchain.spice.text` (hashlib
#: and OpenSSL): those load after the hello, while the parent is still planning (tests/test_imports.py holds this).
TYPE_CHECKING = False
if TYPE_CHECKING:
    from typing import BinaryIO, TypedDict

    class Hello(TypedDict, total=False):
        """The worker's first frame, as JSON: the library's version, or why it could not be loaded."""

        version: str
        error: str

    class RunHeader(TypedDict):
        """The frame before a run's vectors, as JSON: their names and lengths (float64 values, in this order),
        whether the plot held complex vectors (not sent), ngspice's errors and wall seconds, the worker's resident
        bytes, ngspice's exit status when it asked to exit (else None), and the digest of the lines it was given."""

        names: list[str]
        lengths: list[int]
        complex: bool
        errors: list[str]
        wall_s: float
        rss: int
        exit: int | None
        lines: str


_HEADER = struct.Struct("<Q")


class _VectorInfo(ctypes.Structure):
    _fields_ = [("v_name", ctypes.c_char_p), ("v_type", ctypes.c_int), ("v_flags", ctypes.c_short),
                ("v_realdata", ctypes.POINTER(ctypes.c_double)), ("v_compdata", ctypes.c_void_p),
                ("v_length", ctypes.c_int)]


_SendChar = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.c_char_p, ctypes.c_int, ctypes.c_void_p)
_SendStat = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.c_char_p, ctypes.c_int, ctypes.c_void_p)
_Exit = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.c_int, ctypes.c_bool, ctypes.c_bool, ctypes.c_int, ctypes.c_void_p)
_SendData = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.c_void_p, ctypes.c_int, ctypes.c_int, ctypes.c_void_p)
_SendInit = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.c_void_p, ctypes.c_int, ctypes.c_void_p)
_Running = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.c_bool, ctypes.c_int, ctypes.c_void_p)


class Library:
    """libngspice, initialised once; ``run`` loads and runs one netlist and frees it again."""

    def __init__(self, path: str) -> None:
        self.printed: list[str] | None = None  # a list while the version is asked: lines kept, not written
        self.exit_status: int | None = None
        lib = ctypes.CDLL(path)
        lib.ngSpice_Init.argtypes = [_SendChar, _SendStat, _Exit, _SendData, _SendInit, _Running, ctypes.c_void_p]
        lib.ngSpice_Command.argtypes = [ctypes.c_char_p]
        lib.ngSpice_Circ.argtypes = [ctypes.POINTER(ctypes.c_char_p)]
        lib.ngSpice_CurPlot.restype = ctypes.c_char_p
        lib.ngSpice_AllVecs.argtypes = [ctypes.c_char_p]
        lib.ngSpice_AllVecs.restype = ctypes.POINTER(ctypes.c_char_p)
        lib.ngGet_Vec_Info.argtypes = [ctypes.c_char_p]
        lib.ngGet_Vec_Info.restype = ctypes.POINTER(_VectorInfo)
        self.lib = lib
        # The callbacks must outlive the library's use of them: kept on the instance.
        self._callbacks = (_SendChar(self._print), _SendStat(lambda *_: 0), _Exit(self._exit), _SendData(),
                           _SendInit(), _Running())
        lib.ngSpice_Init(*self._callbacks, None)

    def _print(self, text: bytes | None, ident: int, user: object) -> int:
        line = (text or b"").decode("utf-8", "replace")
        line = line.partition(" ")[2] if line.startswith(("stdout ", "stderr ")) else line
        if self.printed is not None:
            self.printed.append(line)
        else:
            os.write(2, (line + "\n").encode("utf-8", "replace"))
        return 0

    def _exit(self, status: int, unload: bool, quit_: bool, ident: int, user: object) -> int:
        self.exit_status = status
        return 0

    def command(self, text: str) -> int:
        return int(self.lib.ngSpice_Command(text.encode("utf-8")))

    def version(self) -> str:
        self.printed = []
        self.command("version")
        version = _version_in("\n".join(self.printed))
        self.printed = None
        if not version:
            raise RuntimeError("the library did not report an ngspice version")
        return version

    def run(self, netlist: str) -> tuple[RunHeader, bytes]:
        from lcchain.spice.text import circuit_lines, text_digest  # loaded after the hello (main)

        errors: list[str] = []
        try:
            given = circuit_lines(netlist)  # split at LF alone, as the allow-list split it
        except ValueError as error:  # not canonical: nothing of it reaches the library
            return {"names": [], "lengths": [], "complex": False, "errors": [str(error)], "wall_s": 0.0,
                    "rss": _rss(), "exit": None, "lines": ""}, b""
        lines = [line.encode("utf-8") for line in given]
        array = (ctypes.c_char_p * (len(lines) + 1))(*lines, None)
        start = time.perf_counter()
        if self.lib.ngSpice_Circ(array) != 0:
            errors.append("the circuit was not loaded")
        elif self.exit_status is None and self.command("run") != 0:
            errors.append("the run command failed")
        wall = time.perf_counter() - start
        names: list[str] = []
        lengths: list[int] = []
        chunks: list[bytes] = []
        is_complex = False
        plot = self.lib.ngSpice_CurPlot() if self.exit_status is None else None
        if plot and plot.startswith(b"tran") and not errors:
            vectors = self.lib.ngSpice_AllVecs(plot)
            index = 0
            while vectors[index]:
                name = vectors[index]
                index += 1
                info = self.lib.ngGet_Vec_Info(plot + b"." + name)
                if not info or info.contents.v_compdata:
                    is_complex = is_complex or bool(info and info.contents.v_compdata)
                    continue
                length = info.contents.v_length
                names.append(name.decode("utf-8", "replace"))
                lengths.append(length)
                chunks.append(ctypes.string_at(info.contents.v_realdata, 8 * length) if length else b"")
        if self.exit_status is None:
            for command in ("destroy all", "remcirc"):
                self.command(command)
        header: RunHeader = {"names": names, "lengths": lengths, "complex": is_complex, "errors": errors,
                             "wall_s": wall, "rss": _rss(), "exit": self.exit_status, "lines": text_digest(given)}
        return header, b"".join(chunks)


def _hello(version: str) -> bytes:
    """The hello frame's JSON, ``{"version": "39"}``, written without the json module when the version is plain
    (digits, letters and ``.+-_``, as ngspice's are), by ``json.dumps`` otherwise."""
    if version.isascii() and version.replace(".", "").replace("+", "").replace("-", "").replace("_", "").isalnum():
        return b'{"version": "' + version.encode("ascii") + b'"}'
    import json

    hello: Hello = {"version": version}
    return json.dumps(hello).encode("utf-8")


def _version_in(printed: str) -> str:
    """The version in what ``version`` printed: the word after the first ``ngspice-`` that a digit follows
    ("" when there is none)."""
    for piece in printed.split("ngspice-")[1:]:
        if piece[:1] in tuple("0123456789"):
            return piece.split(None, 1)[0]
    return ""


def _rss() -> int:
    try:
        with open("/proc/self/statm", "rb") as statm:
            return int(statm.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")
    except (OSError, ValueError, IndexError):  # pragma: no cover - not Linux
        return 0


def _read_exact(stream: BinaryIO, size: int) -> bytes | None:
    """``size`` bytes, or None at the end of the stream (a pipe returns what it has: read until complete)."""
    parts: list[bytes] = []
    while size:
        part = stream.read(size)
        if not part:
            return None
        parts.append(part)
        size -= len(part)
    return b"".join(parts)


def _read_frame(stream: BinaryIO) -> bytes | None:
    head = _read_exact(stream, _HEADER.size)
    if head is None:
        return None
    return _read_exact(stream, _HEADER.unpack(head)[0])


def _write_frame(stream: BinaryIO, data: bytes) -> None:
    stream.write(_HEADER.pack(len(data)))
    stream.write(data)


def main(argv: list[str]) -> int:
    """Serve netlists until stdin closes (or ngspice asks to exit)."""
    requests = os.fdopen(0, "rb", buffering=0)
    replies = os.fdopen(os.dup(1), "wb")
    os.dup2(2, 1)  # what the library prints on stdout must not reach the frames
    sys.stdout = sys.stderr
    try:
        library = Library(argv[1])
        version = library.version()
    except (OSError, RuntimeError, IndexError) as error:
        import json

        refused: Hello = {"error": str(error)}
        _write_frame(replies, json.dumps(refused).encode("utf-8"))
        replies.flush()
        return 1
    _write_frame(replies, _hello(version))
    replies.flush()
    # loaded after the hello, while the parent plans: the headers' JSON, each run's line split and digest
    import json

    import lcchain.spice.text  # noqa: F401

    while (request := _read_frame(requests)) is not None:
        header, data = library.run(request.decode("utf-8"))
        _write_frame(replies, json.dumps(header).encode("utf-8"))
        _write_frame(replies, data)
        replies.flush()
        del header, data  # not held while waiting: what the worker said of its memory is what it holds
        if library.exit_status is not None:
            return 3
    return 0


if __name__ == "__main__":
    status = main(sys.argv)
    sys.stderr.flush()
    # Every reply is flushed and nothing else is owed: no interpreter shutdown, no library destructors (a worker
    # that ends with its batch then exits in a few milliseconds, not tens).
    os._exit(status)
