"""Foreign netlists priced against what they cost: a hostile family, each run by ``lcchain batch``.

Run from the repository root (it prints the section of ``benchmarks/pricing.md`` on foreign netlists):

    .venv/bin/python benchmarks/bench_foreign_pricing.py

Each netlist of the family (what the analysis card alone priced at milliseconds: picosecond edges, long PWL
sources, fast SIN sources, K lines by the thousand, huge titles and comments, long B expressions, many elements)
runs as ``lcchain batch NETLIST --store S --executor serial --transport T`` for T = process and warm, with the
default budget. Its price is what lcchain holds the command to (the netlist's price plus the interpreter's start
and memory: the smallest --max-time and --max-memory it accepts); measured are the command's wall time and the
peak of the resident memory of its whole process tree (lcchain, bubblewrap, ngspice or the warm worker),
sampled every 20 ms. Target (issue 29): every accepted request within 2x its time and memory price.

Then the issue's batch of four dear netlists under ``--max-time 20s`` (82 s before): refused before any run,
naming its price, or stopped at its budget with the runs left pending.
"""

from __future__ import annotations

import os
import platform
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

from lcchain.core.budget import INTERPRETER_BYTES, INTERPRETER_SECONDS, show_bytes
from lcchain.spice.foreign import analysis_of, foreign_price
from lcchain.spice.processes import resident_bytes
from lcchain.spice.text import saved_vectors
from lcchain.studies.plan import batch_plan

RC = "R1 in out 50\nC1 out 0 1p\n"


def _netlist(title: str, body: str, tran: str, save: str = ".save v(out)") -> str:
    return f"{title}\n{body}{tran}\n{save}\n.end\n"


def _ladder(cells: int, source: str, coupled: int = 0) -> str:
    lines = [source] + [f"L{i} n{i - 1} n{i} 1u\nC{i} n{i} 0 1p" for i in range(1, cells + 1)]
    pairs = [(i, j) for i in range(1, coupled + 1) for j in range(i + 1, coupled + 1)]
    lines += [f"K{k} L{i} L{j} {0.5 / (j - i + 1):.4f}" for k, (i, j) in enumerate(pairs, start=1)]
    return "\n".join(lines) + "\n"


