"""gnucap as an :class:`~lcchain.spice.engine.Engine`: lcchain's own ladders, in gnucap's dialect.

gnucap (Debian package ``gnucap``; measured with ``master 2017.10.03``) is
an independent circuit simulator: agreement between it and ngspice is
evidence that neither has a bug of its own.  It runs only netlists lcchain
wrote (``RunSpec.foreign`` False): the allow-list and the sandbox of foreign
netlists are ngspice's.  ``lcchain check --engine gnucap`` runs a foreign
linear netlist in it as a netlist lcchain writes from its cards' numbers
(:mod:`lcchain.spice.gnucap_check`, ``checks_cards``).

The dialect (measured on this machine)
--------------------------------------
:meth:`Gnucap.dialect` translates line by line and refuses what it cannot
translate exactly, naming it:

* the title becomes a fixed line and ``*`` comments are dropped, so no text
  a user wrote reaches gnucap;
* ``L``, ``C``, ``R``, ``V`` (a constant) and ``K`` lines are kept, ``IC=``
  becomes ``ic=``; pulses are refused: a ``B`` line (ngspice's behavioural
  source, lcchain's gaussian pulse) because gnucap has no such source, a
  ``PWL`` source (the rect pulse) because gnucap takes its fall (1e-9 of the
  width) inside one trapezoidal step, which kicks loop 1 by half a step of
  the pulse too much (measured: max error 1.6e-2 where ngspice's is 7.6e-4,
  two-mass N = 16, dt = 0.05);
* coupled coils: gnucap reads an inductor's ``ic=`` as its flux over its own
  inductance, not as its current (two coils, k = 0.03, ``ic=1`` on the first
  gave currents summing to 1/(1 + k)), so the wanted currents I become
  ``ic_j = (L_j I_j + sum_k k_jk sqrt(L_j L_k) I_k) / L_j`` from the ``L``
  and ``K`` lines;
* ``.options``: ``numdgt=14`` (14 significant digits in the table) and
  ``method=trap``; ``reltol``, ``abstol``, ``vntol``, ``chgtol`` and
  ``trtol`` are kept, ``maxord`` is dropped (gnucap's trapezoidal rule is
  second order), any other option (and ``method=gear``) is refused;
* ``.tran step tstop 0 maxstep uic`` with ``step == maxstep`` (lcchain's
  fixed steps) becomes ``.print tran ...`` and ``.tran h tstop 0 dtmax=h uic``
  with h = tstop / ceil(tstop / step) <= step: gnucap prints, and stops, on
  multiples of its print step only, so the step is shortened a little to
  land on tstop.  Adaptive steps (``maxstep != step``) and aligned runs
  (``step == tstop``) are refused: gnucap's table holds only print steps;
* ``.print`` comes before ``.tran`` (gnucap runs each dot-command as it
  reads it), and names ``i(name)`` / ``v(node)`` vectors only.

The AC analysis (:meth:`Gnucap.run_ac`, measured on this machine)
-----------------------------------------------------------------
* ``.ac lin P f1 f2`` is kept (gnucap reads SPICE's order; it gave the P
  frequencies asked for, 16 to 8000), several of them too (a sweep in
  segments: one table each), and ``V ... DC 0 AC 1`` is kept;
* ``noopac`` is dropped: gnucap's ``.ac`` needs no operating point (a free
  chain, whose inductor loop has none, runs);
* ``short=1e-30`` (:data:`SOURCE_RESISTANCE`): gnucap's voltage source is a
  Norton equivalent with its ``short`` option, 1e-5 ohm, in series: one coil
  of 1 mH at 1 kHz gave I = 2.5e-7 - 0.159155i A with it, -0.15915494309189535i
  (1 / (omega L) to the last digit) without;
* ``numdgt=20`` (:data:`AC_DIGITS`): every value is read back as the double
  gnucap holds (20 digits gave the same doubles as 25; 17 left one ulp on a
  tenth of them, as gnucap rounds after scaling by its suffix), and each
  complex current is printed as its real and imaginary parts,
  ``ir(l1) ii(l1)``;
* two-mass N = 20 (928 frequencies), a walled N = 20, uniform-bounded N = 24
  and coupled coils (k = 0.03, gnucap's ``K``) agreed with ngspice to a median
  of 1e-14 relative; the largest differences (2e-11 .. 4e-9) lie next to
  poles, where the two engines' frequencies (equal within 1.4e-15) already
  move the admittance that much.

Its output (tables with SPICE suffixes, messages before them) is read by
:mod:`lcchain.spice.gnucap_table`.
"""

