"""Where ngspice runs a netlist lcchain did not write: a sandbox that can write nowhere but its own scratch.

The allow-list (:mod:`lcchain.spice.foreign`) decides what ngspice sees; this
is the defence behind it, for a netlist that gets past the parser or that the
user runs as it is (``lcchain batch --allow-control``):

* ngspice reads no init file (``-n``) and starts with ``HOME``, ``TMPDIR``
  and its working folder in an empty scratch folder, with a minimal
  environment (``PATH``, ``LANG``);
* on Linux, with Debian's ``bubblewrap`` (``bwrap``), it runs in a sandbox
  whose whole file system is read-only but for its private ``/tmp``, a tmpfs
  of :data:`SCRATCH_BYTES` that holds the scratch folder and vanishes with the
  run, with a private ``/dev``, and in namespaces of its own: no network, no other process.
  Its raw file is a descriptor lcchain hands it, so that is the one thing it
  writes outside.
* without bubblewrap (not installed, not Linux, or user namespaces refused),
  the scratch folder is a temporary folder of lcchain's, removed after the
  run; ``lcchain doctor`` says that the sandbox is missing.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from collections.abc import Sequence
from dataclasses import dataclass

__all__ = ["SCRATCH", "SCRATCH_BYTES", "Sandbox", "find_sandbox", "likely_sandbox", "scratch_env"]

#: The scratch folder inside the sandbox (its own tmpfs): HOME, TMPDIR and the working folder.
SCRATCH = "/tmp/lcchain-scratch"
#: Size of the sandbox's /tmp, where the scratch folder is: what a run may write besides its raw file.
SCRATCH_BYTES = 64 * 2**20


@dataclass(frozen=True)
class Sandbox:
    """A command prefix that runs a program in bubblewrap's sandbox (empty: no sandbox here).

    Attributes
    ----------
    prefix : tuple of str
        ``bwrap`` and its options, or ``()``; :meth:`command` completes it.
    why_not : str
        Why there is no sandbox ("" when there is one).
    """

    prefix: tuple[str, ...] = ()
    why_not: str = ""

    @property
    def available(self) -> bool:
        return bool(self.prefix)

    def command(self, program: Sequence[str], cwd: str = SCRATCH, shown: Sequence[str] = ()) -> list[str]:
        """The command line that runs ``program`` in the sandbox, in ``cwd``, with the host paths ``shown``
        bound back read-only (the sandbox's /tmp is its own)."""
        binds = [word for path in shown for word in ("--ro-bind", path, path)]
        return [*self.prefix, *binds, "--chdir", cwd, "--", *program]


def scratch_env(home: str) -> dict[str, str]:
    """The whole environment of a foreign run: no variable of the user's reaches ngspice (SPICE_LIB_DIR,
    SPICE_SCRIPTS and the like would point it at other files)."""
    return {"PATH": os.environ.get("PATH", "/usr/bin:/bin"), "LANG": "C", "LC_ALL": "C", "HOME": home,
            "TMPDIR": home}


def _bwrap_prefix(bwrap: str) -> tuple[str, ...]:
    return (bwrap, "--ro-bind", "/", "/", "--dev", "/dev", "--proc", "/proc", "--size", str(SCRATCH_BYTES),
            "--tmpfs", "/tmp", "--dir", SCRATCH, "--unshare-all", "--die-with-parent", "--new-session")


def likely_sandbox() -> Sandbox:
    """The sandbox :func:`find_sandbox` finds if its trial run works (bubblewrap installed, on Linux), without the
    trial: a guess, for starting a worker before the trial has said (its start then proves nothing)."""
    if not sys.platform.startswith("linux"):
        return Sandbox(why_not=f"no sandbox on {sys.platform} (bubblewrap is Linux only)")
    bwrap = shutil.which("bwrap")
    if bwrap is None:
        return Sandbox(why_not="bubblewrap (bwrap) is not installed: sudo apt-get install bubblewrap")
    return Sandbox(_bwrap_prefix(bwrap))


def find_sandbox() -> Sandbox:
    """bubblewrap's sandbox if it works here (one trial run of ``true`` in it), else the reason it does not."""
    sandbox = likely_sandbox()
    if not sandbox.available:
        return sandbox
    try:
        done = subprocess.run(sandbox.command([shutil.which("true") or "/bin/true"]), capture_output=True, timeout=30,
                              stdin=subprocess.DEVNULL, env=scratch_env("/"))
    except (OSError, subprocess.TimeoutExpired) as error:
        return Sandbox(why_not=f"bwrap could not start: {error}")
    if done.returncode != 0:
        said = done.stderr.decode("utf-8", "replace").strip().splitlines()
        return Sandbox(why_not=f"bwrap refused to start here ({said[-1] if said else done.returncode}); user "
                       "namespaces may be disabled")
    return sandbox
