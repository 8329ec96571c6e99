"""Every mode of the ladder, with its shape, from one AC analysis that drives every loop.

:func:`measure_modes` puts an AC source in series with every loop's coil (amplitudes and phases from a seeded
generator, :func:`lcchain.compare.survey.survey_amplitudes`), saves every coil's current
(:func:`lcchain.circuit.netlist.survey_netlist_text`) on the sweep of even segments placed from the predicted
poles (:func:`lcchain.compare.grid.sweep_segments`, :data:`SURVEY_DENSITY` samples per spacing), and identifies
every mode's frequency, decay rate and shape (:func:`lcchain.compare.survey.fit_survey`).  A drive in loop 1 sees
mode n through u_1n only (a perfect cradle's edge modes weigh 2^-(2N-3) at the ends); here every mode has a
strong residue on the loops where it lives, so each of the N is measured.

Each is set beside the chain's exact eigensolution (LAPACK, tridiagonal; dense for coupled coils): omega_n, Q_n
(with losses), the M-orthonormal shape u_n over the loops, and the ends' weight P_n = m_1 u_1n u_Nn, which
follows from the measured shape.

With losses, the modes they merge are decided from theory before the fit, by the loop-1 fit's own rule
(:func:`lcchain.compare.spectral.merged_modes`: below the Q range the lossy fit separates modes in, those whose
half-power band overlaps a neighbour's), so that ``spectrum`` and ``spectrum --shapes`` say the same modes merged.
Their exact model is subtracted from the samples (:func:`lcchain.compare.survey.remove_modes`) and the others are
fitted; a merged mode has no measured value and no error.  What they make together, every loop's current over the
sweep, is compared with the chain's own (:func:`lcchain.theory.spectrum.loop_currents`: ``envelope_error``).
"""

from __future__ import annotations

import hashlib
import math
import time
from dataclasses import dataclass, field

import numpy as np

from ..circuit.effects import Losses
from ..circuit.ladder import Ladder
from ..circuit.netlist import probe_names, survey_netlist_text
from ..compare.grid import MIN_SEGMENT_POINTS, sweep_segments
from ..compare.spectral import OMEGA_MARGIN, merged_modes, merged_text
from ..compare.survey import (
    ModeSurvey,
    PoleStart,
    SurveyOptions,
    currents_error,
    fit_survey,
    remove_modes,
    signed_shapes,
    survey_amplitudes,
)
from ..core.checks import instance, real
from ..core.errors import ParameterError
from ..core.json import JSONDict, JSONValue
from ..core.limits import COUPLED_MAX_N
from ..core.show import short_repr
from ..core.types import DEFAULT_C0, DEFAULT_L0
from ..spice.ac import AcJob, run_ac
from ..spice.simulator import Simulator
from ..theory.chain import Chain
from ..theory.modes import Modes

__all__ = ["ModeReport", "measure_modes", "exact_shapes", "SURVEY_DENSITY", "SURVEY_MAX_N", "OMEGA_TARGET",
           "SHAPE_TARGET", "SEPARATION"]

#: Samples per smallest spacing of the poles in each even segment of the sweep (the fewest that separate them,
#: :data:`lcchain.compare.grid.POINTS_PER_SPACING`): the loops' currents are N x samples complex values.
SURVEY_DENSITY = 4.0
#: Neighbours closer than this many widths 1/Q overlap: Q_n's target holds beyond (issue 32).
SEPARATION = 3.0
#: Complex values (frequencies x loops) one engine run returns at most: a larger sweep is cut into several runs, so
#: the engine's raw file and the vectors read from it stay near 64 MB beside the samples' own array.
RUN_VALUES = 2**22
#: The most loops a survey measures (its exact reference is dense for coupled coils).
SURVEY_MAX_N = COUPLED_MAX_N
#: A mode is resolved when its frequency is within this (relative) of theory ...
OMEGA_TARGET = 1e-9
#: ... and its shape within this (largest error over the loops, relative to its largest entry).
SHAPE_TARGET = 1e-7


