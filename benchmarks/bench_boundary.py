"""What the boundary of issue 19 costs: the allow-list parse and the sandbox, per run.

Run from the repository root:

    .venv/bin/python benchmarks/bench_boundary.py > benchmarks/boundary.md

* the allow-list (:func:`lcchain.spice.foreign.allowed_netlist`) on lcchain's
  own netlists, which every run passes (in process, median of many calls);
* one N = 20 and one N = 100 run through :func:`lcchain.spice.ngspice.runner.run` as
  lcchain's own netlist (no sandbox) and as a foreign one (bubblewrap),
  interleaved, median of the wall time lcchain waits for;
* ngspice's process alone (``ngspice -n -b -r FILE``, a bash loop), for scale;
* the price of each reference netlist run as a foreign one, beside its wall time.
"""

from __future__ import annotations

import platform
import statistics
import subprocess
import tempfile
import time
from pathlib import Path

import lcchain
from lcchain.circuit.netlist import ChainNetlist, make_netlist
from lcchain.spice.foreign import allowed_netlist, foreign_estimate, transient_of
from lcchain.spice.job import RunJob
from lcchain.spice.ngspice.find import find_simulator
from lcchain.spice.ngspice.runner import run
from lcchain.spice.text import saved_vectors

REPEAT = 30


def _median_ms(action, repeat: int) -> float:  # type: ignore[no-untyped-def]
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        action()
        times.append(time.perf_counter() - start)
    return 1e3 * statistics.median(times)


def main() -> None:
    simulator = find_simulator("batch")
    print("# The boundary's cost: the allow-list and the sandbox\n")
    print("Command: `.venv/bin/python benchmarks/bench_boundary.py > benchmarks/boundary.md`  ")
    print(f"Machine: {platform.machine()}, 2 cores, Python {platform.python_version()}, ngspice {simulator.version}, "
          f"sandbox: {'bubblewrap' if simulator.sandbox.available else simulator.sandbox.why_not}  ")
    print("Chains: the optimal two-mass chain, kick, dt = 0.05, one transit.\n")
    print("## The allow-list on lcchain's own netlists (every run passes it)\n")
    print("| N | lines | ms per netlist |")
    print("|---:|---:|---:|")
    for N in (20, 100, 1000, 10000):
        text, _, _ = make_netlist(lcchain.Chain.from_rw(N, r=0.5873, w=0.0972), ChainNetlist(dt=0.05))
        repeat = 200 if N <= 1000 else 20
        cost = _median_ms(lambda t=text: allowed_netlist(t, "own", None), repeat)
        print(f"| {N} | {text.count(chr(10))} | {cost:.3f} |")
    print("\n## One run: lcchain's own netlist against the same netlist as a foreign one\n")
    print(f"Median of {REPEAT} interleaved runs, milliseconds of wall time around `spice.run` "
          "(ngspice's process, its start and lcchain's reading of the raw file).\n")
    print("| N | points | `ngspice -n -b` alone (bash loop) | own netlist | foreign (allow-list + sandbox) "
          "| sandbox's share |")
    print("|---:|---:|---:|---:|---:|---:|")
    for N in (20, 100):
        text, _, _ = make_netlist(lcchain.Chain.from_rw(N, r=0.5873, w=0.0972), ChainNetlist(dt=0.05))
        tstop = transient_of(text, "own").stop
        vectors = saved_vectors(text)
        own: list[float] = []
        foreign: list[float] = []
        points = 0
        for _ in range(REPEAT):
            for flag, times in ((False, own), (True, foreign)):
                start = time.perf_counter()
                result = run(RunJob(text, vectors, tstop, foreign=flag), simulator)
                times.append(time.perf_counter() - start)
                points = result.points
        with tempfile.TemporaryDirectory() as folder:
            path = Path(folder) / "n.cir"
            path.write_text(text)
            loop = f"for i in $(seq {REPEAT}); do ngspice -n -b -r {folder}/r.raw {path} >/dev/null 2>&1; done"
            start = time.perf_counter()
            subprocess.run(["bash", "-c", loop], check=True)
            alone = (time.perf_counter() - start) / REPEAT
        a, b = 1e3 * statistics.median(own), 1e3 * statistics.median(foreign)
        print(f"| {N} | {points} | {1e3 * alone:.1f} | {a:.1f} | {b:.1f} | {b - a:+.1f} |")


def priced() -> None:
    """Each reference netlist run as a foreign one: its price (from its own .tran) beside its measured wall time."""
    simulator = find_simulator("batch")
    print("\n## Foreign netlists priced from their own `.tran`\n")
    print("The reference netlists of `netlists/`, each run as a foreign netlist (allow-list, sandbox); estimate "
          "from `lcchain.spice.foreign.foreign_estimate`, wall time of `spice.run` (median of 3).\n")
    print("| netlist | time points | unknowns | estimate s | measured s | measured / estimate |")
    print("|---|---:|---:|---:|---:|---:|")
    for path in sorted(Path("netlists").glob("*.cir")):
        text = path.read_text()
        transient = transient_of(text, path.name)
        saved = saved_vectors(text)
        estimate = foreign_estimate(text, transient, len(saved))
        times = []
        for _ in range(3):
            start = time.perf_counter()
            run(RunJob(text, saved, transient.stop), simulator)
            times.append(time.perf_counter() - start)
        measured = statistics.median(times)
        unknowns = estimate.what.rsplit(", ", 1)[-1].split()[0]
        print(f"| {path.name} | {transient.points:.0f} | {unknowns} | {estimate.seconds:.3g} | {measured:.3g} | "
              f"{measured / estimate.seconds:.2f} |")


if __name__ == "__main__":
    main()
    priced()
