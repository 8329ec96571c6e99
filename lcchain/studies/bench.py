"""``lcchain bench accuracy``: what each digit of accuracy costs, per method and size.

On the optimal two-mass chains (:func:`lcchain.theory.cases.chain_for_case`) and
over one transit (t up to :func:`lcchain.theory.arrivals.stop_time` (modes, 1)),
the sweep runs

* ngspice, trap and gear, *fixed* stepping: maximum step dt (the netlist
  lcchain writes), dt swept;
* ngspice, trap and gear, *adaptive* stepping: no maximum step beyond
  tstop/50 (ngspice's own default), reltol in {1e-3, 1e-5};
* ngspice, trap, *extrapolated*: pairs and triples of aligned runs at dt,
  dt/2[, dt/4] combined (:mod:`lcchain.compare.extrapolate`), dt swept;
  their wall time is the runs' ngspice times summed;
* scipy's DOP853 on the 2N-dimensional ladder ODE, rtol swept;
* the exact modal sum (the reference itself: its "error" is its rounding,
  the split cosine sum against direct evaluation).

Each record holds method, stepping, N, dt or rtol, wall_s, error (max over
both ends of |signal - exact theory| at the method's points) and points.
Results go to ``records.csv``, ``records.json``, ``pareto.png`` and
``summary.md`` (cost table and fitted models) in the output folder.

This module orchestrates: every ngspice run is a
:class:`~lcchain.runs.spec.RunSpec` executed by :func:`lcchain.runs.execute.execute`,
and the adaptive netlist is lcchain's own with ``stepping="adaptive"``.  The
files (records.csv, records.json, pareto.png, summary.md) are written by
:func:`lcchain.report.bench.write_accuracy_bench`.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Mapping, Sequence
from typing import TypedDict

import numpy as np

from ..circuit.ladder import Ladder
from ..circuit.netlist import Drive, NetlistOutput, SimulationOptions, netlist_text, probe_names
from ..compare.accuracy import predicted_error
from ..core.blas import fixed_blas_threads
from ..core.budget import RUN_START_SECONDS, Estimate, chain_seconds, ngspice_seconds, run_estimate
from ..core.errors import SimulationError
from ..core.types import DEFAULT_C0, DEFAULT_I0, DEFAULT_L0, METHODS, Method
from ..runs.execute import RunRecord, execute
from ..runs.simulate import ChainOptions, simulate
from ..runs.spec import RunSpec, Theory
from ..spice.ngspice.find import find_simulator
from ..spice.simulator import Simulator
from ..theory.arrivals import stop_time
from ..theory.cases import chain_for_case
from ..theory.chain import Chain
from ..theory.exact import tridiagonal
from ..theory.modes import Modes, cosine_sum
from ..theory.spectrum import normal_modes

__all__ = ["bench_accuracy", "bench_estimate", "ngspice_record", "extrapolated_record", "dop853_record", "modal_record",
           "ladder_energy", "summarise",
           "summary_markdown", "record_label", "FULL_N", "QUICK_N", "RECORD_FIELDS"]

FULL_N = (20, 100, 1000)
QUICK_N = (20, 100)
#: Fixed steps swept (units of sqrt(L0 C0)); gear needs about half trap's step for the same error.
FIXED_DT = {"trap": (0.4, 0.2, 0.1, 0.05, 0.02, 0.01, 0.005), "gear": (0.4, 0.2, 0.1, 0.05, 0.02, 0.01, 0.005, 0.0025)}
QUICK_DT = {"trap": (0.2, 0.1, 0.05, 0.02, 0.01, 0.005), "gear": (0.2, 0.1, 0.05, 0.02, 0.01)}
ADAPTIVE_RELTOL = (1e-3, 1e-5)
#: Coarsest steps of the extrapolated runs (pairs, triples: :mod:`lcchain.compare.extrapolate`).
EXTRAPOLATED_DT = {2: (0.2, 0.1, 0.05, 0.025, 0.0125), 3: (0.4, 0.2, 0.1, 0.05, 0.025)}
QUICK_EXTRAPOLATED_DT = {2: (0.1, 0.05), 3: (0.2, 0.1)}
#: The stepping column of an extrapolated record (its label: "trap pair", "trap triple").
EXTRAPOLATED_LABEL = {2: "pair", 3: "triple"}
#: The full sweep also tries a tight reltol, to see whether adaptive stepping ever pays.
FULL_ADAPTIVE_RELTOL = (1e-3, 1e-5, 1e-7)
DOP853_RTOL = (1e-4, 1e-6, 1e-8, 1e-10, 1e-12)
QUICK_DOP853_RTOL = (1e-4, 1e-7, 1e-10)
#: Points per unit time at which DOP853 (dense output) and the modal sum are evaluated.
PEER_GRID_STEP = 0.05
ACCURACY_TARGETS = (1e-3, 1e-5)
TARGET_N = (100, 1000)
L0, C0, I0 = DEFAULT_L0, DEFAULT_C0, DEFAULT_I0

class BenchRecord(TypedDict):
    """One run of the accuracy bench: how it was made, what it cost and how far it is from exact theory."""

    method: str
    stepping: str
    N: int
    dt: float | None
    rtol: float | None
    wall_s: float
    error: float
    points: int
    predicted_error: float | None


class TargetCheck(TypedDict):
    """``simulate(accuracy=eps)`` against the cheapest fixed step of the sweep that met eps."""

    N: int
    accuracy: float
    dt: float
    runs: int
    error: float
    predicted_error: float | None
    integration_error: float | None
    wall_s: float
    points: int
    cheapest_fixed_dt: float | None
    cheapest_fixed_wall_s: float | None
    wall_ratio: float | None
    met: bool


class BenchSummary(TypedDict):
    """The fitted models (``fits``: ``error_c`` and ``cost_k`` by ``"method N=..."``), the cost of each accuracy
    target by method and N (``cost``: seconds by ``f"{eps:g}"``, and ``best_error``), and the target checks."""

    fits: dict[str, dict[str, float]]
    cost: dict[str, dict[str, float | None]]
    targets: list[TargetCheck]


class BenchDocument(TypedDict):
    """What :func:`bench_accuracy` measured, and its summary as a Markdown table: the JSON document the bench
    writes, typed (not a result class of its own)."""

    records: list[BenchRecord]
    targets: list[TargetCheck]
    summary: BenchSummary
    markdown: str


class LadderEnergy(TypedDict):
    """:func:`ladder_energy`: its arrays against ``t`` (units of sqrt(L0 C0)), and the simulator's seconds."""

    t: np.ndarray
    energy: np.ndarray
    momentum: np.ndarray
    wall_s: float


