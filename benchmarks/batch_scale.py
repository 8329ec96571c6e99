"""Is a batch's cost a run flat from 100 to 100,000 runs?  ``lcchain batch`` of the first COUNT of a folder of
distinct N = 10 netlists: its wall time, rate, CPU (all processes) and the driver's peak resident memory, and its
rate as it went (from its progress lines), beside ``xargs -P2 ngspice -b`` on the same netlists up to
``--xargs-up-to`` runs.

    .venv/bin/python benchmarks/batch_scale.py FOLDER 100 1000 10000 100000 [--xargs-up-to 10000]

FOLDER holds the netlists, named so that their names sort in order and are short (100,000 names on one command
line): made by ``--make COUNT`` (the chain cycles through the optimal two-mass, the optimal one-mass and the
uniform free chain, the step is 0.04 (1 + i / COUNT), the title names the run), in a folder outside the
repository, deleted by hand after.  Every store goes to a temporary folder, removed at the end.  CPU is ``perf
stat -e task-clock`` (children included) where ``perf`` is on the PATH.
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import lcchain
from lcchain.runs.simulate import ChainOptions, simulation_spec

LCCHAIN = str(Path(sys.executable).with_name("lcchain"))
ENV = {name: value for name, value in os.environ.items() if name != "PYTHONDONTWRITEBYTECODE"}
CASES = ("two-mass", "one-mass", "uniform-free")


def make(folder: Path, count: int) -> None:
    folder.mkdir(parents=True)
    chains = {case: lcchain.chain_for_case(case, 10) for case in CASES}
    for i in range(count):
        case = CASES[i % len(CASES)]
        spec, _, _ = simulation_spec(chains[case], ChainOptions(dt=0.04 * (1 + i / count)))
        _, _, body = spec.netlist.partition("\n")
        (folder / f"{i:05d}").write_text(f"run {i} of a user's study: {case} N=10\n{body}")


def counted(command: list[str], cwd: Path, csv: Path) -> list[str]:
    perf = shutil.which("perf")
    return [perf, "stat", "-x,", "-e", "task-clock", "-o", str(csv), "--", *command] if perf else command


def cpu_of(csv: Path) -> str:
    if not csv.exists():
        return ""
    line = next((line for line in csv.read_text().splitlines() if "task-clock" in line), "")
    return f"{float(line.split(',')[0]) / 1e3:.1f}" if line else ""


def lcchain_row(names: list[str], folder: Path, work: Path) -> str:
    csv = work / "lcchain.csv"
    store = work / f"s{len(names)}.sqlite"
    load = os.getloadavg()[0]
    start = time.perf_counter()
    process = subprocess.Popen(counted([LCCHAIN, "batch", *names, "--store", str(store)], folder, csv), cwd=folder,
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=ENV, text=True)
    rates: list[tuple[int, float]] = []
    assert process.stderr is not None
    for line in process.stderr:  # "lcchain: 1000/10000 runs, 141/s, ..."
        words = line.split()
        if len(words) > 3 and words[2].rstrip(",") == "runs" and "/" in words[1] and words[3].endswith("/s,"):
            rates.append((int(words[1].split("/")[0]), time.perf_counter() - start))
    _, status, usage = os.wait4(process.pid, 0)
    wall = time.perf_counter() - start
    assert process.stdout is not None
    said = process.stdout.read().strip()
    if os.waitstatus_to_exitcode(status) != 0:
        raise SystemExit(f"lcchain batch failed: {said}")
    # the rate over the 5th and the 9th tenth of the batch, from the times its progress lines (one every 10 %)
    # arrived
    marks = []
    for tenth in (5, 9):
        lo = next(((n, t) for n, t in rates if n >= len(names) * (tenth - 1) // 10), None)
        hi = next(((n, t) for n, t in rates if n >= len(names) * tenth // 10), None)
        if lo and hi and hi[1] > lo[1]:
            marks.append(f"{(hi[0] - lo[0]) / (hi[1] - lo[1]):.0f}")
    # perf stat wraps the command: the driver is its child, and ru_maxrss is the largest of the children
    peak = usage.ru_maxrss / 1024
    store.unlink(missing_ok=True)
    for suffix in ("-wal", "-shm"):
        Path(f"{store}{suffix}").unlink(missing_ok=True)
    return (f"| `lcchain batch` | {len(names)} | {wall:.1f} | {len(names) / wall:.1f} | {cpu_of(csv)} | {peak:.0f} | "
            f"{', '.join(marks)} | {load:.1f} to {os.getloadavg()[0]:.1f} |")


def xargs_row(names: list[str], folder: Path, work: Path) -> str:
    csv = work / "xargs.csv"
    ngspice = shutil.which("ngspice") or "ngspice"
    load = os.getloadavg()[0]
    start = time.perf_counter()
    # each run writes its raw file beside its netlist, as bench_batch.py's xargs does (never to a device: a
    # benchmark run as root must not be able to touch the machine's /dev/null), removed after the timing
    subprocess.run(counted(["bash", "-c", f'printf "%s\\n" "$@" | xargs -P2 -I{{}} {ngspice} -b -r {{}}.raw {{}} '
                            '>/dev/null 2>&1', "_", *names], folder, csv), cwd=folder, check=True, env=ENV)
    wall = time.perf_counter() - start
    for name in names:
        (folder / f"{name}.raw").unlink(missing_ok=True)
    return (f"| `xargs -P2 ngspice -b` | {len(names)} | {wall:.1f} | {len(names) / wall:.1f} | {cpu_of(csv)} | | | "
            f"{load:.1f} to {os.getloadavg()[0]:.1f} |")


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("folder", type=Path)
    parser.add_argument("counts", type=int, nargs="*")
    parser.add_argument("--make", type=int, metavar="COUNT", help="write COUNT netlists into FOLDER first")
    parser.add_argument("--xargs-up-to", type=int, default=10000)
    args = parser.parse_args()
    if args.make:
        make(args.folder, args.make)
    names = sorted(os.listdir(args.folder))
    print("| command | runs | wall (s) | runs/s | CPU (s) | driver peak RSS (MB) | runs/s over the 5th, 9th "
          "tenth | load (1 min) |")
    print("|---|---:|---:|---:|---:|---:|---|---|")
    work = Path(tempfile.mkdtemp(prefix="lcchain-batch-scale-"))
    try:
        for count in args.counts:
            if count <= args.xargs_up_to:
                print(xargs_row(names[:count], args.folder, work), flush=True)
            print(lcchain_row(names[:count], args.folder, work), flush=True)
    finally:
        shutil.rmtree(work)


if __name__ == "__main__":
    main()
