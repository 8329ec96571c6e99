"""The only code that starts ngspice or imports PySpice.

It works on netlist text and vector names and knows nothing of chains: find
the simulator once (:func:`~lcchain.spice.simulator.find_simulator`), run a
netlist (:func:`~lcchain.spice.runner.run`), read its raw file, check a
foreign netlist for unsafe lines, and say what is missing (``doctor``).
"""
