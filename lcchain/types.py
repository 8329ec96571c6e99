"""The option sets of lcchain, in one place."""

from __future__ import annotations

from typing import Literal, get_args

#: Families of chains lcchain can build by name.
Case = Literal["one-mass", "two-mass", "uniform-free", "uniform-bounded", "perfect", "custom"]
#: How loop 1 (mass 1) is set in motion: an initial current (velocity) or charge (position).
Excitation = Literal["kick", "displacement"]
#: How ngspice is driven: ``ngspice -b`` subprocess, or the shared library through PySpice.
Backend = Literal["batch", "shared"]
#: How normal modes are computed: exact diagonalisation or the paper's closed form.
ModeMethod = Literal["auto", "exact", "closed-form"]
#: The two optimised designs of the paper (Tables I and II).
DesignCase = Literal["one-mass", "two-mass"]

CASES: tuple[str, ...] = get_args(Case)
EXCITATIONS: tuple[str, ...] = get_args(Excitation)
BACKENDS: tuple[str, ...] = get_args(Backend)
MODE_METHODS: tuple[str, ...] = get_args(ModeMethod)
DESIGN_CASES: tuple[str, ...] = get_args(DesignCase)
