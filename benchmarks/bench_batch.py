"""Batches against ngspice itself: ``lcchain batch`` beside ``xargs -P2 ngspice -b``, a bash loop and spicelib.

Run from the repository root, on a quiet machine:

    .venv/bin/python benchmarks/bench_batch.py [--spicelib PYTHON] [--large 10000] > benchmarks/batch.md

``--spicelib PYTHON``: an interpreter with spicelib installed (a benchmark-only dependency, kept out of
lcchain's environment: ``python3 -m venv /tmp/spl && /tmp/spl/bin/pip install spicelib``).  ``--large COUNT``
adds one round of COUNT distinct N = 10 netlists (``lcchain batch --workers 2`` against ``xargs -P2``, the
driver's peak memory beside it); ``--skip-single`` leaves out the table of one run by itself.

Every contender runs the same distinct netlists, written once by lcchain into a temporary folder the way a
user's netlists differ: the chain (the optimal two-mass, the optimal one-mass and the uniform free chain in
turn), the step (0.04 (1 + i / count)) and the title line.  Each time is the wall time of the whole command
(interpreter start, imports, store and all), measured from here, in interleaved rounds (each round runs every
contender once, in a rotated order) so that a change in the machine's load falls on all of them alike; the
table gives the median over the rounds and the load average (1 min) before and after.  lcchain is the installed
``lcchain`` command (the console script beside this interpreter), reading its bytecode as an installed lcchain
does (``PYTHONDONTWRITEBYTECODE`` dropped).  ``xargs`` and the bash loop run ``ngspice -b`` alone: they are the
limit one process per run can reach.  lcchain's foreign netlists run in its sandbox (bubblewrap), which the bare
ngspice contenders do not pay.  The first table measures one run by itself
(``lcchain.spice.ngspice.runner.run``): a new ``ngspice -b`` process against a warm worker, where the crossover that
:data:`lcchain.spice.ngspice.warm.WARM_BELOW_SECONDS` is set from shows.

"runs only" is lcchain's own ``wall_s`` (from the first run's start to the last one stored); the difference
from the whole command is split after each table: the command's fixed start (``lcchain batch --help``: the
interpreter, the imports and the parser), the plan (:func:`lcchain.studies.plan.batch_plan` of the same
netlists, in this process: reading each, the allow-list and the price) and the rest (the store made, the
executor's start and end, the summary).
"""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import platform
import shutil
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from collections.abc import Callable
from pathlib import Path

import lcchain
from lcchain.runs.simulate import ChainOptions, simulation_spec
from lcchain.spice.job import RunJob
from lcchain.spice.ngspice.find import find_simulator
from lcchain.spice.ngspice.runner import run
from lcchain.spice.ngspice.warm import WARM_BELOW_SECONDS, close_workers, warm_simulator
from lcchain.studies.plan import _seconds, batch_plan

ROUNDS = int(os.environ.get("LCCHAIN_BENCH_ROUNDS", "5"))
#: The installed command, as a user runs it.
LCCHAIN = [str(Path(sys.executable).with_name("lcchain"))]
#: Every process may write and read its bytecode, as an installed lcchain does.
ENV = {name: value for name, value in os.environ.items() if name != "PYTHONDONTWRITEBYTECODE"}
#: The chains a user's netlists cycle through.
CASES = ("two-mass", "one-mass", "uniform-free")
SPICELIB = """
import sys, tempfile
from spicelib import SimRunner
from spicelib.simulators.ngspice_simulator import NGspiceSimulator
with tempfile.TemporaryDirectory() as out:
    runner = SimRunner(simulator=NGspiceSimulator, parallel_sims=2, output_folder=out, verbose=False)
    for path in sys.argv[1:]:
        runner.run(path)
    runner.wait_completion()
    assert runner.okSim == len(sys.argv) - 1, (runner.okSim, runner.failSim)
"""


