"""lcchain's own time per Monte Carlo sample of examples/scenes/bench.toml, beside ngspice's (issue 23).

Run from the repository root, once per tree to compare (PYTHONPATH selects the tree measured):

    PYTHONPATH=. .venv/bin/python benchmarks/bench_theory_per_sample.py --label after

The 20 samples of bench.toml (N = 50 two-mass, gaussian pulse, Q = 100, 5 %
tolerances, seed 7) run serially in this process.  Per sample:

* ngspice: ``RunRecord.wall_s``, ngspice's process as lcchain waits for it;
* lcchain in ``execute``: ``total_s - wall_s`` (netlist, raw file, theory,
  comparison, digest);
* the theory alone, on ngspice's results kept from the first round (no
  ngspice running), as ``execute`` computes it: the chain's modes, the
  response prepared once (the pulse's mode states), the theory at ngspice's
  time points (``signals_of``), and the errors and the peak search
  (``metrics_of``, which refines the theory's peak with about 40 evaluations);
* the cost of entering the BLAS thread limit (an empty decorated function).

The theory's rows are CPU time of this process (``time.process_time``: the
theory runs on one thread, and on a machine shared with other jobs CPU time
moves less than wall time); ngspice's and ``execute``'s are wall time.
Medians over every sample of ``--repeat`` rounds, in milliseconds.
"""

from __future__ import annotations

import argparse
import platform
import statistics
import time

import numpy as np

from lcchain.core.blas import fixed_blas_threads
from lcchain.runs.execute import _response, execute, metrics_of, signals_of
from lcchain.spice.engines import find_engine
from lcchain.studies.plan import scene_sweep_plan
from lcchain.theory.spectrum import normal_modes

SCENE = "examples/scenes/bench.toml"


def ms(values: list[float]) -> str:
    return f"{1e3 * statistics.median(values):.1f}"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--label", default="this tree", help="what the measured tree is (e.g. before, after)")
    parser.add_argument("--repeat", type=int, default=5, help="rounds of the 20 samples")
    args = parser.parse_args()

    specs = [task.spec for task in scene_sweep_plan(SCENE, []).tasks]
    simulator = find_engine(specs[0].engine, specs[0].backend)
    execute(specs[0], simulator)  # imports, caches
    rows: dict[str, list[float]] = {k: [] for k in ("ngspice", "execute", "modes", "prepare", "grid", "peaks",
                                                    "theory", "blas")}
    results = []
    for round_ in range(args.repeat):
        for spec in specs:
            record = execute(spec, simulator)
            assert record.ok and record.run is not None, record.reason
            rows["ngspice"].append(record.wall_s)
            rows["execute"].append(record.total_s - record.wall_s)
            if round_ == 0:
                results.append(record.run)
    points = results[0].points
    limited = fixed_blas_threads(lambda: None)
    for _ in range(args.repeat):
        for spec, result in zip(specs, results, strict=True):
            theory = spec.theory
            assert theory is not None
            clock = time.process_time
            start = clock()
            limited()
            rows["blas"].append(clock() - start)
            start = clock()
            modes = normal_modes(theory.chain)
            rows["modes"].append(clock() - start)
            start = clock()
            ends = _response(theory, "ends", modes)
            rows["prepare"].append(clock() - start)
            start = clock()
            signals = signals_of(theory, result, modes, response=ends)
            rows["grid"].append(clock() - start)
            start = clock()
            metrics_of(theory, signals, modes=modes, ends=ends)
            rows["peaks"].append(clock() - start)
            rows["theory"].append(rows["modes"][-1] + rows["prepare"][-1] + rows["grid"][-1] + rows["peaks"][-1])

    print(f"## {args.label}\n")
    print(f"Machine: {platform.machine()}, 2 cores, Python {platform.python_version()}, numpy {np.__version__}, "
          f"ngspice {simulator.version}.  {len(specs)} samples x {args.repeat} rounds, serial, {points} time "
          f"points a sample; medians, milliseconds.\n")
    print("| per sample | ms |")
    print("|---|---:|")
    print(f"| ngspice (`wall_s`: its process as lcchain waits for it) | {ms(rows['ngspice'])} |")
    print(f"| lcchain in `execute` beyond ngspice (`total_s - wall_s`) | {ms(rows['execute'])} |")
    print(f"| theory alone (CPU): modes | {ms(rows['modes'])} |")
    print(f"| theory alone (CPU): the response prepared once (`_response`) | {ms(rows['prepare'])} |")
    print(f"| theory alone (CPU): at ngspice's points (`signals_of`) | {ms(rows['grid'])} |")
    print(f"| theory alone (CPU): errors and peak search (`metrics_of`) | {ms(rows['peaks'])} |")
    print(f"| theory alone (CPU): total | {ms(rows['theory'])} |")
    print(f"| entering the BLAS thread limit (outermost call, CPU) | {ms(rows['blas'])} |\n")


if __name__ == "__main__":
    main()