from __future__ import annotations

import hashlib
import math
import os
import re
import shutil
import subprocess
import tempfile
import time
from collections.abc import Sequence
from typing import IO, ClassVar

from ..core.budget import show_bytes
from ..core.errors import ParameterError, SimulatorMissingError
from ..core.frozen import FrozenMap
from ..core.types import Backend
from .acdata import ac_result
from .engine import Engine
from .gnucap_table import TITLE, failure, quiet, quote, read_ac_table, read_table, table_number, without_rows
from .job import AcJob, Progress, RunJob, TransportJob
from .log import trim_log
from .processes import child_env, kill_group, outgrown, progress_reporter, read_all, wait_watching
from .result import RunResult, TransientData, validate_columns
from .sandbox import SCRATCH, Sandbox, scratch_env
from .scratch import scratch_folder
from .simulator import Simulator, child_launcher
from .text import canonical_vector_name, netlist_lines, parse_options, saved_vectors

__all__ = ["Gnucap", "INSTALL_COMMAND", "gnucap_version", "read_table", "read_ac_table", "coupled_initial_currents",
           "MAX_OUTPUT_BYTES", "DTMIN_FRACTION", "VOLTAGE_LIMIT", "GMIN", "SOURCE_RESISTANCE", "AC_DIGITS"]

#: How to install gnucap on Debian/Ubuntu.
INSTALL_COMMAND = "sudo apt-get install gnucap"
#: What a gnucap run may print (its table) when no smaller limit is given.
MAX_OUTPUT_BYTES = 2 * 2**30
#: gnucap's smallest step over the print step.  Its default, 1e-12 s, is absolute: on a ladder whose time unit is
#: 1 s its start-up steps were 1e-12 of the step and the run erred 3.2 times its prediction.  Measured on two-mass
#: N = 20 and perfect N = 60 at dt = 0.05, 0.005, 0.001 and five scales: 1e-2 fails ("zero time step"), 3e-3 and
#: 1e-3 meet the prediction within 1.18 and 1.24 times, 1e-4 errs 5.2 times it (L0 = 1 mH, C0 = 1 pF, dt = 0.001).
DTMIN_FRACTION = 1e-3
#: gnucap's Newton limit on node voltages, volts (its default, a few volts, slowed a 100 A kick's ladder, ~3 kV, to
#: 240 times its predicted error).
VOLTAGE_LIMIT = 1e12
#: gnucap's conductance from every node to ground, siemens (its default, 1e-12 S, damped a 31.6 kOhm ladder by 2e-6
#: over 60 transit units, 19 times its predicted error; ngspice puts gmin on junctions only, and a ladder has none).
GMIN = 1e-30
#: gnucap's series resistance of a voltage source (its ``short`` option, default 1e-5 ohm), for the AC analysis.
SOURCE_RESISTANCE = 1e-30
#: Significant digits of gnucap's AC table: read back, 20 gave the same doubles as 25 (every value of two-mass
#: N = 20, 928 frequencies); 17 left 1 ulp on 10% of them (gnucap rounds after scaling by its suffix), 14 5e-14.
AC_DIGITS = 20
#: Options gnucap is given as lcchain wrote them.
_KEPT_OPTIONS = ("reltol", "abstol", "vntol", "chgtol", "trtol")
#: Options that do not apply to gnucap and are dropped: its trapezoidal rule is second order, and its .ac needs no
#: operating point.
_DROPPED_OPTIONS = ("maxord", "noopac")

