"""Reading a file a user names: a regular file, within its size limit, as UTF-8 text, or a clear refusal.

A FIFO would block the read forever, a device (``/dev/zero``) would never end,
and a folder is not text: each is refused naming the option before a byte is
read.  The file is opened without blocking (``O_NONBLOCK``: opening a FIFO
with no writer would wait) and checked on the descriptor it was opened as
(``fstat``), so a file swapped after the check is never read; then at most
``max_bytes`` + 1 bytes are read.
"""

from __future__ import annotations

import os
import stat

from ..core.budget import show_bytes
from ..core.errors import ParameterError

__all__ = ["read_input", "open_input", "file_kind", "shown_name"]


def file_kind(mode: int) -> str:
    """A file's kind in words, for a message ("a folder", "a FIFO", ...), from its ``st_mode``."""
    for test, name in ((stat.S_ISDIR, "a folder"), (stat.S_ISFIFO, "a FIFO"), (stat.S_ISCHR, "a character device"),
                       (stat.S_ISBLK, "a block device"), (stat.S_ISSOCK, "a socket")):
        if test(mode):
            return name
    return "not a regular file"


def open_input(path: str | os.PathLike[str], option: str, max_bytes: int) -> int:
    """A descriptor of the regular file at ``path``, opened without blocking and checked on that descriptor: the
    refusals of :func:`read_input` (unreadable, not a regular file, larger than ``max_bytes``), before a byte is
    read.  The caller closes it."""
    name = str(path)
    try:
        fd = os.open(name, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0))
    except OSError as error:
        raise ParameterError(option, name, f"a readable file ({error.strerror})") from None
    except ValueError:  # a NUL byte, which no file's name holds (a list read from `find -print0`, say)
        raise ParameterError(option, name, "the name of a file (a name holds no NUL byte)") from None
    try:
        info = os.fstat(fd)
        if not stat.S_ISREG(info.st_mode):
            raise ParameterError(option, name, f"a regular file (this is {file_kind(info.st_mode)})")
        if info.st_size > max_bytes:
            raise ParameterError(option, name, f"a file of at most {show_bytes(max_bytes)} (this one has "
                                 f"{show_bytes(info.st_size)})")
    except OSError as error:
        os.close(fd)
        raise ParameterError(option, name, f"a readable file ({error.strerror})") from None
    except BaseException:
        os.close(fd)
        raise
    return fd


def shown_name(name: str) -> str:
    """A file's name as lcchain shows and stores it: ``name`` itself when it is printable UTF-8; else each byte of it
    that is no UTF-8 (a name the system gave as bytes, Latin-1 say) as ``\\xNN`` and each character that is not
    printable (a newline, an escape) as Python escapes it, so that it stays on one line of a message, in a store's
    text and on any terminal.  The file itself is opened by its own name."""
    if name.isprintable():
        try:
            name.encode("utf-8")
        except UnicodeEncodeError:
            pass
        else:
            return name
    try:
        text = name.encode("utf-8", "surrogateescape").decode("utf-8", "backslashreplace")
    except UnicodeEncodeError:  # a surrogate no byte was decoded to
        text = name.encode("utf-8", "backslashreplace").decode("utf-8")
    return "".join(c if c.isprintable() else repr(c)[1:-1] for c in text)


def read_input(path: str | os.PathLike[str], option: str, max_bytes: int) -> str:
    """The UTF-8 text of the regular file at ``path``.

    Parameters
    ----------
    path : path-like
        The file.
    option : str
        What named it (``"--chain"``, ``"NETLIST"``, ``"x.cir: line 3"``), for messages.
    max_bytes : int
        The largest file read.

    Raises
    ------
    ParameterError
        Naming ``option`` and the path: missing or unreadable, not a regular
        file (a folder, a FIFO, a device, a socket), larger than ``max_bytes``,
        or not UTF-8.
    """
    name = str(path)
    fd = open_input(path, option, max_bytes)
    try:
        chunks: list[bytes] = []
        size = 0
        while size <= max_bytes:
            chunk = os.read(fd, min(1 << 20, max_bytes + 1 - size))
            if not chunk:
                break
            chunks.append(chunk)
            size += len(chunk)
    except OSError as error:
        raise ParameterError(option, name, f"a readable file ({error.strerror})") from None
    finally:
        os.close(fd)
    if size > max_bytes:  # it grew while being read
        raise ParameterError(option, name, f"a file of at most {show_bytes(max_bytes)}")
    data = b"".join(chunks)
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as error:  # strict: overlong forms, surrogates and UTF-16 are refused too
        line = data.count(b"\n", 0, error.start) + 1
        raise ParameterError(option, name, f"UTF-8 text ({error.reason}: byte {data[error.start]:#04x} at byte "
                             f"{error.start}, line {line})") from None

