"""The paper's mechanism in the circuit: the ladder's normal frequencies, decay rates and mode weights from an
AC analysis.

:func:`measure_spectrum` drives the ladder in loop 1 with a unit AC voltage in ngspice or gnucap
(:func:`lcchain.circuit.netlist.ac_netlist_text`, :func:`lcchain.spice.ac.run_ac`) on a sweep in even segments
placed from the predicted poles (:func:`lcchain.compare.grid.sweep_segments`), identifies the modes of
I_1/V_1 and I_N/V_1 from the predicted poles (:func:`lcchain.compare.spectrum.fit_from_theory`; from the samples
alone where those do not explain them, :func:`lcchain.compare.spectrum.fit_spectrum`), and sets them beside the
exact theory:
omega_n, and P_n, the mode's coefficient in alpha_N(t) = sum_n P_n cos(omega_n t) (m_1 times the residue of
Y_N1 Z0; for a symmetric chain (-1)^(n-1) times the mode density of Eq. e.Pn).

With losses (:class:`lcchain.circuit.effects.Losses`, the transient's resistors R_i = L_i / (Q tau)) the damping
is proportional to the masses: the modes and P_n stay, and every pole moves to -gamma/2 +- j sqrt(omega_n^2 -
gamma^2/4) with gamma = 1/Q, so each mode's quality factor omega_n / gamma_n is omega_n Q.  The fitted model's
alpha_N(t) is also set beside the exact lossy response (:func:`lcchain.theory.response.linear_response`).

A mode whose weight at the ends is below what the samples resolve has no visible pole there: the circuit
does not show it between its ends.  Such modes are listed as unseen, with their theoretical weight; the
error of P counts them with P = 0 (the weakest of a perfect cradle's binomial end weights is 2^-(2N-3)).

Effects whose elements are no chain's (a coil's self-capacitance or winding resistance, a capacitor's ESR or ESL,
coupled coils with losses: ``effects=``) are compared with the circuit's own exact poles and residues instead
(:meth:`lcchain.circuit.exact.CircuitTheory.admittances`, :func:`lcchain.compare.poles.compare_poles`): its modes
(as many as the circuit has), their end weights and, with resistors, each one's own decay rate.

It is the request's AC analysis (:class:`lcchain.runs.request.AC`) planned and executed like any run
(:func:`lcchain.runs.request.plan_request`, :func:`lcchain.runs.execute.execute`): scenes, sweeps and stores
make the same run.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING

import numpy as np

from ..circuit.effects import Effect, Losses
from ..compare.spectral import (
    DEFAULT_OVERSAMPLING,
    OMEGA_MARGIN,
    OMEGA_WEIGHT_FLOOR,
    SPECTRUM_MAX_N,
    SpectrumMetrics,
    largest_relative_error,
    merged_text,
    relative_errors,
)
from ..compare.spectrum import SpectrumFit
from ..core.budget import Budget
from ..core.checks import instance
from ..core.errors import ParameterError, SimulationError
from ..core.extras import dataset_attrs
from ..core.json import JSONDict, JSONValue
from ..core.show import Figure, html_table, plot, short_repr
from ..core.types import DEFAULT_C0, DEFAULT_L0
from ..spice.engine import Engine
from ..spice.engines import DEFAULT_ENGINE, engine_named, find_engine
from ..spice.simulator import Simulator
from ..theory.arrivals import stop_time
from ..theory.chain import Chain
from ..theory.modes import WEIGHT_PRECISION, Modes
from ..theory.response import linear_response
from .datasets import Variable, make_dataset
from .execute import circuit_modes, execute, sweep_omega
from .request import AC, Request, plan_request

if TYPE_CHECKING:
    import xarray as xr
from .spec import SpectrumTheory
from .survey import ModeReport, measure_modes

__all__ = ["SpectrumReport", "SpectrumOptions", "measure_spectrum", "spectrum", "merged_text", "OMEGA_MARGIN",
           "SPECTRUM_MAX_N", "OMEGA_WEIGHT_FLOOR", "DEFAULT_OVERSAMPLING", "RESPONSE_TIMES"]

#: Times at which the fitted model's alpha_N(t) is set beside the exact response, evenly on [0, first transit].
RESPONSE_TIMES = 2001


@dataclass(frozen=True, eq=False)
class SpectrumReport:
    """A ladder's spectrum from an engine's AC analysis beside theory.

    Every public array (``omega``, ``P``, ``gamma``, ``Q``, ``poles``, their ``*_theory``, ``seen``,
    ``resolved``) has one entry per theoretical mode, n = 1..``theory.N`` in order; the circuit's values are NaN
    where the mode was not seen at the ends (``seen`` False).

    Attributes
    ----------
    chain : Chain
    theory : Modes
        The driven modes (omega_n, density m_1 u_1n^2, transfer P_n = m_1 u_1n u_Nn); with effects that are no
        chain's, the circuit's own modes (omega_n = |p_n|, density m_1 a_n, transfer m_1 b_n from the sections of
        its exact admittances, ``method`` ``"circuit"``).
    fit : SpectrumFit
        The modes found in the circuit, in the fit's own order and number (fewer than the theory's where some
        are unseen): the per-mode arrays below are the ones to use.
    fitted : ndarray of int
        For each fitted mode (each entry of ``fit``'s arrays), the index of its theoretical mode.
    points : int
        Frequencies of the AC sweep on (0, omega_max], in ``segments`` even segments.
    omega_max : float
    engine_version, netlist_sha256 : str
    timings : dict
        Seconds: the engine's process (``ngspice_s``, whichever engine ran: the key predates engines), the fit, and
        the whole call.
    losses : float or None
        The quality factor Q of every inductor (``--Q``); None: a lossless ladder.
    segments : int
        ``.ac lin`` cards of the sweep.
    response_error : float or None
        Largest |alpha_N(t) of the fitted modes - exact alpha_N(t)| over the first transit
        (:data:`RESPONSE_TIMES` times); None for coupled coils (a kick excites their modes otherwise than the
        drive).
    engine : str
        The engine that ran the AC analysis.
    gamma_theory : ndarray or None
        The circuit's own decay rate of every mode (effects that are no chain's, with resistors): Q_theory is then
        omega_n / gamma_n.
    time_unit : float
        sqrt(L0 C0), seconds: omega_n / (2 pi time_unit) is the mode's frequency in hertz.
    merged : ndarray of bool or None
        The modes the losses merge (:func:`lcchain.compare.spectral.merged_modes`: half-power bands overlapping,
        below the Q range the fit separates them in): said, not compared; their circuit values are NaN.
    envelope_error : float or None
        With losses: max |Y_11 - exact Y_11| / |exact Y_11| over the sweep
        (:func:`lcchain.theory.spectrum.driving_admittance`), the response the merged modes make together.
    envelope_bound : float or None
        The exact admittance's own relative error bound, the largest over the sweep
        (:func:`lcchain.compare.spectral.compare_envelope`).
    modes : ModeReport or None
        Every mode with its shape from a second AC run that drives every loop (``measure_spectrum(...,
        SpectrumOptions(shapes=True))``, ``lcchain spectrum --shapes``: :func:`lcchain.runs.survey.measure_modes`);
        None: not asked.
    """

    chain: Chain
    theory: Modes
    fit: SpectrumFit
    fitted: np.ndarray
    points: int
    omega_max: float
    engine_version: str
    netlist_sha256: str
    timings: dict[str, float] = field(default_factory=dict)
    losses: float | None = None
    segments: int = 1
    response_error: float | None = None
    engine: str = DEFAULT_ENGINE
    gamma_theory: np.ndarray | None = None
    time_unit: float = math.sqrt(DEFAULT_L0 * DEFAULT_C0)
    merged: np.ndarray | None = None
    envelope_error: float | None = None
    modes: ModeReport | None = None
    envelope_bound: float | None = None

    @property
    def merged_modes(self) -> np.ndarray:
        """Whether each theoretical mode is merged with a neighbour by the losses, bool per mode."""
        return np.zeros(self.theory.N, dtype=bool) if self.merged is None else np.asarray(self.merged, dtype=bool)

    @property
    def lossy(self) -> bool:
        """The fit found decay rates: the chain's losses, or a circuit's resistors."""
        return self.losses is not None or self.gamma_theory is not None

    def _per_mode(self, values: np.ndarray, missing: float = np.nan) -> np.ndarray:
        out = np.full(self.theory.N, missing)
        out[self.fitted] = values
        out[self.merged_modes] = missing  # the fit's guess inside a merged cluster is no mode of the circuit
        return out

    @property
    def seen(self) -> np.ndarray:
        """Whether each theoretical mode was seen at the ends (a pole the fit found), bool per mode."""
        return self._per_mode(np.ones(self.fitted.size), 0.0).astype(bool)

    @property
    def omega_theory(self) -> np.ndarray:
        """The exact normal frequency omega_n of every mode, units of 1/sqrt(L0 C0)."""
        return np.asarray(self.theory.omega, dtype=float)

    @property
    def P_theory(self) -> np.ndarray:
        """The exact P_n = m_1 u_1n u_Nn of every mode (its weight in alpha_N(t)); NaN where it is below the
        precision it was computed with (:attr:`below_precision`: rounding noise, not a value)."""
        return np.where(self.below_precision, np.nan, np.asarray(self.theory.transfer, dtype=float))

    @property
    def below_precision(self) -> np.ndarray:
        """Whether each mode's theoretical P_n is below the precision it was computed with
        (:meth:`lcchain.theory.modes.Modes.precise`): |P_n| < 1e-15 max |P| from an eigenvector; never for the free
        perfect cradle, whose binomial weights are exact (2^-(2N-3) = 5.0e-60 at N = 100)."""
        return ~self.theory.precise()

    @property
    def omega(self) -> np.ndarray:
        """The circuit's undamped frequency |p_n| of every theoretical mode (NaN where unseen)."""
        return self._per_mode(self.fit.omega)

    @property
    def P(self) -> np.ndarray:
        """The circuit's P_n of every theoretical mode (NaN where unseen; the error of P counts it as 0)."""
        return self._per_mode(self.chain.masses[0] * self.fit.last)

    @property
    def gamma(self) -> np.ndarray:
        """The circuit's decay rate gamma_n of every theoretical mode, units of 1/sqrt(L0 C0) (NaN where unseen;
        0 without losses)."""
        return self._per_mode(self.fit.gamma)

    @property
    def Q(self) -> np.ndarray:
        """The circuit's quality factor omega_n / gamma_n of every theoretical mode (NaN where unseen, and for a
        lossless ladder)."""
        if not self.lossy:
            return np.full(self.theory.N, np.nan)
        return np.asarray(self.omega / self.gamma)

    @property
    def Q_theory(self) -> np.ndarray:
        """omega_n Q: every mode decays at gamma = 1/Q (NaN for a lossless ladder); a circuit's own omega_n /
        gamma_n."""
        if self.gamma_theory is not None:
            with np.errstate(divide="ignore", invalid="ignore"):
                return np.asarray(self.theory.omega / self.gamma_theory)
        return self.theory.omega * (np.nan if self.losses is None else self.losses)

    @property
    def poles(self) -> np.ndarray:
        """The circuit's pole of every mode, -gamma_n/2 + j sqrt(omega_n^2 - gamma_n^2/4) (NaN where unseen)."""
        return _pole(self.omega, self.gamma)

    @property
    def poles_theory(self) -> np.ndarray:
        """-gamma/2 + j sqrt(omega_n^2 - gamma^2/4), gamma = 1/Q (0 without losses; a circuit's own gamma_n)."""
        if self.gamma_theory is not None:
            return _pole(self.theory.omega, self.gamma_theory)
        return _pole(self.theory.omega, np.full(self.theory.N, 0.0 if self.losses is None else 1.0 / self.losses))

    @property
    def resolved(self) -> np.ndarray:
        """Whether each theoretical mode weighs enough at the ends to be placed to the targets (|P_n| >=
        :data:`OMEGA_WEIGHT_FLOOR`) and is not merged by the losses."""
        return np.asarray((np.abs(self.theory.transfer) >= OMEGA_WEIGHT_FLOOR) & ~self.merged_modes)

    @property
    def metrics(self) -> SpectrumMetrics:
        """The circuit's modes beside theory, as a run's record holds them."""
        return SpectrumMetrics(self.theory.omega, self.omega, self.theory.transfer, np.nan_to_num(self.P, nan=0.0),
                               self.resolved,
                               gamma=self.gamma if self.lossy else None, losses=self.losses,
                               gamma_theory=self.gamma_theory, omega_low=self.theory.omega_low,
                               omega_bound=self.theory.omega_bound, P_bound=self.theory.transfer_bound,
                               merged=self.merged, envelope_error=self.envelope_error,
                               envelope_bound=self.envelope_bound)

    @property
    def omega_error(self) -> np.ndarray:
        """|omega_circuit - omega_theory| / omega_theory of every mode, against the reference beyond float64 where
        it has one (NaN where unseen; a zero mode: absolute)."""
        return relative_errors(self.omega, self.omega_theory, self.theory.omega_low)

    @property
    def reference_bounds(self) -> dict[str, float | None]:
        """The reference's own error bounds, beside the errors they let be measured: ``reference_bound_omega``
        (relative, the resolved modes'), ``reference_bound_P`` (absolute), ``reference_bound_Q`` (relative; None
        without losses); None where the reference states none (a circuit's own poles)."""
        return self.metrics.reference_bounds

    @property
    def max_rel_error_omega(self) -> float:
        """Largest |omega_circuit - omega_theory| / omega_theory over the resolved modes (a zero mode: absolute);
        an unseen resolved mode is an infinite error; NaN when no mode is resolved (nothing compared, not an error
        of 0)."""
        return self.metrics.max_rel_error_omega if self.resolved.any() else math.nan

    @property
    def max_rel_error_Q(self) -> float:
        """Largest |Q_circuit - Q_theory| / Q_theory over the resolved modes of nonzero frequency (NaN for a
        lossless ladder, and when none is resolved: every mode merged, or a circuit's zero mode alone); an unseen
        resolved mode is an infinite error."""
        return self.metrics.max_rel_error_Q if self.resolved.any() else math.nan

    @property
    def max_rel_error_pole(self) -> float:
        """Largest |p_circuit - p_theory| / |p_theory| over the resolved modes (a zero pole: absolute)."""
        return largest_relative_error(self.poles, self.poles_theory, self.resolved)

    @property
    def max_abs_error_P(self) -> float:
        """Largest |P_circuit - P_theory| over every mode not merged (an unseen one counts with P = 0); NaN when
        every mode is merged."""
        return self.metrics.max_abs_error_P if self.metrics.compared.any() else math.nan

    @property
    def failure(self) -> str:
        """Why the comparison failed, in one line, or '' when it held: a resolved mode the fit left unseen, or an
        error that is no number (infinite, NaN).  Merged modes are no failure: they are said (:attr:`merged`),
        and what they make together, Y_11, is compared.  ``lcchain spectrum`` then exits 1: a failed comparison is a
        failed check, whatever it printed."""
        unseen = np.flatnonzero(self.resolved & ~self.seen) + 1
        if unseen.size:
            listed = ", ".join(str(n) for n in unseen[:5]) + (" ..." if unseen.size > 5 else "")
            return (f"the fit left {unseen.size} resolved mode{'s' if unseen.size > 1 else ''} unseen (n = {listed}): "
                    "the comparison with theory failed")
        errors = {"omega_n": self.max_rel_error_omega, "P_n": self.max_abs_error_P} if self.resolved.any() else {}
        if self.lossy and (self.resolved & (np.asarray(self.theory.omega) > 0)).any():  # a zero mode has no Q_n
            errors["Q_n"] = self.max_rel_error_Q
        if self.envelope_error is not None:
            errors["Y_11"] = self.envelope_error
        bad = [name for name, value in errors.items() if not np.isfinite(value)]
        return f"the error of {', '.join(bad)} is not a number: the comparison with theory failed" if bad else ""

    def to_dict(self) -> JSONDict:
        """``lcchain spectrum --json``: a mode's ``P_theory`` is null, ``below_precision`` true, where the theory's
        value is rounding noise (:attr:`below_precision`)."""
        omega, P = self.omega, self.P
        lossy = self.lossy
        Q, Q_theory, gamma = self.Q, self.Q_theory, self.gamma
        noise = self.below_precision
        omega_error = self.omega_error
        omega_bound, P_bound = self.theory.omega_bound, self.theory.transfer_bound
        merged = self.merged_modes
        compared = bool(self.resolved.any())  # every mode merged: no error to give, not an error of 0
        modes: list[JSONValue] = []
        for n in range(self.theory.N):
            seen = bool(np.isfinite(omega[n]))
            mode: JSONDict = {"n": n + 1, "omega": float(omega[n]) if seen else None,
                              "P": float(P[n]) if seen else None,
                    "omega_theory": float(self.theory.omega[n]),
                    "P_theory": None if noise[n] else float(self.theory.transfer[n]),
                    "below_precision": bool(noise[n]), "seen": seen, "resolved": bool(self.resolved[n]),
                    "omega_error": float(omega_error[n]) if seen else None,
                    "omega_bound": None if omega_bound is None else float(omega_bound[n]),
                    "P_bound": None if P_bound is None else float(P_bound[n]), "merged": bool(merged[n])}
            if lossy:
                mode |= {"Q": _finite(Q[n]), "Q_theory": _finite(Q_theory[n]), "gamma": _finite(gamma[n])}
                if self.gamma_theory is not None:
                    mode["gamma_theory"] = float(self.gamma_theory[n])
            modes.append(mode)
        data: JSONDict = {
                "N": self.chain.N, "case": self.chain.name, "points": self.points, "omega_max": self.omega_max,
                "engine": self.engine, "engine_version": self.engine_version, "netlist_sha256": self.netlist_sha256,
                "modes": modes, "seen": int(self.seen.sum()),
                "max_rel_error_omega": _finite(self.max_rel_error_omega) if compared else None,
                "max_abs_error_P": self.max_abs_error_P if compared else None, "fit_steps": self.fit.sweeps,
                "timings": self.timings,
                "Q": self.losses, "max_rel_error_Q": _finite(self.max_rel_error_Q) if lossy and compared else None,
                "max_rel_error_pole": _finite(self.max_rel_error_pole) if compared else None,
                "max_abs_error_response": self.response_error,
                "segments": self.segments, "merged": [int(n) + 1 for n in np.flatnonzero(merged)],
                "max_rel_error_Y11": self.envelope_error, "reference_bound_Y11": self.envelope_bound,
                "failure": self.failure}
        data.update(self.reference_bounds)
        data.update({} if self.theory.method != "circuit" else {"theory": "circuit"})
        data.update({} if self.modes is None else {"survey": self.modes.to_dict()})
        return data

    def _rows(self) -> list[tuple[str, object]]:
        bounds = self.reference_bounds
        lossy = f", losses Q = {self.losses:g}" if self.losses is not None else ""
        rows: list[tuple[str, object]] = [
            ("chain", f"{self.chain.name}, N = {self.chain.N}{lossy}"),
            ("engine", f"{self.engine} {self.engine_version} AC, {self.points} frequencies up to "
                       f"{self.omega_max:.4g}"),
            ("modes seen", f"{int(self.seen.sum())} of {self.theory.N}"),
            ("max rel. error of omega_n", _beside(self.max_rel_error_omega, bounds["reference_bound_omega"])),
            ("max abs. error of P_n", _beside(self.max_abs_error_P, bounds["reference_bound_P"]))]
        if self.lossy:
            rows.append(("max rel. error of Q_n", _beside(self.max_rel_error_Q, bounds["reference_bound_Q"],
                                                          "no resolved mode rings")))
        if self.merged_modes.any():
            rows.append(("merged by the losses", merged_text(self.merged_modes)))
        if self.envelope_error is not None:
            rows.append(("max rel. error of Y_11", _beside(self.envelope_error, self.envelope_bound)))
        if self.modes is not None:
            rows += self.modes.rows()
        return rows

    def __repr__(self) -> str:
        """A few lines (the per-mode arrays: ``omega``, ``P`` ...; all of it: :meth:`to_dict`)."""
        return short_repr("SpectrumReport", self._rows())

    def _repr_html_(self) -> str:
        return html_table("SpectrumReport", self._rows())

    def plot(self, ax: object = None) -> Figure:
        """|P_n| against omega_n, the circuit's over theory, with the spacing below (``lcchain spectrum --plot``).

        Parameters
        ----------
        ax : matplotlib.axes.Axes, optional
            Draw |P_n| into it (no spacing panel).

        Returns
        -------
        matplotlib.figure.Figure
            Never shown; save it with ``fig.savefig(...)``.  matplotlib is imported here, not by
            ``import lcchain``.
        """
        return plot("spectrum", self, ax=ax)

    def to_xarray(self) -> xr.Dataset:
        """The modes as an xarray Dataset on the dimension ``mode`` (n = 1..N): the circuit's ``omega``, ``P``
        (and ``Q``, ``gamma`` with losses) beside theory's ``*_theory``, ``seen`` and ``resolved``, NaN where a mode
        was not seen; ``frequency`` and ``frequency_theory`` in hertz; the scalar summary as attributes.
        xarray is optional: ``pip install 'lcchain[data]'``."""
        hertz = 1.0 / (2 * math.pi * self.time_unit)
        per_unit = {"units": "1", "comment": "units of 1/sqrt(L0 C0)"}
        variables: dict[str, Variable] = {
            "omega": ("mode", self.omega, {"long_name": "normal frequency in the circuit"} | per_unit),
            "omega_theory": ("mode", self.omega_theory, {"long_name": "exact normal frequency"} | per_unit),
            "frequency": ("mode", self.omega * hertz, {"long_name": "normal frequency in the circuit", "units": "Hz"}),
            "frequency_theory": ("mode", self.omega_theory * hertz,
                                 {"long_name": "exact normal frequency", "units": "Hz"}),
            "P": ("mode", self.P, {"long_name": "end-to-end weight P_n in the circuit", "units": "1"}),
            "P_theory": ("mode", self.P_theory, {"long_name": "exact end-to-end weight P_n (NaN: below precision)",
                                                 "units": "1"}),
            "seen": ("mode", self.seen, {"long_name": "the fit found the mode"}),
            "resolved": ("mode", self.resolved, {"long_name": "the sweep's spacing resolves the mode"}),
            "merged": ("mode", self.merged_modes, {"long_name": "merged with a neighbour by the losses"})}
        if self.lossy:
            variables |= {"Q": ("mode", self.Q, {"long_name": "quality factor in the circuit", "units": "1"}),
                          "Q_theory": ("mode", self.Q_theory, {"long_name": "exact quality factor", "units": "1"}),
                          "gamma": ("mode", self.gamma, {"long_name": "decay rate in the circuit"} | per_unit)}
        summary = {key: value for key, value in self.to_dict().items() if key not in ("modes", "timings")}
        return make_dataset("SpectrumReport.to_xarray", variables,
                            {"mode": ("mode", np.arange(1, self.theory.N + 1), {"units": "1"})},
                            dataset_attrs(summary | {"time_unit_s": self.time_unit}))

