"""The fixed start of a command, before and after a change (issue 35): ``--version``, ``--help``, ``batch --help``
and a one-netlist ``lcchain batch`` (interpreter start to its first subprocess, ngspice's or the sandbox's, and the
whole run), each source tree's runs interleaved with the other's so that a noisy machine weighs on both alike.

Run from the repository root:

    .venv/bin/python benchmarks/bench_start.py --before REF > benchmarks/start.md

``REF``'s ``lcchain/`` is extracted (``git archive``) into a temporary folder and run from there with
``python -m lcchain`` (the current folder comes first on ``sys.path``); "after" is this working tree.  Wall times
are medians of ``--repeat`` runs, with the load average (1 min) before and after; the import times are
``python -X importtime`` of the batch run, medians of the same runs.  Every process may write its bytecode
(``PYTHONDONTWRITEBYTECODE`` is dropped from its environment) and one warm-up round runs first, so that lcchain is
read from ``__pycache__`` as an installed lcchain is, not compiled each time.  Which modules a command may import is
asserted by ``tests/test_imports.py``, not here.
"""

from __future__ import annotations

import argparse
import io
import os
import platform
import resource
import statistics
import subprocess
import sys
import tarfile
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

sys.path.insert(0, str(ROOT / "tests"))
from helpers.netlists import RC_NETLIST  # noqa: E402  (the netlist tests/test_imports.py batches)

#: Runs lcchain as ``python -m lcchain`` does, and writes the time of its first subprocess to $BENCH_STAMP (the
#: wall clock, and the process's CPU time so far).
FIRST_START = """\
import os, runpy, sys, time
seen = []
def hook(event, args):
    if event == "subprocess.Popen" and not seen:
        seen.append(1)
        with open(os.environ["BENCH_STAMP"], "w") as out:
            out.write(f"{time.time()!r} {time.process_time()!r}")
sys.addaudithook(hook)
sys.argv = ["lcchain", *sys.argv[1:]]
runpy.run_module("lcchain", run_name="__main__", alter_sys=True)
"""


#: The environment of every process: bytecode written and read (a user's lcchain is compiled once).
ENV = {name: value for name, value in os.environ.items() if name != "PYTHONDONTWRITEBYTECODE"}


