"""The paper's mechanism in the circuit: the ladder's normal frequencies, decay rates and mode weights from an
AC analysis.

:func:`measure_spectrum` drives the ladder in loop 1 with a unit AC voltage in ngspice
(:func:`lcchain.circuit.netlist.ac_netlist_text`, :func:`lcchain.spice.ac.run_ac`) on a sweep in even segments
placed from the predicted poles (:func:`lcchain.compare.grid.sweep_segments`), identifies the modes of
I_1/V_1 and I_N/V_1 (:func:`lcchain.compare.spectrum.fit_spectrum`), and sets them beside the exact theory:
omega_n, and P_n, the mode's coefficient in alpha_N(t) = sum_n P_n cos(omega_n t) (m_1 times the residue of
Y_N1 Z0; for a symmetric chain (-1)^(n-1) times the mode density of Eq. e.Pn).

With losses (:class:`lcchain.circuit.effects.Losses`, the transient's resistors R_i = L_i / (Q tau)) the damping
is proportional to the masses: the modes and P_n stay, and every pole moves to -gamma/2 +- j sqrt(omega_n^2 -
gamma^2/4) with gamma = 1/Q, so each mode's quality factor omega_n / gamma_n is omega_n Q.  The fitted model's
alpha_N(t) is also set beside the exact lossy response (:func:`lcchain.theory.response.linear_response`).

A mode whose weight at the ends is below what the samples resolve has no visible pole there: the circuit
does not show it between its ends.  Such modes are listed as unseen, with their theoretical weight; the
error of P counts them with P = 0 (a perfect cradle's edge modes weigh ~2^-(N-1)).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..circuit.effects import Losses
from ..circuit.ladder import Ladder
from ..circuit.netlist import ac_netlist_text
from ..compare.grid import POINTS_PER_SPACING, min_points, sweep_segments
from ..compare.spectrum import SpectrumFit, fit_spectrum
from ..core.budget import Budget, ac_estimate
from ..core.checks import instance, integer, real
from ..core.errors import ParameterError
from ..core.limits import COUPLED_MAX_N, MAX_AC_POINTS
from ..core.types import DEFAULT_C0, DEFAULT_L0
from ..spice.ac import run_ac
from ..spice.simulator import Simulator
from ..theory.arrivals import stop_time
from ..theory.chain import Chain
from ..theory.exact import driven_modes
from ..theory.modes import Modes
from ..theory.response import linear_response

__all__ = ["SpectrumReport", "measure_spectrum", "OMEGA_MARGIN", "SPECTRUM_MAX_N", "OMEGA_WEIGHT_FLOOR",
           "RESPONSE_TIMES"]

#: The sweep ends this far above the highest normal frequency (relative).
OMEGA_MARGIN = 0.05
#: The largest chain measured (its exact modes for the comparison, O(N^3); the fit itself grows like N^2).
SPECTRUM_MAX_N = COUPLED_MAX_N
#: A mode's frequency is held to the targets when its weight at the far end is at least this: below, the pole is
#: nearly cancelled in I_N/V_1 and I_1/V_1 and double precision places it to ~1e-16 / |P_n| only (measured on the
#: perfect cradle, N = 100: 1.1e-9 at |P| = 3.9e-8, 2.4e-8 at |P| = 2.0e-10).
OMEGA_WEIGHT_FLOOR = 1e-6
#: Samples per spacing of the poles by default: twice what the fit needs at least.
DEFAULT_OVERSAMPLING = 2
#: Times at which the fitted model's alpha_N(t) is set beside the exact response, evenly on [0, first transit].
RESPONSE_TIMES = 2001


@dataclass(frozen=True, eq=False)
class SpectrumReport:
    """A ladder's spectrum from ngspice beside theory.

    Attributes
    ----------
    chain : Chain
    theory : Modes
        The driven modes (omega_n, density m_1 u_1n^2, transfer P_n = m_1 u_1n u_Nn).
    fit : SpectrumFit
        The modes found in the circuit.
    seen : ndarray of int
        For each fitted mode, the index of its theoretical mode.
    points : int
        Frequencies of the AC sweep on (0, omega_max], in ``segments`` even segments.
    omega_max : float
    engine_version, netlist_sha256 : str
    timings : dict
        Seconds: ngspice's process, the fit, and the whole call.
    losses : float or None
        The quality factor Q of every inductor (``--Q``); None: a lossless ladder.
    segments : int
        ``.ac lin`` cards of the sweep.
    response_error : float or None
        Largest |alpha_N(t) of the fitted modes - exact alpha_N(t)| over the first transit
        (:data:`RESPONSE_TIMES` times); None for coupled coils (a kick excites their modes otherwise than the
        drive).
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
    losses: float | None = None
    segments: int = 1
    response_error: float | None = None

    def _per_mode(self, values: np.ndarray, missing: float = np.nan) -> np.ndarray:
        out = np.full(self.theory.N, missing)
        out[self.seen] = values
        return out

    @property
    def omega(self) -> np.ndarray:
        """The circuit's undamped frequency |p_n| of every theoretical mode (NaN where unseen)."""
        return self._per_mode(self.fit.omega)

    @property
    def P(self) -> np.ndarray:
        """The circuit's P_n of every theoretical mode (0 where unseen)."""
        return self._per_mode(self.chain.masses[0] * self.fit.last, 0.0)

    @property
    def gamma(self) -> np.ndarray:
        """The circuit's decay rate gamma_n of every theoretical mode, units of 1/sqrt(L0 C0) (NaN where unseen;
        0 without losses)."""
        return self._per_mode(self.fit.gamma)

    @property
    def Q(self) -> np.ndarray:
        """The circuit's quality factor omega_n / gamma_n of every theoretical mode (NaN where unseen, and for a
        lossless ladder)."""
        if self.losses is None:
            return np.full(self.theory.N, np.nan)
        return self.omega / self.gamma

    @property
    def Q_theory(self) -> np.ndarray:
        """omega_n Q: every mode decays at gamma = 1/Q (NaN for a lossless ladder)."""
        return self.theory.omega * (np.nan if self.losses is None else self.losses)

    @property
    def poles(self) -> np.ndarray:
        """The circuit's pole of every mode, -gamma_n/2 + j sqrt(omega_n^2 - gamma_n^2/4) (NaN where unseen)."""
        return _pole(self.omega, self.gamma)

    @property
    def poles_theory(self) -> np.ndarray:
        """-gamma/2 + j sqrt(omega_n^2 - gamma^2/4), gamma = 1/Q (0 without losses)."""
        return _pole(self.theory.omega, np.full(self.theory.N, 0.0 if self.losses is None else 1.0 / self.losses))

    @property
    def resolved(self) -> np.ndarray:
        """Whether each theoretical mode weighs enough at the ends to be placed to the targets (|P_n| >=
        :data:`OMEGA_WEIGHT_FLOOR`)."""
        return np.abs(self.theory.transfer) >= OMEGA_WEIGHT_FLOOR

    @property
    def max_rel_error_omega(self) -> float:
        """Largest |omega_circuit - omega_theory| / omega_theory over the resolved modes (a zero mode: absolute);
        an unseen resolved mode is an infinite error."""
        return _largest_relative(self.omega, self.theory.omega, self.resolved)

    @property
    def max_rel_error_Q(self) -> float:
        """Largest |Q_circuit - Q_theory| / Q_theory over the resolved modes of nonzero frequency (NaN for a
        lossless ladder); an unseen resolved mode is an infinite error."""
        if self.losses is None:
            return float("nan")
        return _largest_relative(self.Q, self.Q_theory, self.resolved & (self.theory.omega > 0))

    @property
    def max_rel_error_pole(self) -> float:
        """Largest |p_circuit - p_theory| / |p_theory| over the resolved modes (a zero pole: absolute)."""
        return _largest_relative(self.poles, self.poles_theory, self.resolved)

    @property
    def max_abs_error_P(self) -> float:
        """Largest |P_circuit - P_theory| over every mode (an unseen one counts with P = 0)."""
        return float(np.max(np.abs(self.P - self.theory.transfer)))

    def to_dict(self) -> dict[str, Any]:
        """``lcchain spectrum --json``."""
        omega, P = self.omega, self.P
        lossy = self.losses is not None
        Q, Q_theory, gamma = self.Q, self.Q_theory, self.gamma
        modes = []
        for n in range(self.theory.N):
            seen = bool(np.isfinite(omega[n]))
            mode = {"n": n + 1, "omega": float(omega[n]) if seen else None, "P": float(P[n]) if seen else None,
                    "omega_theory": float(self.theory.omega[n]), "P_theory": float(self.theory.transfer[n]),
                    "seen": seen, "resolved": bool(self.resolved[n])}
            if lossy:
                mode |= {"Q": _finite(Q[n]), "Q_theory": float(Q_theory[n]), "gamma": _finite(gamma[n])}
            modes.append(mode)
        return {"N": self.chain.N, "case": self.chain.name, "points": self.points, "omega_max": self.omega_max,
                "engine": "ngspice", "engine_version": self.engine_version, "netlist_sha256": self.netlist_sha256,
                "modes": modes, "seen": int(self.seen.size), "max_rel_error_omega": self.max_rel_error_omega,
                "max_abs_error_P": self.max_abs_error_P, "fit_steps": self.fit.sweeps, "timings": self.timings,
                "Q": self.losses, "max_rel_error_Q": self.max_rel_error_Q if lossy else None,
                "max_rel_error_pole": self.max_rel_error_pole, "max_abs_error_response": self.response_error,
                "segments": self.segments}


