"""
The ladder in ngspice against exact theory
==========================================

The two-mass optimal chain, N = 20, as an LC ladder: every mass an inductor, every spring a capacitor. A
kick is an initial current in the first coil; ngspice integrates the ladder with the trapezoidal rule at a
step chosen for the requested accuracy, and lcchain compares the current in the last coil with alpha_N(t).
The error is predicted before the run (the accuracy model) and measured after it.
"""

import lcchain

chain = lcchain.chain_for_case("two-mass", 20)
report = lcchain.simulate(lcchain.Request(chain, lcchain.Transient(accuracy=1e-4, transits=2)))
print(report)
print(f"max |simulation - theory| = {report.comparison.max_abs_error:.2e}")
fig = report.plot()
