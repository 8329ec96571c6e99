"""Shared test helpers: named tolerances, comparison with printed digits, ngspice fixtures."""
