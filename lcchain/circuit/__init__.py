"""The chain as an LC ladder: component values, real-world effects, netlist text.

Pure: text and numbers in, text out.  Masses become inductors, springs
capacitors (C = C0/K; a free end is a wire, a wall spring a capacitor to
ground).  Nothing here starts ngspice or touches a file.
"""