def exact_shapes(chain: Chain) -> tuple[np.ndarray, np.ndarray]:
    """The chain's normal frequencies omega_n (ascending) and M-orthonormal shapes u (loops x modes), signed as
    the survey's (:func:`lcchain.compare.survey.signed_shapes`): LAPACK on the symmetric tridiagonal
    M^-1/2 K M^-1/2, or the dense generalised problem with coupled coils."""
    from ..theory.exact import coupled_vectors, diagonalise

    if chain.coupled:
        omega, u = coupled_vectors(chain)
    else:
        omega, U = diagonalise(chain)
        u = U / np.sqrt(np.asarray(chain.masses, dtype=float))[:, None]
    return np.asarray(omega, dtype=float), signed_shapes(u)


@dataclass(frozen=True, eq=False)
class ModeReport:
    """Every mode of a ladder from an AC survey beside the chain's exact eigensolution.

    Attributes
    ----------
    chain : Chain
    omega, omega_theory : ndarray
        Normal frequencies, units of 1/sqrt(L0 C0), one per mode n = 1..N.
    gamma : ndarray
        Decay rates in the circuit (0 without losses).
    shapes, shapes_theory : ndarray, (loops, modes)
        M-orthonormal shapes u_n, each signed so that its first entry of at least half its largest is positive.
    losses : float or None
        Every coil's Q (``--Q``), None: lossless.
    points, segments : int
        The sweep's frequencies and ``.ac lin`` cards (over one or more engine runs: :data:`RUN_VALUES`).
    sweeps : int
        Gauss-Newton steps on the poles.
    residual : float
        The fit's largest misfit relative to the largest sample of its window.
    engine_version, netlist_sha256 : str
        The engine's version; the SHA-256 of the runs' netlists' digests, in order.
    timings : dict
        Seconds: the engine's process (``engine_s``), the fit (``fit_s``), the exact eigensolution (``theory_s``)
        and the whole call (``total_s``).
    merged : ndarray of bool or None
        The modes the losses merge (:func:`lcchain.compare.spectral.merged_modes`, the loop-1 fit's rule): said,
        not measured; their ``omega``, ``gamma`` and shapes are NaN and they have no error.
    envelope_error : float or None
        With merged modes: the largest misfit of every loop's current to the chain's exact one over the sweep,
        max_w max_k |g_k - g_k exact| / max_k |g_k exact| (:func:`lcchain.theory.spectrum.loop_currents`), what is
        measured however the modes merge; None without merged modes.

    The error columns (``max_*``) cover the measured modes (:attr:`measured`), NaN when there are none.
    """

    chain: Chain
    omega: np.ndarray
    omega_theory: np.ndarray
    gamma: np.ndarray
    shapes: np.ndarray
    shapes_theory: np.ndarray
    losses: float | None
    points: int
    segments: int
    sweeps: int
    residual: float
    engine_version: str
    netlist_sha256: str
    timings: dict[str, float] = field(default_factory=dict)
    merged: np.ndarray | None = None
    envelope_error: float | None = None

    @property
    def N(self) -> int:
        return int(self.omega.size)

    @property
    def merged_modes(self) -> np.ndarray:
        """Whether each mode is merged with a neighbour by the losses, bool per mode."""
        return np.zeros(self.N, dtype=bool) if self.merged is None else np.asarray(self.merged, dtype=bool)

    @property
    def measured(self) -> np.ndarray:
        """The modes the survey measured: every mode but the merged ones, bool per mode."""
        return np.asarray(~self.merged_modes)

    @property
    def moving(self) -> np.ndarray:
        """Modes of nonzero frequency (a free chain's translation mode has omega = 0)."""
        return np.asarray(self.omega_theory > 1e-9 * float(np.max(self.omega_theory)))

    @property
    def omega_error(self) -> np.ndarray:
        """|omega_n - omega_theory| / omega_theory per mode (absolute for a zero mode)."""
        scale = np.where(self.moving, self.omega_theory, 1.0)
        return np.asarray(np.abs(self.omega - self.omega_theory) / scale)

    @property
    def shape_error(self) -> np.ndarray:
        """max over loops |u_kn - u_kn theory| / max_k |u_kn theory|, per mode (NaN for a merged mode)."""
        return np.asarray(np.max(np.abs(self.shapes - self.shapes_theory), axis=0)
                          / np.max(np.abs(self.shapes_theory), axis=0))

    @property
    def Q(self) -> np.ndarray:
        """omega_n / gamma_n in the circuit (NaN without losses, and for a zero mode)."""
        if self.losses is None:
            return np.full(self.N, np.nan)
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.asarray(np.where(self.moving, self.omega / self.gamma, np.nan))

    @property
    def Q_theory(self) -> np.ndarray:
        """omega_n Q: every mode decays at 1/Q (NaN without losses, and for a zero mode)."""
        if self.losses is None:
            return np.full(self.N, np.nan)
        return np.asarray(np.where(self.moving, self.omega_theory * self.losses, np.nan))

    @property
    def separated(self) -> np.ndarray:
        """Modes of nonzero frequency at least :data:`SEPARATION` widths (1/Q) from both neighbours, where Q_n is
        held to its target (all of them without losses)."""
        if self.losses is None:
            return self.moving
        gaps = np.diff(self.omega_theory)
        nearest = np.minimum(np.r_[np.inf, gaps], np.r_[gaps, np.inf])
        return np.asarray(self.moving & (nearest * self.losses >= SEPARATION) & self.measured)

    @property
    def Q_error(self) -> np.ndarray:
        """|Q_n - Q_theory| / Q_theory per mode (NaN without losses, and for a zero mode)."""
        return np.asarray(np.abs(self.Q - self.Q_theory) / self.Q_theory)

    @property
    def P(self) -> np.ndarray:
        """The ends' weight m_1 u_1n u_Nn from the measured shapes."""
        return np.asarray(self.chain.masses[0] * self.shapes[0] * self.shapes[-1])

    @property
    def P_theory(self) -> np.ndarray:
        return np.asarray(self.chain.masses[0] * self.shapes_theory[0] * self.shapes_theory[-1])

    @property
    def resolved(self) -> np.ndarray:
        """Modes within :data:`OMEGA_TARGET` in frequency and :data:`SHAPE_TARGET` in shape, bool per mode."""
        return np.asarray((self.omega_error <= OMEGA_TARGET) & (self.shape_error <= SHAPE_TARGET))

    @property
    def max_rel_error_omega(self) -> float:
        """Largest omega_n error over the measured modes (NaN: none measured)."""
        return _largest(self.omega_error, self.measured)

    @property
    def max_shape_error(self) -> float:
        """Largest shape error over the measured modes (NaN: none measured)."""
        return _largest(self.shape_error, self.measured)

    @property
    def max_rel_error_Q(self) -> float:
        """Largest Q_n error over the :attr:`separated` modes (NaN without losses, or none separated)."""
        if self.losses is None or not np.any(self.separated):
            return math.nan
        return float(np.max(self.Q_error[self.separated]))

    @property
    def max_abs_error_P(self) -> float:
        """Largest |P_n - P_theory| over the measured modes (NaN: none measured)."""
        return _largest(np.abs(self.P - self.P_theory), self.measured)

    @property
    def spacing_deviation(self) -> float:
        """max_n |(omega_n+1 - omega_n) - s| / s over the whole band, s the median spacing in the circuit: a
        perfect cradle's is constant (its theory's to rounding).  Over the spacings between measured neighbours
        (NaN: none)."""
        gaps = np.diff(self.omega)
        gaps = gaps[np.isfinite(gaps)]
        if not gaps.size:
            return math.nan
        middle = float(np.median(gaps))
        return float(np.max(np.abs(gaps - middle)) / middle)

    @property
    def failure(self) -> str:
        """Why the survey failed, in one line, or '' when it held: a measured mode outside the targets, or an
        envelope error that is no number.  Merged modes are no failure: they are said (:attr:`merged`), and what
        they make together is compared (:attr:`envelope_error`).  ``lcchain spectrum --shapes`` then exits 1."""
        missed = np.flatnonzero(self.measured & ~self.resolved) + 1
        if missed.size:
            listed = ", ".join(str(n) for n in missed[:5]) + (" ..." if missed.size > 5 else "")
            merged = int(self.merged_modes.sum())
            return (f"the survey of every loop resolved {int(self.resolved.sum())} of {int(self.measured.sum())} "
                    f"measured modes (not n = {listed}){f'; {merged} merged by the losses' if merged else ''}")
        if self.envelope_error is not None and not math.isfinite(self.envelope_error):
            return "the error of the loops' currents is not a number: the survey's comparison with theory failed"
        return ""

    def to_dict(self) -> JSONDict:
        """Per mode: omega, Q (with losses), P and the shape over the loops, each beside theory, and its errors; a
        merged mode's measured values and errors are null (said, not measured), as are the summary's errors when no
        mode was measured."""
        lossy = self.losses is not None
        merged = self.merged_modes
        modes: list[JSONValue] = []
        for n in range(self.N):
            mode: JSONDict = {
                "n": n + 1, "omega": _finite(self.omega[n]), "omega_theory": float(self.omega_theory[n]),
                "omega_error": _finite(self.omega_error[n]), "P": _finite(self.P[n]),
                "P_theory": float(self.P_theory[n]), "shape_error": _finite(self.shape_error[n]),
                "resolved": bool(self.resolved[n]), "merged": bool(merged[n]),
                "shape": None if merged[n] else [float(v) for v in self.shapes[:, n]],
                "shape_theory": [float(v) for v in self.shapes_theory[:, n]]}
            if lossy:
                mode |= {"Q": _finite(self.Q[n]), "Q_theory": _finite(self.Q_theory[n]),
                         "gamma": _finite(self.gamma[n])}
            modes.append(mode)
        return {"N": self.N, "case": self.chain.name, "Q": self.losses, "points": self.points,
                "segments": self.segments, "engine_version": self.engine_version,
                "netlist_sha256": self.netlist_sha256, "resolved": int(self.resolved.sum()),
                "measured": int(self.measured.sum()), "merged": [int(n) + 1 for n in np.flatnonzero(merged)],
                "max_rel_error_omega": _finite(self.max_rel_error_omega),
                "max_shape_error": _finite(self.max_shape_error), "max_abs_error_P": _finite(self.max_abs_error_P),
                "spacing_deviation": _finite(self.spacing_deviation),
                "max_rel_error_Q": _finite(self.max_rel_error_Q) if lossy else None,
                "max_rel_error_currents": self.envelope_error, "sweeps": self.sweeps,
                "residual": _finite(self.residual), "timings": self.timings, "failure": self.failure, "modes": modes}

    def rows(self) -> list[tuple[str, object]]:
        """The summary lines ``lcchain spectrum --shapes`` prints (no error of a merged mode: none is measured)."""
        merged = self.merged_modes
        measured = int(self.measured.sum())
        rows: list[tuple[str, object]] = [
            ("every-loop survey", f"{self.points} frequencies, {self.segments} segments, "
                                  f"ngspice {self.engine_version}"),
            ("modes resolved", f"{int(self.resolved.sum())} of {measured} measured"
                               f"{f' ({self.N} modes, {int(merged.sum())} merged)' if merged.any() else ''} "
                               f"(omega to {OMEGA_TARGET:g}, shape to {SHAPE_TARGET:g})")]
        if merged.any():
            rows.append(("merged by the losses (said, not measured)", merged_text(merged)))
        if measured:
            rows += [("max rel. error of omega_n", self.max_rel_error_omega),
                     ("max error of the shapes u_n", self.max_shape_error),
                     ("max abs. error of P_n (from the shapes)", self.max_abs_error_P)]
            if math.isfinite(self.spacing_deviation):
                rows.append(("spacing's largest deviation", self.spacing_deviation))
            if self.losses is not None:
                rows.append((f"max rel. error of Q_n ({int(self.separated.sum())} modes {SEPARATION:g} widths "
                             "apart)", self.max_rel_error_Q if self.separated.any() else "none compared"))
        else:
            rows.append(("no mode is measured", "omega_n, the shapes, P_n and Q_n are not compared"))
        if self.envelope_error is not None:
            rows.append(("max rel. error of the loops' currents over the sweep", self.envelope_error))
        rows.append(("seconds (engine, fit)", f"{self.timings.get('engine_s', math.nan):.2f}, "
                                              f"{self.timings.get('fit_s', math.nan):.2f}"))
        return rows

    def __repr__(self) -> str:
        return short_repr("ModeReport", self.rows())