class _Params(TypedDict, total=False):
    """The keywords of one run of the sweep, as its solver takes them."""

    method: Method
    dt: float
    reltol: float
    runs: int
    rtol: float


#: The bench's columns, from :class:`BenchRecord` (stated once).
RECORD_FIELDS: tuple[str, ...] = tuple(BenchRecord.__annotations__)


# ------------------------------------------------------------------ one run of each kind
def _exact_error(modes: Modes, t: np.ndarray, first: np.ndarray, last: np.ndarray) -> float:
    e_first = np.max(np.abs(first - cosine_sum(modes.density, modes.omega, t)))
    e_last = np.max(np.abs(last - cosine_sum(modes.transfer, modes.omega, t)))
    return float(max(e_first, e_last))


def _checked(record: RunRecord) -> RunRecord:
    if not record.ok:
        raise SimulationError(record.reason, record.log_tail, record.status)
    return record


@fixed_blas_threads
def ngspice_record(chain: Chain, modes: Modes, *, method: Method, dt: float | None = None,
                   reltol: float = 1e-3, transits: int = 1, simulator: Simulator | None = None) -> BenchRecord:
    """One ngspice run: fixed maximum step ``dt``, or adaptive (dt None: ngspice's own steps up to tstop/50)."""
    tstop = stop_time(modes, transits)
    ladder = Ladder(chain, L0, C0)
    options = SimulationOptions(dt=dt if dt is not None else 0.1, tstop=tstop, method=method, reltol=reltol,
                                stepping="fixed" if dt is not None else "adaptive")
    text = netlist_text(ladder, options, Drive(I0=I0), output=NetlistOutput(title=f"lcchain bench N={chain.N}"))
    theory = Theory(chain, ladder.time_unit, I0=I0, transits=transits, method=method, modes=modes)
    record = _checked(execute(RunSpec(text, tuple(probe_names(chain.N)), tstop * ladder.time_unit, theory=theory,
                                      foreign=False), simulator))
    assert record.run is not None and record.metrics is not None
    return {
        "method": method, "stepping": options.stepping, "N": chain.N,
        "dt": dt, "rtol": reltol if dt is None else None, "wall_s": record.wall_s,
        "error": max(record.metrics.max_abs_error_first, record.metrics.max_abs_error_last),
        "points": record.run.points,
        "predicted_error": predicted_error(modes, dt, tstop, method=method) if dt is not None else None,
    }


