"""A batch's path to its first warm run: the shared library's version checked (:func:`warm_simulator`) and a
thread's worker for a foreign netlist taken (:func:`worker_for`, in the sandbox), seconds, in one process.

    for i in 1 2 3 4 5 6 7; do
        PYTHONPATH=/tmp/before .venv/bin/python benchmarks/warm_first_worker.py
        .venv/bin/python benchmarks/warm_first_worker.py
    done
"""

from __future__ import annotations

import time

from lcchain.spice.ngspice.find import find_simulator
from lcchain.spice.ngspice.place import placement
from lcchain.spice.ngspice.warm import close_workers, warm_simulator, worker_for

simulator = find_simulator("batch")
start = time.perf_counter()
warm = warm_simulator(simulator)
with placement(warm, True, None) as place:
    worker_for(warm.executable, place.prefix, place.cwd, place.env)
print(f"{time.perf_counter() - start:.4f}")
close_workers()
