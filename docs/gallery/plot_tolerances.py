"""
Real parts: a Monte Carlo of 5 % coils and capacitors
=====================================================

A scene (written here as a dictionary; a TOML file says the same) draws 8 boards whose every coil and
capacitor is off by up to 5 %, rounds them to the E24 series, and runs each in ngspice. Each board is
compared with the exact theory of its own parts, so the error stays the simulator's; the spread of the
transmitted peak is what the parts cost the cradle.
"""

import lcchain

scene = lcchain.parse_scene({
    "title": "Two-mass N = 20, E24 parts at 5 %",
    "chain": {"case": "two-mass", "N": 20},
    "effects": {"tolerance": {"L": 0.05, "C": 0.05, "samples": 8, "seed": 1},
                "preferred_values": {"series": "E24"}},
    "analysis": {"transits": 1, "accuracy": 1e-3},
}, source="plot_tolerances.py")
result = lcchain.run_scene(scene, lcchain.SceneRun(write_outputs=False))
print(result)
fig = result.plot()
