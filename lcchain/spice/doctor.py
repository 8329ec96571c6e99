"""``lcchain doctor``: does ngspice work here, its optional parts (the sandbox, the shared library, PySpice), and
which engines (:data:`lcchain.spice.engines.ENGINES`) are installed?"""

from __future__ import annotations

import functools
import math
import os
import subprocess
import sys
from collections.abc import Callable
from dataclasses import dataclass

from ..core.errors import ParameterError, SimulationError, SimulatorMissingError
from ..core.types import Backend
from .engines import DEFAULT_ENGINE, ENGINES, find_engine, run_engine
from .job import RunJob
from .ngspice.find import INSTALL_COMMAND, PYSPICE_INSTALL_COMMAND, find_shared_library, find_simulator, require_pyspice
from .ngspice.runner import run
from .sandbox import find_sandbox
from .simulator import Simulator

__all__ = ["Check", "doctor"]

#: The shared library alone, for a machine whose ngspice executable was found.
LIBRARY_INSTALL_COMMAND = "sudo apt-get install libngspice0"


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
    required : bool
        Whether lcchain's default (``ngspice -b``) needs it; the shared
        backend and the sandbox are optional, and ``lcchain doctor`` exits 0
        without them.
    """

    name: str
    ok: bool
    detail: str
    fix: str = ""
    required: bool = True


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
#: The doctor's run: the unit LC loop for 1 s, lcchain's own text.
_DOCTOR_JOB = RunJob(_DOCTOR_NETLIST, ["i(l1)"], 1.0, timeout=60.0, foreign=False)
#: Tolerance of the doctor's check i(l1)(t=1 s) = cos(1) for the unit LC loop.
_DOCTOR_ATOL = 1e-4


def _doctor_run(simulator: Simulator) -> str:
    result = run(_DOCTOR_JOB, simulator)
    error = abs(float(result.vectors["i(l1)"][-1]) - math.cos(1.0))
    if error > _DOCTOR_ATOL:
        raise SimulationError(f"i(l1)(1 s) differs from cos(1) by {error:.3g}")
    return f"{result.points} points in {result.wall_s:.3f} s, |i - cos t| = {error:.1e}"


def _engine_run(name: str) -> str:
    simulator = find_engine(name)
    result = run_engine(_DOCTOR_JOB, simulator)
    error = abs(float(result.vectors["i(l1)"][-1]) - math.cos(1.0))
    if error > _DOCTOR_ATOL:
        raise SimulationError(f"i(l1)(1 s) differs from cos(1) by {error:.3g}")
    usable, missing = [], []
    for transport in ENGINES[name].user_transports():  # each found, as a run on it would find it
        try:
            find_engine(name, transport)
            usable.append(transport)
        except (SimulatorMissingError, ParameterError):
            missing.append(transport)
    unusable = f" ({', '.join(missing)}: not usable here, see above)" if missing else ""
    return (f"{simulator.executable} ({name} {simulator.version}; transports {', '.join(usable)}{unusable})"
            f", a run: |i - cos t| = {error:.1e}")


def doctor() -> list[Check]:
    """Check that ngspice, its shared library and PySpice work here, and which engines are installed.

    Never raises: every failure becomes a :class:`Check` with ``ok=False``
    that says what is missing and how to fix it.

    Returns
    -------
    list[Check]
        ngspice executable, batch run, sandbox, shared library, PySpice,
        shared run (the last four optional), then one line per engine
        (found, its version and a run; optional but for the default one).
    """
    checks: list[Check] = []

    def attempt(name: str, fix: str, action: Callable[[], str], required: bool = True) -> bool:
        try:
            detail = action()
        except Exception as exc:  # noqa: BLE001 - the doctor reports, never raises
            checks.append(Check(name, False, f"{type(exc).__name__}: {exc}", fix, required))
            return False
        checks.append(Check(name, True, detail, "", required))
        return True

    found: dict[str, Simulator] = {}

    def locate(backend: Backend) -> Simulator:
        found[backend] = find_simulator(backend)
        return found[backend]

    have_exe = attempt("ngspice executable", f"install ngspice: {INSTALL_COMMAND}",
                       lambda: (lambda s: f"{s.executable} (ngspice {s.version})")(locate("batch")))
    if have_exe:
        attempt("batch run", "run `ngspice -b` on the netlist of `lcchain doctor --help` to see why it fails",
                lambda: _doctor_run(found["batch"]))
    else:
        checks.append(
            Check("batch run", False, "skipped: no ngspice executable", f"install ngspice: {INSTALL_COMMAND}")
        )
    sandbox = find_sandbox()
    checks.append(Check("sandbox for foreign netlists", sandbox.available,
                        "bubblewrap: read-only file system, private /tmp, no network" if sandbox.available else
                        f"{sandbox.why_not}; lcchain batch runs foreign netlists without it (allow-list only)",
                        "" if sandbox.available else "sudo apt-get install bubblewrap", required=False))
    library_fix = LIBRARY_INSTALL_COMMAND if have_exe else INSTALL_COMMAND  # not the ngspice just found
    library_advice = f"install the library: {library_fix}"
    if os.environ.get("NGSPICE_LIBRARY_PATH"):  # the one library looked for: the variable's, not a package's
        library_fix = library_advice = "unset NGSPICE_LIBRARY_PATH, or point it at libngspice.so.0"
    have_lib = attempt("ngspice shared library", library_advice, find_shared_library, required=False)
    have_pyspice = attempt("PySpice", PYSPICE_INSTALL_COMMAND + " (only the shared backend needs it)",
                           _pyspice_version, required=False)
    if have_lib and have_pyspice:
        attempt("shared run", "see the error; try `python -m lcchain.spice.ngspice.shared_worker` by hand",
                lambda: _doctor_run(locate("shared")), required=False)
    else:  # the fix names only what is missing: never a library that was just found
        missing = [(what, fix) for what, have, fix in (("shared library", have_lib, library_fix),
                                                        ("PySpice", have_pyspice, PYSPICE_INSTALL_COMMAND)) if not have]
        checks.append(Check("shared run", False, f"skipped: {' and '.join(what for what, _ in missing)} missing",
                            "; ".join(fix for _, fix in missing), required=False))
    for name, engine in ENGINES.items():
        attempt(f"engine {name}", f"install it: {engine.install}", functools.partial(_engine_run, name),
                required=name == DEFAULT_ENGINE)
    return checks


def _pyspice_version() -> str:
    require_pyspice()
    # Imported in a child so that lcchain itself never loads PySpice.
    proc = subprocess.run(
        [sys.executable, "-c", "import PySpice.Spice.NgSpice.Shared, PySpice; print(PySpice.__version__)"],
        capture_output=True, text=True, timeout=120, stdin=subprocess.DEVNULL,
    )
    if proc.returncode != 0:
        raise ImportError(proc.stderr.strip().splitlines()[-1] if proc.stderr.strip() else "import failed")
    return f"PySpice {proc.stdout.strip()}"
