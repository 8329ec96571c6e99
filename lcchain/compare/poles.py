"""Poles and residues of any linear circuit's AC response, and the comparison with its exact ones (pure arrays).

A chain's admittances are sums of sections a_n s / (s^2 + gamma s + w_n^2) with a_n > 0 at the driven end
(:mod:`lcchain.compare.spectrum` relies on both).  A circuit with real parts (a coil's self-capacitance, a
capacitor's ESL, resistors not proportional to the coils) is no chain: a residue at the driven end can be negative
(the current in L_1 is not the source's when a capacitor bridges L_1), and with losses that are not proportional
to the inductances each pair of poles p, conj(p) carries a complex residue r::

    Y(s) Z0 = sum_n r_n / (s - p_n) + conj(r_n) / (s - conj(p_n))   (+ r / (s - p) for a real pole)

so its section's numerator is 2 Re(r) s - 2 Re(r conj(p)), not a_n s alone.  :func:`fit_poles` fits that model:

1. the poles of one rational fit (AAA, ``scipy.interpolate.AAA``) of Y_11 Z0 against s = j w, those in the closed
   left half plane inside the sweep with a residue that is not negligible;
2. variable projection: the poles refined by ``scipy.optimize.least_squares`` on the misfit of both admittances
   (each sample relative to its own size), their residues the linear least squares for the poles at hand.
   Without losses the poles stay on the imaginary axis and each pair has one real coefficient (a s / (s^2 + w^2),
   a free chain's zero mode a / s), which is exact for a lossless circuit.

It is dense (the model's columns for every mode at every sample): meant for circuits of a few dozen modes
(:data:`CIRCUIT_SPECTRUM_MAX_MODES`).  :func:`compare_poles` matches the fitted modes with the circuit's exact ones
(:meth:`lcchain.circuit.exact.CircuitTheory.admittances`) into the same :class:`SpectrumMetrics` a chain's run has.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np
import scipy  # its submodules load on first use: runs.request imports this module for every request

from ..core.blas import fixed_blas_threads
from ..core.errors import ParameterError
from ..core.frozen import FrozenArrays
from .spectral import LOSSY_GAP_Q, OMEGA_WEIGHT_FLOOR, SpectrumMetrics
from .spectrum import SpectrumFit

__all__ = ["CircuitModes", "fit_poles", "compare_poles", "measurable", "merged_poles", "CIRCUIT_SPECTRUM_MAX_MODES",
           "FIT_MAX_EVALUATIONS", "MERGED_BELOW_Q"]

#: The most modes a circuit's AC comparison fits at once (dense variable projection: samples x modes columns).
CIRCUIT_SPECTRUM_MAX_MODES = 64
#: The most evaluations of the misfit the fit makes.  Measured (two-mass, N = 12 to 60, parasitics and losses): a fit
#: whose modes all compare converged in 3 to 13; fits of circuits damped past what the samples resolve (an ESR of 1 to
#: 10 sqrt(L0/C0)) took 47 to 850 and left modes unseen anyway, the last in 44 s against its price of 6.8 s.
FIT_MAX_EVALUATIONS = 100
#: A mode whose half-power band overlaps another's is merged when it rings fewer times than this (omega_n / gamma_n,
#: :func:`merged_poles`).  Measured (``benchmarks/bench_merged_poles.py``, recorded in benchmarks/merged_poles.md:
#: ngspice, one- and two-mass N = 8 to 16, an ESR, a winding resistance, with a coil's capacitance or a capacitor's
#: ESL, R = 0.03 to 5 sqrt(L0/C0); 1,023 modes): overlapping modes of Q_n >= 16 were seen to 2.4e-9 (35 modes; two-
#: mass N = 20 with every part: to 2e-13, 0.34 widths apart), those of Q_n < 8 (real poles among them) were off by up
#: to 150 % or unseen (288 of 706); each of the 295 modes the rule leaves resolved was seen, omega_n to 1.0e-3 at
#: worst (Q_n = 1.96, its band clear of every other) and 3.2e-10 from Q_n = 8.
MERGED_BELOW_Q = 16.0
#: AAA's relative tolerance (ngspice's samples are good to about 1e-12).
_AAA_RTOL = 1e-13
#: A rational fit's pole whose residue is below this (relative to the largest) is the fit's, not a mode.
_WEAKEST = 1e-10
#: A pole with a real part above this (relative to the sweep's end) is in the right half plane: the fit's.
_RIGHT = 1e-9
#: AAA's most terms: two per pole (each pair is two poles of s), and some to spare.
_AAA_TERMS = 2 * CIRCUIT_SPECTRUM_MAX_MODES + 16


@dataclass(frozen=True, eq=False)
class CircuitModes(FrozenArrays):
    """A circuit's modes as its AC run is compared with them, dimensionless (s in units of 1/sqrt(L0 C0),
    admittances times sqrt(L0/C0)), ascending in omega.

    Attributes
    ----------
    omega, gamma : ndarray
        |p_n| and -2 Re p_n of each pole in the upper half plane; a real pole p_n: 0 and -p_n (a free chain's
        zero mode, as :mod:`lcchain.compare.spectrum` writes it).
    first, last : ndarray
        Each section's coefficient of s in I_1/V and I_N/V (2 Re r_n; a real pole's r_n).
    lossy : bool
        Any pole off the imaginary axis (the circuit has resistors).
    """

    omega: np.ndarray
    gamma: np.ndarray
    first: np.ndarray
    last: np.ndarray
    lossy: bool

    def __post_init__(self) -> None:
        self._freeze_arrays()

    @property
    def N(self) -> int:
        """How many modes."""
        return int(self.omega.size)

    @classmethod
    def from_poles(cls, poles: np.ndarray, residues: np.ndarray, time_unit: float, impedance: float, *,
                   lossy: bool) -> CircuitModes:
        """From the poles (rad/s) and the residues (S rad/s, rows I_1/V and I_N/V) of
        :meth:`lcchain.circuit.exact.CircuitTheory.admittances`; ``time_unit`` sqrt(L0 C0) in s, ``impedance``
        sqrt(L0/C0) in ohm."""
        p = np.asarray(poles, dtype=complex) * time_unit
        r = np.asarray(residues, dtype=complex) * (impedance * time_unit)
        scale = max(float(np.max(np.abs(p), initial=0.0)), 1e-300)
        p = np.where(np.abs(p) <= 1e-12 * scale, 0.0, p)  # a zero mode's rounding (a free chain's translation)
        real = np.abs(p.imag) <= 1e-12 * scale
        keep = real | (p.imag > 0)
        p, r, real = p[keep], r[:, keep], real[keep]
        omega = np.where(real, 0.0, np.abs(p))
        gamma = np.where(real, -p.real, -2.0 * p.real)
        first, last = (np.where(real, row.real, 2.0 * row.real) for row in r)
        order = np.argsort(omega, kind="stable")
        return cls(omega[order], np.maximum(gamma[order], 0.0), first[order], last[order], lossy)


def _model(s: np.ndarray, params: np.ndarray, kinds: np.ndarray, lossy: bool
           ) -> tuple[np.ndarray, list[tuple[int, list[int], list[np.ndarray]]]]:
    """The model's complex columns at s for the poles ``params`` (per mode: (re, im) for a pair with losses, (w,)
    without, (re,) for a real pole, none for a lossless zero mode), and for every parameter the columns it moves
    with their derivatives: (parameter, [column, ...], [d column / d parameter, ...])."""
    columns: list[np.ndarray] = []
    slopes: list[tuple[int, list[int], list[np.ndarray]]] = []
    k = 0
    for kind in kinds:
        c = len(columns)
        if kind == "pair" and lossy:
            p = params[k] + 1j * params[k + 1]
            up, down = 1.0 / (s - p), 1.0 / (s - np.conj(p))
            up2, down2 = up * up, down * down
            columns += [up + down, 1j * (up - down)]
            # d/d Re p and d/d Im p of 1/(s - p) are 1/(s - p)^2 and j/(s - p)^2 (conjugate pole: -j)
            slopes.append((k, [c, c + 1], [up2 + down2, 1j * (up2 - down2)]))
            slopes.append((k + 1, [c, c + 1], [1j * (up2 - down2), -(up2 + down2)]))
            k += 2
        elif kind == "pair":
            w = params[k]
            denominator = 1.0 / (s * s + w * w)
            columns.append(s * denominator)
            slopes.append((k, [c], [-2.0 * w * s * denominator * denominator]))
            k += 1
        elif kind == "real":
            up = 1.0 / (s - params[k])
            columns.append(up)
            slopes.append((k, [c], [up * up]))
            k += 1
        else:  # a lossless zero mode: a / s
            columns.append(1.0 / s)
    if lossy:  # what the poles far beyond the sweep add over it, a real pole's r / (s - p) ~ -r/p - r s/p^2 - ...
        columns += [np.ones_like(s), s, s * s]
    return np.stack(columns, axis=1), slopes


def _stacked(a: np.ndarray) -> np.ndarray:
    return np.concatenate((a.real, a.imag))


def _project(columns: np.ndarray, slopes: list[tuple[int, list[int], list[np.ndarray]]], y: np.ndarray,
             weight: np.ndarray, size: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(real coefficients x, weighted misfit, its Jacobian in the parameters) of the least squares y ~ columns @ x
    with x real: variable projection, Kaufman's Jacobian (P_perp dA/dtheta x, the term that dominates near the
    solution)."""
    a = _stacked(columns * weight[:, None])
    b = _stacked(y * weight)
    scale = np.maximum(np.linalg.norm(a, axis=0), 1e-300)
    q, r = np.linalg.qr(a / scale)
    x = np.linalg.lstsq(r, q.T @ b, rcond=None)[0] / scale
    misfit = a @ x - b
    jacobian = np.zeros((a.shape[0], size))
    for k, cols, derivatives in slopes:
        moved = sum(derivative * x[c] for c, derivative in zip(cols, derivatives, strict=True))
        jacobian[:, k] += _stacked(moved * weight)
    jacobian -= q @ (q.T @ jacobian)
    return x, misfit, jacobian