_VERSION = re.compile(r"main version:\s*(?:\S+\s+)?([0-9][0-9.]*)")
_ELEMENT = re.compile(r"^([LC])(\w+)\s+(\S+)\s+(\S+)\s+(\S+)(?:\s+IC=(\S+))?$", re.IGNORECASE)
_RESISTOR = re.compile(r"^R\w+\s+\S+\s+\S+\s+\S+$", re.IGNORECASE)
_SOURCE = re.compile(r"^V\w+\s+\S+\s+\S+\s+([-+0-9.eE]+)$", re.IGNORECASE)
_COUPLING = re.compile(r"^K\w+\s+(L\w+)\s+(L\w+)\s+(\S+)$", re.IGNORECASE)
_TRAN = re.compile(r"^\.tran\s+(\S+)\s+(\S+)\s+0\s+(\S+)\s+uic$", re.IGNORECASE)
_AC = re.compile(r"^\.ac\s+lin\s+([0-9]+)\s+(\S+)\s+(\S+)$", re.IGNORECASE)
_AC_SOURCE = re.compile(r"^V\w+\s+\S+\s+\S+\s+DC\s+0\s+AC\s+1$", re.IGNORECASE)
_PRINTABLE = re.compile(r"^([iv])\((\w+)\)$")


def _refuse(what: str) -> ParameterError:
    return ParameterError("engine", "gnucap", f"ngspice for {what}")


def _value(text: str, line: str) -> float:
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not math.isfinite(value):
        raise _refuse(f"the line {line!r}: gnucap's dialect takes plain numbers, as lcchain writes them")
    return value


def coupled_initial_currents(inductances: dict[str, float], currents: dict[str, float],
                             couplings: Sequence[tuple[str, str, float]]) -> dict[str, float]:
    """The ``ic=`` gnucap needs so that coupled coils start with the given currents.

    gnucap sets each coil's flux to ``L_j ic_j`` (measured), so
    ``ic_j = (L_j I_j + sum_k k_jk sqrt(L_j L_k) I_k) / L_j``.

    Parameters
    ----------
    inductances : dict
        Name -> inductance L_j, henry.
    currents : dict
        Name -> wanted initial current I_j, ampere (missing: 0).
    couplings : sequence of (name, name, k)
        The ``K`` lines: coupling coefficients.

    Returns
    -------
    dict
        Name -> ``ic=`` value for every coil whose value is not zero.
    """
    flux = {name: L * currents.get(name, 0.0) for name, L in inductances.items()}
    for a, b, k in couplings:
        mutual = k * math.sqrt(inductances[a] * inductances[b])
        flux[a] += mutual * currents.get(b, 0.0)
        flux[b] += mutual * currents.get(a, 0.0)
    return {name: value / inductances[name] for name, value in flux.items() if value != 0.0}


def _print_name(name: str, ac: bool = False) -> str:
    """gnucap's probe of a canonical vector: ``i(l1)``, or its real and imaginary parts ``ir(l1) ii(l1)``."""
    match = _PRINTABLE.match(canonical_vector_name(name))
    if match is None:
        raise _refuse(f"the vector {name!r}: gnucap's dialect prints i(element) and v(node) only")
    kind, what = match.groups()
    return f"{kind}r({what}) {kind}i({what})" if ac else f"{kind}({what})"


def _options(line: str) -> list[str]:
    """The options gnucap is given as lcchain wrote them (refusing those it cannot translate)."""
    words = []
    for name, value in parse_options(line).items():
        if name == "method":
            if value.lower() != "trap":
                raise _refuse(f"method = {value!r}: lcchain runs gnucap with the trapezoidal rule only")
        elif name in _KEPT_OPTIONS:
            words.append(f"{name}={repr(_value(value, line))}")
        elif name not in _DROPPED_OPTIONS:
            raise _refuse(f"the option {name!r}: gnucap's dialect translates method, maxord, "
                          + ", ".join(_KEPT_OPTIONS))
    return words