def _pole(omega: np.ndarray, gamma: np.ndarray) -> np.ndarray:
    """-gamma/2 + j sqrt(omega^2 - gamma^2/4): the upper pole, the faster one of an overdamped mode (-gamma for a
    zero mode, whose other pole, at 0, cancels)."""
    half = 0.5 * gamma
    return -half + 1j * np.sqrt((omega - half) * (omega + half) + 0j)


def _finite(value: float) -> float | None:
    return float(value) if np.isfinite(value) else None


def _largest_relative(values: np.ndarray, theory: np.ndarray, where: np.ndarray) -> float:
    """max |values - theory| / |theory| over ``where`` (|theory| = 0: absolute; NaN: infinite)."""
    scale = np.abs(theory)
    error = np.abs(values - theory) / np.where(scale > 0, scale, 1.0)
    error = np.where(np.isnan(error), np.inf, error)
    return float(np.max(error[where], initial=0.0))


def _matched(fit: SpectrumFit, theory: Modes) -> SpectrumFit:
    """The fitted modes, one per theoretical mode: where two match the same mode (a spurious pole of the rational
    fit beside a weak mode), the one with the larger residue at loop 1 stays."""
    nearest = _nearest(fit.omega, theory.omega)
    keep = np.zeros(nearest.size, dtype=bool)
    for mode in np.unique(nearest):
        candidates = np.flatnonzero(nearest == mode)
        keep[candidates[np.argmax(np.abs(fit.first[candidates]))]] = True
    return fit if keep.all() else fit.subset(keep)


