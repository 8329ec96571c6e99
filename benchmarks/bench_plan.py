"""A batch's plan per netlist beside reading the file: ``lcchain batch``'s allow-list and pricing (issue 35 item 1).

Run from the repository root::

    .venv/bin/python benchmarks/bench_plan.py [--before REV] [--sizes 10 100 1000] [--count 200] [--rounds 5]

For each N it writes ``count`` distinct netlists the way :mod:`bench_batch` does (the chain cycling through the
optimal two-mass, the optimal one-mass and the uniform free chain, the step 0.04 (1 + i / count), the title naming
the run), then times, in one process, ``rounds`` times each: reading every file
(:func:`lcchain.spice.result.read_include`), reading and splitting every file into lines
(``path.read_text().split("\\n")``: what any reader of lines costs in Python, the fairer floor) and
:func:`lcchain.studies.plan.batch_plan` of them all (each read,
made canonical, allow-listed, its analysis read, priced, its limits set).  It prints the fastest round per netlist
(the machine is shared: the least disturbed round is the closest to the code's own cost) and the load average
(1 min) before and after.  The engine's version is given (``"39"``): no ngspice is started.

``--before REV`` measures lcchain as it was at the commit REV too (``git archive REV lcchain`` into a temporary
folder, imported from there), in a process of its own beside this tree's, alternating, on the same files.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent


def fastest(work: Callable[[], object], rounds: int) -> float:
    best = float("inf")
    for _ in range(rounds):
        start = time.perf_counter()
        work()
        best = min(best, time.perf_counter() - start)
    return best


def measure(folder: Path, rounds: int) -> dict[str, float]:
    """Seconds a netlist of ``folder``: reading it, reading and splitting it into lines, and its plan (fastest of
    ``rounds``, in this process)."""
    from lcchain.spice.result import read_include
    from lcchain.studies.plan import batch_plan

    paths = sorted(str(p) for p in folder.glob("*.cir"))

    def read() -> None:
        for path in paths:
            read_include(Path(path), "NETLIST")

    def split() -> None:  # the floor of any reader of lines in Python: the file read and split at LF
        for path in paths:
            Path(path).read_text().split("\n")

    def plan() -> None:
        made = batch_plan(paths, engine_version=lambda: "39")
        assert len(made.tasks) == len(paths), made.refusals

    return {"read": fastest(read, rounds) / len(paths), "split": fastest(split, rounds) / len(paths),
            "plan": fastest(plan, rounds) / len(paths)}


def _measured(folder: Path, rounds: int, tree: Path | None) -> dict[str, float]:
    env = dict(os.environ, PYTHONPATH=str(tree) if tree is not None else str(ROOT))
    done = subprocess.run([sys.executable, __file__, "--measure", str(folder), "--rounds", str(rounds)], env=env,
                          capture_output=True, text=True, check=True)
    result: dict[str, float] = json.loads(done.stdout)
    return result


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--sizes", type=int, nargs="+", default=[10, 100, 1000])
    parser.add_argument("--count", type=int, default=200, help="netlists of each size")
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--before", help="a commit to measure beside this tree")
    parser.add_argument("--measure", type=Path, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.measure is not None:
        print(json.dumps(measure(args.measure, args.rounds)))
        return 0
    sys.path.insert(0, str(HERE))
    from bench_batch import write_netlists

    with tempfile.TemporaryDirectory() as folder:
        before: Path | None = None
        if args.before:
            before = Path(folder) / "before"
            before.mkdir()
            archive = subprocess.run(["git", "-C", str(ROOT), "archive", args.before, "lcchain"], capture_output=True,
                                     check=True).stdout
            subprocess.run(["tar", "-x", "-C", str(before)], input=archive, check=True)
        rows = []
        for N in args.sizes:
            paths = write_netlists(Path(folder) / f"N{N}", N, args.count)
            texts = [Path(p).read_text() for p in paths]
            rows.append((N, sum(len(t.encode()) for t in texts) / len(texts),
                         sum(t.count("\n") for t in texts) / len(texts)))
        load = os.getloadavg()[0]
        results: dict[tuple[int, str], dict[str, float]] = {}
        for N, _, _ in rows:
            trees: list[tuple[str, Path | None]] = [("before", before), ("after", None)] if before else [
                ("this tree", None)]
            for name, tree in trees:
                results[(N, name)] = _measured(Path(folder) / f"N{N}", args.rounds, tree)
        after_load = os.getloadavg()[0]
    print(f"Load average (1 min): {load:.2f} before, {after_load:.2f} after; fastest of {args.rounds} rounds of "
          f"{args.count} netlists each.")
    print()
    names = ["before", "after"] if before else ["this tree"]
    head = " | ".join(f"`batch_plan` {n} (ms) | {n} / read | {n} / split" for n in names)
    print(f"| N | bytes | lines | read (ms) | read + split (ms) | {head} |" + (" after / before |" if before else ""))
    print("|---:|---:|---:|---:|---:|" + "---:|---:|---:|" * len(names) + ("---:|" if before else ""))
    for N, size, lines in rows:
        read = min(results[(N, n)]["read"] for n in names)
        split = min(results[(N, n)]["split"] for n in names)
        cells = " | ".join(f"{1e3 * results[(N, n)]['plan']:.3f} | {results[(N, n)]['plan'] / read:.0f} | "
                           f"{results[(N, n)]['plan'] / split:.1f}" for n in names)
        ratio = f" {results[(N, 'after')]['plan'] / results[(N, 'before')]['plan']:.2f} |" if before else ""
        print(f"| {N} | {size:.0f} | {lines:.0f} | {1e3 * read:.3f} | {1e3 * split:.3f} | {cells} |{ratio}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