def write_netlists(folder: Path, N: int, count: int) -> list[str]:
    """``count`` distinct netlists of N masses: the chain cycles through :data:`CASES`, the step is
    0.04 (1 + i / count) and the title line names the run."""
    folder.mkdir()
    chains = {case: lcchain.chain_for_case(case, N) for case in CASES}
    paths = []
    for i in range(count):
        case = CASES[i % len(CASES)]
        spec, _, _ = simulation_spec(chains[case], ChainOptions(dt=0.04 * (1 + i / count)))
        title, _, body = spec.netlist.partition("\n")
        path = folder / f"n{i:05d}.cir"
        path.write_text(f"run {i} of a user's study: {case} N={N}\n{body}")
        paths.append(str(path))
    return paths


def per_run_table() -> list[str]:
    batch = find_simulator("batch")
    hot = warm_simulator(batch)
    lines = ["| N | predicted (s) | `ngspice -b` process (ms) | warm worker (ms) | process / warm |",
             "|---:|---:|---:|---:|---:|"]
    for N in (10, 30, 100, 150, 200, 300, 1000):
        spec, _, _ = simulation_spec(lcchain.chain_for_case("two-mass", N), ChainOptions(dt=0.05))
        repeat = 21 if N <= 100 else 7 if N <= 300 else 3
        times: dict[str, list[float]] = {"batch": [], "warm": []}
        run(RunJob(spec.netlist, spec.vectors, spec.tstop, trusted=True, foreign=False), hot)  # worker started
        for _ in range(repeat):
            for name, simulator in (("batch", batch), ("warm", hot)):
                start = time.perf_counter()
                run(RunJob(spec.netlist, spec.vectors, spec.tstop, trusted=True, foreign=False), simulator)
                times[name].append(time.perf_counter() - start)
        b, w = (statistics.median(times[k]) for k in ("batch", "warm"))
        lines.append(f"| {N} | {_seconds(spec):.3f} | {1e3 * b:.1f} | {1e3 * w:.1f} | {b / w:.2f} |")
    close_workers()
    return lines


def timed(command: list[str], cwd: Path) -> tuple[float, dict[str, float]]:
    start = time.perf_counter()
    done = subprocess.run(command, cwd=cwd, capture_output=True, env=ENV)
    wall = time.perf_counter() - start
    if done.returncode != 0:
        raise SystemExit(f"{command[:4]} failed: {done.stderr.decode()[-2000:]}")
    extra = {}
    if b'"wall_s"' in done.stdout:
        extra["in_batch"] = float(json.loads(done.stdout)["wall_s"])
    return wall, extra


def contenders(paths: list[str], work: Path, spicelib: str | None,
               quick: bool) -> dict[str, Callable[[int], list[str]]]:
    ngspice = shutil.which("ngspice") or "ngspice"
    found: dict[str, Callable[[int], list[str]]] = {
        "`xargs -P2 ngspice -b`": lambda r: ["bash", "-c", f'printf "%s\\n" "$@" | xargs -P2 -I{{}} {ngspice} -b '
                                             '-r {}.raw {} >/dev/null 2>&1', "_", *paths],
        "`lcchain batch` (default options: 2 workers)": lambda r: [*LCCHAIN, "batch", *paths, "--json",
                                                                   "--store", str(work / f"w{r}.sqlite")],
        START: lambda r: [*LCCHAIN, "batch", "--help"],
    }
    if quick:
        return found
    found.update({
        "bash loop of `ngspice -b`": lambda r: ["bash", "-c", f'for f in "$@"; do {ngspice} -b -r "$f.raw" "$f" '
                                                '>/dev/null 2>&1 || exit 1; done', "_", *paths],
        "`lcchain batch --transport process`": lambda r: [
            *LCCHAIN, "batch", *paths, "--json", "--transport", "process", "--store", str(work / f"p{r}.sqlite")],
        "`lcchain batch --executor serial`": lambda r: [*LCCHAIN, "batch", *paths, "--executor", "serial",
                                                        "--json", "--store", str(work / f"s{r}.sqlite")],
    })
    if spicelib:
        found["spicelib 1.6.4 `SimRunner(parallel_sims=2)`"] = lambda r: [spicelib, "-c", SPICELIB, *paths]
    return found