def _nearest(omega: np.ndarray, theory: np.ndarray) -> np.ndarray:
    """The index of the theoretical frequency (ascending) nearest each of ``omega``."""
    right = np.clip(np.searchsorted(theory, omega), 1, max(theory.size - 1, 1))
    left = right - 1
    return np.where(np.abs(theory[right] - omega) < np.abs(omega - theory[left]), right, left).astype(int)


def _response_error(chain: Chain, theory: Modes, fit: SpectrumFit, Q: float | None) -> float | None:
    """Largest |alpha_N(t) of the fitted modes - the exact (lossy) response| over the first transit."""
    if chain.coupled:
        return None
    t = np.linspace(0.0, stop_time(theory, 1), RESPONSE_TIMES)
    exact = linear_response(chain, t, Q=Q, modes=theory)[1]
    return float(np.max(np.abs(fit.impulse(t, chain.masses[0] * fit.last) - exact)))


def _check_losses(chain: Chain, Q: float | None) -> Losses | None:
    """The losses asked for, validated as the transient's (:class:`Losses`), or None."""
    if Q is None:
        return None
    Q = real("Q", Q, above=0.0, allowed="a finite quality factor > 0")
    if chain.coupled:
        raise ParameterError("Q", Q, "no losses with coupled coils: lcchain has no exact theory for them (the "
                             "damping is not proportional to the mass matrix)")
    return Losses(Q)