def _pole(omega: np.ndarray, gamma: np.ndarray) -> np.ndarray:
    """-gamma/2 + j sqrt(omega^2 - gamma^2/4): the upper pole, the faster one of an overdamped mode (-gamma for a
    zero mode, whose other pole, at 0, cancels)."""
    half = 0.5 * gamma
    return np.asarray(-half + 1j * np.sqrt((omega - half) * (omega + half) + 0j))


def _beside(error: float, bound: float | None, why: str = "every mode merged by the losses") -> str:
    """An error with its reference's own bound beside it ("not compared" for NaN: no mode was, and why)."""
    if math.isnan(error):
        return f"not compared ({why})"
    return f"{error:.3e}" + ("" if bound is None else f" (reference bound {bound:.1e})")


def _finite(value: float) -> float | None:
    return float(value) if np.isfinite(value) else None


def _response_error(chain: Chain, theory: Modes, fit: SpectrumFit, Q: float | None) -> float | None:
    """Largest |alpha_N(t) of the fitted modes - the exact (lossy) response| over the first transit."""
    if chain.coupled:
        return None
    t = np.linspace(0.0, stop_time(theory, 1), RESPONSE_TIMES)
    exact = linear_response(chain, t, Q=Q, modes=theory)[1]
    return float(np.max(np.abs(fit.impulse(t, chain.masses[0] * fit.last) - exact)))