#: The fixed start of a command, timed beside the batches: the interpreter, the imports and the parser.
START = "`lcchain batch --help`"


def plan_seconds(paths: list[str]) -> float:
    """The batch's plan made in this process (each netlist read, allowed and priced), median of 3."""
    times = []
    for _ in range(3):
        start = time.perf_counter()
        batch_plan(paths)
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def race(paths: list[str], work: Path, spicelib: str | None, quick: bool, rounds: int) -> list[str]:
    runners = contenders(paths, work, spicelib, quick)
    names = list(runners)
    walls: dict[str, list[float]] = {name: [] for name in names}
    inside: dict[str, list[float]] = {name: [] for name in names}
    before = os.getloadavg()[0]
    for r in range(rounds):
        order = names[r % len(names):] + names[:r % len(names)]
        for name in order:
            wall, extra = timed(runners[name](r), work)
            walls[name].append(wall)
            if "in_batch" in extra:
                inside[name].append(extra["in_batch"])
    after = os.getloadavg()[0]
    limit = statistics.median(walls[names[0]])
    lines = [f"Load average (1 min): {before:.2f} before, {after:.2f} after; {rounds} rounds.", "",
             "| command | runs/s | wall (s) | each round (s) | vs `xargs -P2` | runs only (s) |",
             "|---|---:|---:|---|---:|---:|"]
    for name in names:
        if name == START:
            continue
        wall = statistics.median(walls[name])
        runs_only = f"{statistics.median(inside[name]):.2f}" if inside[name] else ""
        each = ", ".join(f"{w:.2f}" for w in walls[name])
        lines.append(f"| {name} | {len(paths) / wall:.1f} | {wall:.2f} | {each} | {wall / limit:.2f} | "
                     f"{runs_only} |")
    default = names[1]
    whole, runs = statistics.median(walls[default]), statistics.median(inside[default])
    start, plan = statistics.median(walls[START]), plan_seconds(paths)
    lines += ["", f"Where {default}'s whole command ({whole:.2f} s) and its runs ({runs:.2f} s) differ: "
              f"{whole - runs:.2f} s, of which the fixed start ({START}, same rounds) {start:.3f} s, the plan "
              f"(`batch_plan` of the {len(paths)} netlists, in one process) {plan:.3f} s "
              f"({1e3 * plan / len(paths):.2f} ms a netlist), and the rest (the store made, the workers' start and "
              f"end, the summary) {whole - runs - start - plan:.3f} s."]
    return lines


