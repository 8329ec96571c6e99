"""What a request will cost, estimated before any work starts, and the budget it must fit.

Nothing lcchain is asked to do may exhaust the machine: a simulation, a scene
or a design is estimated first (time points x unknowns -> memory and ngspice's
wall time; N -> an optimiser's time) and refused with one line giving the
estimate and the limit when it does not fit.  The defaults fit a 2-core, 24 GiB
machine with room for two runs at once; ``--max-memory`` and ``--max-time``
raise them.

Cost models (measured on this 2-core machine, benchmarks/accuracy/ and
benchmarks/theory.md):

* ngspice's wall time: :data:`NGSPICE_SECONDS_PER_UNKNOWN_POINT` (98-114 ns per
  unknown per time point with the trapezoidal rule) times the unknowns (about
  2 N, 3 N with losses) times the time points.  ngspice itself streams its
  raw file and stays near 13 MB whatever the length of the run.
* lcchain's memory: the raw file is read whole and its columns copied, then
  the compared loops are made dimensionless, compared with the theory at the
  same points, and subtracted: :data:`BYTES_PER_VALUE` bytes for every saved
  value of every time point (six copies of a float64).  Exact modes of N
  masses add two N x N matrices.
* ``lcchain spectrum``: ngspice's AC analysis, :data:`AC_SECONDS_PER_UNKNOWN_FREQUENCY` per frequency per
  unknown, and the fit, whose Gauss-Newton matrices are frequencies x the sections of one window
  (:data:`FIT_BYTES_PER_SAMPLE_SECTION`; up to 128 sections, more when a sweep much finer than the poles
  gives the rational fits spurious poles) (:func:`ac_estimate`).
* an optimal design: :data:`DESIGN_SECONDS_FIXED` plus
  :data:`DESIGN_SECONDS_PER_MASS` per mass (closed-form modes and arrival
  searches are linear in N).
* the interpreter itself: :data:`INTERPRETER_BYTES`, added to every memory
  estimate checked against the budget.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

from .checks import real
from .errors import ParameterError
from .limits import WORST_CASE_MODEL_NODES

__all__ = ["Budget", "Estimate", "BudgetError", "DEFAULT_MAX_MEMORY", "DEFAULT_MAX_SECONDS",
           "NGSPICE_SECONDS_PER_UNKNOWN_POINT", "NGSPICE_SECONDS_PER_POINT", "ngspice_seconds",
           "BYTES_PER_VALUE", "DESIGN_SECONDS_PER_MASS", "DESIGN_SECONDS_FIXED",
           "INTERPRETER_BYTES", "INTERPRETER_SECONDS", "RUN_START_SECONDS", "run_estimate", "sample_theory_seconds",
           "AC_SECONDS_PER_UNKNOWN_FREQUENCY", "AC_SECONDS_PER_FREQUENCY", "FIT_SECONDS_PER_SAMPLE_MODE",
           "FIT_SECONDS_PER_SAMPLE", "FIT_SECONDS_PER_SAMPLE_SECTION", "FIT_SECONDS_PER_SAMPLE_SECTION2",
           "FIT_BYTES_PER_SAMPLE_SECTION", "SIMULATOR_BYTES", "POOL_WORKER_BYTES", "POOL_TRACKER_BYTES",
           "DASK_WORKER_BYTES", "DASK_SCHEDULER_BYTES", "WARM_WORKER_BYTES", "DASK_START_SECONDS", "POOL_START_SECONDS",
           "accuracy_plan_seconds", "export_estimate", "EXPORT_IMPORT_BYTES", "EXPORT_IMPORT_SECONDS",
           "EXPORT_COPIES", "EXPORT_BYTES_PER_CELL", "METRICS_BYTES_PER_BYTE", "TEXT_BYTES_PER_BYTE",
           "EXPORT_BYTES_PER_SECOND", "ac_estimate", "ac_run_estimate", "chain_seconds", "sensitivity_estimate",
           "max_points", "design_estimate", "perfect_estimate", "show_bytes", "show_seconds"]

#: Memory one request may use: a third of this machine's 24 GiB, so two runs fit beside the system.
DEFAULT_MAX_MEMORY = 8 * 2**30
#: Wall time one request may take before it is refused, seconds.
DEFAULT_MAX_SECONDS = 3600.0
#: ngspice's cost, trapezoidal rule (benchmarks/accuracy: 98-114 ns).
NGSPICE_SECONDS_PER_UNKNOWN_POINT = 1.1e-7
#: ngspice's cost per time point whatever the circuit (a 9-unknown ladder: 3e7 points in 141 s on a loaded
#: machine, 4.7 us a point, where the per-unknown cost alone said 30 s).
NGSPICE_SECONDS_PER_POINT = 3e-6
#: lcchain's memory per saved value per time point: six float64 copies (raw, columns, signals, theory, error).
BYTES_PER_VALUE = 48
#: An optimal design's cost per mass, two-mass (the slower case): 8.6 s at N = 1e5 (benchmarks/foundation.md).
DESIGN_SECONDS_PER_MASS = {"one-mass": 2.5e-5, "two-mass": 9e-5}
#: An optimal design's fixed cost, whatever N: its searches start from scratch (measured: two-mass 0.20-0.22 s
#: at N = 10-100, one-mass 0.025 s; without it `table` with 5000 values was priced at 25 s and ran past 150 s).
DESIGN_SECONDS_FIXED = {"one-mass": 0.03, "two-mass": 0.22}
#: The interpreter's own memory with lcchain, numpy and scipy loaded (ru_maxrss after importing lcchain.runs and
#: lcchain.studies: 84 MiB), counted in every estimate checked against --max-memory.
INTERPRETER_BYTES = 96 * 2**20
#: The interpreter's start with lcchain, numpy and scipy imported, seconds (0.6-0.9 s measured for a command
#: that does no work), counted in every estimate checked against --max-time.
INTERPRETER_SECONDS = 0.8
#: A simulator's own process beside lcchain's (``ngspice -b`` streams its raw file: 12 MiB resident measured
#: for ladders of 20 .. 300 masses).
SIMULATOR_BYTES = 16 * 2**20
#: A study's pool worker beside the driver: a spawned interpreter with lcchain's runs, numpy and scipy imported
#: (84-92 MiB resident measured in sweeps and sensitivity checks); and multiprocessing's resource tracker, once
#: per pool (12 MiB).
POOL_WORKER_BYTES = 96 * 2**20
POOL_TRACKER_BYTES = 16 * 2**20
#: A Dask worker (its interpreter with distributed imported: 111 MiB measured) and the scheduler of a local
#: cluster in the driver (24 MiB more than a pool's driver).
DASK_WORKER_BYTES = 128 * 2**20
DASK_SCHEDULER_BYTES = 32 * 2**20
#: A warm worker (ngspice's shared library in a light interpreter: 23 MiB measured), one per study worker.
WARM_WORKER_BYTES = 32 * 2**20
#: A spawn pool's workers ready, one per core at a time: their interpreters with lcchain's runs imported, and the
#: pool's own start (two on this machine: 3.0 to 3.6 s under a load of 5, where the driver's imports took 1.7 to
#: 1.9 s against the 0.8 s of :data:`INTERPRETER_SECONDS`).
POOL_START_SECONDS = 1.2
#: A Dask local cluster's start beside its workers' imports (its scheduler, nannies and handshakes), seconds.
DASK_START_SECONDS = 2.0


class BudgetError(ParameterError):
    """A request whose estimated cost exceeds the budget (exit status 2, like any bad input)."""


@dataclass(frozen=True)
class Budget:
    """The most one request may use.

    Parameters
    ----------
    max_memory : float
        Bytes of memory, > 0.
    max_seconds : float
        Seconds of wall time, > 0.
    """

    max_memory: float = DEFAULT_MAX_MEMORY
    max_seconds: float = DEFAULT_MAX_SECONDS

    def __post_init__(self) -> None:
        object.__setattr__(self, "max_memory", real("max_memory", self.max_memory, above=0.0, unit="bytes"))
        object.__setattr__(self, "max_seconds", real("max_seconds", self.max_seconds, above=0.0, unit="seconds"))

    def describe(self) -> str:
        return f"{show_bytes(self.max_memory)} and {show_seconds(self.max_seconds)}"


@dataclass(frozen=True)
class Estimate:
    """The estimated cost of a request.

    Attributes
    ----------
    what : str
        What is estimated, in words ("4.3e+10 time points x 3 saved values").
    memory : float
        Bytes.
    seconds : float
        Wall time.
    """

    what: str
    memory: float
    seconds: float

    @property
    def total_memory(self) -> float:
        """The memory with the interpreter's own (:data:`INTERPRETER_BYTES`)."""
        return self.memory + INTERPRETER_BYTES

    @property
    def total_seconds(self) -> float:
        """The wall time with the interpreter's start (:data:`INTERPRETER_SECONDS`)."""
        return self.seconds + INTERPRETER_SECONDS

    def fits(self, budget: Budget) -> bool:
        return self.total_memory <= budget.max_memory and self.total_seconds <= budget.max_seconds

    def check(self, budget: Budget, field: str, value: object, advice: str = "") -> None:
        """Raise :class:`BudgetError` naming ``field`` and ``value`` unless the estimate fits the budget."""
        if self.fits(budget):
            return
        more = f"; {advice}" if advice else ""
        raise BudgetError(field, value, f"a request this machine can afford: {self.what} would take about "
                          f"{show_bytes(self.total_memory)} and {show_seconds(self.total_seconds)}, beyond the "
                          f"limits of {budget.describe()} (--max-memory, --max-time){more}")