def _wall(command: list[str], cwd: Path, env: dict[str, str] | None = None) -> tuple[float, str, float]:
    """(wall seconds, stderr, CPU seconds: user + system) of one process."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    done = subprocess.run(command, capture_output=True, text=True, cwd=cwd, env=env or ENV)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if done.returncode != 0:
        raise SystemExit(f"{' '.join(command)} in {cwd}: exit {done.returncode}\n{done.stderr[-2000:]}")
    return wall, done.stderr, after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime


def _imports(stderr: str) -> dict[str, float]:
    """``-X importtime``: seconds of the top-level imports together, and of each top-level package."""
    top: dict[str, float] = {"all": 0.0}
    for line in stderr.splitlines():
        if line.startswith("import time:") and "[us]" not in line:
            _, cumulative, name = line.split("|")
            if not name.startswith("  "):  # depth 0: imported by the command itself
                seconds = int(cumulative) / 1e6
                top["all"] += seconds
                package = name.strip().split(".")[0]
                top[package] = top.get(package, 0.0) + seconds
    return top


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--before", default="main", help="git ref of the 'before' tree (default main)")
    parser.add_argument("--repeat", type=int, default=11)
    args = parser.parse_args()
    python = sys.executable
    load_start = os.getloadavg()[0]
    with tempfile.TemporaryDirectory(prefix="lcchain-bench-start-") as folder:
        work = Path(folder)
        before = work / "before"
        before.mkdir()
        archive = subprocess.run(["git", "archive", args.before, "lcchain"], cwd=ROOT, capture_output=True,
                                 check=True).stdout
        tarfile.open(fileobj=io.BytesIO(archive)).extractall(before, filter="data")
        commit = subprocess.run(["git", "rev-parse", "--short", args.before], cwd=ROOT, capture_output=True,
                                text=True, check=True).stdout.strip()
        after_commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True,
                                      text=True, check=True).stdout.strip()
        netlist = work / "rc.cir"
        netlist.write_text(RC_NETLIST)
        trees = {"before": before, "after": ROOT}
        floors = {"`python -c pass` (the interpreter alone)": [python, "-c", "pass"],
                  "`python -c 'import numpy'`": [python, "-c", "import numpy"]}
        commands = {"`lcchain --version`": ["--version"], "`lcchain --help`": ["--help"],
                    "`lcchain batch --help`": ["batch", "--help"]}
        # (row, tree) -> wall seconds, and CPU seconds (user + system) of the same processes
        walls: dict[tuple[str, str], list[float]] = {}
        cpus: dict[tuple[str, str], list[float]] = {}
        imported: dict[str, list[dict[str, float]]] = {tree: [] for tree in trees}
        first, whole = "`lcchain batch rc.cir`: to its first subprocess (the fixed start)", \
            "`lcchain batch rc.cir`: the whole run (ngspice in its sandbox, the store)"

        def record(row: str, tree: str, wall: float, cpu: float) -> None:
            walls.setdefault((row, tree), []).append(wall)
            cpus.setdefault((row, tree), []).append(cpu)

        for tree, cwd in trees.items():  # warm-up: the bytecode of both trees written
            _wall([python, "-m", "lcchain", "batch", str(netlist), "--store", str(work / f"{tree}-warm.sqlite")],
                  cwd)
            _wall([python, "-m", "lcchain", "--help"], cwd)
        for r in range(args.repeat):
            for name, command in floors.items():
                wall, _, cpu = _wall(command, work)
                record(name, "", wall, cpu)
            for tree, cwd in trees.items():
                for name, argv in commands.items():
                    wall, _, cpu = _wall([python, "-m", "lcchain", *argv], cwd)
                    record(name, tree, wall, cpu)
                stamp = work / "stamp"
                stamp.unlink(missing_ok=True)
                env = {**ENV, "BENCH_STAMP": str(stamp)}
                started = time.time()
                wall, _, cpu = _wall([python, "-c", FIRST_START, "batch", str(netlist), "--store",
                                      str(work / f"{tree}-{r}-first.sqlite")], cwd, env)
                at, cpu_at = (float(v) for v in stamp.read_text().split())
                record(first, tree, at - started, cpu_at)
                record(whole, tree, wall, cpu)
                _, stderr, _ = _wall([python, "-X", "importtime", "-m", "lcchain", "batch", str(netlist), "--store",
                                      str(work / f"{tree}-{r}-imports.sqlite")], cwd)
                imported[tree].append(_imports(stderr))
    load_end = os.getloadavg()[0]
    floor = "`python -c pass` (the interpreter alone)"

    def cell(row: str, tree: str) -> str:
        wall, base = statistics.median(walls[(row, tree)]), statistics.median(walls[(floor, "")])
        cpu, cpu_base = statistics.median(cpus[(row, tree)]), statistics.median(cpus[(floor, "")])
        return f"{wall:.3f} (+{wall - base:.3f}) | {cpu:.3f} (+{cpu - cpu_base:.3f})"

    print("# The fixed start of a command: before and after issue 35\n")
    print(f"Command: `.venv/bin/python benchmarks/bench_start.py --before {args.before} > benchmarks/start.md`  ")
    print(f"Before: {args.before} ({commit}); after: this tree ({after_commit} and its uncommitted edits).  ")
    print(f"Machine: {platform.machine()}, {os.cpu_count()} cores shared with other jobs, Python "
          f"{platform.python_version()}; load average (1 min) {load_start:.2f} at the start, {load_end:.2f} at the "
          f"end.  Seconds, median of {args.repeat}, interleaved: the wall time of the whole process and its CPU "
          "time (user + system of every thread, children included; to the first subprocess: the process's own), "
          "in brackets above the interpreter alone's.  numpy's BLAS threads start with it and spin, so CPU time "
          "can exceed the wall time.  The fixed start is the interpreter's start to lcchain's first subprocess "
          "(`ngspice -v`, then the sandboxed run): the imports, the parser, the allow-list, the price and the "
          "store.\n")
    print("| command | before: wall | before: CPU | after: wall | after: CPU |")
    print("|---|---:|---:|---:|---:|")
    for name in floors:
        print(f"| {name} | {cell(name, '')} | | |")
    for name in [*commands, first, whole]:
        print(f"| {name} | {cell(name, 'before')} | {cell(name, 'after')} |")
    packages = sorted({p for tree in imported.values() for run in tree for p in run},
                      key=lambda p: -statistics.median(run.get(p, 0.0) for run in imported["before"]))
    print("\n`python -X importtime -m lcchain batch rc.cir --store S`: seconds importing, all top-level imports "
          "and by package (its own cumulative time; numpy counted where lcchain first imports it), median:\n")
    print("| imported | before | after |")
    print("|---|---:|---:|")
    for package in packages:
        values = {tree: statistics.median(run.get(package, 0.0) for run in imported[tree]) for tree in trees}
        if max(values.values()) >= 0.002:
            print(f"| {package} | {values['before']:.3f} | {values['after']:.3f} |")
    print("\nWhich modules each command imports is asserted by `tests/test_imports.py` (no scipy, matplotlib, "
          "pandas, xarray, dask or PySpice for any `--help`, `--version` or a batch of foreign netlists); the "
          "times are here because a noisy machine cannot fail a benchmark.")


if __name__ == "__main__":
    main()
