"""Is every request priced honestly? Each command's own estimate beside its measured wall time.

Run from the repository root:

    .venv/bin/python benchmarks/bench_pricing.py > benchmarks/pricing.md

(``--section studies`` runs the second table alone: spectra, sensitivity checks, worst cases, study workers and
``results`` exports, priced in time and in memory; see :func:`studies_section`.)

The estimate is the one lcchain itself holds each command to: the smallest
``--max-time`` it accepts, found by bisection (a refused command exits 2 at
once, before any work; one still running after 3 s was accepted and is
stopped). Then the command runs with the default limits and its wall time is
measured (the whole command, interpreter start included). Target (issue 19):
nothing runs beyond 2x its estimate.
"""

from __future__ import annotations

import math
import os
import platform
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SCENE = """[chain]
case = "two-mass"
N = 50
[excitation]
kind = "pulse"
shape = "gaussian"
width = 0.2
[effects.losses]
Q = 100
[effects.tolerance]
L = 0.05
C = 0.05
samples = 40
seed = 7
[analysis]
dt = 0.05
"""
COMMANDS = [
    ["design", "--case", "two-mass", "--N", "3000"],
    ["design", "--case", "perfect", "--N", "2000"],
    ["table", "--case", "two-mass", "--N", ",".join(str(n) for n in range(10, 110, 10))],
    ["table", "--case", "one-mass", "--N", ",".join(str(n) for n in range(3, 43))],
    ["simulate", "--case", "two-mass", "--N", "100", "--dt", "0.05"],
    ["simulate", "--case", "perfect", "--N", "200", "--dt", "0.02"],
    ["simulate", "--case", "two-mass", "--N", "300", "--dt", "0.02", "--transits", "2"],
    ["run", "samples.toml"],
    ["run", str(ROOT / "examples" / "scenes" / "cradle.toml")],
    ["sweep", "--case", "two-mass,one-mass", "--N", "20,50,100", "--dt", "0.05,0.02", "--store", "s.sqlite",
     "--workers", "2"],
    ["sweep", "samples.toml", "--vary", "chain.N=20,40", "--store", "m.sqlite", "--workers", "2"],
    ["batch", *[str(p) for p in sorted((ROOT / "netlists").glob("*N20.cir"))], "--store", "b.sqlite",
     "--executor", "serial"],
    ["bench", "accuracy", "--quick", "--out", "bq"],
]


def _accepted(command: list[str], seconds: float, folder: str) -> bool:
    """Whether lcchain accepts the command under --max-time SECONDS (it refuses at once, before any work)."""
    with subprocess.Popen([*command, "--max-time", repr(seconds)], cwd=folder, stdout=subprocess.DEVNULL,
                          stderr=subprocess.PIPE, text=True, start_new_session=True) as proc:
        try:
            _, err = proc.communicate(timeout=3.0)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.communicate()
            return True
    for leftover in Path(folder).glob("*.sqlite*"):
        leftover.unlink()
    return not (proc.returncode == 2 and "--max-time" in err)


def _price(command: list[str], folder: str) -> float:
    """The smallest --max-time the command is accepted under, within 3 %."""
    lo, hi = 0.01, 1e5
    while hi / lo > 1.03:
        mid = math.sqrt(lo * hi)
        lo, hi = (lo, mid) if _accepted(command, mid, folder) else (mid, hi)
    return hi


