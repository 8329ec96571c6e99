"""How much of a batch's whole command its imports are: ``lcchain batch`` run by ``main()`` in a fresh interpreter,
its modules imported before the clock starts (``pre``), numpy alone imported first (``numpy``), or nothing
(``cold``), interleaved.  Used in benchmarks/batch.md's thirteenth pass.

    .venv/bin/python benchmarks/batch_preimported.py [N] [COUNT] [ROUNDS]

(N = 100, COUNT = 40 distinct netlists of ``bench_batch.write_netlists``, ROUNDS = 5.)
"""

from __future__ import annotations

import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_batch import write_netlists  # noqa: E402

CHILD = """
import sys, time, os
what = sys.argv[1]
t0 = time.perf_counter()
if what == "pre":
    import numpy, lcchain.cli.main, lcchain.app.batch, lcchain.cli.batch, lcchain.spice.engines
    import lcchain.studies.executors, lcchain.studies.plan, lcchain.studies.stream, lcchain.studies.run
    import lcchain.spice.ngspice.warm
elif what == "numpy":
    import numpy
t1 = time.perf_counter()
from lcchain.cli.main import main
sys.argv = ["lcchain", "batch", *sys.argv[3:], "--json", "--store", sys.argv[2]]
out, sys.stdout = sys.stdout, open(sys.argv[2] + ".out", "w")
try:
    main()
except SystemExit:
    pass
sys.stdout = out
print(f"{time.perf_counter() - t1:.4f}")
"""


def main() -> None:
    N, count, rounds = (int(v) for v in (sys.argv[1:] + ["100", "40", "5"][len(sys.argv) - 1:])[:3])
    work = Path(tempfile.mkdtemp(prefix="lcchain-preimported-"))
    paths = write_netlists(work / "netlists", N, count)
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    times: dict[str, list[float]] = {"cold": [], "numpy": [], "pre": []}
    for r in range(rounds):
        for what in times:
            store = work / f"{what}-{r}.sqlite"
            done = subprocess.run([sys.executable, "-c", CHILD, what, str(store), *paths], capture_output=True,
                                  text=True, env=env, check=True)
            times[what].append(float(done.stdout.split()[-1]))
    for what, values in times.items():
        print(f"{what}: batch {statistics.median(values):.3f} s (median of {rounds}; "
              f"{', '.join(f'{v:.3f}' for v in values)})")


if __name__ == "__main__":
    main()
