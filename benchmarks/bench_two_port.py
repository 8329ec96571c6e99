"""The two-port's price (:func:`lcchain.runs.twoport.two_port_estimate`) against its wall time: two ngspice AC
analyses and the exact phasors, as ``lcchain spectrum --touchstone`` runs them.

    .venv/bin/python benchmarks/bench_two_port.py
"""

from __future__ import annotations

import time

from lcchain.circuit.effects import CapacitorESR, CoilCapacitance, Losses
from lcchain.runs.request import AC, Request
from lcchain.runs.twoport import two_port, two_port_estimate, two_port_theory
from lcchain.theory.cases import chain_for_case


def main() -> None:
    for N, effects in ((8, ()), (100, ()), (30, (CoilCapacitance(0.01), CapacitorESR(0.01))), (400, (Losses(100.0),)),
                       (2000, ())):
        request = Request(chain_for_case("two-mass", N), AC(None), effects=effects)
        price = two_port_estimate(request)
        start = time.perf_counter()
        measured = two_port(request)
        two_port_theory(request, measured.frequency)
        wall = time.perf_counter() - start
        names = ", ".join(effect.key for effect in effects) or "none"
        print(f"N = {N:5d}, effects {names}: price {price.seconds:.2f} s, wall {wall:.2f} s "
              f"({wall / price.seconds:.2f} of the price); {price.what}")


if __name__ == "__main__":
    main()
