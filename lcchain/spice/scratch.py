"""Scratch folders of lcchain's own, gone when their process is: nothing is left in the temporary folder.

A folder made here is named ``lcchain-<kind>-<pid>-<random>`` (hidden with a leading dot when it sits beside a
user's file): the pid of the process that owns it.  It is removed when its block ends; a process killed
outright (SIGKILL: no ``finally`` runs) cannot do that, so

* every new scratch folder first removes those of its folder whose owner is dead (the same user, the pid no
  longer running, the folder holding lcchain's marker file with that pid: a folder of a live process, of
  another user, or of the user's own that only looks like one, is never touched);
* with ``watch=True`` a small watcher process, in a session of its own, holds the read end of a pipe whose
  write end only the owner holds: when the owner dies, however, the pipe closes and the watcher removes the
  folder (again for a moment, while what the owner started may still write into it), then exits.  A Dask
  cluster's scratch space is watched so: killing its driver leaves nothing behind.
"""

from __future__ import annotations

import contextlib
import os
import re
import shutil
import subprocess
import sys
import tempfile
from collections.abc import Iterator
from pathlib import Path

__all__ = ["scratch_folder", "remove_stale", "owner_pid"]

#: A scratch folder's name: optional dot, "lcchain-", a kind, the owner's pid, tempfile's 8 random characters.
_NAME = re.compile(r"^\.?lcchain-[a-z]+-(\d+)-[a-z0-9_]{8}$")
#: The file every scratch folder holds from its start (the owner's pid): only a folder that has it is ever removed
#: as stale, so a user's own folder that happens to look like one (beside a store) is never touched.
MARKER = ".lcchain-scratch"
#: How long the watcher keeps removing the folder after its owner died (what the owner started, Dask's
#: workers say, may still write into it for a moment), seconds.
WATCH_SECONDS = 10.0
_WATCHER = r"""
import os, shutil, sys, time
folder = sys.argv[1]
sys.stdin.buffer.read()  # returns when the owner closed the pipe or died
if not os.path.lexists(folder):
    sys.exit(0)  # the owner removed it: an ordinary end
end = time.monotonic() + float(sys.argv[2])
quiet = 0
while os.path.lexists(folder) or (quiet < 4 and time.monotonic() < end):
    shutil.rmtree(folder, ignore_errors=True)
    quiet = 0 if os.path.lexists(folder) else quiet + 1
    if time.monotonic() >= end:
        break
    time.sleep(0.25)
"""


def owner_pid(name: str) -> int | None:
    """The pid in a scratch folder's name, or None when the name is not one of lcchain's scratch folders."""
    match = _NAME.match(name)
    return int(match.group(1)) if match else None


def _alive(pid: int) -> bool:
    """Whether a process runs: a zombie (killed, not yet reaped by its parent) does not."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # another user's process: alive
        return True
    try:
        with open(f"/proc/{pid}/stat", "rb") as stat:
            return stat.read().rsplit(b")", 1)[1].split()[0] != b"Z"
    except (OSError, IndexError):  # no /proc: os.kill said it exists
        return True


def remove_stale(parent: str | os.PathLike[str]) -> list[str]:
    """Remove the scratch folders in ``parent`` whose owner is dead (the same user, the pid not running); return
    their names.  Anything else in ``parent`` (another name, a file, a link, another user's) is left alone."""
    removed: list[str] = []
    try:
        entries = list(os.scandir(parent))
    except OSError:
        return removed
    uid = os.getuid()
    for entry in entries:
        pid = owner_pid(entry.name)
        if pid is None or pid == os.getpid():
            continue
        try:
            info = entry.stat(follow_symlinks=False)
            if not entry.is_dir(follow_symlinks=False) or info.st_uid != uid or _alive(pid):
                continue
            marker = Path(entry.path, MARKER)
            if marker.is_symlink() or marker.read_text(encoding="ascii").strip() != str(pid):
                continue
        except (OSError, ValueError):
            continue
        shutil.rmtree(entry.path, ignore_errors=True)
        removed.append(entry.name)
    return removed


def _watcher(folder: Path) -> subprocess.Popen[bytes] | None:
    try:
        return subprocess.Popen([sys.executable, "-I", "-S", "-c", _WATCHER, str(folder), str(WATCH_SECONDS)],
                                stdin=subprocess.PIPE, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                start_new_session=True, close_fds=True)
    except OSError:  # no watcher: the next start removes the folder if this process is killed
        return None


@contextlib.contextmanager
def scratch_folder(kind: str, parent: str | os.PathLike[str] | None = None, *, watch: bool = False,
                   hidden: bool = False) -> Iterator[Path]:
    """A folder of this process's own, removed when the block ends (and when this process is killed).

    Parameters
    ----------
    kind : str
        Lower-case letters: what the folder is for (``"dask"``, ``"gnucap"``), part of its name.
    parent : path, optional
        Where to make it (default: the temporary folder, ``TMPDIR``).
    watch : bool
        Start a watcher that removes the folder if this process dies without doing so (see the module).
    hidden : bool
        A leading dot in the name: for a folder made beside the user's own files (a store's).
    """
    if not kind.isalpha() or not kind.islower():
        raise ValueError(f"a scratch folder's kind is lower-case letters, not {kind!r}")
    where = Path(parent) if parent is not None else Path(tempfile.gettempdir())
    remove_stale(where)
    folder = Path(tempfile.mkdtemp(prefix=f"{'.' if hidden else ''}lcchain-{kind}-{os.getpid()}-", dir=where))
    watcher = None
    try:
        (folder / MARKER).write_text(str(os.getpid()), encoding="ascii")
        watcher = _watcher(folder) if watch else None
        yield folder
    finally:
        shutil.rmtree(folder, ignore_errors=True)
        if watcher is not None:
            assert watcher.stdin is not None  # a pipe, opened above
            with contextlib.suppress(OSError):
                watcher.stdin.close()  # the folder is gone: the watcher finds nothing and exits
            with contextlib.suppress(subprocess.TimeoutExpired):
                watcher.wait(timeout=WATCH_SECONDS)