def _residues(x: np.ndarray, kinds: np.ndarray, lossy: bool) -> np.ndarray:
    """Each mode's residue at its upper pole from the real coefficients ``x``: x_k + j x_k+1 for a pair with
    losses, else its one coefficient (a lossless pair's a of a s / (s^2 + w^2), a real pole's r)."""
    out = []
    k = 0
    for kind in kinds:
        if kind == "pair" and lossy:
            out.append(x[k] + 1j * x[k + 1])
            k += 2
        else:
            out.append(complex(x[k]))
            k += 1
    return np.asarray(out, dtype=complex)


def _start(s: np.ndarray, y: np.ndarray, omega_max: float, lossy: bool) -> tuple[np.ndarray, np.ndarray]:
    """The modes of one rational fit: (params, kinds)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # AAA warns when it stops at its largest degree
        fit = scipy.interpolate.AAA(s, y, rtol=_AAA_RTOL, max_terms=_AAA_TERMS)
        poles, residues = fit.poles(), fit.residues()
    keep = (poles.real <= _RIGHT * omega_max) & (poles.imag >= -_RIGHT * omega_max)
    keep &= np.abs(poles) <= 1.05 * omega_max
    keep &= np.abs(residues) >= _WEAKEST * np.max(np.abs(residues), initial=0.0)
    poles = poles[keep]
    params: list[float] = []
    kinds: list[str] = []
    for p in poles[np.argsort(np.abs(poles))]:
        real = abs(p.imag) <= 1e-8 * max(abs(p), 1e-300) or abs(p) < 1e-9 * omega_max
        if real and not lossy:
            kinds.append("zero")  # a free chain's zero mode: a / s
        elif real:
            params.append(min(float(p.real), 0.0))
            kinds.append("real")
        elif lossy:
            params += [min(float(p.real), 0.0), float(p.imag)]
            kinds.append("pair")
        else:
            params.append(float(abs(p)))
            kinds.append("pair")
    return np.asarray(params, dtype=float), np.asarray(kinds)


@fixed_blas_threads
def fit_poles(omega: np.ndarray, y11: np.ndarray, yN1: np.ndarray, *, lossy: bool) -> SpectrumFit:
    """The poles and residues of a circuit's I_1/V_1 and I_N/V_1 (module docstring).

    Parameters
    ----------
    omega : ndarray
        The sweep's angular frequencies, units of 1/sqrt(L0 C0).
    y11, yN1 : ndarray, complex
        The admittances times sqrt(L0/C0).
    lossy : bool
        Poles off the imaginary axis with complex residues; False: a lossless circuit's model.

    Returns
    -------
    SpectrumFit
        Per mode: omega = |p| (0 for a real pole), gamma = -2 Re p (-p for a real pole), ``first`` and ``last``
        the coefficient of s in its section (2 Re r), ascending in omega.
    """
    omega = np.asarray(omega, dtype=float)
    s = 1j * omega
    data = (np.asarray(y11, dtype=complex), np.asarray(yN1, dtype=complex))
    omega_max = float(np.max(omega))
    params, kinds = _start(s, data[0], omega_max, lossy)
    if kinds.size == 0 or kinds.size > CIRCUIT_SPECTRUM_MAX_MODES:
        raise ParameterError("modes", kinds.size, f"1 to {CIRCUIT_SPECTRUM_MAX_MODES} poles in the sweep")
    weights = [1.0 / np.maximum(np.abs(y), 1e-3 * np.max(np.abs(y))) for y in data]

    def solved(x: np.ndarray) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
        columns, slopes = _model(s, x, kinds, lossy)
        return [_project(columns, slopes, y, w, x.size) for y, w in zip(data, weights, strict=True)]

    def misfit(x: np.ndarray) -> np.ndarray:
        return np.concatenate([part[1] for part in solved(x)])

    def jacobian(x: np.ndarray) -> np.ndarray:
        return np.vstack([part[2] for part in solved(x)])

    if params.size:
        scale = np.maximum(np.abs(params), 1e-3 * omega_max)
        solution = scipy.optimize.least_squares(misfit, params, jac=jacobian, x_scale=scale, xtol=1e-15,
                                                ftol=1e-15, gtol=1e-15, max_nfev=FIT_MAX_EVALUATIONS)
        params, steps = solution.x, int(solution.nfev)
    else:
        steps = 0
    first, last = (_residues(part[0], kinds, lossy) for part in solved(params))
    poles, k = [], 0
    for kind in kinds:
        if kind == "pair" and lossy:
            poles.append(params[k] + 1j * params[k + 1])
            k += 2
        elif kind == "pair":
            poles.append(1j * params[k])
            k += 1
        elif kind == "real":
            poles.append(complex(params[k]))
            k += 1
        else:
            poles.append(0j)
    pole = np.asarray(poles)
    real = kinds != "pair"
    w = np.where(real, 0.0, np.abs(pole))
    gamma = np.where(real, -pole.real, -2.0 * pole.real)
    a, b = (np.where(real if lossy else True, r.real, 2.0 * r.real) for r in (first, last))
    order = np.argsort(w, kind="stable")
    residual = float(np.max(np.abs(misfit(params)), initial=0.0))
    return SpectrumFit(w[order], a[order], b[order], steps, residual, gamma[order])


def measurable(theory: CircuitModes, omega_max: float) -> CircuitModes:
    """The modes a sweep up to ``omega_max`` can measure: all but the real poles far beyond it (a capacitor's RC
    through an ESR), which :func:`compare_poles` leaves out, and a report's modes with them."""
    beyond = (theory.omega == 0) & (theory.gamma > 1.05 * omega_max)
    if not np.any(beyond):
        return theory
    return CircuitModes(theory.omega[~beyond], theory.gamma[~beyond], theory.first[~beyond], theory.last[~beyond],
                        theory.lossy)


