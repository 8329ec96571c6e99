"""Output files: checked before any work, written whole or not at all, under the name the user gave.

* :func:`check_output` runs before a simulation starts: the folder exists and
  is a folder, a file can really be created in it (a probe file is made and
  removed: ``os.access`` says yes to root for ``/proc``), the path is not a
  folder itself, and a figure's name ends in a format matplotlib writes, so
  that the file lands exactly where the user said (matplotlib would append
  ``.png`` to ``/dev/full`` and write ``/dev/full.png``).
* :func:`check_not_input` refuses an output that is one of the command's
  inputs (by resolved path or, for hard links, by inode), and
  :func:`check_inside` one that leaves the current folder through a symlink;
  folders are made only after every check (``make_folder``, ``parents``).
* :func:`write_text` and :func:`save_figure` write to a hidden temporary name
  in the same folder and rename it over the target, so an interrupted or
  failed write never leaves half a file.
"""

from __future__ import annotations

import contextlib
import os
import stat
import tempfile
from collections.abc import Iterable, Iterator
from pathlib import Path
from typing import TYPE_CHECKING

from ..core.errors import ParameterError

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["FIGURE_FORMATS", "check_output", "check_output_folder", "check_not_input", "check_inside", "same_file",
           "write_text", "save_figure", "atomic_path"]

#: Figure formats matplotlib writes from a file name's ending.
FIGURE_FORMATS = ("png", "svg", "pdf", "eps", "ps", "jpg", "jpeg", "tif", "tiff", "webp")


def _probe(option: str, text: str, folder: Path, wanted: str) -> None:
    """Refuse a folder where no file can really be created (a probe file is made and removed)."""
    try:
        with tempfile.NamedTemporaryFile(dir=folder, prefix=".lcchain-probe-"):
            pass
    except OSError as error:
        raise ParameterError(option, text, f"{wanted} ({folder}: {error.strerror or error})") from None


def _path_text(option: str, path: object, allowed: str) -> str:
    """A path given from Python as text (a number or bytes is refused, naming the option)."""
    text = os.fspath(path) if isinstance(path, (str, os.PathLike)) else None
    if not isinstance(text, str):
        raise ParameterError(option, type(path).__name__, allowed)
    return text


def _existing_ancestor(option: str, text: str, folder: Path) -> Path:
    """The nearest folder above (or at) ``folder`` that exists; a file on the way is refused."""
    current = folder
    while not current.exists() and not current.is_symlink():
        if current.parent == current:
            break
        current = current.parent
    if not current.is_dir():
        raise ParameterError(option, text, f"a path whose folders are folders ({current} is a file)")
    return current


def _name_fits(option: str, text: str, target: Path, folder: Path) -> None:
    """Refuse a file name longer than the file system allows (checked before the work, not when writing)."""
    try:
        longest = os.pathconf(folder, "PC_NAME_MAX")
    except (OSError, ValueError):
        longest = 255
    if len(os.fsencode(target.name)) > longest:
        raise ParameterError(option, text, f"a file name of at most {longest} bytes")


def check_output(option: str, path: str | os.PathLike[str], formats: tuple[str, ...] | None = None, *,
                 make_folder: bool = False) -> Path:
    """Refuse, before any work, an output path that could not be written under its own name.

    Parameters
    ----------
    option : str
        The option or key that named the file (``"--plot"``, ``"output.report"``).
    path : path-like
        The file to write.
    formats : tuple of str, optional
        Endings the file must have (lower case, no dot); None: any name.
    make_folder : bool
        The caller creates the file's folder (after every check has passed):
        a missing folder is accepted when the nearest existing one above it
        is a writable folder.

    Returns
    -------
    Path
    """
    text = _path_text(option, path, "a file name (str or os.PathLike)")
    try:
        return _check_output(option, text, formats, make_folder)
    except OSError as error:  # a folder name too long, a loop of symlinks
        raise ParameterError(option, text, f"a path this system can use ({error.strerror or error})") from None


def _check_output(option: str, text: str, formats: tuple[str, ...] | None, make_folder: bool) -> Path:
    target = Path(text)
    if not text:
        raise ParameterError(option, text, "a file name (an empty name names nothing)")
    _name_fits(option, text, target, target.parent)
    if text.endswith(os.sep) or target.is_dir():
        raise ParameterError(option, text, "a file name, not a folder")
    if formats is not None:
        ending = target.suffix.lower().lstrip(".")
        if ending not in formats:
            raise ParameterError(option, text, f"a file name ending in .{', .'.join(formats)} (the format is "
                                 "taken from the name; any other name would be changed)")
    folder = target.parent
    if make_folder and not folder.is_dir():
        folder = _existing_ancestor(option, text, folder)
    elif not folder.is_dir():
        raise ParameterError(option, text, f"a file in an existing folder ({folder} does not exist)")
    _probe(option, text, folder, "a file in a writable folder")
    if target.exists() and not os.access(target, os.W_OK):
        raise ParameterError(option, text, "a file lcchain may overwrite (this one is read-only)")
    return target


