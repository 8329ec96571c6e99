"""A batch of netlists as engineers write them, against ``xargs -P2 ngspice -b`` on the same files (issue 31).

Run from the repository root, on a quiet machine:

    .venv/bin/python benchmarks/bench_batch_mixed.py [--count 200] [--rounds 3] > benchmarks/batch_mixed.md

The netlists, written into a temporary folder, are a mix:

* RC low-passes with ``.param`` values and ``.meas tran`` (rise time, a value at a time);
* RLC band-passes swept by ``.ac dec`` with ``.meas ac`` (the peak and the response at 1 MHz);
* two-stage RC filters as ``.subckt`` instances with parameters;
* diode half-wave rectifiers (``.model D``) with ``.meas``;
* LC ladders of 10 to 40 sections as nested subcircuits;
* one in ten refused by the allow-list: a ``.control`` block (ngspice runs it, lcchain stores the refusal), an
  ``.option`` that names an output file format, a ``.four`` card.

Each contender is the whole command, timed from here: ``lcchain batch FILES --store S --workers 2`` (a fresh
store each round) and ``xargs -P2 -n1 ngspice -b -r RAW`` writing each raw file beside its netlist, as lcchain
does (xargs runs the refused files too: ngspice has no allow-list). Rounds are interleaved; the table gives the
median of each, and the first lcchain round's counts (ok, refused, failed, measurements stored).
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

RC = """RC low-pass {i}
.param r = {r} c = {c}
V1 in 0 PULSE(0 1 0 1n 1n 1 2)
R1 in out {{r}}
C1 out 0 {{c}}
.tran {step} {stop}
.meas tran trise trig v(out) val=0.1 rise=1 targ v(out) val=0.9 rise=1
.meas tran vmid find v(out) at={mid}
.end
"""
RLC = """RLC band-pass {i}
V1 in 0 AC 1
R1 in a {r}
L1 a b {l}
C1 b out {c}
R2 out 0 50
.ac dec 200 1k 100meg
.meas ac peak max v(out)
.meas ac v1meg find v(out) at=1meg
.end
"""
SUBCKT = """Two RC stages {i}
.subckt stage a b params: r=1k c=1n
R1 a b {{r}}
C1 b 0 {{c}}
.ends stage
V1 in 0 PULSE(0 1 0 1n 1n 1 2)
X1 in m stage r={r} c=1n
X2 m out stage r={r2} c=2n
.tran 10n {stop}
.meas tran vend find v(out) at={stop}
.end
"""
DIODE = """Half-wave rectifier {i}
.model dmod D (is=1e-14 n=1.05)
V1 in 0 SIN(0 5 {f})
D1 in out dmod
R1 out 0 1k
C1 out 0 {c}
.tran {step} {stop}
.meas tran vmax max v(out)
.end
"""
LADDER = """LC ladder of {n} sections {i}
.subckt cell a b
L1 a b 1u
C1 b 0 1n
.ends cell
.subckt four a b
X1 a c1 cell
X2 c1 c2 cell
X3 c2 c3 cell
X4 c3 b cell
.ends four
V1 in 0 PULSE(0 1 0 1n 1n 1 2)
R1 in n0 31.6
{cells}
R2 n{last} 0 31.6
.tran 1n {stop}
.meas tran tdelay trig v(n0) val=0.25 rise=1 targ v(n{last}) val=0.25 rise=1
.end
"""
REFUSED = [
    "Control block {i}\nR1 a 0 1k\nV1 a 0 1\n.tran 1u 10u\n.control\nrun\n.endc\n.end\n",
    "Output format {i}\nR1 a 0 1k\nV1 a 0 1\n.options filetype=ascii\n.tran 1u 10u\n.end\n",
    "Fourier {i}\nR1 a 0 1k\nV1 a 0 SIN(0 1 1meg)\n.tran 10n 10u\n.four 1meg v(a)\n.end\n",
]


def write_netlists(folder: Path, count: int) -> list[str]:
    paths = []
    for i in range(count):
        kind = i % 10
        if kind == 9:
            text = REFUSED[(i // 10) % len(REFUSED)].format(i=i)
        elif kind in (0, 1):
            r, c = 1e3 * (1 + i / 100), 1e-9
            tau = r * c
            text = RC.format(i=i, r=r, c=c, step=tau / 50, stop=8 * tau, mid=tau)
        elif kind in (2, 3):
            text = RLC.format(i=i, r=10 + i, l=1e-6 * (1 + i / 200), c=1e-9)
        elif kind in (4, 5):
            text = SUBCKT.format(i=i, r=1e3 + i, r2=2e3 + i, stop=20e-6)
        elif kind in (6, 7):
            f = 1e3 * (1 + i / 100)
            text = DIODE.format(i=i, f=f, c=1e-6, step=1 / f / 200, stop=5 / f)
        else:
            fours = 3 + (i // 10) % 8  # 12 to 40 sections
            cells = "\n".join(f"X{k} n{k} n{k + 1} four" for k in range(fours))
            text = LADDER.format(i=i, n=4 * fours, cells=cells, last=fours, stop=4 * fours * 40e-9)
        path = folder / f"n{i:04d}.cir"
        path.write_text(text)
        paths.append(str(path))
    return paths


def time_lcchain(paths: list[str], store: Path) -> tuple[float, dict[str, object]]:
    start = time.perf_counter()
    done = subprocess.run([sys.executable, "-m", "lcchain", "batch", *paths, "--store", str(store), "--workers", "2",
                           "--json"], capture_output=True, text=True)
    seconds = time.perf_counter() - start
    if done.returncode not in (0, 1):
        raise SystemExit(done.stderr[-2000:])
    return seconds, json.loads(done.stdout)


def time_xargs(paths: list[str], folder: Path) -> float:
    listing = folder / "list.txt"
    listing.write_text("\n".join(paths) + "\n")
    script = 'ngspice -b -r "${0%.cir}.raw" "$0" >"${0%.cir}.log" 2>&1; true'
    start = time.perf_counter()
    subprocess.run(["xargs", "-a", str(listing), "-P2", "-n1", "sh", "-c", script], check=True)
    return time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--count", type=int, default=200)
    parser.add_argument("--rounds", type=int, default=3)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp) / "netlists"
        folder.mkdir()
        paths = write_netlists(folder, args.count)
        times: dict[str, list[float]] = {"lcchain": [], "xargs": []}
        first: dict[str, object] = {}
        for round_ in range(args.rounds):
            order = ["lcchain", "xargs"] if round_ % 2 == 0 else ["xargs", "lcchain"]
            for who in order:
                if who == "lcchain":
                    store = Path(tmp) / f"store{round_}.sqlite"
                    seconds, summary = time_lcchain(paths, store)
                    first = first or summary
                    times["lcchain"].append(seconds)
                else:
                    times["xargs"].append(time_xargs(paths, folder))
                    for raw in folder.glob("*.raw"):
                        raw.unlink()
        measured = 0
        if first:
            done = subprocess.run([sys.executable, "-m", "lcchain", "results", str(Path(tmp) / "store0.sqlite"),
                                   "--json"], capture_output=True, text=True, check=True)
            runs = json.loads(done.stdout)
            runs = runs["runs"] if isinstance(runs, dict) else runs
            measured = sum(len(run.get("measurements") or {}) for run in runs)
        shutil.rmtree(folder)
    load = os.getloadavg()
    lc, xa = statistics.median(times["lcchain"]), statistics.median(times["xargs"])
    print(f"Machine: {platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}; load average "
          f"after the runs {load[0]:.2f} {load[1]:.2f} {load[2]:.2f}.  {args.count} netlists, {args.rounds} "
          "interleaved rounds, medians.\n")
    print("| contender | wall s (median) | each round |")
    print("|---|---:|---|")
    print(f"| `lcchain batch --workers 2` | {lc:.2f} | {', '.join(f'{t:.2f}' for t in times['lcchain'])} |")
    print(f"| `xargs -P2 ngspice -b` | {xa:.2f} | {', '.join(f'{t:.2f}' for t in times['xargs'])} |")
    print(f"\nlcchain / xargs: {lc / xa:.2f}.  lcchain's first round: {first.get('ok')} ok, {first.get('refused')} "
          f"refused, {first.get('failed')} failed; {measured} `.meas` values stored.")


if __name__ == "__main__":
    main()
