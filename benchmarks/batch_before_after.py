"""``lcchain batch`` of one tree against another, beside ``xargs -P2 ngspice -b``, in interleaved rounds.

Run from the repository root, with the tree before the change unpacked elsewhere
(``git archive COMMIT | tar -x -C /tmp/before``):

    .venv/bin/python benchmarks/batch_before_after.py /tmp/before [N] [COUNT] [ROUNDS]

Each round runs, in a rotated order, ``xargs -P2 ngspice -b`` on the same distinct netlists
(:func:`bench_batch.write_netlists`), ``lcchain batch --json`` (default options) of each tree and
``lcchain batch --help`` of each tree; a tree is chosen by ``PYTHONPATH`` under this interpreter, and
bytecode is written and read as an installed lcchain does.  Prints each contender's median wall time, its ratio
to xargs, lcchain's own ``wall_s`` ("runs only") and every round's time, with the load average (1 min) before
and after.  Where ``perf`` is on the PATH each command runs under ``perf stat -e task-clock``, and the median CPU
of all its processes (the sandbox, ngspice and the warm workers included; the load changes it less than the wall
time) is printed beside it, with how busy it kept the cores (CPU / (cores x wall)) and its floor: that CPU over
all the cores, the wall time of a command that kept every core busy from its start to its end, as a ratio to
xargs' wall time (a command whose floor is past 1.10x cannot be within 10 % of xargs, however it is arranged).
Last, each contender's ratio to the xargs of its own round, paired (median and quartiles): what drifts over the run
(the machine's speed moved xargs' time by 10 % between passes) cancels in it.
"""

from __future__ import annotations

import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_batch import write_netlists  # noqa: E402

AFTER = str(Path(__file__).resolve().parent.parent)
ENV = {name: value for name, value in os.environ.items() if name != "PYTHONDONTWRITEBYTECODE"}
# ``python -m lcchain``: the console script's own entry (lcchain.__main__), with its ending, as a user runs it
LCCHAIN = [sys.executable, "-m", "lcchain"]


def main() -> None:
    before = sys.argv[1]
    N, count, rounds = (int(v) for v in (sys.argv[2:] + ["100", "40", "7"][len(sys.argv) - 2:])[:3])
    work = Path(tempfile.mkdtemp(prefix="lcchain-before-after-"))
    paths = write_netlists(work / "netlists", N, count)
    ngspice = shutil.which("ngspice") or "ngspice"

    def batch(tree: str) -> Callable[[str], tuple[list[str], dict[str, str]]]:
        return lambda tag: ([*LCCHAIN, "batch", *paths, "--json", "--store", str(work / f"{tag}.sqlite")],
                            {**ENV, "PYTHONPATH": tree})

    def helps(tree: str) -> Callable[[str], tuple[list[str], dict[str, str]]]:
        return lambda tag: ([*LCCHAIN, "batch", "--help"], {**ENV, "PYTHONPATH": tree})

    contenders: dict[str, Callable[[str], tuple[list[str], dict[str, str]]]] = {
        "xargs -P2 ngspice -b": lambda tag: (["bash", "-c", f'printf "%s\\n" "$@" | xargs -P2 -I{{}} {ngspice} -b '
                                              '-r {}.raw {} >/dev/null 2>&1', "_", *paths], ENV),
        "lcchain batch, before": batch(before), "lcchain batch, after": batch(AFTER),
        "lcchain batch --help, before": helps(before), "lcchain batch --help, after": helps(AFTER)}
    names = list(contenders)
    walls: dict[str, list[float]] = {name: [] for name in names}
    inside: dict[str, list[float]] = {name: [] for name in names}
    cpus: dict[str, list[float]] = {name: [] for name in names}
    perf = shutil.which("perf")
    load = os.getloadavg()[0]
    for r in range(rounds):
        for i, name in enumerate(names[r % len(names):] + names[:r % len(names)]):
            command, env = contenders[name](f"r{r}c{i}")
            counted = work / "task-clock.csv"
            if perf is not None:
                command = [perf, "stat", "-x,", "-e", "task-clock", "-o", str(counted), "--", *command]
            start = time.perf_counter()
            done = subprocess.run(command, capture_output=True, env=env, cwd=work)
            walls[name].append(time.perf_counter() - start)
            if done.returncode:
                raise SystemExit(f"{name}: {done.stderr.decode()[-1500:]}")
            if perf is not None:
                line = next(line for line in counted.read_text().splitlines() if "task-clock" in line)
                cpus[name].append(float(line.split(",")[0]) / 1e3)
            if b'"wall_s"' in done.stdout:
                inside[name].append(float(json.loads(done.stdout)["wall_s"]))
    print(f"{count} distinct N = {N} netlists, {rounds} rounds; load average (1 min) {load:.2f} before, "
          f"{os.getloadavg()[0]:.2f} after")
    xargs = statistics.median(walls[names[0]])
    cores = os.cpu_count() or 1
    for name in names:
        median = statistics.median(walls[name])
        runs = f"{statistics.median(inside[name]):.3f}" if inside[name] else "-"
        cpu = ""
        if cpus[name]:  # its floor: that CPU spread over every core, all busy all the time
            used = statistics.median(cpus[name])
            cpu = (f", CPU {used:.3f} s (the cores {used / (cores * median):.0%} busy; CPU / {cores} cores "
                   f"{used / cores:.3f} s, {used / cores / xargs:.2f}x xargs)")
        print(f"{name}: {median:.3f} s ({median / xargs:.2f}x xargs){cpu}, runs only {runs} s; each "
              + ", ".join(f"{v:.2f}" for v in walls[name]))
    # Each round's own ratio to the xargs of that round (the commands of a round follow one another): a drift of
    # the machine's speed over the run, which moves every median, cancels in it.
    print("paired with the same round's xargs (median, quartiles):")
    for name in names[1:]:
        ratios = sorted(wall / base for wall, base in zip(walls[name], walls[names[0]], strict=True))
        quartiles = statistics.quantiles(ratios, n=4) if len(ratios) > 1 else [ratios[0]] * 3
        print(f"  {name}: {statistics.median(ratios):.3f}x ({quartiles[0]:.3f} to {quartiles[2]:.3f})")
    shutil.rmtree(work)


if __name__ == "__main__":
    main()