def _finite(value: float) -> float | None:
    return float(value) if np.isfinite(value) else None


def _largest(values: np.ndarray, where: np.ndarray) -> float:
    """The largest of ``values`` where ``where`` holds; NaN where it holds nowhere (nothing measured: no error to
    give, not an error of 0)."""
    return float(np.max(values[where])) if np.any(where) else math.nan


def measure_modes(chain: Chain, *, Q: float | None = None, L0: float = DEFAULT_L0, C0: float = DEFAULT_C0,
                  simulator: Simulator | None = None, timeout: float = 3600.0,
                  density: float = SURVEY_DENSITY) -> ModeReport:
    """Every mode of the ladder from one ngspice AC analysis driven in every loop, beside exact theory.

    Parameters
    ----------
    chain : Chain
        Walls and coupled coils included; N <= :data:`SURVEY_MAX_N`.
    Q : float, optional
        Every coil's quality factor (a resistor L_i / (Q sqrt(L0 C0)) in series, as ``--Q``); None: lossless.
        Not with coupled coils.
    L0, C0 : float
        Bulk inductance (H) and capacitance (F).
    simulator : Simulator, optional
        ngspice's batch transport.
    timeout : float
        Seconds.
    density : float
        Samples per smallest spacing of the poles in each segment, >= 3.

    Raises
    ------
    ParameterError
        Before ngspice starts.
    """
    instance("chain", chain, Chain)
    if chain.N > SURVEY_MAX_N:
        raise ParameterError("N", chain.N, f"N <= {SURVEY_MAX_N} for a survey of every loop")
    density = real("density", density, at_least=3.0, at_most=64.0)
    if Q is not None and chain.coupled:  # the resistors damp L_i, not the mutual inductances: no common 1/Q
        raise ParameterError("Q", Q, "none with coupled coils (their losses are not proportional to M: the modes "
                             "and decay rates differ from the lossless chain's)")
    effects = () if Q is None else (_losses(Q),)
    ladder = Ladder(chain, L0, C0)
    clock = time.perf_counter()
    omega_theory, shapes_theory = exact_shapes(chain)
    theory_s = time.perf_counter() - clock
    top = float(omega_theory[-1])
    segments = sweep_segments(omega_theory, (1.0 + OMEGA_MARGIN) * top, density)
    amplitudes = survey_amplitudes(chain.N)
    points = sum(count for count, _, _ in segments)
    names = probe_names(chain.N, "all")
    g = np.empty((points, chain.N), dtype=complex)
    w = np.empty(points)
    engine_s, version, digest, row = 0.0, "", hashlib.sha256(), 0
    fill_s = 0.0
    for part in _runs(segments, chain.N):  # several runs: each one's raw file and vectors stay small
        netlist = survey_netlist_text(ladder, part, list(amplitudes), effects=effects)
        count = sum(n for n, _, _ in part)
        result = run_ac(AcJob(netlist, names, count, timeout=timeout), simulator)
        started = time.perf_counter()
        rows = slice(row, row + count)
        w[rows] = np.asarray(result.frequency) * (2.0 * math.pi * ladder.time_unit)
        scale = ladder.impedance / (1j * w[rows])
        for k, name in enumerate(names):
            g[rows, k] = result.vectors[name] * scale
        engine_s, version, row = engine_s + result.wall_s, result.engine_version, row + count
        digest.update(result.netlist_sha256.encode())
        del result  # before the next run's
        fill_s += time.perf_counter() - started
    started = time.perf_counter() - fill_s
    engine = (engine_s, version, digest.hexdigest())
    zero = omega_theory <= 1e-9 * top
    x0 = np.where(zero, 0.0, omega_theory ** 2)
    gamma0 = np.full(chain.N, 1.0 / Q if Q else 0.0)
    merged = _merged(chain, np.where(zero, 0.0, omega_theory), shapes_theory, Q)
    envelope = None
    if merged.any():  # what the merged modes make together, before their theory leaves the samples
        envelope = currents_error(chain, w, g, amplitudes, Q)
        remove_modes(w, g, x0[merged], gamma0[merged], shapes_theory[:, merged], amplitudes)
    kept = np.flatnonzero(~merged)
    omega = np.full(chain.N, np.nan)
    gamma = np.full(chain.N, np.nan)
    shapes = np.full((chain.N, chain.N), np.nan)
    sweeps, residual = 0, math.nan
    if kept.size:  # the merged modes cost no sweep: only the others' poles are fitted
        fit: ModeSurvey = fit_survey(w, g, PoleStart(x0[kept], gamma0[kept], zero[kept]),
                                     SurveyOptions(lossy=Q is not None))
        omega[kept], gamma[kept], shapes[:, kept] = fit.omega, fit.gamma, fit.shapes(amplitudes)
        sweeps, residual = fit.sweeps, fit.residual
    del g
    fit_s = time.perf_counter() - started
    timings = {"engine_s": engine[0], "fit_s": fit_s, "theory_s": theory_s,
               "total_s": time.perf_counter() - clock}
    return ModeReport(chain, omega, omega_theory, gamma, shapes, shapes_theory, Q, points, len(segments), sweeps,
                      residual, engine[1], engine[2], timings, merged if Q is not None else None, envelope)