def main() -> None:
    if sys.argv[1:] == ["--section", "studies"]:
        studies_section()
        return
    lcchain = [sys.executable, "-m", "lcchain"]
    print("# Requests priced against what they cost\n")
    print("Command: `.venv/bin/python benchmarks/bench_pricing.py > benchmarks/pricing.md`  ")
    print(f"Machine: {platform.machine()}, 2 cores, Python {platform.python_version()}. Estimate: the smallest "
          "`--max-time` lcchain accepts the command under (bisection); measured: the command's wall time, "
          "interpreter start included.\n")
    print("| command | estimate s | measured s | measured / estimate |")
    print("|---|---:|---:|---:|")
    worst = 0.0
    with tempfile.TemporaryDirectory() as folder:
        (Path(folder) / "samples.toml").write_text(SCENE)
        for argv in COMMANDS:
            estimate = _price([*lcchain, *argv], folder)
            with tempfile.TemporaryDirectory() as fresh:  # nothing the bisection's runs left can be resumed
                (Path(fresh) / "samples.toml").write_text(SCENE)
                start = time.perf_counter()
                done = subprocess.run([*lcchain, *argv], cwd=fresh, capture_output=True, text=True)
                measured = time.perf_counter() - start
            if done.returncode != 0:
                raise RuntimeError(f"{argv}: exit {done.returncode}: {done.stderr[-500:]}")
            worst = max(worst, measured / estimate)
            shown = " ".join(a if len(a) < 40 else a[:37] + "..." for a in argv).replace(str(ROOT) + "/", "")
            print(f"| `lcchain {shown}` | {estimate:.3g} | {measured:.3g} | {measured / estimate:.2f} |")
    print(f"\nWorst ratio: {worst:.2f} (target: at most 2).")
    studies_section()


# ------------------------------------------------------------------ spectra, studies' workers and exports
#: A worst case's scene: its corners at an accuracy (each corner's step chosen in the driver, two runs each).
WORST_ACCURACY = """[chain]
case = "two-mass"
N = 30
[effects.tolerance]
L = 0.05
C = 0.02
samples = 50
seed = 3
[analysis]
accuracy = 1e-4
"""
#: ... and at a fixed step, for a store of 2^8 + 3 = 259 corners that the exports read.
WORST_DT = WORST_ACCURACY.replace("samples = 50", "samples = 1").replace("accuracy = 1e-4", "dt = 0.05")
#: A command whose price the studies' table does not touch: its ratio now against its ratio on a quiet machine
#: says how loaded the machine was while the table was measured.
GAUGE = ["design", "--case", "perfect", "--N", "2000"]
GAUGE_QUIET = 0.80
#: Commands priced in time and memory; ``{stores}`` is the folder of the stores the exports read.
STUDY_COMMANDS = [
    ["spectrum", "--case", "two-mass", "--N", "20"],
    ["spectrum", "--case", "two-mass", "--N", "20", "--points", "50000"],
    ["spectrum", "--case", "two-mass", "--N", "100", "--points", "20000"],
    ["spectrum", "--case", "two-mass", "--N", "20", "--Q", "100", "--points", "20000"],
    ["spectrum", "--case", "two-mass", "--N", "500"],
    ["spectrum", "--case", "two-mass", "--N", "1000"],
    ["sensitivity", "--case", "two-mass", "--N", "50", "--check", "3"],
    ["sensitivity", "--case", "two-mass", "--N", "20", "--check", "6", "--workers", "2"],
    ["sweep", "worst.toml", "--worst-case", "--components", "4", "--store", "w.sqlite"],
    ["sweep", "worst-dt.toml", "--worst-case", "--components", "6", "--store", "w6.sqlite"],
    ["sweep", "--case", "two-mass,one-mass", "--N", "100,200", "--analysis", "ac", "--store", "a.sqlite",
     "--workers", "2"],
    ["sweep", "--case", "two-mass,one-mass", "--N", "20,50,100", "--dt", "0.05,0.02", "--store", "d.sqlite",
     "--workers", "2", "--executor", "dask"],
    ["results", "{stores}/w8.sqlite", "--netcdf", "w8.nc", "--waveforms"],
    ["results", "{stores}/w8.sqlite", "--json"],
    ["results", "{stores}/a.sqlite", "--netcdf", "a.nc", "--waveforms"],
]


def _cmdline(pid: int) -> bytes:
    try:
        with open(f"/proc/{pid}/cmdline", "rb") as cmdline:
            return cmdline.read()
    except OSError:
        return b""


