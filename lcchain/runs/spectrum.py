"""The paper's mechanism in the circuit: the ladder's normal frequencies and mode weights from an AC analysis.

:func:`measure_spectrum` drives the ladder in loop 1 with a unit AC voltage in ngspice
(:func:`lcchain.circuit.netlist.ac_netlist_text`, :func:`lcchain.spice.ac.run_ac`), identifies the poles
and residues of I_1/V_1 and I_N/V_1 (:func:`lcchain.compare.spectrum.fit_spectrum`), and sets them beside
the exact theory: omega_n, and P_n, the mode's coefficient in alpha_N(t) = sum_n P_n cos(omega_n t)
(m_1 times the residue of Y_N1 Z0; for a symmetric chain (-1)^(n-1) times the mode density of Eq. e.Pn).

A mode whose weight at the ends is below what the samples resolve has no visible pole there: the circuit
does not show it between its ends.  Such modes are listed as unseen, with their theoretical weight; the
error of P counts them with P = 0 (a perfect cradle's edge modes weigh ~2^-(N-1)).

It is the request's AC analysis (:class:`lcchain.runs.request.AC`) planned and executed like any run
(:func:`lcchain.runs.request.plan_request`, :func:`lcchain.runs.execute.execute`): scenes, sweeps and stores
make the same run.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..compare.spectral import (
    DEFAULT_OVERSAMPLING,
    OMEGA_MARGIN,
    OMEGA_WEIGHT_FLOOR,
    SPECTRUM_MAX_N,
    SpectrumMetrics,
)
from ..compare.spectrum import SpectrumFit
from ..core.budget import Budget
from ..core.checks import instance
from ..core.errors import SimulationError
from ..core.types import DEFAULT_C0, DEFAULT_L0
from ..spice.engines import DEFAULT_ENGINE
from ..spice.simulator import Simulator
from ..theory.chain import Chain
from ..theory.modes import Modes
from .execute import execute
from .request import AC, Request, plan_request
from .spec import SpectrumTheory

__all__ = ["SpectrumReport", "measure_spectrum", "OMEGA_MARGIN", "SPECTRUM_MAX_N", "OMEGA_WEIGHT_FLOOR",
           "DEFAULT_OVERSAMPLING"]


@dataclass(frozen=True, eq=False)
class SpectrumReport:
    """A ladder's spectrum from ngspice beside theory.

    Attributes
    ----------
    chain : Chain
    theory : Modes
        The driven modes (omega_n, density m_1 u_1n^2, transfer P_n = m_1 u_1n u_Nn).
    fit : SpectrumFit
        The poles and residues found in the circuit.
    seen : ndarray of int
        For each fitted pole, the index of its theoretical mode.
    points : int
        Frequencies of the AC sweep, evenly spaced on (0, omega_max].
    omega_max : float
    engine_version, netlist_sha256 : str
    timings : dict
        Seconds: the engine's process (``ngspice_s``, whichever engine ran: the key predates engines), the fit, and
        the whole call.
    engine : str
        The engine that ran the AC analysis.
    """

    chain: Chain
    theory: Modes
    fit: SpectrumFit
    seen: np.ndarray
    points: int
    omega_max: float
    engine_version: str
    netlist_sha256: str
    timings: dict[str, float] = field(default_factory=dict)
    engine: str = DEFAULT_ENGINE

    @property
    def omega(self) -> np.ndarray:
        """The circuit's frequency of every theoretical mode (NaN where unseen)."""
        out = np.full(self.theory.N, np.nan)
        out[self.seen] = self.fit.omega
        return out

    @property
    def P(self) -> np.ndarray:
        """The circuit's P_n of every theoretical mode (0 where unseen)."""
        out = np.zeros(self.theory.N)
        out[self.seen] = self.chain.masses[0] * self.fit.last
        return out

    @property
    def resolved(self) -> np.ndarray:
        """Whether each theoretical mode weighs enough at the ends to be placed to the targets (|P_n| >=
        :data:`OMEGA_WEIGHT_FLOOR`)."""
        return np.abs(self.theory.transfer) >= OMEGA_WEIGHT_FLOOR

    @property
    def metrics(self) -> SpectrumMetrics:
        """The circuit's modes beside theory, as a run's record holds them."""
        return SpectrumMetrics(self.theory.omega, self.omega, self.theory.transfer, self.P, self.resolved)

    @property
    def max_rel_error_omega(self) -> float:
        """Largest |omega_circuit - omega_theory| / omega_theory over the resolved modes (a zero mode: absolute);
        an unseen resolved mode is an infinite error."""
        return self.metrics.max_rel_error_omega

    @property
    def max_abs_error_P(self) -> float:
        """Largest |P_circuit - P_theory| over every mode (an unseen one counts with P = 0)."""
        return self.metrics.max_abs_error_P

    def to_dict(self) -> dict[str, Any]:
        """``lcchain spectrum --json``."""
        omega, P = self.omega, self.P
        modes = []
        for n in range(self.theory.N):
            seen = bool(np.isfinite(omega[n]))
            modes.append({"n": n + 1, "omega": float(omega[n]) if seen else None, "P": float(P[n]) if seen else None,
                          "omega_theory": float(self.theory.omega[n]), "P_theory": float(self.theory.transfer[n]),
                          "seen": seen, "resolved": bool(self.resolved[n])})
        return {"N": self.chain.N, "case": self.chain.name, "points": self.points, "omega_max": self.omega_max,
                "engine": self.engine, "engine_version": self.engine_version, "netlist_sha256": self.netlist_sha256,
                "modes": modes, "seen": int(self.seen.size), "max_rel_error_omega": self.max_rel_error_omega,
                "max_abs_error_P": self.max_abs_error_P, "fit_steps": self.fit.sweeps, "timings": self.timings}