def merged_poles(theory: CircuitModes) -> np.ndarray:
    """Which of a circuit's modes its resistors merge past what its sweep resolves, bool per mode: said, not
    compared (:func:`compare_poles`), as a chain's (:func:`lcchain.compare.spectral.merged_modes`).

    Mode n's pole p_n has the half-power half-width h_n = -Re p_n (gamma_n / 2 for a resonance, gamma_n for a
    real pole); its band overlaps mode m's when |p_n - p_m| < h_n + h_m (a chain's |omega_n - omega_m| < 1/Q,
    where every gamma is 1/Q); two lossless poles have no band, and never overlap.  Mode n is merged when

    * its band overlaps another's and it rings less than :data:`MERGED_BELOW_Q` times (omega_n / gamma_n; a real
      pole, a decay and no ring, whenever it overlaps another pole);
    * or the two are closer than :data:`~lcchain.compare.spectral.LOSSY_GAP_Q` widths, |p_n - p_m| <
      LOSSY_GAP_Q (h_n + h_m), as close as a chain's fit separates modes;
    * or, a resonance, it reaches zero frequency as a chain's rule says, 0 < omega_n < gamma_n (a chain's
      0 < omega_n Q < 1; its half-power band itself reaches zero below omega_n < gamma_n / sqrt(2));
    * or it is a free chain's translation (a pole at 0, undamped) and another mode's band reaches zero frequency
      (a real pole's, or one of those), which is then merged with it (a chain's translation "merges only with a
      mode within 1/Q of it").

    Any other lossless mode never is.
    """
    omega, gamma = np.asarray(theory.omega, dtype=float), np.asarray(theory.gamma, dtype=float)
    half = 0.5 * gamma
    pole = np.where(omega == 0, -gamma, -half + 1j * np.sqrt(np.maximum((omega - half) * (omega + half), 0.0)))
    width = np.abs(pole.real)  # a real pole's band: |1/(j w + g)|^2 halves at w = g
    widths = width[:, None] + width[None, :]
    apart = np.divide(np.abs(pole[:, None] - pole[None, :]), widths, out=np.full(widths.shape, np.inf),
                      where=widths > 0)
    np.fill_diagonal(apart, np.inf)
    nearest = np.min(apart, axis=1, initial=np.inf)
    damped = omega < MERGED_BELOW_Q * gamma
    reaches_zero = (gamma > 0) & (omega < gamma)  # a band reaching zero frequency: a real pole's, a slow ring's
    zero, real = (omega == 0) & (gamma == 0), (omega == 0) & (gamma > 0)
    return np.asarray(((nearest < 1.0) & damped) | (nearest < LOSSY_GAP_Q) | ((omega > 0) & reaches_zero)
                      | (zero & reaches_zero.any()) | (real & zero.any()))