def extrapolated_record(chain: Chain, modes: Modes, *, runs: int, dt: float, transits: int = 1,
                        simulator: Simulator | None = None) -> BenchRecord:
    """Runs at dt, dt/2[, dt/4] combined (:mod:`lcchain.compare.extrapolate`); wall: the runs' ngspice times summed
    (what they cost on one core: ``simulate`` runs two at a time)."""
    options = ChainOptions(dt=dt, extrapolate=runs, transits=transits, L0=L0, C0=C0, I0=I0)
    report = simulate(options.request(chain), modes=modes, simulator=simulator)
    x = report.extrapolation
    assert x is not None and x.runs == runs
    return {
        "method": "trap", "stepping": EXTRAPOLATED_LABEL[runs], "N": chain.N, "dt": dt, "rtol": None,
        "wall_s": sum(m.wall_s for m in x.members),
        "error": max(report.comparison.max_abs_error_first, report.comparison.max_abs_error_last),
        "points": sum(m.run.points for m in x.members if m.run is not None),
        "predicted_error": report.predicted_error,
    }


def _ladder_ode(chain: Chain) -> Callable[[float, np.ndarray], np.ndarray]:
    diagonal, off = tridiagonal(chain)

    def rhs(_t: float, y: np.ndarray) -> np.ndarray:
        n = diagonal.size
        q, p = y[:n], y[n:]
        acc = -diagonal * q
        acc[:-1] -= off * q[1:]
        acc[1:] -= off * q[:-1]
        return np.concatenate((p, acc))

    return rhs


