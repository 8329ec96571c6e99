"""The paper's mechanism in the circuit: the ladder's normal frequencies and mode weights from an AC analysis.

:func:`measure_spectrum` drives the ladder in loop 1 with a unit AC voltage in ngspice or gnucap
(:func:`lcchain.circuit.netlist.ac_netlist_text`, :func:`lcchain.spice.ac.run_ac`), identifies the poles
and residues of I_1/V_1 and I_N/V_1 (:func:`lcchain.compare.spectrum.fit_spectrum`), and sets them beside
the exact theory: omega_n, and P_n, the mode's coefficient in alpha_N(t) = sum_n P_n cos(omega_n t)
(m_1 times the residue of Y_N1 Z0; for a symmetric chain (-1)^(n-1) times the mode density of Eq. e.Pn).

A mode whose weight at the ends is below what the samples resolve has no visible pole there: the circuit
does not show it between its ends.  Such modes are listed as unseen, with their theoretical weight; the
error of P counts them with P = 0 (a perfect cradle's edge modes weigh ~2^-(N-1)).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from ..circuit.ladder import Ladder
from ..circuit.netlist import ac_netlist_text
from ..compare.spectrum import SpectrumFit, fit_spectrum, min_points
from ..core.budget import Budget, run_estimate
from ..core.checks import instance, integer
from ..core.errors import ParameterError
from ..core.limits import COUPLED_MAX_N, MAX_AC_POINTS
from ..core.types import DEFAULT_C0, DEFAULT_L0
from ..spice.ac import run_ac
from ..spice.engines import DEFAULT_ENGINE, ac_engine
from ..spice.simulator import Simulator
from ..theory.chain import Chain
from ..theory.exact import driven_modes
from ..theory.modes import Modes

__all__ = ["SpectrumReport", "measure_spectrum", "OMEGA_MARGIN", "SPECTRUM_MAX_N", "OMEGA_WEIGHT_FLOOR"]

#: The sweep ends this far above the highest normal frequency (relative).
OMEGA_MARGIN = 0.05
#: The largest chain measured (exact modes for the comparison, and the fit's dense least squares).
SPECTRUM_MAX_N = COUPLED_MAX_N
#: A mode's frequency is held to the targets when its weight at the far end is at least this: below, the pole is
#: nearly cancelled in I_N/V_1 and I_1/V_1 and double precision places it to ~1e-16 / |P_n| only (measured on the
#: perfect cradle, N = 100: 1.1e-9 at |P| = 3.9e-8, 2.4e-8 at |P| = 2.0e-10).
OMEGA_WEIGHT_FLOOR = 1e-6
#: Samples per smallest spacing by default: twice what the fit needs at least.
DEFAULT_OVERSAMPLING = 2


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
    def max_rel_error_omega(self) -> float:
        """Largest |omega_circuit - omega_theory| / omega_theory over the resolved modes (a zero mode: absolute);
        an unseen resolved mode is an infinite error."""
        omega, theory = self.omega, self.theory.omega
        error = np.abs(omega - theory) / np.where(theory > 0, theory, 1.0)
        error = np.where(np.isnan(error), np.inf, error)
        return float(np.max(error[self.resolved], initial=0.0))

    @property
    def max_abs_error_P(self) -> float:
        """Largest |P_circuit - P_theory| over every mode (an unseen one counts with P = 0)."""
        return float(np.max(np.abs(self.P - self.theory.transfer)))

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


def _matched(fit: SpectrumFit, theory: Modes) -> SpectrumFit:
    """The fitted poles, one per theoretical mode: where two match the same mode (a spurious pole of the rational
    fit beside a weak mode), the one with the larger residue at loop 1 stays."""
    nearest = np.array([int(np.argmin(np.abs(theory.omega - w))) for w in fit.omega], dtype=int)
    keep = np.zeros(nearest.size, dtype=bool)
    for mode in np.unique(nearest):
        candidates = np.flatnonzero(nearest == mode)
        keep[candidates[np.argmax(np.abs(fit.first[candidates]))]] = True
    if keep.all():
        return fit
    return SpectrumFit(fit.omega[keep], fit.first[keep], fit.last[keep], fit.sweeps, fit.residual)


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
    clock = time.perf_counter()
    instance("chain", chain, Chain)
    cost = ac_engine(engine).ac_relative_cost
    if chain.N > SPECTRUM_MAX_N:
        raise ParameterError("N", chain.N, f"N <= {SPECTRUM_MAX_N} for a spectrum (exact modes of the chain)")
    ladder = Ladder(chain, L0, C0)
    theory = driven_modes(chain)
    omega_max = float(theory.omega[-1]) * (1.0 + OMEGA_MARGIN)
    needed = min_points(theory.omega, omega_max)
    if needed > MAX_AC_POINTS:
        spacing = float(np.min(np.diff(theory.omega[theory.omega > 0])))
        raise ParameterError("N", chain.N, f"a chain whose poles an even sweep of at most {MAX_AC_POINTS} frequencies "
                             f"separates: two of this one's normal frequencies are {spacing:.3g} apart, which needs "
                             f"{needed} frequencies")
    chosen = points is None
    if points is None:
        points = min(MAX_AC_POINTS, DEFAULT_OVERSAMPLING * needed)
    points = integer("points", points, at_least=needed, at_most=MAX_AC_POINTS,
                     allowed=f"at least {needed} frequencies (4 per smallest spacing of the normal frequencies, "
                             f"up to {omega_max:.4g}) and at most {MAX_AC_POINTS}")
    estimate = run_estimate(points=points, saved=4, compared=4, unknowns=2 * chain.N)
    estimate = replace(estimate, seconds=estimate.seconds * cost)
    if chosen:  # the sweep lcchain chose: the chain is what costs
        estimate.check(budget if budget is not None else Budget(), "N", chain.N,
                       f"a smaller chain, or --points between {needed} and {points}")
    else:
        estimate.check(budget if budget is not None else Budget(), "points", points,
                       f"fewer frequencies (at least {needed})")
    text = ac_netlist_text(ladder, points=points, omega_max=omega_max,
                           title=f"lcchain {chain.name} chain N={chain.N}, AC")
    last = f"i(l{chain.N})"
    result = run_ac(text, ("i(l1)", last), points, simulator=simulator, timeout=timeout, engine=engine)
    ran = time.perf_counter()
    omega = 2.0 * np.pi * result.frequency * ladder.time_unit
    fit = fit_spectrum(omega, result.vectors["i(l1)"] * ladder.impedance, result.vectors[last] * ladder.impedance)
    fitted = time.perf_counter()
    fit = _matched(fit, theory)
    seen = np.array([int(np.argmin(np.abs(theory.omega - w))) for w in fit.omega], dtype=int)
    return SpectrumReport(chain, theory, fit, seen, points, omega_max, result.engine_version,
                          result.netlist_sha256, {"ngspice_s": result.wall_s, "fit_s": fitted - ran,
                                                  "total_s": fitted - clock}, result.engine)