def large(count: int, work: Path) -> list[str]:
    """One round of ``count`` N = 10 netlists: ``lcchain batch`` (its peak memory and its rate as it went, from its
    progress lines) and ``xargs -P2``, one after the other."""
    paths = write_netlists(work / f"large{count}", 10, count)
    runners = contenders(paths, work, None, True)
    before = os.getloadavg()[0]
    xargs, _ = timed(runners["`xargs -P2 ngspice -b`"](0), work)
    command = [*LCCHAIN, "batch", *paths, "--store", str(work / "large.sqlite")]
    start = time.perf_counter()
    process = subprocess.Popen(command, cwd=work, stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=ENV, text=True)
    high = [0]  # the driver's own VmHWM (kB), read every 0.2 s: wait4's ru_maxrss also counts its children

    def watch() -> None:
        while process.poll() is None:
            with contextlib.suppress(OSError, ValueError), open(f"/proc/{process.pid}/status") as status:
                high[0] = max([high[0], *(int(line.split()[1]) for line in status if line.startswith("VmHWM"))])
            time.sleep(0.2)

    watcher = threading.Thread(target=watch, daemon=True)
    watcher.start()
    rates = []
    assert process.stderr is not None
    for line in process.stderr:  # "lcchain: 1000/10000 runs, 141/s, ..."
        words = line.split()
        if len(words) > 3 and words[2].rstrip(",") == "runs" and "/" in words[1] and words[3].endswith("/s,"):
            rates.append((int(words[1].split("/")[0]), words[3].rstrip(",").removesuffix("/s")))
    status = process.wait()
    wall = time.perf_counter() - start
    watcher.join()
    assert process.stdout is not None
    said = process.stdout.read().strip()
    after = os.getloadavg()[0]
    marks = [rates[min(range(len(rates)), key=lambda i: abs(rates[i][0] - m))] for m in (100, 1000, count)] \
        if rates else []
    return [f"Load average (1 min): {before:.2f} before, {after:.2f} after; one round.", "",
            "| command | runs/s | wall (s) | vs `xargs -P2` |", "|---|---:|---:|---:|",
            f"| `xargs -P2 ngspice -b` | {count / xargs:.1f} | {xargs:.1f} | 1.00 |",
            f"| `lcchain batch` | {count / wall:.1f} | {wall:.1f} | {wall / xargs:.2f} |", "",
            f"lcchain said: {said} (exit {status}). The driver's peak resident memory (its own VmHWM, read every "
            f"0.2 s; its ngspice workers are other processes): {high[0] / 1024:.0f} MB. Its rate as it went "
            "(progress lines: runs done, runs/s so far): " + "; ".join(f"{n}: {r}/s" for n, r in marks) + "."]


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--spicelib", metavar="PYTHON", help="an interpreter with spicelib installed")
    parser.add_argument("--large", type=int, metavar="COUNT", help="one round of COUNT N = 10 netlists")
    parser.add_argument("--quick", action="store_true", help="xargs -P2 and lcchain batch only")
    parser.add_argument("--skip-single", action="store_true", help="no table of one run by itself")
    args = parser.parse_args()
    batch = find_simulator("batch")
    flags = "".join(f" {flag}" for flag, on in (("--spicelib PYTHON", args.spicelib), ("--quick", args.quick),
                                                 ("--skip-single", args.skip_single),
                                                 (f"--large {args.large}", args.large)) if on)
    out = ["# Batches against ngspice itself", "",
           f"Command: `LCCHAIN_BENCH_ROUNDS={ROUNDS} .venv/bin/python benchmarks/bench_batch.py{flags} "
           "> benchmarks/batch.md`  ",
           f"Machine: {platform.machine()}, {os.cpu_count()} cores (shared with other jobs: see each table's load "
           f"average), Python {platform.python_version()}, ngspice {batch.version}, lcchain {lcchain.__version__}. "
           "Netlists: the chain cycles through the optimal two-mass, the optimal one-mass and the uniform free "
           "chain, the step through 0.04 (1 + i / count), the title names the run; kick, one transit."]
    if not args.skip_single:
        out += ["", "## One run by itself", "",
                "Wall time of `lcchain.spice.ngspice.runner.run` on lcchain's own netlist (no sandbox), median: a "
                "new `ngspice -b` process each time, or the same warm worker (`lcchain.spice.ngspice.warm`). "
                "\"predicted\" is the study planner's price of the run; studies send runs predicted under "
                f"{WARM_BELOW_SECONDS} s to warm workers (`--transport auto`).", ""]
        out += per_run_table()
    with tempfile.TemporaryDirectory(prefix="lcchain-bench-batch-") as folder:
        work = Path(folder)
        for N, count in ((100, 40), (10, 400)):
            paths = write_netlists(work / f"N{N}", N, count)
            out += ["", f"## {count} distinct N = {N} netlists", "",
                    f"Wall time of each whole command (start-up included), median of {ROUNDS} interleaved rounds. "
                    "\"runs only\": lcchain's own `wall_s`, from the first run's start to the last one stored.", ""]
            stores = work / f"stores{N}"
            stores.mkdir()
            out += race(paths, stores, args.spicelib, args.quick, ROUNDS)
        if args.large:
            out += ["", f"## {args.large} distinct N = 10 netlists", ""]
            out += large(args.large, work)
    print("\n".join(out))


if __name__ == "__main__":
    main()
