"""ngspice's ``"batch"`` transport: ``ngspice -b``, the netlist on standard input, the raw file on a descriptor.

No file or folder ever has a name (the raw file goes to an inherited descriptor of an *unlinked* temporary
file), so nothing is left behind however lcchain ends.  The progress of a run is read from ngspice's
``Reference value`` lines.
"""

from __future__ import annotations

import os
import re
import subprocess
import tempfile
import time
from typing import IO, TYPE_CHECKING

from ...core.budget import show_bytes
from ...core.errors import SimulationError
from ..job import Progress, TransportJob
from ..log import failure_reason, useful_output
from ..measure import measure_control
from ..processes import (
    PROGRESS_INTERVAL,
    WATCH_INTERVAL,
    kill_group,
    outgrown,
    progress_reporter,
    read_all,
    wait_watching,
)
from ..simulator import Simulator
from ..text import parse_options, require_canonical
from .place import Place
from .raw import read_raw

if TYPE_CHECKING:
    import numpy as np

__all__ = ["run_batch"]


# Only complete lines (ngspice ends each with "\r"): a number cut by a partial write must not count.
_REFERENCE_VALUE = re.compile(rb"Reference value\s*:\s*([-+0-9.eE]+)[ \t]*[\r\n]")


def _simulated_time(err: IO[bytes]) -> float | None:
    """The last ``Reference value : t`` ngspice wrote to stderr (its progress, in seconds)."""
    fd = err.fileno()
    size = os.fstat(fd).st_size
    tail = os.pread(fd, 256, max(0, size - 256))
    found = _REFERENCE_VALUE.findall(tail)
    return float(found[-1]) if found else None



def _wait(proc: subprocess.Popen[bytes], job: TransportJob, files: tuple[IO[bytes], IO[bytes], IO[bytes]],
          progress: Progress | None) -> int | None:
    """Exit status of ngspice, or None after the job's timeout; reports progress meanwhile and stops a run that
    outgrows its limits (:func:`~lcchain.spice.processes.outgrown`: its raw file, the last of ``files`` (out,
    err, raw), past ``job.max_output_bytes``, its output past :data:`MAX_LOG_BYTES`, its memory past
    ``job.max_resident_bytes``)."""
    out, err, raw = files
    timeout, limit, resident = job.timeout, job.max_output_bytes, job.max_resident_bytes
    report = progress_reporter(progress, job.tstop, lambda: _simulated_time(err)) if progress is not None else None
    watched = limit is not None or resident is not None

    def look() -> None:
        why = outgrown(proc.pid, "ngspice", printed=(out, err), output=raw, max_output_bytes=limit,
                       max_resident_bytes=resident) if watched else None
        if why is not None:
            kill_group(proc)
            raise SimulationError(why, "")
        if report is not None:  # at every poll, so that a caller can also stop the run from it
            report()

    return wait_watching(proc, timeout, look if (progress is not None or watched) else None,
                         WATCH_INTERVAL if watched else PROGRESS_INTERVAL)


def run_batch(job: TransportJob, simulator: Simulator, place: Place,
              progress: Progress | None = None) -> tuple[dict[str, np.ndarray], str, float]:
    """Run the job's checked text in ``ngspice -b`` at ``place``: the columns of its raw file's ``job.plot``, its
    output, its wall time (s)."""
    timeout = job.timeout
    with tempfile.TemporaryFile() as source, tempfile.TemporaryFile() as raw, \
            tempfile.TemporaryFile() as out, tempfile.TemporaryFile() as err:
        fd = raw.fileno()
        # ngspice measures nothing in batch mode with -r: a netlist with .meas cards writes its raw file from
        # lcchain's control block instead (lcchain.spice.measure)
        interpolated = "interp" in job.text.lower() and "interp" in parse_options(job.text)  # read when it may be
        measured = measure_control(job.text, f"/dev/fd/{fd}", always=interpolated)
        text = measured if measured is not None else job.text
        source.write(require_canonical(text).encode("utf-8"))  # ngspice splits a file at LF, as the check did
        source.seek(0)
        command = [*place.prefix, simulator.executable, "-n", "-b",
                   *(("-r", f"/dev/fd/{fd}") if measured is None else ())]
        start = time.perf_counter()
        proc = subprocess.Popen(command, cwd=place.cwd, env=place.env, stdin=source, stdout=out, stderr=err,
                                pass_fds=(fd,), start_new_session=True)
        try:
            status = _wait(proc, job, (out, err, raw), progress)
        finally:
            if proc.poll() is None:  # timed out, or interrupted: the whole group goes
                kill_group(proc)
        wall = time.perf_counter() - start
        log = (read_all(out) + b"\n" + read_all(err)).decode("utf-8", "replace")
        if status is None:
            raise SimulationError(f"ngspice timed out after {timeout:g} s and was killed", useful_output(log),
                                  "timeout")
        if status != 0:
            raise SimulationError(failure_reason(log, f"ngspice exited with status {status}"), useful_output(log))
        data = read_all(raw)
        # read while the raw file is open: a run that wrote none, or a cut one, asks how full its folder is
        if not data:
            # what ngspice said of its failure (a timestep too small at the operating point) before the missing file
            raise SimulationError(failure_reason(log, "ngspice wrote no raw file" + _full(fd)), useful_output(log))
        try:
            columns = read_raw(data, job.plot, joined=job.joined)
        except SimulationError as exc:
            raise SimulationError(exc.reason + _full(fd), useful_output(log)) from None
    return columns, log, wall


#: Free space below which a missing or cut raw file is put down to a full temporary folder.
NEARLY_FULL_BYTES = 1 << 20


def _full(fd: int) -> str:
    """Why a raw file may be missing or cut short, when the file system holding it (the temporary folder) has less
    than :data:`NEARLY_FULL_BYTES` free: ``": the temporary folder /tmp (TMPDIR) has 4 KiB free"``; else ""."""
    try:
        stats = os.fstatvfs(fd)
    except OSError:
        return ""
    free = stats.f_bavail * stats.f_frsize
    if free >= NEARLY_FULL_BYTES:
        return ""
    return (f": the temporary folder {tempfile.gettempdir()} (TMPDIR) has {show_bytes(free)} free, where ngspice "
            "writes it: make room there, or set TMPDIR to a folder that has some")