def _tran(line: str) -> tuple[str, float]:
    match = _TRAN.match(line)
    if match is None:
        raise _refuse(f"the analysis {line!r}: gnucap's dialect translates '.tran step tstop 0 maxstep uic'")
    step, tstop, max_step = (_value(g, line) for g in match.groups())
    if step != max_step or not 0 < step < tstop:
        raise _refuse("adaptive or aligned steps (the .tran print step must equal its maximum step and be "
                      "below tstop): gnucap's table holds only print steps, so lcchain runs it at fixed steps")
    # gnucap stops at the last multiple of its print step not after tstop: shorten the step to land on it.
    h = tstop / math.ceil(tstop / step * (1 - 1e-12))
    return f".tran {h!r} {tstop!r} 0 dtmax={h!r} uic", h


def _ac(line: str) -> str:
    match = _AC.match(line)
    if match is None:
        raise _refuse(f"the analysis {line!r}: gnucap's dialect translates '.ac lin points f1 f2'")
    start, stop = (_value(g, line) for g in match.group(2, 3))
    if not 0 < start < stop:
        raise _refuse(f"the sweep {line!r}: 0 < f1 < f2")
    return f".ac lin {int(match.group(1))} {start!r} {stop!r}"


class Gnucap(Engine):
    """gnucap, run as ``gnucap -b /dev/stdin`` in a child process (the ``"batch"`` transport only)."""

    name: ClassVar[str] = "gnucap"
    transports: ClassVar[tuple[Backend, ...]] = ("batch",)
    install: ClassVar[str] = INSTALL_COMMAND
    runs_foreign: ClassVar[bool] = False
    #: ``lcchain check`` runs a foreign linear netlist in it rewritten from its cards' numbers (gnucap_check).
    checks_cards: ClassVar[bool] = True
    extrapolates: ClassVar[bool] = False
    no_extrapolation: ClassVar[str] = ("gnucap prints, and stops, on multiples of its print step only, so it cannot "
                                       "run the aligned steps (print step = tstop) that lcchain's extrapolation "
                                       "and its model of the members' grid need")
    #: Its start-up steps (from 2e-4 of the step) are not ngspice's, which the error split models: measured, the
    #: split's "integration error" of a perfect N = 100 cradle at dt = 0.02 was 8e-6 where ngspice's is ~1e-13.
    steps_modelled: ClassVar[bool] = False
    #: gnucap's wall time over ngspice's model of the same run (:func:`lcchain.core.budget.ngspice_seconds`),
    #: measured here: 3.5 (two-mass N = 400, dt = 0.02), 4.0 (perfect N = 100, dt = 0.02), 4.8 (two-mass
    #: N = 100, dt = 0.05), 9.2 (two-mass N = 20, dt = 0.005: gnucap's cost per point is higher, its cost per
    #: unknown lower), all on a loaded machine where ngspice itself took 1.4-1.7 times its model.
    relative_cost: ClassVar[float] = 6.0
    runs_ac: ClassVar[bool] = True
    ac_transports: ClassVar[tuple[Backend, ...]] = ("batch",)
    threaded_transports: ClassVar[tuple[Backend, ...]] = ("batch",)
    #: gnucap's AC process time over ngspice's for the same sweep (benchmarks/spectrum.md, "gnucap", idle machine,
    #: segmented sweeps): 1.1 to 1.8 (two-mass N = 20 to 200, perfect and uniform-bounded N = 100); 2.0 keeps a
    #: margin.  (On a loaded machine, with even sweeps, it was 1.2 to 4.2.)
    ac_relative_cost: ClassVar[float] = 2.0

    def find(self, backend: str = "batch") -> Simulator:
        if backend not in self.transports:
            raise ParameterError("backend", backend, "batch with engine gnucap (the shared library is ngspice's)")
        exe = shutil.which("gnucap")
        if exe is None:
            raise SimulatorMissingError(f"the gnucap executable is not on PATH; install it with: {INSTALL_COMMAND}")
        launcher = child_launcher()
        return Simulator("batch", exe, gnucap_version(exe, launcher), launcher,
                         Sandbox(why_not="gnucap runs only netlists lcchain wrote"), engine=self.name)

    def dialect(self, netlist: str, vectors: Sequence[str]) -> str:
        lines = netlist_lines(netlist)  # at LF alone, as ngspice and the allow-list split it
        if not netlist.strip():
            raise ParameterError("netlist", netlist, "non-empty netlist text")
        body: list[str] = []
        inductances: dict[str, float] = {}
        currents: dict[str, float] = {}
        couplings: list[tuple[str, str, float]] = []
        analyses: list[tuple[str, str]] = []  # (kind, gnucap's line)
        options: list[str] = []
        step = 0.0
        names = list(vectors) or list(saved_vectors(netlist))
        ended = False
        for line in (raw.strip() for raw in lines[1:]):
            if not line or line.startswith("*"):
                continue
            if ended:
                raise _refuse(f"the line {line!r} after .end")
            head = line.split()[0].lower()
            if (match := _ELEMENT.match(line)) is not None:
                kind, rest, a, b, value = match.group(1).upper(), *match.group(2, 3, 4, 5)
                name = f"{kind}{rest}".lower()
                _value(value, line)
                ic = None if match.group(6) is None else _value(match.group(6), line)
                if kind == "L":
                    inductances[name] = _value(value, line)
                    if ic is not None:
                        currents[name] = ic
                    body.append(f"{kind}{rest} {a} {b} {value}")  # ic= added below, from the currents
                else:
                    body.append(f"{kind}{rest} {a} {b} {value}" + ("" if ic is None else f" ic={ic!r}"))
            elif (match := _COUPLING.match(line)) is not None:
                a, b = match.group(1).lower(), match.group(2).lower()
                k = _value(match.group(3), line)
                if not 0 < abs(k) < 1:
                    raise _refuse(f"the coupling {line!r}: |k| must lie in (0, 1)")
                couplings.append((a, b, k))
                body.append(line)
            elif _RESISTOR.match(line) or _SOURCE.match(line) or _AC_SOURCE.match(line):
                body.append(line)
            elif head.startswith("b"):
                raise _refuse("a behavioural source (the gaussian pulse's 'B1 ... V=expression' line): "
                              "gnucap has none")
            elif head.startswith("v") and "pwl" in line.lower():
                raise _refuse("a PWL source (the rect pulse): gnucap steps across its fall, 1e-9 of the width "
                              "long, in one trapezoidal step and kicks loop 1 too hard (measured: max error "
                              "1.6e-2 where ngspice's is 7.6e-4, two-mass N = 16, dt = 0.05)")
            elif head in (".option", ".options", ".opt"):
                options = _options(line)
            elif head == ".tran":
                tran, step = _tran(line)
                analyses.append(("tran", tran))
            elif head == ".ac":
                analyses.append(("ac", _ac(line)))
            elif head == ".save":
                names = names or [canonical_vector_name(v) for v in line.split()[1:]]
            elif head == ".end":
                ended = True
            else:
                raise _refuse(f"the line {line!r}: gnucap's dialect translates lcchain's own ladders only "
                              "(L, C, R, V, K lines, .options, .tran, .ac, .save, .end)")
        cards = [card for card, _ in analyses]  # the words of the netlist's analysis cards
        if cards not in (["tran"], ["ac"] * len(cards)) or not cards or not names:
            raise _refuse("a netlist without one analysis ('.tran ... uic', or '.ac lin ...' cards: a sweep in "
                          "segments) or without vectors to save")
        for a, b, _ in couplings:
            for coil in (a, b):
                if coil not in inductances:
                    raise _refuse(f"a K line that couples {coil!r}, which is not an inductor of the netlist")
        ics = coupled_initial_currents(inductances, currents, couplings)
        body = [_with_ic(line, ics) for line in body]
        card = cards[0]
        printed = " ".join(_print_name(name, card == "ac") for name in names)
        if card == "ac":
            options = [f"numdgt={AC_DIGITS}", f"short={SOURCE_RESISTANCE!r}", f"gmin={GMIN!r}", *options]
        else:
            # gnucap's absolute scales, made the circuit's: its smallest step (its start-up ramp begins there) and its
            # Newton limits on node voltages (a linear ladder needs none).
            options = ["numdgt=14", "method=trap", *options, f"dtmin={step * DTMIN_FRACTION!r}",
                       f"vmax={VOLTAGE_LIMIT!r}", f"vmin={-VOLTAGE_LIMIT!r}", f"gmin={GMIN!r}"]
        return "\n".join([TITLE, *body, ".options " + " ".join(options), f".print {card} {printed}",
                          *(line for _, line in analyses), ".end"]) + "\n"

    def run(self, job: RunJob, simulator: Simulator, progress: Progress | None = None) -> RunResult:
        if job.foreign or job.trusted:
            raise _refuse("a netlist lcchain did not write (gnucap runs only lcchain's own ladders; the "
                          "allow-list and the sandbox of foreign netlists are ngspice's)")
        if simulator.engine != self.name:
            raise ParameterError("simulator", simulator.engine, "a simulator found for engine gnucap")
        netlist, tstop = job.netlist, job.tstop
        names = job.vectors or tuple(canonical_vector_name(v) for v in saved_vectors(netlist))
        text = self.dialect(netlist, names)
        if progress is not None:
            progress(0.0)
        output, log, wall = _run_child(TransportJob.checked(text, job), simulator, progress)
        columns = read_table(output, log)
        time_s, found = validate_columns(columns, quiet(log), names, tstop, self.name)
        if progress is not None:
            progress(1.0)
        return RunResult(data=TransientData(time_s, FrozenMap(found)), engine_version=simulator.version,
                         netlist_sha256=_sha256(netlist), wall_s=wall, log=trim_log(without_rows(log)),
                         engine=self.name, options=FrozenMap(parse_options(netlist)), backend=simulator.backend)

    def run_ac(self, job: AcJob, simulator: Simulator) -> RunResult:
        if job.foreign:
            raise ParameterError("engine", self.name, "ngspice for a netlist lcchain did not write (the allow-list "
                                 "and the sandbox are ngspice's)")
        if simulator.engine != self.name:
            raise ParameterError("simulator", simulator.engine, "a simulator found for engine gnucap")
        # its table's text, not the raw bytes a price holds the AC run to: gnucap's own bound
        text = self.dialect(job.netlist, job.vectors)
        output, log, wall = _run_child(TransportJob(text, 1.0, job.timeout, MAX_OUTPUT_BYTES, job.max_resident_bytes),
                                       simulator)
        columns = read_ac_table(output, log)
        return ac_result(job, columns, quiet(log), simulator, wall)