def _losses(Q: object) -> Losses:
    """The losses of ``Q``, refused under its own name (``--Q``), not the scene key ``effects.losses.Q``."""
    try:
        return Losses(Q)  # type: ignore[arg-type]  # checked there
    except ParameterError as error:
        raise error.renamed("Q") from None


@dataclass(frozen=True)
class SpectrumOptions:
    """How :func:`measure_spectrum` measures a chain's spectrum, checked when made.

    Parameters
    ----------
    Q : float, optional
        Losses: the quality factor (> 0) of every inductor, a resistor L_i / (Q sqrt(L0 C0)) in series with each
        (:class:`lcchain.circuit.effects.Losses`, as the transient's); not with coupled coils.  None: lossless.
    points : int, optional
        Frequencies of the sweep; default twice the fewest that separate every pole
        (:func:`lcchain.compare.grid.min_points`).  Fewer than that are refused, naming the minimum.
    L0, C0 : float
        Bulk inductance (H) and capacitance (F).
    timeout : float
        Seconds before the engine is stopped.
    engine : str or Engine
        An engine with an AC analysis (:func:`lcchain.spice.engines.ac_engine`): ``"ngspice"`` or ``"gnucap"``, or
        an :class:`~lcchain.spice.engine.Engine` itself (registered under its name, which the options keep).
    effects : tuple of Effect
        More effects on the ladder (walls, coupling, the parts of real coils and capacitors ...), as a request's;
        those whose elements are no chain's are compared with the circuit's own poles and residues (module
        docstring).
    shapes : bool
        Also every mode with its shape, from a second AC run (ngspice) that drives every loop
        (:func:`lcchain.runs.survey.measure_modes`): the report's ``modes``.  A chain with walls, coupled coils and
        losses (``Q``); no other effects.

    Raises
    ------
    ParameterError
        A value out of its range, naming the field (``Q``, not the scene's ``effects.losses.Q``).
    """

    Q: float | None = None
    points: int | None = None
    L0: float = DEFAULT_L0
    C0: float = DEFAULT_C0
    timeout: float = 3600.0
    engine: str | Engine = DEFAULT_ENGINE
    effects: tuple[Effect, ...] = ()
    shapes: bool = False

    def __post_init__(self) -> None:
        if not isinstance(self.effects, tuple):
            raise ParameterError("effects", self.effects, "a tuple of lcchain effects")
        if self.shapes is not True and self.shapes is not False:
            raise ParameterError("shapes", self.shapes, "True or False")
        if self.shapes and self.effects:
            raise ParameterError("shapes", self.shapes, "False with effects other than --Q (a survey of every loop "
                                 "measures a chain's modes: walls, coupled coils and losses)")
        if self.Q is not None:
            object.__setattr__(self, "Q", _losses(self.Q).Q)
        object.__setattr__(self, "engine", engine_named(self.engine).name)  # an Engine itself: registered

    def request(self, chain: Chain) -> Request:
        """The AC :class:`~lcchain.runs.request.Request` these options make of ``chain``."""
        effects = self.effects + (() if self.Q is None else (Losses(self.Q),))
        return Request(chain, AC(self.points), effects=effects, L0=self.L0, C0=self.C0, timeout=self.timeout,
                       engine=str(self.engine))


