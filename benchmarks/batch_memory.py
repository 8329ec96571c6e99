"""The driver's peak memory of ``lcchain batch`` against the batch's size (issue 35: flat memory from 100 to
100,000 runs), with the names on the command line and listed in a file (``--from LIST``).

    .venv/bin/python benchmarks/batch_memory.py FOLDER 1000 10000 100000 > benchmarks/batch_memory.md
    .venv/bin/python benchmarks/batch_memory.py FOLDER 1000 10000 100000 --listed --resume

``--listed``: only the names listed in a file; ``--resume``: each batch run a second time into its store, every run
stored (what a resume costs: its netlists planned again, nothing run).

FOLDER holds the netlists (``benchmarks/batch_scale.py --make COUNT FOLDER``: distinct N = 10 netlists); the first
COUNT of them, sorted, make each batch.  The peak is the driver's own ``VmHWM`` (``/proc/PID/status``, the kernel's
high-water mark of its resident memory), read every 0.2 s while it runs: its ngspice workers are other processes,
not counted.  Every store and list goes to a temporary folder, removed at the end.
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

LCCHAIN = str(Path(sys.executable).with_name("lcchain"))
ENV = {name: value for name, value in os.environ.items() if name != "PYTHONDONTWRITEBYTECODE"}


def peak(command: list[str], cwd: Path) -> tuple[float, float, str]:
    """(wall seconds, the driver's VmHWM in MB, what it printed)."""
    start = time.perf_counter()
    process = subprocess.Popen(command, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, env=ENV,
                               text=True)
    high = 0
    while process.poll() is None:
        try:
            with open(f"/proc/{process.pid}/status") as status:
                for line in status:
                    if line.startswith("VmHWM"):
                        high = max(high, int(line.split()[1]))
        except OSError:
            pass
        time.sleep(0.2)
    assert process.stdout is not None
    said = process.stdout.read().strip()
    if process.returncode != 0:
        raise SystemExit(f"lcchain batch failed: {said}")
    return time.perf_counter() - start, high / 1024, said


def main() -> None:
    flags = {arg for arg in sys.argv[1:] if arg.startswith("--")}
    given = [arg for arg in sys.argv[1:] if not arg.startswith("--")]
    folder, counts = Path(given[0]).resolve(), [int(c) for c in given[1:]]
    names = sorted(os.listdir(folder))
    print("# A batch's driver memory against its size\n")
    print(f"Command: `.venv/bin/python benchmarks/batch_memory.py FOLDER {' '.join(map(str, counts))}"
          f"{''.join(' ' + flag for flag in sorted(flags))}` (FOLDER: "
          "`benchmarks/batch_scale.py --make`'s distinct N = 10 netlists). The driver's own peak resident memory "
          "(VmHWM, read every 0.2 s), the whole command's wall time, the load average (1 min) before and after.\n")
    print("| runs | names | wall (s) | runs/s | driver peak (MB) | load |")
    print("|---:|---|---:|---:|---:|---|")
    with tempfile.TemporaryDirectory() as scratch:
        work = Path(scratch)
        for count in counts:
            listed = work / f"names{count}.txt"
            listed.write_text("\n".join(names[:count]) + "\n")
            ways = (("on the command line", names[:count]), ("`--from LIST`", ["--from", str(listed)]))
            for how, args in ways[1:] if "--listed" in flags else ways:
                store = work / f"s{count}.sqlite"
                for again in (False, True) if "--resume" in flags else (False,):
                    load = os.getloadavg()[0]
                    wall, high, _ = peak([LCCHAIN, "batch", *args, "--store", str(store)], folder)
                    print(f"| {count} | {how}{', resumed (all stored)' if again else ''} | {wall:.1f} | "
                          f"{count / wall:.0f} | {high:.0f} | {load:.1f} to {os.getloadavg()[0]:.1f} |", flush=True)
                for suffix in ("", "-wal", "-shm"):
                    Path(f"{store}{suffix}").unlink(missing_ok=True)


if __name__ == "__main__":
    main()