def same_file(a: str | os.PathLike[str], b: str | os.PathLike[str]) -> bool:
    """``a`` and ``b`` name one file: the same resolved path (symlinks followed), or the same inode (hard links)."""
    first, second = Path(a), Path(b)
    try:
        return first.resolve() == second.resolve() or os.path.samefile(first, second)
    except (OSError, RuntimeError):  # one of them does not exist (yet), or is a loop of symlinks: not one file
        return False


def check_not_input(option: str, path: str | os.PathLike[str],
                    inputs: Iterable[tuple[str, str | os.PathLike[str]]], where: str | None = None) -> None:
    """Refuse an output that would overwrite one of the command's input files (the scene, the --chain file).

    Parameters
    ----------
    option : str
        The option or key that names the output.
    path : path-like
        The output.
    inputs : iterable of (str, path-like)
        What named each input (``"--chain"``, ``"SCENE"``) and its path.
    where : str, optional
        The file the output was named in (a scene), for the message.
    """
    for named, source in inputs:
        if same_file(path, source):
            raise ParameterError(option, os.fspath(path), f"a file that is not an input of this command ({named} "
                                 f"reads {os.fspath(source)}: writing it would destroy it)", where)


def check_inside(option: str, path: str | os.PathLike[str], folder: str | os.PathLike[str],
                 where: str | None = None) -> None:
    """Refuse an output that, symlinks followed, lands outside ``folder`` (a scene writes into the current one)."""
    base = Path(folder).resolve()
    try:
        leads_to = Path(base, path).resolve()
    except RuntimeError:  # a loop of symlinks (Python 3.11 raises this, later ones OSError)
        raise ParameterError(option, os.fspath(path), "a path without a loop of symlinks", where) from None
    if not leads_to.is_relative_to(base):
        raise ParameterError(option, os.fspath(path), f"a path that stays in the current folder {base}, symlinks "
                             f"followed (it leads to {leads_to})", where)


def check_output_folder(option: str, path: str | os.PathLike[str], *, parents: bool = False) -> Path:
    """Refuse, before any work, a folder that could not receive files: no name, a file of that name, a parent
    missing or read-only.  A folder that does not exist yet is created by the caller after every check (one
    level, or with ``parents`` every missing level)."""
    text = _path_text(option, path, "a folder name (str or os.PathLike)")
    try:
        return _check_output_folder(option, text, parents)
    except OSError as error:
        raise ParameterError(option, text, f"a path this system can use ({error.strerror or error})") from None


def _check_output_folder(option: str, text: str, parents: bool) -> Path:
    target = Path(text)
    if not text.strip():
        raise ParameterError(option, text, "a folder name (an empty name would mean the current folder)")
    if text == "-":  # standard output elsewhere: no folder of files goes there (write ./- to mean that folder)
        raise ParameterError(option, text, "a folder name (- is standard output, which takes no folder of files; "
                             "./- names a folder called -)")
    if (target.exists() or target.is_symlink()) and not target.is_dir():
        raise ParameterError(option, text, "a folder (this is a file)")
    probe_in = target if target.is_dir() else target.parent
    if parents and not probe_in.is_dir():
        probe_in = _existing_ancestor(option, text, probe_in)
    if not probe_in.is_dir():
        raise ParameterError(option, text, f"a folder in an existing folder ({probe_in} does not exist)")
    _probe(option, text, probe_in, "a writable folder")
    return target


def _open_special(target: Path) -> None:
    """Refuse to hang on a FIFO nobody reads: open it without waiting, which fails at once (ENXIO) then."""
    if stat.S_ISFIFO(target.stat().st_mode):
        os.close(os.open(target, os.O_WRONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0)))


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike[str]) -> Iterator[Path]:
    """A temporary name beside ``path``, renamed over it when the block ends without error.

    A special file (a device such as ``/dev/full``, a pipe) is written in place:
    renaming over it would replace the device itself.  A FIFO that nobody
    reads is an error (OSError, "No such device or address") rather than a wait
    for ever.
    """
    target = Path(path)
    if target.exists() and not target.is_file():
        _open_special(target)
        yield target
        return
    # the temporary name is cut short so that a file name near the system's limit still has room for it
    descriptor, name = tempfile.mkstemp(dir=target.parent, prefix=f".{target.stem[:64]}.", suffix=target.suffix[:16])
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


def save_figure(figure: Figure, path: str | os.PathLike[str], *, dpi: float | None = None) -> Path:
    """Save a matplotlib Figure to ``path`` atomically, in the format its name says, at ``dpi`` (None:
    matplotlib's ``savefig.dpi``)."""
    target = Path(path)
    with atomic_path(target) as temporary:
        figure.savefig(temporary, format=target.suffix.lower().lstrip(".") or None, dpi=dpi)
    return target