def measure_spectrum(chain: Chain, *, Q: float | None = None, points: int | None = None, L0: float = DEFAULT_L0,
                     C0: float = DEFAULT_C0, simulator: Simulator | None = None, budget: Budget | None = None,
                     timeout: float = 3600.0) -> SpectrumReport:
    """The ladder's spectrum in ngspice (an AC analysis) against exact theory.

    Parameters
    ----------
    chain : Chain
        A chain (walls and coupled coils included), N <= :data:`SPECTRUM_MAX_N`.
    Q : float, optional
        Losses: the quality factor (> 0) of every inductor, a resistor L_i / (Q sqrt(L0 C0)) in series with each
        (:class:`lcchain.circuit.effects.Losses`, as the transient's); not with coupled coils.  None: lossless.
    points : int, optional
        Frequencies of the sweep; default twice the fewest that separate every pole
        (:func:`lcchain.compare.grid.min_points`).  Fewer than that are refused, naming the minimum.
    L0, C0 : float
        Bulk inductance (H) and capacitance (F).
    simulator : Simulator, optional
        ngspice's batch transport.
    budget : Budget, optional
        The AC run and the fit are priced first (:func:`lcchain.core.budget.ac_estimate`).

    Raises
    ------
    ParameterError, BudgetError
        Before ngspice starts.
    """
    clock = time.perf_counter()
    instance("chain", chain, Chain)
    if chain.N > SPECTRUM_MAX_N:
        raise ParameterError("N", chain.N, f"N <= {SPECTRUM_MAX_N} for a spectrum (exact modes of the chain)")
    losses = _check_losses(chain, Q)
    ladder = Ladder(chain, L0, C0)
    theory = driven_modes(chain)
    omega_max = float(theory.omega[-1]) * (1.0 + OMEGA_MARGIN)
    needed = min_points(theory.omega, omega_max)
    if needed > MAX_AC_POINTS:
        raise ParameterError("N", chain.N, f"a chain whose poles a sweep of at most {MAX_AC_POINTS} frequencies "
                             f"separates: this one needs {needed}")
    chosen = points is None
    points = integer("points", DEFAULT_OVERSAMPLING * needed if points is None else points, at_least=needed,
                     at_most=MAX_AC_POINTS,
                     allowed=f"at least {needed} frequencies ({POINTS_PER_SPACING} per spacing of the normal "
                             f"frequencies, up to {omega_max:.4g}) and at most {MAX_AC_POINTS}")
    segments = sweep_segments(theory.omega, omega_max, POINTS_PER_SPACING, points)
    estimate = ac_estimate(points=points, N=chain.N, losses=losses is not None)
    if chosen:  # the sweep lcchain chose: the chain is what costs
        estimate.check(budget if budget is not None else Budget(), "N", chain.N,
                       f"a smaller chain, or --points between {needed} and {points}")
    else:
        estimate.check(budget if budget is not None else Budget(), "points", points,
                       f"fewer frequencies (at least {needed})")
    text = ac_netlist_text(ladder, segments=segments, effects=() if losses is None else (losses,),
                           title=f"lcchain {chain.name} chain N={chain.N}, AC")
    last = f"i(l{chain.N})"
    result = run_ac(text, ("i(l1)", last), points, simulator=simulator, timeout=timeout)
    ran = time.perf_counter()
    omega = 2.0 * np.pi * result.frequency * ladder.time_unit
    fit = fit_spectrum(omega, result.vectors["i(l1)"] * ladder.impedance, result.vectors[last] * ladder.impedance,
                       lossy=losses is not None)
    fitted = time.perf_counter()
    fit = _matched(fit, theory)
    response = _response_error(chain, theory, fit, None if losses is None else losses.Q)
    return SpectrumReport(chain, theory, fit, _nearest(fit.omega, theory.omega), points, omega_max,
                          result.engine_version, result.netlist_sha256,
                          {"ngspice_s": result.wall_s, "fit_s": fitted - ran, "total_s": time.perf_counter() - clock},
                          None if losses is None else losses.Q, len(segments), response)
