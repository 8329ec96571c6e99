"""ngspice's waveforms against theory: dimensionless signals, errors, arrivals, the accuracy model.

Arrays in, numbers out: nothing here starts ngspice or touches a file.
"""