def _merged(chain: Chain, omega: np.ndarray, shapes: np.ndarray, Q: float | None) -> np.ndarray:
    """The modes losses of quality factor ``Q`` merge, by the loop-1 fit's own rule on the same frequencies and end
    weights P_n = m_1 u_1n u_Nn (:func:`lcchain.compare.spectral.merged_modes`), bool per mode; none without
    losses."""
    if Q is None:
        return np.zeros(chain.N, dtype=bool)
    first = float(chain.masses[0]) * shapes[0]
    return merged_modes(Modes(omega, first * shapes[0], first * shapes[-1], "exact"), Q)


def _runs(segments: list[tuple[int, float, float]], N: int) -> list[list[tuple[int, float, float]]]:
    """The sweep's segments in groups of at most :data:`RUN_VALUES` / N frequencies (a segment longer than that cut
    into pieces of the same step), one engine run each."""
    most = max(RUN_VALUES // N, 2 * MIN_SEGMENT_POINTS)
    pieces: list[tuple[int, float, float]] = []
    for count, lowest, highest in segments:
        step = (highest - lowest) / count
        start = 0
        while start < count:
            take = count - start if count - start <= most + MIN_SEGMENT_POINTS else most
            pieces.append((take, lowest + start * step, highest if start + take == count else
                           lowest + (start + take) * step))
            start += take
    groups: list[list[tuple[int, float, float]]] = [[]]
    held = 0
    for piece in pieces:
        if groups[-1] and held + piece[0] > most:
            groups.append([])
            held = 0
        groups[-1].append(piece)
        held += piece[0]
    return groups


def _losses(Q: object) -> Losses:
    """The losses of ``Q``, refused under its own name (``--Q``)."""
    value = real("Q", Q, above=0.0)
    try:
        return Losses(value)
    except ParameterError as error:
        raise error.renamed("Q") from None