def family() -> dict[str, str]:
    """The hostile pricing family: each member at the size that ran for seconds to minutes when priced at ms."""
    pulse = "V1 n0 0 PULSE(0 1 0 1n 1n 10n 100n)"
    return {
        "PULSE of 4 ps edges every 20 ps, 1 us": _netlist("p", "V1 in 0 PULSE(0 1 0 4p 4p 5p 20p)\n" + RC,
                                                          ".tran 1n 1u"),
        "two PULSEs 1 fs apart, 1 us": _netlist("p", "V1 in 0 PULSE(0 1 0 10p 10p 50p 100p)\nV2 in2 0 PULSE(0 1 1f "
                                                "10p 10p 50p 100p)\nR2 in2 out 50\n" + RC, ".tran 1n 1u"),
        "TRNOISE every 5 ps, 1 us": _netlist("n", "V1 in 0 TRNOISE(0.1 5p 0 0)\n" + RC, ".tran 1n 1u"),
        "PWL of 20,000 points": _netlist("w", "V1 in 0 PWL(" + " ".join(f"{k * 5e-11:.6g} {k % 2}"
                                                                         for k in range(20_000)) + ")\n" + RC,
                                         ".tran 1n 1u"),
        "SIN at 10 GHz, 5 us": _netlist("s", "V1 in 0 SIN(0 1 10g)\n" + RC, ".tran 1n 5u"),
        "100 inductors all coupled (4,950 K lines), 300 ns": _netlist("k", _ladder(100, pulse, 100), ".tran 1n 300n",
                                                                      ".save v(n100)"),
        "200 inductors all coupled (19,900 K lines), 10 ns": _netlist("k", _ladder(200, pulse, 200), ".tran 1n 10n",
                                                                      ".save v(n200)"),
        "LC ladder of 2,000 cells ringing, 1 us": _netlist("l", _ladder(2000, pulse), ".tran 1n 1u", ".save v(n2000)"),
        "R ladder of 200,000 cells": _netlist("r", "V1 n0 0 SIN(0 1 10meg)\n" + "".join(
            f"R{k} n{k - 1} n{k} 1\n" for k in range(1, 200_001)) + "R0 n200000 0 1\nC1 n1 0 1p\n", ".tran 1n 100n",
            ".save v(n100000)"),
        "B expression of 300 kB (50,000 terms), 1 us": _netlist("b", "V1 in 0 PULSE(0 1 0 1n 1n 10n 100n)\n" + RC
                                                                + "B1 b 0 V=" + "+".join(["v(in)"] * 50_000)
                                                                + "\nR2 b 0 1k\n", ".tran 1n 1u"),
        "title of 32 MiB": _netlist("t" * 32 * 2**20, "V1 in 0 PULSE(0 1 0 1n 1n 10n 100n)\n" + RC, ".tran 1n 1u"),
        "comments of 32 MiB": _netlist("c", ("* " + "y" * 98 + "\n") * (32 * 2**20 // 100)
                                       + "V1 in 0 PULSE(0 1 0 1n 1n 10n 100n)\n" + RC, ".tran 1n 1u"),
    }


def _tree_peak(pid: int, stop: threading.Event, peak: list[int]) -> None:
    while not stop.is_set():
        peak[0] = max(peak[0], resident_bytes(pid))
        stop.wait(0.02)


def measure(argv: list[str], folder: Path) -> tuple[float, int, int, str]:
    """(wall seconds, peak resident bytes of the process tree, exit status, its last line: of stdout when it printed
    one, else of stderr) of one lcchain command."""
    start = time.perf_counter()
    proc = subprocess.Popen([sys.executable, "-m", "lcchain", *argv], cwd=folder, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    stop, peak = threading.Event(), [0]
    watcher = threading.Thread(target=_tree_peak, args=(proc.pid, stop, peak))
    watcher.start()
    out, err = proc.communicate()
    wall = time.perf_counter() - start
    stop.set()
    watcher.join()
    said = (out.strip() or err.strip()).splitlines()
    return wall, peak[0], proc.returncode, said[-1] if said else ""


def main() -> None:
    load = os.getloadavg()
    print("## Foreign netlists: the hostile family\n")
    print("Command: `.venv/bin/python benchmarks/bench_foreign_pricing.py` (this section)  ")
    print(f"Machine: {platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}, ngspice 39; "
          f"load average {load[0]:.1f} at the start")
    print("Price: what lcchain holds `lcchain batch NETLIST --store S --executor serial` to (the netlist's price "
          "from its elements, K lines, source edges, fast dynamics, expressions and text, plus the interpreter's "
          "start and memory). Measured: the command's wall time, and the peak resident memory of its whole "
          "process tree sampled every 20 ms. Status: the run's record (ngspice echoes a 32 MiB title past the "
          "16 MiB a run may print, so that run is stopped and fails, after lcchain has read, checked and priced "
          "its text).\n")
    print("| netlist | transport | status | priced s | measured s | time ratio | priced | measured | memory ratio |")
    print("|---|---|---|---:|---:|---:|---:|---:|---:|")
    worst_time = worst_memory = 0.0
    with tempfile.TemporaryDirectory() as scratch:
        folder = Path(scratch)
        for name, text in family().items():
            path = folder / "n.cir"
            path.write_text(text)
            (task,) = batch_plan([path]).tasks
            price = foreign_price(task.spec.netlist, analysis_of(task.spec.netlist, "n"),
                                  len(saved_vectors(task.spec.netlist)))
            seconds, memory = price.seconds + INTERPRETER_SECONDS, price.memory + INTERPRETER_BYTES
            for transport in ("process", "warm"):
                store = folder / f"{transport}.sqlite"
                wall, peak, status, said = measure(["batch", str(path), "--store", str(store), "--executor",
                                                    "serial", "--transport", transport], folder)
                outcome = "ok" if status == 0 else "failed" if status == 1 else f"exit {status}"
                store.unlink(missing_ok=True)
                worst_time, worst_memory = max(worst_time, wall / seconds), max(worst_memory, peak / memory)
                print(f"| {name} | {transport} | {outcome} | {seconds:.3g} | {wall:.3g} | {wall / seconds:.2f} | "
                      f"{show_bytes(memory)} | {show_bytes(peak)} | {peak / memory:.2f} |", flush=True)
        print(f"\nWorst ratios: time {worst_time:.2f}, memory {worst_memory:.2f} (target: at most 2); load average "
              f"{os.getloadavg()[0]:.1f} at the end.\n")

        print("The issue's batch of four dear netlists (82 s under `--max-time 20s` before), on 2 workers: refused "
              "before any run under a budget below its price, run within it otherwise, and resumed by the same "
              "command:\n")
        dear = ["PULSE of 4 ps edges every 20 ps, 1 us", "two PULSEs 1 fs apart, 1 us", "TRNOISE every 5 ps, 1 us",
                "200 inductors all coupled (19,900 K lines), 10 ns"]
        paths = []
        for k, name in enumerate(dear):
            paths.append(folder / f"d{k}.cir")
            paths[-1].write_text(family()[name])
        for budget, attempt in (("12s", "under its price"), ("20s", "first"), ("20s", "same command again")):
            wall, _, status, line = measure(["batch", *map(str, paths), "--store", str(folder / "d.sqlite"),
                                             "--max-time", budget, "--workers", "2"], folder)
            line = line.replace(str(folder) + "/", "")
            print(f"- `--max-time {budget}`, {attempt}: exit {status} after {wall:.1f} s: {line[:400]}")
        print(f"\n(Netlists: {'; '.join(dear)}.) Load average {os.getloadavg()[0]:.1f} at the end.")


if __name__ == "__main__":
    main()