def run_estimate(*, points: float, saved: int, compared: int, unknowns: float, exact_N: int = 0) -> Estimate:
    """The cost of one ngspice run and its comparison.

    Parameters
    ----------
    points : float
        Time points (tstop / dt for a fixed step).
    saved : int
        Vectors saved (time excluded).
    compared : int
        Loops compared with theory (0 without a theory).
    unknowns : float
        ngspice's unknowns (about 2 N; 3 N with losses).
    exact_N : int
        N when the theory needs every eigenvector (N x N), else 0.
    """
    memory = BYTES_PER_VALUE * points * (saved + 1 + compared) + 16.0 * exact_N * exact_N
    return Estimate(f"{points:.3g} time points x {saved} saved values", memory,
                    ngspice_seconds(points, unknowns))


#: ngspice's AC analysis: one complex sparse solve per frequency, per unknown (about 2 N, 3 N with losses);
#: measured 1.4e-7 .. 1.5e-7 s for two-mass N = 500 .. 2000 (6,700 .. 26,000 frequencies, under load).
AC_SECONDS_PER_UNKNOWN_FREQUENCY = 1.5e-7
#: ... and per frequency whatever the circuit.
AC_SECONDS_PER_FREQUENCY = 2e-5
#: The fit from theory's poles (:func:`lcchain.compare.spectrum.fit_from_theory`, what a chain's AC run fits, with
#: losses or without): per sample whatever N (each window's least squares on its rows, its far modes' sections)
#: and per sample per mode (the whole model, formed twice a sweep, one or two sweeps), with the reading of the
#: engine's output and the fitted alpha_N(t) beside the exact one.  Measured in-process on ngspice's samples: lossy
#: two-mass N = 100, 200, 400 (1444 .. 5402 samples) 0.04 .. 0.08, 0.10 .. 0.17, 0.25 .. 0.46 s (load 2 to 7),
#: perfect N = 1000 at Q = 1e4 (8072) 0.48 s (load 2); lossless (benchmarks/spectrum.md, everything around the
#: engine) two-mass N = 100 .. 2000 0.057 .. 3.2 s (26092 samples).
THEORY_FIT_SECONDS_PER_SAMPLE = 3e-5
THEORY_FIT_SECONDS_PER_SAMPLE_MODE = 1.5e-7
#: With losses, Y_11 is compared over the whole sweep with the chain's exact admittance, a continued fraction in
#: float64 with a running error bound, in long double where that bound is too wide
#: (:func:`lcchain.compare.spectral.compare_envelope`): per sample per mass, measured 1.4e-8 .. 3.5e-8 (two-mass
#: N = 100 .. 2000 at Q = 1000 and 1e4, perfect N = 400 and 1000 at 1e4; two-mass N = 2000: 1.0 s, load 2); it was
#: 2.0e-7 .. 4.6e-7 in long double everywhere.  The fit's kept sections (at most 64 MiB, samples x modes) are within
#: the memory priced for the fit from the samples (:data:`FIT_BYTES_PER_SAMPLE_SECTION`, the bound used for both).
ENVELOPE_SECONDS_PER_SAMPLE_MODE = 5e-8
#: The fit from the samples alone (:func:`lcchain.compare.spectrum.fit_spectrum`, the rational fits; and a circuit's
#: own poles, :func:`lcchain.compare.poles.fit_poles`): per sample per mode beyond its windows, the model's update
#: in every Gauss-Newton sweep (O(points x N) each) and each window's choice of rows; measured (under load,
#: benchmarks/spectrum.md before the fit from theory) 0.5e-6 .. 1.4e-6 at N = 500 .. 2000.
FIT_SECONDS_PER_SAMPLE_MODE = 6e-7
#: The fit's cost per sample whatever N: its rational fits (pieces of fixed size) and windows' least squares'
#: setup; with losses the rational fits of pieces of 512 samples take up to 256 terms (two-mass N = 100, Q = 100:
#: 0.55 ms a sample, idle).
FIT_SECONDS_PER_SAMPLE = {False: 5e-5, True: 6e-4}
#: The fit's cost per sample per section of a window, and per sample per section squared (Gauss-Newton's
#: Jacobian, samples x 2 or 3 sections, and its least squares): two-mass N = 20 .. 100, 5,000 .. 200,000
#: frequencies, one window of 20 .. 128 sections, 2e-6 and 4e-8 (under load).
FIT_SECONDS_PER_SAMPLE_SECTION = 2e-6
FIT_SECONDS_PER_SAMPLE_SECTION2 = 4e-8
#: The fit's memory per sample per section of its window: the Jacobian's blocks, the Jacobian, its scaled copy
#: and the least squares' own (measured: ru_maxrss - the interpreter's over samples x sections, 160 bytes without
#: losses at 50,000 .. 200,000 frequencies and 20 .. 128 sections; 224 with losses, whose Jacobian has a third
#: block).
FIT_BYTES_PER_SAMPLE_SECTION = {False: 160.0, True: 224.0}
#: Times at which the fitted model's response is set beside the exact one (``lcchain spectrum``): both are
#: (times x N) complex arrays with a few temporaries each.
RESPONSE_TIMES = 2001