def measure_spectrum(chain: Chain, *, points: int | None = None, L0: float = DEFAULT_L0, C0: float = DEFAULT_C0,
                     simulator: Simulator | None = None, budget: Budget | None = None,
                     timeout: float = 3600.0, engine: str = DEFAULT_ENGINE) -> SpectrumReport:
    """The ladder's spectrum in an engine's AC analysis against exact theory.

    Parameters
    ----------
    chain : Chain
        A lossless chain (walls and coupled coils included), N <= :data:`SPECTRUM_MAX_N`.
    points : int, optional
        Frequencies of the sweep; default twice the fewest that separate every pole
        (:func:`lcchain.compare.spectrum.min_points`).  Fewer than that are refused, naming the minimum.
    L0, C0 : float
        Bulk inductance (H) and capacitance (F).
    simulator : Simulator, optional
        The engine's batch transport.
    budget : Budget, optional
        The AC run is priced first (points x unknowns, times the engine's ``ac_relative_cost``).
    engine : str
        An engine with an AC analysis (:func:`lcchain.spice.engines.ac_engine`): ``"ngspice"`` or ``"gnucap"``.

    Raises
    ------
    ParameterError, BudgetError
        Before the engine starts.
    """
    instance("chain", chain, Chain)
    plan = plan_request(Request(chain, AC(points), L0=L0, C0=C0, timeout=timeout, engine=engine), budget)
    spec = plan.specs[0]
    record = execute(spec, simulator)
    if not record.ok or record.spectrum is None or record.ac is None:
        raise SimulationError(record.reason, record.log_tail, record.status)
    spectrum, theory = record.spectrum, spec.theory
    assert spectrum.fit is not None and spectrum.seen is not None and spec.points is not None  # execute's own
    assert plan.omega_max is not None and isinstance(theory, SpectrumTheory) and theory.modes is not None
    return SpectrumReport(chain, theory.modes, spectrum.fit, spectrum.seen, spec.points, plan.omega_max,
                          record.engine_version, record.ac.netlist_sha256,
                          {"ngspice_s": record.wall_s, "fit_s": record.total_s - record.wall_s,
                           "total_s": record.total_s}, record.engine)
