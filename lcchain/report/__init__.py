"""Figures, reports and files: the only place matplotlib is imported.

Everything here can be rebuilt from results (records, scene reports) without
running ngspice again.  matplotlib is imported inside the functions, so
``import lcchain.report`` stays light.
"""