def ac_run_estimate(*, points: float, saved: int, unknowns: float) -> Estimate:
    """The simulator's part alone: one AC analysis of ``points`` frequencies and ``unknowns`` unknowns, saving
    ``saved`` complex vectors (a netlist lcchain did not write: nothing is fitted)."""
    seconds = points * (AC_SECONDS_PER_UNKNOWN_FREQUENCY * unknowns + AC_SECONDS_PER_FREQUENCY)
    return Estimate(f"{points:.3g} frequencies x {saved} saved complex values", 2 * BYTES_PER_VALUE * points
                    * (saved + 1), seconds)


def ac_estimate(*, points: float, N: int, sections: float, losses: bool = False, from_theory: bool = False
                ) -> Estimate:
    """The cost of an AC run of lcchain's ladder and its comparison (``lcchain spectrum``, and each AC run of a
    study): ngspice's AC analysis of ``points`` frequencies, the fit, and the exact modes and response it is
    compared with.

    Parameters
    ----------
    points : float
        Frequencies of the sweep.
    N : int
        Masses (loops): 2 N unknowns, 3 N with losses (a node between each coil and its resistor).
    sections : float
        The most sections one Gauss-Newton step of the fit from the samples moves at once (its matrices are points
        x sections: :func:`lcchain.compare.spectrum.fit_sections` says how many): the memory of either fit (a bound
        of the fit from theory's, whose windows hold fewer), and the fit's time unless ``from_theory``.
    losses : bool
    from_theory : bool
        The fit starts from theory's poles (:data:`THEORY_FIT_SECONDS_PER_SAMPLE`, and with losses the envelope's
        :data:`ENVELOPE_SECONDS_PER_SAMPLE_MODE`); else it is made from the samples alone (the rational fits).
    """
    unknowns = (3 if losses else 2) * N
    engine = ac_run_estimate(points=points, saved=2, unknowns=unknowns)
    if from_theory:
        fit = points * (THEORY_FIT_SECONDS_PER_SAMPLE + THEORY_FIT_SECONDS_PER_SAMPLE_MODE * N
                        + (ENVELOPE_SECONDS_PER_SAMPLE_MODE * N if losses else 0.0))
    else:
        fit = points * (FIT_SECONDS_PER_SAMPLE[losses] + FIT_SECONDS_PER_SAMPLE_MODE * N
                        + FIT_SECONDS_PER_SAMPLE_SECTION * sections + FIT_SECONDS_PER_SAMPLE_SECTION2 * sections**2)
    seconds = engine.seconds + fit + 3e-10 * N**3  # exact modes
    # ngspice's process; the fit's matrices; the exact modes (eigh: the matrix, its eigenvectors, workspace); the
    # fitted and the exact responses (times x N complex, each with its temporaries)
    memory = (engine.memory + SIMULATOR_BYTES + FIT_BYTES_PER_SAMPLE_SECTION[losses] * points * sections + 32.0 * N * N
              + 16.0 * 6 * RESPONSE_TIMES * N)
    return Estimate(f"{points:.3g} frequencies x {unknowns} unknowns, fitted {sections:.0f} sections at a time",
                    memory, seconds)