def dop853_record(chain: Chain, modes: Modes, *, rtol: float, transits: int = 1) -> BenchRecord:
    """scipy's DOP853 on q'' = -B q (mass-weighted coordinates), kick of mass 1.

    The end signals are velocity ratios: p_1 and p_N sqrt(m_1/m_N) for
    p_1(0) = 1; they are read from the dense output on a grid of step
    :data:`PEER_GRID_STEP` (the error between the solver's steps counts).
    """
    from scipy.integrate import solve_ivp

    N = chain.N
    tstop = stop_time(modes, transits)
    y0 = np.zeros(2 * N)
    y0[N] = 1.0
    grid = np.linspace(0.0, tstop, int(math.ceil(tstop / PEER_GRID_STEP)) + 1)
    start = time.perf_counter()
    sol = solve_ivp(_ladder_ode(chain), (0.0, tstop), y0, method="DOP853", rtol=rtol, atol=rtol * 1e-3, t_eval=grid)
    wall = time.perf_counter() - start
    first = sol.y[N]
    last = sol.y[2 * N - 1] * math.sqrt(chain.masses[0] / chain.masses[-1])
    return {"method": "DOP853", "stepping": "adaptive", "N": N, "dt": None, "rtol": rtol, "wall_s": wall,
            "error": _exact_error(modes, sol.t, first, last), "points": int(sol.nfev // 12),
            "predicted_error": None}


def modal_record(chain: Chain, transits: int = 1) -> BenchRecord:
    """The modal sum itself: modes plus both end signals on a grid of step :data:`PEER_GRID_STEP`."""
    start = time.perf_counter()
    modes = normal_modes(chain)
    tstop = stop_time(modes, transits)
    grid = np.linspace(0.0, tstop, int(math.ceil(tstop / PEER_GRID_STEP)) + 1)
    first = np.asarray(cosine_sum(modes.density, modes.omega, grid))
    last = np.asarray(cosine_sum(modes.transfer, modes.omega, grid))
    wall = time.perf_counter() - start
    # Its error is rounding: the split evaluation against the direct one at a few points.
    pick = grid[:: max(1, grid.size // 50)]
    direct = np.cos(np.multiply.outer(pick, modes.omega))
    rounding = max(np.max(np.abs(first[:: max(1, grid.size // 50)] - direct @ modes.density)),
                   np.max(np.abs(last[:: max(1, grid.size // 50)] - direct @ modes.transfer)),
                   abs(float(np.sum(modes.density)) - 1.0), 1e-16)
    return {"method": "modal sum", "stepping": "exact", "N": chain.N, "dt": PEER_GRID_STEP, "rtol": None,
            "wall_s": wall, "error": float(rounding), "points": int(grid.size), "predicted_error": None}


def ladder_energy(chain: Chain, *, method: Method, dt: float, transits: int, L0: float = L0, C0: float = C0,
                  I0: float = I0, simulator: Simulator | None = None) -> LadderEnergy:
    """Energy and momentum of the ladder over a run, from every loop current and node voltage.

    Returns
    -------
    dict
        ``t`` (units of sqrt(L0 C0)), ``energy`` (sum L I^2/2 + sum C V^2/2
        over the initial L_1 I0^2/2) and ``momentum`` (sum L_i I_i over
        L_1 I0: constant for a free chain, the zero mode), ``wall_s``.
    """
    modes = normal_modes(chain)
    tstop = stop_time(modes, transits)
    ladder = Ladder(chain, L0, C0)
    caps = [(i, c) for i, c in enumerate(ladder.capacitances()) if c is not None]
    volts = tuple(f"v({ladder.node(i)})" for i, _ in caps)
    currents = tuple(probe_names(chain.N, "all"))
    text = netlist_text(ladder, SimulationOptions(dt=dt, tstop=tstop, method=method), Drive(I0=I0),
                        output=NetlistOutput(probes="all", extra_vectors=volts, title=f"lcchain energy N={chain.N}"))
    record = _checked(execute(RunSpec(text, currents + volts, tstop * ladder.time_unit, foreign=False), simulator))
    run = record.run
    assert run is not None
    L = np.array(ladder.inductances())
    current = np.array([run.vectors[name] for name in currents])
    voltage = np.array([run.vectors[name] for name in volts])
    C = np.array([c for _, c in caps])
    energy = 0.5 * (L @ (current * current)) + 0.5 * (C @ (voltage * voltage))
    return {"t": np.asarray(run.time) / ladder.time_unit, "energy": energy / (0.5 * L[0] * I0 * I0),
            "momentum": (L @ current) / (L[0] * I0), "wall_s": run.wall_s}


# ------------------------------------------------------------------ the sweep
def _plan(Ns: Sequence[int], quick: bool) -> list[tuple[str, int, _Params]]:
    jobs: list[tuple[str, int, _Params]] = []
    dts = QUICK_DT if quick else FIXED_DT
    for N in Ns:
        for method in METHODS:
            jobs += [("ngspice", N, {"method": method, "dt": dt}) for dt in dts[method]]
            jobs += [("ngspice", N, {"method": method, "reltol": r})
                     for r in (ADAPTIVE_RELTOL if quick else FULL_ADAPTIVE_RELTOL)]
        for runs, steps in (QUICK_EXTRAPOLATED_DT if quick else EXTRAPOLATED_DT).items():
            jobs += [("extrapolated", N, {"runs": runs, "dt": dt}) for dt in steps]
        jobs += [("dop853", N, {"rtol": r}) for r in (QUICK_DOP853_RTOL if quick else DOP853_RTOL)]
        jobs.append(("modal", N, {}))
    return jobs


def bench_estimate(Ns: Sequence[int] | None = None, *, quick: bool = False, targets: bool | None = None) -> Estimate:
    """What :func:`bench_accuracy` will cost, from its plan alone (one transit of about 1.2 N per run; adaptive
    runs priced at dt = 0.05; DOP853 and the modal sum as a run at dt = 0.05; each accuracy target as the
    cheapest fixed step meeting it, about 0.3 dt^2 = eps)."""
    Ns = tuple(Ns) if Ns else (QUICK_N if quick else FULL_N)
    targets = (not quick) if targets is None else targets

    def run(N: int, dt: float) -> float:
        return ngspice_seconds(1.2 * (N + 5) / dt, 2 * N) + RUN_START_SECONDS

    seconds = sum(chain_seconds("two-mass", N) for N in Ns)
    for kind, N, params in _plan(Ns, quick):
        dt = params.get("dt") or 0.05
        members = (1.0, 0.5, 0.25)[:params["runs"]] if kind == "extrapolated" else (1.0,)
        seconds += sum(run(N, dt * m) for m in members)
    if targets:
        seconds += sum(2 * run(N, math.sqrt(eps / 0.3)) for eps in ACCURACY_TARGETS for N in TARGET_N if N in Ns)
    memory = max(run_estimate(points=1.2 * (N + 5) / 0.0025, saved=2, compared=2, unknowns=2 * N,
                              exact_N=N).memory for N in Ns)  # its finest run saves the two end loops
    return Estimate(f"the accuracy bench at N = {', '.join(map(str, Ns))}", memory, seconds)


def bench_accuracy(Ns: Sequence[int] | None = None, *, quick: bool = False, targets: bool | None = None,
                   progress: Callable[[int, int, str], None] | None = None,
                   simulator: Simulator | None = None) -> BenchDocument:
    """Run the sweep (the files are written by :func:`lcchain.report.bench.write_accuracy_bench`).

    Parameters
    ----------
    Ns : sequence of int, optional
        Chain sizes (default 20, 100, 1000; quick: 20, 100).
    quick : bool
        Fewer steps and tolerances (under 2 minutes).
    targets : bool, optional
        Also check ``simulate(accuracy=eps)`` against the cheapest fixed step
        for eps in {1e-3, 1e-5} and N in {100, 1000} (default: not quick).
    progress : callable, optional
        Called as ``progress(done, total, label)`` before each run and at
        the end (the CLI draws it as a bar on a terminal).
    simulator : Simulator, optional
        Found once by the caller (batch backend); found here when omitted.

    Returns
    -------
    dict
        ``records`` (list of dict), ``targets`` (list of dict), ``summary``
        (dict) and ``markdown`` (the summary table).
    """
    Ns = tuple(Ns) if Ns else (QUICK_N if quick else FULL_N)
    targets = (not quick) if targets is None else targets
    simulator = simulator if simulator is not None else find_simulator("batch")

    def show(done: int, total: int, label: str) -> None:
        if progress is not None:
            progress(done, total, label)

    chains = {N: chain_for_case("two-mass", N) for N in Ns}
    modes = {N: normal_modes(chains[N]) for N in Ns}
    jobs = _plan(Ns, quick)
    target_jobs = [(eps, N) for eps in ACCURACY_TARGETS for N in TARGET_N if N in Ns] if targets else []
    total = len(jobs) + len(target_jobs)
    records: list[BenchRecord] = []
    solvers: dict[str, Callable[[int, _Params], BenchRecord]] = {
        "ngspice": lambda N, params: ngspice_record(chains[N], modes[N], simulator=simulator, method=params["method"],
                                                    dt=params.get("dt"), reltol=params.get("reltol", 1e-3)),
        "extrapolated": lambda N, params: extrapolated_record(chains[N], modes[N], simulator=simulator,
                                                              runs=params["runs"], dt=params["dt"]),
        "dop853": lambda N, params: dop853_record(chains[N], modes[N], rtol=params["rtol"]),
        "modal": lambda N, params: modal_record(chains[N]),
    }
    for k, (solver, N, params) in enumerate(jobs):
        show(k, total, f"{solver} N={N} {params}")
        records.append(solvers[solver](N, params))
    checks = []
    for k, (eps, N) in enumerate(target_jobs):
        show(len(jobs) + k, total, f"--accuracy {eps:g} N={N}")
        checks.append(_target_check(chains[N], modes[N], eps, records, simulator))
    show(total, total, "done")
    summary = summarise(records, checks)
    return {"records": records, "targets": checks, "summary": summary, "markdown": summary_markdown(summary)}


def _target_check(chain: Chain, modes: Modes, eps: float, records: list[BenchRecord],
                  simulator: Simulator) -> TargetCheck:
    report = simulate(ChainOptions(accuracy=eps, transits=1).request(chain), modes=modes, simulator=simulator)
    fixed = [r for r in records if r["method"] == "trap" and r["stepping"] == "fixed" and r["N"] == chain.N
             and r["error"] <= eps]
    cheapest = min(fixed, key=lambda r: r["wall_s"]) if fixed else None
    wall = report.wall_s  # every run's ngspice time
    assert report.extrapolation is not None  # an accuracy asked for: its plan chose the runs
    return {
        "N": chain.N, "accuracy": eps, "dt": report.options.dt, "runs": report.extrapolation.runs,
        "error": report.comparison.max_abs_error,
        "predicted_error": report.predicted_error, "integration_error": report.integration_error,
        "wall_s": wall, "points": report.points,
        "cheapest_fixed_dt": cheapest["dt"] if cheapest else None,
        "cheapest_fixed_wall_s": cheapest["wall_s"] if cheapest else None,
        "wall_ratio": wall / cheapest["wall_s"] if cheapest else None,
        "met": bool(report.comparison.max_abs_error <= eps and (cheapest is None or wall <= 1.5 * cheapest["wall_s"])),
    }


# ------------------------------------------------------------------ models and summary
def record_label(record: BenchRecord | Mapping[str, object]) -> str:
    method = record["method"]
    return method if method in ("DOP853", "modal sum") else f"{method} {record['stepping']}"


def summarise(records: Sequence[BenchRecord], checks: Sequence[TargetCheck] = ()) -> BenchSummary:
    """Fitted error and cost models and the cost of 1e-3 and 1e-5 per method and N.

    Error model (fixed steps): error = c dt^2, c the median of error/dt^2 over
    dt <= 0.1.  Cost model: wall = k N points, points ~ (N + s)/dt (k per
    loop per time point; ngspice's unknowns are about 2N, so k/2 per unknown),
    fitted on the largest N (start-up costs dominate small runs).
    """
    fits: dict[str, dict[str, float]] = {"error_c": {}, "cost_k": {}}
    for method in METHODS:
        for N in sorted({r["N"] for r in records}):
            rs = [r for r in records if r["method"] == method and r["stepping"] == "fixed" and r["N"] == N]
            ratios = [r["error"] / dt ** 2 for r in rs if (dt := r["dt"]) is not None and dt <= 0.1]
            if ratios:
                fits["error_c"][f"{method} N={N}"] = float(np.median(ratios))
            costs = [r["wall_s"] / (N * r["points"]) for r in rs if r["wall_s"] > 0.5]
            if costs:
                fits["cost_k"][f"{method} N={N}"] = float(np.median(costs))
    cost: dict[str, dict[str, float | None]] = {}
    for label in sorted({record_label(r) for r in records}):
        for N in sorted({r["N"] for r in records if record_label(r) == label}):
            rs = [r for r in records if record_label(r) == label and r["N"] == N]
            row: dict[str, float | None] = {}
            for eps in ACCURACY_TARGETS:
                ok = [r for r in rs if r["error"] <= eps]
                row[f"{eps:g}"] = min(r["wall_s"] for r in ok) if ok else None
            row["best_error"] = min(r["error"] for r in rs)
            cost[f"{label} N={N}"] = row
    return {"fits": fits, "cost": cost, "targets": list(checks)}


def _fmt(value: float | None, spec: str = ".3g") -> str:
    return "–" if value is None else format(value, spec)


def summary_markdown(summary: BenchSummary) -> str:
    lines = ["| method | N | 1e-3 costs (s) | 1e-5 costs (s) | best error |", "|---|---:|---:|---:|---:|"]
    for key, row in summary["cost"].items():
        label, N = key.rsplit(" N=", 1)
        lines.append(f"| {label} | {N} | {_fmt(row['0.001'])} | {_fmt(row['1e-05'])} | {row['best_error']:.2e} |")
    lines += ["", "Cheapest measured run whose error (max over both ends, one transit) is within the target; "
              "– = no run of the sweep reached it.", "", "| fit | value |", "|---|---:|"]
    for key, c in summary["fits"]["error_c"].items():
        lines.append(f"| error / dt^2, {key} | {c:.3f} |")
    for key, k in summary["fits"]["cost_k"].items():
        lines.append(f"| wall / (N points), {key} | {k * 1e9:.0f} ns |")
    if summary["targets"]:
        lines += ["", "| --accuracy | N | runs | dt | error | wall s | cheapest fixed dt | its wall s | ratio | met |",
                  "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|"]
        for t in summary["targets"]:
            lines.append(f"| {t['accuracy']:g} | {t['N']} | {t.get('runs', 1)} | {t['dt']:.4g} | {t['error']:.3e} | "
                         f"{t['wall_s']:.3g} | "
                         f"{_fmt(t['cheapest_fixed_dt'], 'g')} | {_fmt(t['cheapest_fixed_wall_s'])} | "
                         f"{_fmt(t['wall_ratio'], '.2f')} | {'yes' if t['met'] else 'NO'} |")
    return "\n".join(lines) + "\n"