def compare_poles(theory: CircuitModes, omega: np.ndarray, y11: np.ndarray, yN1: np.ndarray,
                  mass: float, exact_y11: np.ndarray | None = None) -> SpectrumMetrics:
    """An AC run's poles and residues against a circuit's exact ones, mode by mode.

    Parameters
    ----------
    theory : CircuitModes
        The circuit's exact modes; with losses (``theory.lossy``) the metrics hold each mode's decay rate beside
        the circuit's.
    omega, y11, yN1 : ndarray
        The sweep and the engine's admittances times sqrt(L0/C0).
    mass : float
        m_1: P_n = m_1 times the coefficient in I_N/V_1, as a chain's.
    exact_y11 : ndarray, optional
        The circuit's exact Y_11 times sqrt(L0/C0) at ``omega``: where its resistors merge modes
        (:func:`merged_poles`, said and not compared), Y_11 is compared over the whole sweep (``envelope_error``),
        what is measured however the modes merge.
    """
    lossy = theory.lossy
    theory = measurable(theory, float(np.max(omega)))
    merged = merged_poles(theory) if lossy else None
    envelope = None
    if merged is not None and merged.any() and exact_y11 is not None:
        exact = np.asarray(exact_y11, dtype=complex)
        envelope = float(np.max(np.abs(np.asarray(y11, dtype=complex) - exact) / np.abs(exact), initial=0.0))
    fit = fit_poles(omega, y11, yN1, lossy=lossy)
    exact = theory.omega + 1j * theory.gamma
    found = fit.omega + 1j * fit.gamma
    seen = np.argmin(np.abs(found[:, None] - exact[None, :]), axis=1)
    keep = np.zeros(seen.size, dtype=bool)
    for mode in np.unique(seen):  # two fitted poles at one mode: the one with the larger residue stays
        candidates = np.flatnonzero(seen == mode)
        keep[candidates[np.argmax(np.abs(fit.first[candidates]))]] = True
    fit, seen = fit.subset(keep), seen[keep]
    n = theory.N
    circuit, gamma, P = np.full(n, np.nan), np.full(n, np.nan), np.zeros(n)
    circuit[seen], gamma[seen], P[seen] = fit.omega, fit.gamma, mass * fit.last
    P_theory = mass * theory.last
    resolved = np.abs(P_theory) >= OMEGA_WEIGHT_FLOOR
    if merged is not None and merged.any():  # a merged mode's pole is the fit's guess inside the cluster, as a chain's
        circuit[merged], gamma[merged], P[merged] = np.nan, np.nan, 0.0
        resolved &= ~merged
    else:
        merged = None
    return SpectrumMetrics(theory.omega, circuit, P_theory, P, resolved, fit, seen, gamma if lossy else None,
                           gamma_theory=theory.gamma if lossy else None, merged=merged, envelope_error=envelope)