def measure_spectrum(chain: Chain, options: SpectrumOptions | None = None, *, simulator: Simulator | None = None,
                     budget: Budget | None = None, progress: Callable[[float], None] | None = None
                     ) -> SpectrumReport:
    """The ladder's spectrum in an engine's AC analysis against exact theory.

    Parameters
    ----------
    chain : Chain
        A chain (walls and coupled coils included), N <= :data:`SPECTRUM_MAX_N`.
    options : SpectrumOptions, optional
        The losses, the sweep's points, the units, the engine, more effects, the shapes (default
        :class:`SpectrumOptions`: lossless, ngspice, the default sweep).
    simulator : Simulator, optional
        The engine's batch transport.
    budget : Budget, optional
        The AC run and the fit are priced first (:func:`lcchain.compare.spectral.spectrum_estimate`, times the engine's
        ``ac_relative_cost``).
    progress : callable, optional
        Called with the fraction done (0 to 1): the engine's run, then the fit.

    Raises
    ------
    ParameterError, BudgetError
        Before the engine starts.
    """
    instance("chain", chain, Chain)
    if options is None:
        options = SpectrumOptions()
    instance("options", options, SpectrumOptions)
    request = options.request(chain)
    try:
        report = spectrum(request, simulator=simulator, budget=budget, progress=progress)
    except ParameterError as error:  # the AC fit's range of Q for this chain, under the argument's name
        raise (error.renamed("Q") if error.field == "effects.losses.Q" else error) from None
    if not options.shapes:
        return report
    return replace(report, modes=measure_modes(chain, Q=options.Q, L0=options.L0, C0=options.C0,
                                               timeout=options.timeout))


