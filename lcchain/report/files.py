"""Output files: checked before any work, written whole or not at all, under the name the user gave.

* :func:`check_output` runs before a simulation starts: the folder exists and
  is a folder, a file can really be created in it (a probe file is made and
  removed: ``os.access`` says yes to root for ``/proc``), the path is not a
  folder itself, and a figure's name ends in a format matplotlib writes, so
  that the file lands exactly where the user said (matplotlib would append
  ``.png`` to ``/dev/full`` and write ``/dev/full.png``).
* :func:`write_text` and :func:`save_figure` write to a hidden temporary name
  in the same folder and rename it over the target, so an interrupted or
  failed write never leaves half a file.
"""

from __future__ import annotations

import contextlib
import os
import stat
import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import Any

from ..core.errors import ParameterError

__all__ = ["FIGURE_FORMATS", "check_output", "check_output_folder", "write_text", "save_figure", "atomic_path"]

#: Figure formats matplotlib writes from a file name's ending.
FIGURE_FORMATS = ("png", "svg", "pdf", "eps", "ps", "jpg", "jpeg", "tif", "tiff", "webp")


def _probe(option: str, text: str, folder: Path, wanted: str) -> None:
    """Refuse a folder where no file can really be created (a probe file is made and removed)."""
    try:
        with tempfile.NamedTemporaryFile(dir=folder, prefix=".lcchain-probe-"):
            pass
    except OSError as error:
        raise ParameterError(option, text, f"{wanted} ({folder}: {error.strerror or error})") from None


def check_output(option: str, path: str | os.PathLike[str], formats: tuple[str, ...] | None = None) -> Path:
    """Refuse, before any work, an output path that could not be written under its own name.

    Parameters
    ----------
    option : str
        The option or key that named the file (``"--plot"``, ``"output.report"``).
    path : path-like
        The file to write.
    formats : tuple of str, optional
        Endings the file must have (lower case, no dot); None: any name.

    Returns
    -------
    Path
    """
    target = Path(path)
    text = os.fspath(path)
    if not text or text.endswith(os.sep) or target.is_dir():
        raise ParameterError(option, text, "a file name, not a folder")
    if formats is not None:
        ending = target.suffix.lower().lstrip(".")
        if ending not in formats:
            raise ParameterError(option, text, f"a file name ending in .{', .'.join(formats)} (the format is "
                                 "taken from the name; any other name would be changed)")
    folder = target.parent
    if not folder.is_dir():
        raise ParameterError(option, text, f"a file in an existing folder ({folder} does not exist)")
    _probe(option, text, folder, "a file in a writable folder")
    if target.exists() and not os.access(target, os.W_OK):
        raise ParameterError(option, text, "a file lcchain may overwrite (this one is read-only)")
    return target


def check_output_folder(option: str, path: str | os.PathLike[str]) -> Path:
    """Refuse, before any work, a folder that could not receive files: a file of that name, a parent missing
    or read-only.  A folder that does not exist yet is created by the caller (one level, after the check)."""
    target = Path(path)
    text = os.fspath(path)
    if not text:
        raise ParameterError(option, text, "a folder name")
    if target.exists() and not target.is_dir():
        raise ParameterError(option, text, "a folder (this is a file)")
    probe_in = target if target.is_dir() else target.parent
    if not probe_in.is_dir():
        raise ParameterError(option, text, f"a folder in an existing folder ({probe_in} does not exist)")
    _probe(option, text, probe_in, "a writable folder")
    return target


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike[str]) -> Iterator[Path]:
    """A temporary name beside ``path``, renamed over it when the block ends without error.

    A special file (a device such as ``/dev/full``, a pipe) is written in place:
    renaming over it would replace the device itself.
    """
    target = Path(path)
    if target.exists() and not target.is_file():
        yield target
        return
    descriptor, name = tempfile.mkstemp(dir=target.parent, prefix=f".{target.name}.", suffix=target.suffix)
    os.close(descriptor)
    temporary = Path(name)
    try:
        yield temporary
        # mkstemp makes a private file: give the result the mode a plain write would have
        mode = stat.S_IMODE(target.stat().st_mode) if target.exists() else 0o666 & ~_umask()
        os.chmod(temporary, mode)
        os.replace(temporary, target)
    finally:
        temporary.unlink(missing_ok=True)


def _umask() -> int:
    """This process's umask, read without changing it (Linux), else the usual 022."""
    try:
        for line in Path("/proc/self/status").read_text().splitlines():
            if line.startswith("Umask:"):
                return int(line.split()[1], 8)
    except OSError:
        pass
    return 0o022


def write_text(path: str | os.PathLike[str], text: str) -> Path:
    """Write ``text`` (UTF-8) to ``path`` atomically."""
    with atomic_path(path) as temporary:
        temporary.write_text(text, encoding="utf-8")
    return Path(path)


def save_figure(figure: Any, path: str | os.PathLike[str], **kwargs: Any) -> Path:
    """Save a matplotlib Figure to ``path`` atomically, in the format its name says."""
    target = Path(path)
    with atomic_path(target) as temporary:
        figure.savefig(temporary, format=target.suffix.lower().lstrip(".") or None, **kwargs)
    return target
