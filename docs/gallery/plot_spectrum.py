"""
The spectrum measured in the circuit
====================================

Why the pulse arrives: its end masses select modes whose frequencies are almost equally spaced. An AC
analysis of the same ladder (ngspice drives loop 1 with a unit AC voltage) measures every mode's frequency
omega_n and weight P_n, and lcchain sets them beside the theory's.
"""

import numpy as np

import lcchain

report = lcchain.spectrum(lcchain.Request(lcchain.chain_for_case("two-mass", 20), lcchain.AC()))
print(report)
seen = ~np.isnan(report.omega)
print(f"{seen.sum()} modes seen; max |omega - theory| / omega = {report.max_rel_error_omega:.1e}")
fig = report.plot()
