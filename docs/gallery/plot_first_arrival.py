"""
The first arrival: uniform, optimal and perfect chains
======================================================

A kick to mass 1 of a chain of N = 20 masses reaches mass N after about N units of time. How much of it
arrives is the transmission amplitude alpha_N(t) (the velocity of mass N over the kick). A uniform chain
disperses the pulse; the two-mass optimum (tuned m1, m2 and K12 at each end) delivers almost all of it; a
perfect cradle, whose frequencies are equally spaced, delivers all of it. This is theory only, no simulator.
"""

import matplotlib.pyplot as plt
import numpy as np

import lcchain

N = 20
t = np.linspace(0, 2.5 * N, 2001)
fig, ax = plt.subplots(figsize=(7, 3.5))
for case in ("uniform-free", "two-mass", "perfect"):
    chain = lcchain.chain_for_case(case, N)
    modes = lcchain.normal_modes(chain)
    first = lcchain.first_arrival(modes)
    ax.plot(t, lcchain.transmission_amplitude(modes, t), label=f"{case}: peak {first.peak:.4f} at t = {first.time:.2f}")
ax.set_xlabel(r"t  [$\sqrt{L_0 C_0}$, or $\sqrt{m/K}$]")
ax.set_ylabel(r"$\alpha_N(t)$")
ax.set_title(f"N = {N}: the pulse at mass N")
ax.legend(loc="lower left", fontsize="small")
fig.tight_layout()