#: pandas and xarray (or matplotlib) imported for an export: about 55 MiB beside the interpreter, and their start
#: (1.1 to 1.3 s measured under a load of 5).
EXPORT_IMPORT_BYTES = 64 * 2**20
EXPORT_IMPORT_SECONDS = 1.5
#: Copies of the dataset's waveform variables held at once while a netCDF file is written: the variables and the
#: writer's own copy (ru_maxrss 3981 MiB for a 1.7 GB grid of waveforms: 2.3 times).
EXPORT_COPIES = 2.5
#: A study's dataset table: bytes per point of its grid (some 30 columns of 8 bytes, as a frame, its grid and
#: the written copy).
EXPORT_BYTES_PER_CELL = 768.0
#: Bytes in memory per byte of the stored metrics' JSON once parsed (Python floats, lists, dicts), and again per
#: byte of a --json or --csv text built from them.
METRICS_BYTES_PER_BYTE = 8.0
TEXT_BYTES_PER_BYTE = 3.0
#: What an export reads, builds and writes per second (the waveforms of 259 x 259 corners, 1.7 GB, in 20 s under
#: load: 85 MB/s).
EXPORT_BYTES_PER_SECOND = 5e7


def export_estimate(*, runs: int, cells: int, metrics: float, stored: float = 0.0, dense: float = 0.0,
                    files: bool = False, text: bool = False) -> Estimate:
    """The cost of ``lcchain results``: the store's runs read (their metrics parsed), and what is made of them.

    Parameters
    ----------
    runs : int
        Runs read.
    cells : int
        Points of the dataset's grid (the product of the study's dimensions' sizes).
    metrics : float
        Bytes of the stored metrics' JSON.
    stored : float
        Bytes of the saved arrays read back for ``--waveforms``.
    dense : float
        Bytes of the dataset's waveform variables (cells x the longest array x every vector's bytes per value).
    files : bool
        A file made with pandas, xarray or matplotlib (``--netcdf``, ``--parquet``, ``--plot``).
    text : bool
        ``--json`` or ``--csv``: the whole text built before it is written.
    """
    memory = (METRICS_BYTES_PER_BYTE * metrics + (TEXT_BYTES_PER_BYTE * metrics if text else 0.0)
              + (EXPORT_IMPORT_BYTES + EXPORT_BYTES_PER_CELL * cells if files else 0.0)
              + stored + EXPORT_COPIES * dense)
    seconds = (EXPORT_IMPORT_SECONDS if files else 0.0) + (metrics * (1.0 + text) + stored + 2.0 * dense
                                                           + EXPORT_BYTES_PER_CELL * cells) / EXPORT_BYTES_PER_SECOND
    what = f"{runs} runs" + (f" and their waveforms on a grid of {cells} points" if dense else "")
    return Estimate(what, memory, seconds)


