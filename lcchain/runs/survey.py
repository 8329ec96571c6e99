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
from ..compare.spectral import OMEGA_MARGIN
from ..compare.survey import ModeSurvey, PoleStart, SurveyOptions, fit_survey, signed_shapes, survey_amplitudes
from ..core.checks import instance, real
from ..core.errors import ParameterError
from ..core.json import JSONDict, JSONValue
from ..core.limits import COUPLED_MAX_N
from ..core.show import short_repr
from ..core.types import DEFAULT_C0, DEFAULT_L0
from ..spice.ac import AcJob, run_ac
from ..spice.simulator import Simulator
from ..theory.chain import Chain

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

    @property
    def N(self) -> int:
        return int(self.omega.size)

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
        """max over loops |u_kn - u_kn theory| / max_k |u_kn theory|, per mode."""
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
        return np.asarray(self.moving & (nearest * self.losses >= SEPARATION))

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
        return float(np.max(self.omega_error))

    @property
    def max_shape_error(self) -> float:
        return float(np.max(self.shape_error))

    @property
    def max_rel_error_Q(self) -> float:
        """Largest Q_n error over the :attr:`separated` modes (NaN without losses, or none separated)."""
        if self.losses is None or not np.any(self.separated):
            return math.nan
        return float(np.max(self.Q_error[self.separated]))

    @property
    def max_abs_error_P(self) -> float:
        return float(np.max(np.abs(self.P - self.P_theory)))

    @property
    def spacing_deviation(self) -> float:
        """max_n |(omega_n+1 - omega_n) - s| / s over the whole band, s the median spacing in the circuit: a
        perfect cradle's is constant (its theory's to rounding)."""
        gaps = np.diff(self.omega)
        middle = float(np.median(gaps))
        return float(np.max(np.abs(gaps - middle)) / middle)

    def to_dict(self) -> JSONDict:
        """Per mode: omega, Q (with losses), P and the shape over the loops, each beside theory, and its errors."""
        lossy = self.losses is not None
        modes: list[JSONValue] = []
        for n in range(self.N):
            mode: JSONDict = {
                "n": n + 1, "omega": float(self.omega[n]), "omega_theory": float(self.omega_theory[n]),
                "omega_error": float(self.omega_error[n]), "P": float(self.P[n]), "P_theory": float(self.P_theory[n]),
                "shape_error": float(self.shape_error[n]), "resolved": bool(self.resolved[n]),
                "shape": [float(v) for v in self.shapes[:, n]],
                "shape_theory": [float(v) for v in self.shapes_theory[:, n]]}
            if lossy:
                mode |= {"Q": _finite(self.Q[n]), "Q_theory": _finite(self.Q_theory[n]),
                         "gamma": float(self.gamma[n])}
            modes.append(mode)
        return {"N": self.N, "case": self.chain.name, "Q": self.losses, "points": self.points,
                "segments": self.segments, "engine_version": self.engine_version,
                "netlist_sha256": self.netlist_sha256, "resolved": int(self.resolved.sum()),
                "max_rel_error_omega": self.max_rel_error_omega, "max_shape_error": self.max_shape_error,
                "max_abs_error_P": self.max_abs_error_P, "spacing_deviation": self.spacing_deviation,
                "max_rel_error_Q": _finite(self.max_rel_error_Q) if lossy else None, "sweeps": self.sweeps,
                "residual": self.residual, "timings": self.timings, "modes": modes}

    def rows(self) -> list[tuple[str, object]]:
        """The summary lines ``lcchain spectrum --shapes`` prints."""
        rows: list[tuple[str, object]] = [
            ("every-loop survey", f"{self.points} frequencies, {self.segments} segments, "
                                  f"ngspice {self.engine_version}"),
            ("modes resolved", f"{int(self.resolved.sum())} of {self.N} (omega to {OMEGA_TARGET:g}, shape to "
                               f"{SHAPE_TARGET:g})"),
            ("max rel. error of omega_n", self.max_rel_error_omega),
            ("max error of the shapes u_n", self.max_shape_error),
            ("max abs. error of P_n (from the shapes)", self.max_abs_error_P),
            ("spacing's largest deviation", self.spacing_deviation)]
        if self.losses is not None:
            rows.append((f"max rel. error of Q_n ({int(self.separated.sum())} modes {SEPARATION:g} widths apart)",
                         self.max_rel_error_Q))
        rows.append(("seconds (engine, fit)", f"{self.timings.get('engine_s', math.nan):.2f}, "
                                              f"{self.timings.get('fit_s', math.nan):.2f}"))
        return rows

    def __repr__(self) -> str:
        return short_repr("ModeReport", self.rows())


def _finite(value: float) -> float | None:
    return float(value) if np.isfinite(value) else None


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
    lossy = Q is not None
    fit: ModeSurvey = fit_survey(w, g, PoleStart(x0, np.full(chain.N, 1.0 / Q if Q else 0.0), zero),
                                 SurveyOptions(lossy=lossy))
    del g
    shapes = fit.shapes(amplitudes)
    fit_s = time.perf_counter() - started
    timings = {"engine_s": engine[0], "fit_s": fit_s, "theory_s": theory_s,
               "total_s": time.perf_counter() - clock}
    return ModeReport(chain, fit.omega, omega_theory, fit.gamma, shapes, shapes_theory, Q, points, len(segments),
                      fit.sweeps, fit.residual, engine[1], engine[2], timings)


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