def spectrum(request: Request, *, simulator: Simulator | None = None, budget: Budget | None = None,
             progress: Callable[[float], None] | None = None) -> SpectrumReport:
    """Run a request's AC analysis and set the ladder's modes beside theory: ``lcchain.spectrum``.

    ``lcchain.simulate`` runs transients and refuses an AC request, pointing here: the two return different
    reports (a :class:`~lcchain.runs.simulate.SimulationReport` of waveforms; a :class:`SpectrumReport` of modes,
    one entry per theoretical mode).

    Parameters
    ----------
    request : Request
        With ``analysis=AC(points)``; its chain, effects (losses: :class:`~lcchain.circuit.effects.Losses`),
        L0, C0 (H, F), engine and timeout (s) are the run's, as :func:`measure_spectrum`'s arguments are.
    simulator, budget, progress
        As :func:`measure_spectrum`.

    Returns
    -------
    SpectrumReport

    Examples
    --------
    >>> report = lcchain.spectrum(lcchain.Request(lcchain.chain_for_case("two-mass", 20), lcchain.AC()))
    >>> report.omega.shape == report.omega_theory.shape == (20,)   # doctest: +SKIP
    """
    instance("request", request, Request)
    instance("simulator", simulator, Simulator, optional=True)
    if not isinstance(request.analysis, AC):
        raise ParameterError("analysis", type(request.analysis).__name__,
                             "AC(...) for lcchain.spectrum (a Transient: lcchain.simulate(request))")
    losses = request.effect(Losses)
    Q = None if losses is None else float(losses.Q)
    chain = request.chain
    plan = plan_request(request, budget)
    spec = plan.specs[0]
    # found before the run's clock starts: asking the engine its version is no part of the fit's seconds
    simulator = simulator if simulator is not None else find_engine(spec.engine, spec.backend)
    record = execute(spec, simulator, progress=progress)
    if not record.ok or record.spectrum is None or record.run is None:
        raise SimulationError(record.reason, record.log_tail, record.status)
    spectrum, theory = record.spectrum, spec.theory
    assert spectrum.fit is not None and spectrum.seen is not None and spec.points is not None  # execute's own
    assert isinstance(theory, SpectrumTheory)
    segments = sum(line.startswith(".ac ") for line in spec.netlist.splitlines())
    timings = {"ngspice_s": record.wall_s, "fit_s": record.total_s - record.wall_s, "total_s": record.total_s}
    if theory.circuit is not None:  # the circuit's own modes; the chain's alpha_N(t) is not its response
        mass = float(theory.chain.masses[0])
        from ..compare.poles import measurable

        # the modes compared (compare_poles: the real poles far beyond the sweep left out), each with its weight
        poles = measurable(circuit_modes(theory.circuit, chain.N, theory.time_unit, theory.impedance),
                           float(np.max(sweep_omega(theory, record.run))))  # the sweep's end, as compared
        own = Modes(spectrum.omega_theory, mass * poles.first, spectrum.P_theory, "circuit", precision=WEIGHT_PRECISION)
        return SpectrumReport(theory.chain, own, spectrum.fit, spectrum.seen, spec.points, theory.omega_max,
                              record.engine_version, record.run.netlist_sha256, timings, None, segments, None,
                              record.engine, spectrum.gamma_theory, time_unit=theory.time_unit,
                              merged=spectrum.merged, envelope_error=spectrum.envelope_error)
    assert theory.modes is not None
    # the fitted model's alpha_N(t) holds the fit's guesses inside merged clusters: no claim to make of it then
    merged = spectrum.merged is not None and bool(np.any(spectrum.merged))
    response = None if merged else _response_error(theory.chain, theory.modes, spectrum.fit, Q)
    return SpectrumReport(theory.chain, theory.modes, spectrum.fit, spectrum.seen, spec.points, theory.omega_max,
                          record.engine_version, record.run.netlist_sha256, timings, Q, segments, response,
                          record.engine, time_unit=theory.time_unit, merged=spectrum.merged,
                          envelope_error=spectrum.envelope_error, envelope_bound=spectrum.envelope_bound)