def _tree(root: int) -> list[int]:
    """``root`` and every process under it, but a fork that has not yet started its program (its command line is
    its parent's): its pages are its parent's, and read a moment apart the two would count them one and a half
    times."""
    children: dict[int, list[int]] = {}
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                with open(f"/proc/{entry}/stat") as stat:
                    parent = int(stat.read().rsplit(")", 1)[1].split()[1])
            except (OSError, IndexError, ValueError):
                continue
            children.setdefault(parent, []).append(int(entry))
    found, todo = [], [root]
    while todo:
        pid = todo.pop()
        found.append(pid)
        line = _cmdline(pid)
        todo.extend(child for child in children.get(pid, []) if _cmdline(child) != line)
    return found


def _pss(pids: list[int]) -> int:
    """The processes' proportional set size together, bytes (a page two of them share counts once)."""
    total = 0
    for pid in pids:
        try:
            with open(f"/proc/{pid}/smaps_rollup") as rollup:
                total += next(int(line.split()[1]) * 1024 for line in rollup if line.startswith("Pss:"))
        except (OSError, StopIteration, ValueError):
            continue
    return total


#: The environment of the commands: TMPDIR a scratch folder of the benchmark's own (a Dask cluster stopped during
#: the bisection may leave its scratch space there).
_ENV: dict[str, str] = {}


def _measured(command: list[str], folder: str) -> tuple[float, float]:
    """The command's wall time and the peak memory of its process tree (PSS, sampled every 20 ms)."""
    start = time.perf_counter()
    with subprocess.Popen(command, cwd=folder, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                          start_new_session=True, env=_ENV or None) as proc:
        peak = 0
        while proc.poll() is None:
            peak = max(peak, _pss(_tree(proc.pid)))
            time.sleep(0.02)
        err = proc.stderr.read() if proc.stderr else ""
    if proc.returncode != 0:
        raise RuntimeError(f"{command}: exit {proc.returncode}: {err[-500:]}")
    return time.perf_counter() - start, peak


def _started_work(pid: int) -> bool:
    """Whether the process has a child: ngspice, a pool or Dask worker, a warm worker. lcchain starts none before
    every price check has passed, so a child says the command was accepted."""
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                with open(f"/proc/{entry}/stat") as stat:
                    if int(stat.read().rsplit(")", 1)[1].split()[1]) == pid:
                        return True
            except (OSError, IndexError, ValueError):
                continue
    return False


def _refused(command: list[str], option: str, value: str, folder: str) -> bool:
    """Whether lcchain refuses the command under ``option value`` before any work. It was accepted once it starts
    a child process or finishes (a refusal exits 2 naming the option), and is then stopped; a refusal can take
    longer than the whole command took a moment before on a loaded machine, so no fixed cut-off decides. What an
    accepted attempt left in the folder is removed."""
    with subprocess.Popen([*command, option, value], cwd=folder, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                          text=True, start_new_session=True, env=_ENV or None) as proc:
        start = time.perf_counter()
        while proc.poll() is None and not _started_work(proc.pid) and time.perf_counter() - start < 300.0:
            time.sleep(0.05)
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
        err = proc.stderr.read() if proc.stderr else ""
    for leftover in Path(folder).iterdir():
        if leftover.suffix in (".sqlite", ".nc") or ".sqlite-" in leftover.name or leftover.name.startswith("."):
            leftover.unlink()
    return proc.returncode == 2 and option in err


def _smallest(command: list[str], option: str, unit: str, lo: float, hi: float, folder: str) -> float:
    """The smallest value of ``option`` the command is accepted under, within 3 % (bisection)."""
    while hi / lo > 1.03:
        mid = math.sqrt(lo * hi)
        lo, hi = (mid, hi) if _refused(command, option, f"{mid:.6g}{unit}", folder) else (lo, mid)
    return hi


def _study_inputs(folder: Path) -> None:
    (folder / "worst.toml").write_text(WORST_ACCURACY)
    (folder / "worst-dt.toml").write_text(WORST_DT)


