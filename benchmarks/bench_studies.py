"""Studies at scale (issue 11): pool against serial, overhead per run, memory over 1000 runs, a Monte Carlo.

Run from the repository root:

    .venv/bin/python benchmarks/bench_studies.py > benchmarks/studies.md

Writes its stores and figures into benchmarks/studies/ (the Monte Carlo's
histogram is committed; the stores are not).
"""

from __future__ import annotations

import os
import platform
import shutil
import statistics
import tempfile
import time
from pathlib import Path

import numpy as np

from lcchain.report.files import save_figure
from lcchain.report.studies import study_figure
from lcchain.studies.options import RunHooks, RunOptions
from lcchain.studies.plan import RealParts, SweepAxes, scene_sweep_plan, sweep_plan
from lcchain.studies.run import Progress, run_plan
from lcchain.studies.store import Store

OUT = Path("benchmarks/studies")


def rss_mib() -> float:
    for line in Path("/proc/self/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024
    return float("nan")


def throughput(N: int, runs: int, executor: str) -> tuple[float, float]:
    """(wall seconds, runs per second after the first finished) of `runs` distinct runs of size N."""
    plan = sweep_plan(SweepAxes(cases=["two-mass"], Ns=[N], dts=list(np.linspace(0.04, 0.05, runs))))
    finished: list[float] = []
    with tempfile.TemporaryDirectory() as folder:
        start = time.perf_counter()
        run_plan(plan, Path(folder) / "t.sqlite", RunOptions(executor=executor, workers=2),
                 RunHooks(progress=lambda p: finished.append(time.perf_counter())))
        wall = time.perf_counter() - start
    steady = (runs - 1) / (finished[-1] - finished[0]) if len(finished) > 1 and finished[-1] > finished[0] else \
        float("nan")
    return wall, steady


def main() -> None:
    OUT.mkdir(parents=True, exist_ok=True)
    print("# Studies at scale\n")
    print("Command: `.venv/bin/python benchmarks/bench_studies.py > benchmarks/studies.md`  ")
    print(f"Machine: {platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}\n")

    print("## Process pool (2 workers, spawn) against serial\n")
    print("Two-mass chains, one transit, dt from 0.04 to 0.05 (distinct runs). Wall time includes starting the "
          "pool: each spawned worker imports numpy, scipy and lcchain's theory, about 0.6 s, while serial runs "
          "start at once; the steady rate is runs per second between the first and the last finished group.\n")
    print("| runs | serial s | process s | speed-up (wall) | speed-up (steady rate) |")
    print("|---|---:|---:|---:|---:|")
    for N, runs in ((100, 20), (300, 12), (100, 60), (300, 36)):
        serial, serial_rate = throughput(N, runs, "serial")
        pool, pool_rate = throughput(N, runs, "process")
        print(f"| {runs} x N = {N} | {serial:.2f} | {pool:.2f} | {serial / pool:.2f} | {pool_rate / serial_rate:.2f} |",
              flush=True)

    print("\n## 1000 runs of N = 20: lcchain's overhead, the driver's memory, the temporary folder\n")
    plan = sweep_plan(SweepAxes(cases=["two-mass"], Ns=[20], dts=list(np.linspace(0.03, 0.05, 1000))))
    memory: dict[int, float] = {}
    walls: list[float] = []

    def watch(progress: Progress) -> None:
        for mark in (100, 1000):
            if progress.done >= mark and mark not in memory:
                memory[mark] = rss_mib()

    scratch = tempfile.mkdtemp(prefix="lcchain-bench-")
    os.environ["TMPDIR"] = scratch  # the workers' temporary folder: it must stay empty
    tempfile.tempdir = scratch
    store = OUT / "thousand.sqlite"
    for suffix in ("", "-wal", "-shm"):
        Path(f"{store}{suffix}").unlink(missing_ok=True)
    start = time.perf_counter()
    run_plan(plan, store, RunOptions(executor="serial"), RunHooks(progress=watch))
    wall = time.perf_counter() - start
    with Store(store) as results:
        runs = results.runs()
    walls = [r.wall_s or 0.0 for r in runs]
    totals = [r.total_s or 0.0 for r in runs]
    overhead = [t - w for t, w in zip(totals, walls, strict=True)]
    left = os.listdir(scratch)
    shutil.rmtree(scratch)
    print("| what | value |")
    print("|---|---:|")
    print(f"| runs, all ok | {len(runs)}, {all(r.status == 'ok' for r in runs)} |")
    print(f"| wall time, serial | {wall:.1f} s |")
    print(f"| ngspice per run (median) | {1e3 * statistics.median(walls):.1f} ms |")
    print(f"| lcchain per run inside `execute` beyond ngspice (median) | {1e3 * statistics.median(overhead):.1f} ms |")
    print(f"| lcchain per run in the driver, beyond execute (store, scheduling) | "
          f"{1e3 * (wall - sum(totals)) / len(runs):.1f} ms |")
    print(f"| driver RSS at run 100 / run 1000 | {memory[100]:.1f} / {memory[1000]:.1f} MiB "
          f"({100 * (memory[1000] / memory[100] - 1):+.1f} %) |")
    print(f"| files left in the temporary folder | {len(left)} |")

    print("\n## Monte Carlo: 1000 samples of the bench scene (N = 50, E24, 5 %, Q = 100, gaussian pulse)\n")
    store = OUT / "montecarlo.sqlite"
    for suffix in ("", "-wal", "-shm"):
        Path(f"{store}{suffix}").unlink(missing_ok=True)
    start = time.perf_counter()
    plan = scene_sweep_plan("examples/scenes/bench.toml", [], RealParts(samples=1000, seed=7))
    planned = time.perf_counter() - start
    summary = run_plan(plan, store, RunOptions(executor="process", workers=2))
    with Store(store) as results:
        figure = study_figure(results)
        peaks = [r.metrics["arrivals"][0]["peak_sim"] for r in results.runs() if r.metrics]
    save_figure(figure, OUT / "montecarlo-histogram.png", dpi=110)
    total = time.perf_counter() - start
    print("Command: `lcchain sweep examples/scenes/bench.toml --samples 1000 --seed 7 --store mc.sqlite` then "
          "`lcchain results mc.sqlite --plot mc.png`.\n")
    print("| what | value |")
    print("|---|---:|")
    print(f"| samples ok / failed | {summary.ok} / {summary.failed} |")
    print(f"| planning (1000 netlists, samples drawn) | {planned:.1f} s |")
    print(f"| end to end, 2 workers, histogram included | {total:.1f} s |")
    print(f"| transmitted peak: mean, std, worst | {np.mean(peaks):.4f}, {np.std(peaks, ddof=1):.4f}, "
          f"{np.min(peaks):.4f} |")
    print("\n![histogram](studies/montecarlo-histogram.png)")


if __name__ == "__main__":
    main()