def ngspice_seconds(points: float, unknowns: float) -> float:
    """ngspice's wall time for a run of ``points`` time points and ``unknowns`` unknowns."""
    return points * (NGSPICE_SECONDS_PER_UNKNOWN_POINT * unknowns + NGSPICE_SECONDS_PER_POINT)


def max_points(budget: Budget, *, saved: int, compared: int, unknowns: float) -> float:
    """The most time points one run may have within the budget (memory and time alike); at least one, so that a
    budget the interpreter alone exhausts is refused by the caller's check, not divided by."""
    return max(1.0, min(max(budget.max_memory - INTERPRETER_BYTES, 0.0) / (BYTES_PER_VALUE * (saved + 1 + compared)),
               max(budget.max_seconds - INTERPRETER_SECONDS, 0.0) / ngspice_seconds(1.0, unknowns)))


def design_estimate(case: str, N: int) -> Estimate:
    """The cost of an optimal design of N masses (memory: a few dozen arrays of N floats)."""
    return Estimate(f"the {case} design of {N} masses", 400.0 * N,
                    DESIGN_SECONDS_FIXED[case] + DESIGN_SECONDS_PER_MASS[case] * N)


#: A run's fixed cost beyond its time points: ngspice's start, reading its raw file, the record (about 15 ms).
RUN_START_SECONDS = 0.02


