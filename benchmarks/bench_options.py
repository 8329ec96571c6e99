"""ngspice options on this circuit: maxord, interp, KLU and chgtol (issue 4's claims, re-measured).

Run from the repository root:

    .venv/bin/python benchmarks/bench_options.py > benchmarks/options.md

Chain: the optimal two-mass chain N = 100, one transit, a kick.  Errors are
max |I_N/I0 - alpha_N(t)| at ngspice's points.
"""

import numpy as np

from lcchain.circuit.ladder import Ladder
from lcchain.circuit.netlist import Drive, SimulationOptions, netlist_text, probe_names
from lcchain.compare.waveforms import normalise
from lcchain.core.errors import LcchainError
from lcchain.spice.job import RunJob
from lcchain.spice.ngspice.runner import run
from lcchain.theory.arrivals import stop_time
from lcchain.theory.cases import chain_for_case
from lcchain.theory.spectrum import normal_modes, transmission_amplitude

N = 100
CHAIN = chain_for_case("two-mass", N)
MODES = normal_modes(CHAIN)
TSTOP = stop_time(MODES, 1)
NAMES = probe_names(N)
SCALES = {"10 uH / 10 nF / 1 mA": (1e-5, 1e-8, 1e-3), "1 nH / 1 pF / 1 uA": (1e-9, 1e-12, 1e-6)}


def netlist(scale=SCALES["10 uH / 10 nF / 1 mA"], *, extra=(), adaptive=False, defaults=(), dt=0.1, **options):
    """lcchain's netlist with ngspice options said through SimulationOptions (the text is never edited)."""
    L0, C0, I0 = scale
    ladder = Ladder(CHAIN, L0, C0)
    settings = SimulationOptions(dt=dt, tstop=TSTOP, stepping="adaptive" if adaptive else "fixed", extra=extra,
                                 ngspice_defaults=defaults, **options)
    return netlist_text(ladder, settings, Drive(I0=I0)), ladder, I0


def measure(text, ladder, I0):
    result = run(RunJob(text, NAMES, TSTOP * ladder.time_unit))
    w = normalise(result.time, result.vectors[NAMES[0]], result.vectors[NAMES[1]], time_unit=ladder.time_unit,
                  excitation="kick", I0=I0)
    return result, w, float(np.max(np.abs(w.last - transmission_amplitude(MODES, w.t))))


def main() -> None:
    print("# ngspice options on the N = 100 two-mass ladder\n")
    print("Command: `.venv/bin/python benchmarks/bench_options.py > benchmarks/options.md`\n")

    _, g2, e2 = measure(*netlist(method="gear", maxord=2))
    _, g5, e5 = measure(*netlist(method="gear", maxord=5))
    print("## maxord (gear, dt = 0.1)\n")
    print(f"maxord 2: error {e2:.3e}; maxord 5: error {e5:.3e}; "
          f"max |difference| of the waveforms {np.max(np.abs(g2.last - g5.last)):.1e}.\n")

    print("## .options interp (trap, dt = 0.1)\n")
    try:
        measure(*netlist(extra=(("interp", None),)))
        print("the run was read without error.\n")
    except LcchainError as error:
        print(f"rejected: {str(error).splitlines()[0]}\n")

    print("## KLU against Sparse (trap, dt = 0.02; ngspice ignores unknown options silently)\n")
    for option in ("klu", "sparse"):
        walls = [measure(*netlist(extra=((option, None),), dt=0.02))[0].wall_s for _ in range(3)]
        print(f"- `.options {option}`: ngspice wall {min(walls):.3f} s (best of 3)")
    print()

    print("## chgtol and adaptive stepping (trap, maximum step tstop/50)\n")
    print("| scale | tolerances | points | error |")
    print("|---|---|---:|---:|")
    for label, scale in SCALES.items():
        for defaults, what in (((), "lcchain's (scaled to I0)"), (("chgtol",), "default chgtol"),
                               (("chgtol", "abstol", "vntol"), "all defaults")):
            result, _, error = measure(*netlist(scale, adaptive=True, defaults=defaults))
            print(f"| {label} | {what} | {result.points} | {error:.3g} |")


if __name__ == "__main__":
    main()