def _study_stores(lcchain: list[str], stores: Path) -> None:
    """The stores the exports read: 259 corners of a worst case, and a sweep of AC runs."""
    _study_inputs(stores)
    for argv in (["sweep", "worst-dt.toml", "--worst-case", "--components", "8", "--store", "w8.sqlite"],
                 ["sweep", "--case", "two-mass,one-mass,uniform-bounded", "--N", "100,200", "--analysis", "ac",
                  "--store", "a.sqlite"]):
        subprocess.run([*lcchain, *argv], cwd=stores, capture_output=True, check=True)


def studies_section() -> None:
    """Spectra, sensitivity checks, worst cases, studies on pool and Dask workers, and ``results`` exports: each
    command's time price and memory price (the smallest --max-time and --max-memory it is accepted under, by
    bisection) beside its wall time and the peak memory of its whole process tree (its workers and simulators
    included; PSS, so that pages the processes share count once), each run in a fresh folder."""
    lcchain = [sys.executable, "-m", "lcchain"]
    load = os.getloadavg()[0]
    print("\n## Spectra, studies' workers and exports: time and memory\n")
    print("Command: `.venv/bin/python benchmarks/bench_pricing.py --section studies` (also run at the end of the "
          "whole benchmark).  ")
    print(f"Priced: the smallest `--max-time` and `--max-memory` lcchain accepts the command under (bisection; an "
          f"attempt was accepted once it started a child process, ngspice or a worker, or finished); "
          f"measured: its wall time and the peak PSS of its process tree (driver, pool or Dask workers, warm "
          f"workers, ngspice), sampled every 20 ms. Load average at the start: {load:.1f} on "
          f"{os.cpu_count()} cores{' (under load: other work shared the machine)' if load > 1.5 else ''}.\n")
    print("| command | priced s | measured s | ratio | priced MiB | measured MiB | ratio |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    worst_time = worst_memory = 0.0
    with tempfile.TemporaryDirectory() as stores_dir, tempfile.TemporaryDirectory() as folder, \
            tempfile.TemporaryDirectory() as scratch:
        _ENV.update(os.environ, TMPDIR=scratch)
        stores = Path(stores_dir)
        _study_stores(lcchain, stores)
        _study_inputs(Path(folder))
        for template in STUDY_COMMANDS:
            argv = [arg.replace("{stores}", stores_dir) for arg in template]
            command = [*lcchain, *argv]
            with tempfile.TemporaryDirectory() as fresh:
                _study_inputs(Path(fresh))
                wall, peak = _measured(command, fresh)
            seconds = _smallest(command, "--max-time", "", 0.01, 1e5, folder)
            memory = _smallest(command, "--max-memory", "M", 1.0, 65536.0, folder) * 2**20
            worst_time, worst_memory = max(worst_time, wall / seconds), max(worst_memory, peak / memory)
            shown = " ".join(template).replace("{stores}/", "")
            print(f"| `lcchain {shown}` | {seconds:.3g} | {wall:.3g} | {wall / seconds:.2f} | {memory / 2**20:.0f} "
                  f"| {peak / 2**20:.0f} | {peak / memory:.2f} |", flush=True)
        gauge = [*lcchain, *GAUGE]
        with tempfile.TemporaryDirectory() as fresh:
            wall, _ = _measured(gauge, fresh)
        priced = _smallest(gauge, "--max-time", "", 0.01, 1e5, folder)
    print(f"\nWorst ratios: time {worst_time:.2f}, memory {worst_memory:.2f} (target: at most 2). The exports read "
          "a worst case of 2^8 + 3 = 259 corners (N = 30, dt = 0.05) and a sweep of six AC runs (N = 100, 200), "
          f"made first. Load gauge: `lcchain {' '.join(GAUGE)}`, whose price this work left alone, ran "
          f"{wall / priced:.2f} times its price now ({GAUGE_QUIET} on the quiet machine).")


if __name__ == "__main__":
    main()