def _sha256(text: str) -> str:
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


def _with_ic(line: str, ics: dict[str, float]) -> str:
    name = line.split()[0].lower()
    return f"{line} ic={ics[name]!r}" if name.startswith("l") and name in ics else line


def gnucap_version(executable: str, launcher: tuple[str, ...] = ()) -> str:
    """gnucap's version (its banner's ``main version``, e.g. ``"2017.10.03"``).

    Raises
    ------
    SimulatorMissingError
        gnucap cannot run or prints no version.
    """
    with scratch_folder("gnucap") as folder:
        try:  # an empty circuit on a pipe, as a run's netlist goes (not the machine's /dev/null: once, on this
            # machine, something replaced it with a file of ngspice's output, and gnucap read it until the timeout)
            proc = subprocess.run([*launcher, executable, "-b", "/dev/stdin"], capture_output=True, text=True,
                                  timeout=30, input="", cwd=folder, env=child_env(), start_new_session=True)
        except (OSError, subprocess.TimeoutExpired) as exc:
            raise SimulatorMissingError(f"cannot run {executable}: {exc}; install gnucap with: "
                                        f"{INSTALL_COMMAND}") from exc
    match = _VERSION.search(proc.stdout + proc.stderr)
    if match is None:
        output = (proc.stdout + proc.stderr)[:200]
        raise SimulatorMissingError(f"{executable} -b did not report a gnucap version: {output!r}")
    return match.group(1)