def sample_theory_seconds(N: int) -> float:
    """The theory of one realised chain (a tolerance sample): its exact modes (eigh, about 3e-10 N^3 s) and the
    comparison with the arrivals' refinement (about 50 ms at N = 50: a 2000-sample scene priced without it at
    0.14 s ran 119 s); an AC run's frequencies refined in extended precision
    (:func:`lcchain.theory.exact.sharp_frequencies`, about 1e-6 N^2 s: 3.7 s at N = 2000 on a loaded machine) and
    certified in double-double with the weights from them (:mod:`lcchain.theory.reference`; benchmarks/reference.md,
    N = 2000 under a load of 9: bisection 10.3 s, certification 6.1 s, weights 0.6 s: 4e-6 N^2 s in all)."""
    return 0.05 + 3e-10 * N**3 + 4e-6 * N**2 + 2e-4 * N


def accuracy_plan_seconds(N: int) -> float:
    """Choosing a run's step for an accuracy (:func:`lcchain.compare.extrapolate.plan_for_accuracy`: the
    extrapolated error predicted at trial steps, each a cosine sum over the modes): measured under load 0.08 s at
    N = 12, 0.27 s at 50, 0.87 s at 200 per request.  A sensitivity check plans two requests per component and a
    worst case one per corner: 259 corners of N = 50 planned for a minute no price counted."""
    return 0.05 + 5e-3 * N


def sensitivity_estimate(N: int) -> Estimate:
    """The first-arrival peak's sensitivities to every component of N masses
    (:func:`lcchain.theory.sensitivity.peak_sensitivity`): every eigenvector and four dense N x N products,
    O(N^3): 0.03 s at N = 200, 0.71 s at 1000, 5.3 s at 2000 (measured under load); about ten N x N arrays."""
    return Estimate(f"the sensitivities of {N} masses", 80.0 * N * N, 0.02 + 7e-10 * N**3)


def worst_case_search_estimate(N: int, parts: int) -> Estimate:
    """A worst-case search over the tolerance box of ``parts`` components of N masses
    (:func:`lcchain.theory.worst_case.worst_case_search`): up to about 60 exact evaluations per part (the
    Hessian's 2 per part, then the starts' L-BFGS-B and flip searches), each a peak and its sensitivities,
    O(N^3), then the branch and bound on the quadratic model (up to
    :data:`lcchain.core.limits.WORST_CASE_MODEL_NODES` boxes of O(parts^2) each).  Measured under load:
    640 evaluations in 0.6 s at N = 9, 4850 in 16 s at N = 50; 40,000 boxes of 99 parts in 4.1 s."""
    evaluations = 60 * parts
    return Estimate(f"a worst-case search over {parts} parts of {N} masses (about {evaluations} evaluations)",
                    80.0 * N * N + 64.0 * parts * parts + 40.0 * parts * WORST_CASE_MODEL_NODES,
                    evaluations * (6e-4 + 2e-5 * N + 2e-8 * N**3)
                    + WORST_CASE_MODEL_NODES * (3e-5 + 1e-8 * parts**2))


def chain_seconds(case: str, N: int) -> float:
    """Making a named case's chain and its modes before a run is planned: its design, if any, and the modes."""
    design = (design_estimate(case, N).seconds if case in DESIGN_SECONDS_PER_MASS
              else _CASE_SECONDS[case](N) if case in _CASE_SECONDS else 0.0)
    return design + 2e-4 * N


#: Making a named case's chain that is no optimised design (those: :data:`DESIGN_SECONDS_PER_MASS`), seconds; a
#: case not here (a uniform chain, a custom one) costs nothing to make.
_CASE_SECONDS: dict[str, Callable[[int], float]] = {"perfect": lambda N: perfect_estimate(N, 0).seconds}


def perfect_estimate(N: int, walls: int) -> Estimate:
    """The cost of a perfect cradle, O(N^2) (benchmarks/perfect.md: free N = 20000 in 23 s, walls about twice).
    """
    what = f"the perfect cradle of {N} masses" + (f" with walls (j = {walls})" if walls else "")
    return Estimate(what, 8.0 * 512 * N + 2**20 * 8.0 + 400.0 * N, (1.3e-7 if walls else 6e-8) * N * N)


def show_bytes(value: float) -> str:
    """1.9 TiB, 512 MiB, 3 kB."""
    for unit, size in (("TiB", 2.0**40), ("GiB", 2.0**30), ("MiB", 2.0**20), ("kiB", 2.0**10)):
        if value >= size:
            return f"{value / size:.3g} {unit}"
    return f"{value:.0f} B"


def show_seconds(value: float) -> str:
    """13 days, 4.2 h, 12 min, 3.1 s."""
    if not math.isfinite(value):
        return "forever"
    for unit, size in (("days", 86400.0), ("h", 3600.0), ("min", 60.0)):
        if value >= size:
            return f"{value / size:.3g} {unit}"
    return f"{value:.2g} s"