def _last_time(out: IO[bytes]) -> float | None:
    """The time of the last complete row gnucap printed (its progress, in seconds)."""
    fd = out.fileno()
    size = os.fstat(fd).st_size
    tail = os.pread(fd, 512, max(0, size - 512)).decode("ascii", "replace").split("\n")[:-1]
    for row in reversed(tail[1:] if size > 512 else tail):
        words = row.split()
        if words:
            return table_number(words[0])
    return None


def _run_child(job: TransportJob, simulator: Simulator, progress: Progress | None = None,
               sandbox: Sandbox | None = None) -> tuple[str, str, float]:
    """gnucap's stdout and its whole output, and its wall time, for the job's text (gnucap's dialect, canonical);
    in a temporary folder that is then removed (in ``sandbox`` too when it is available: its own scratch folder
    and environment, :mod:`lcchain.spice.sandbox`).  Its output may not pass the job's ``max_output_bytes``
    (default :data:`MAX_OUTPUT_BYTES`)."""
    timeout = job.timeout
    with scratch_folder("gnucap") as folder, tempfile.TemporaryFile() as source, \
            tempfile.TemporaryFile() as out, tempfile.TemporaryFile() as err:
        source.write(job.text.encode("utf-8"))
        source.seek(0)
        program = [simulator.executable, "-b", "/dev/stdin"]
        env = child_env()
        if sandbox is not None and sandbox.available:
            command = [*simulator.launcher, *sandbox.command(program)]
            env = scratch_env(SCRATCH)
        else:
            command = [*simulator.launcher, *program]
        start = time.perf_counter()
        proc = subprocess.Popen(command, cwd=folder, env=env, stdin=source, stdout=out, stderr=err,
                                start_new_session=True)
        try:
            status = _wait(proc, job, (out, err), progress)
        finally:
            if proc.poll() is None:  # timed out, or interrupted: the whole group goes
                kill_group(proc)
        wall = time.perf_counter() - start
        output = read_all(out).decode("utf-8", "replace")
        log = output + "\n" + read_all(err).decode("utf-8", "replace")
    if status is None:
        raise failure(f"gnucap timed out after {timeout:g} s and was killed", quote(log), "timeout")
    if status != 0:
        raise failure(f"gnucap exited with status {status}", quote(log))
    return output, log, wall


def _wait(proc: subprocess.Popen[bytes], job: TransportJob, files: tuple[IO[bytes], IO[bytes]],
          progress: Progress | None) -> int | None:
    """gnucap's exit status, or None after the job's timeout; reports progress and stops a run whose output
    (``files``: out, err) outgrows the job's ``max_output_bytes``, or whose memory outgrows its
    ``max_resident_bytes``, meanwhile."""
    out, err = files
    limit, resident = job.max_output_bytes or MAX_OUTPUT_BYTES, job.max_resident_bytes
    report = progress_reporter(progress, job.tstop, lambda: _last_time(out)) if progress is not None else None

    def look() -> None:
        if os.fstat(out.fileno()).st_size + os.fstat(err.fileno()).st_size > limit:
            kill_group(proc)
            raise failure(f"gnucap printed more than {show_bytes(limit)}, the most the memory budget allows, and "
                           "the run was stopped", "")
        why = outgrown(proc.pid, "gnucap", max_resident_bytes=resident) if resident is not None else None
        if why is not None:
            kill_group(proc)
            raise failure(why, "")
        if report is not None:
            report()

    return wait_watching(proc, job.timeout, look)
