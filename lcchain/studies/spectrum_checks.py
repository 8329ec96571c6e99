"""The spectrum in the circuit: ngspice's normal frequencies and mode weights against theory (runs, no rendering).

Each :class:`SpectrumJob` is one reference ladder measured by an AC analysis
(:func:`lcchain.runs.spectrum.measure_spectrum`); :func:`run_spectrum_check` turns it into a
:class:`SpectrumCheck`: per mode omega_n, the spacing delta omega_n = omega_n - omega_(n-1) and P_n from the
circuit and from theory, the worst errors, the tolerances and the verdict.  The report runs the jobs in its
background pool beside the transient checks (:mod:`.validation`) and :mod:`lcchain.report.spectrum` renders
them.

A job is one line of :func:`spectrum_jobs`: a chain (made in the worker) and the effects that realise it.  An
effect's ``response()`` keywords reach ``measure_spectrum`` too: the lossy ladder is the line with
``effects=(Losses(LOSSY_Q),)``, whose check adds each mode's Q_n.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from functools import partial
from typing import Any

import numpy as np

from ..circuit.effects import Effect, Losses, Walls
from ..core.blas import fixed_blas_threads
from ..core.checks import real
from ..core.errors import ParameterError, SimulationError
from ..core.json import JSONDict, LooseJSONObject
from ..core.types import DEFAULT_C0, DEFAULT_L0
from ..runs.spectrum import SpectrumOptions, measure_spectrum
from ..spice.simulator import Simulator
from ..theory.cases import chain_for_case
from ..theory.chain import Chain

__all__ = ["SpectrumTolerances", "SpectrumJob", "SpectrumCheck", "spectrum_jobs", "run_spectrum_check",
           "spectrum_checks", "RTOL_OMEGA", "RTOL_SPACING", "ATOL_P", "RTOL_Q", "LOSSY_Q", "VK_DELTAS", "VK_N"]

#: omega_n, relative, over the modes that weigh |P_n| >= 1e-6 at the ends (the others are nearly cancelled poles,
#: :data:`lcchain.runs.spectrum.OMEGA_WEIGHT_FLOOR`): benchmarks/spectrum.md measured at most 4.8e-10 over every
#: chain it runs (perfect N = 200; the chains here: <= 8e-13), so 1e-8 leaves a margin of 20.
RTOL_OMEGA = 1e-8
#: delta omega_n, relative to its theoretical value, over neighbours both resolved: two frequencies off by the
#: worst measured 4.8e-10 in opposite directions (omega <= 2) over the smallest spacing checked here (7.1e-4, the
#: top of two-mass N = 100's band) give 2.7e-6; 1e-5 leaves a margin of 4 (measured here: <= 6e-11).
RTOL_SPACING = 1e-5
#: P_n, absolute, over every mode (an unseen one counted with P = 0): benchmarks/spectrum.md measured at most
#: 4.4e-11 (perfect N = 400; the chains here: <= 1.2e-12), so 1e-9 leaves a margin of 20.
ATOL_P = 1e-9
#: Q_n = omega_n / gamma_n of a lossy ladder, relative, over the resolved modes of nonzero frequency:
#: benchmarks/spectrum.md measured 7.8e-13 for two-mass N = 20 at Q = 100 (and at most 4.1e-9 up to Q = 1e4 at
#: N = 20 and 100), so 1e-8 leaves a margin of 2.5 at the worst chain measured.
RTOL_Q = 1e-8
#: The lossy ladder of the report: two-mass N = 20 with every inductor's Q = 100.
LOSSY_Q = 100.0

#: Fig. vk's chain: the one-mass chain of N = 50 at the three Δ of its panels (Δ = x^2 / (2 - x^2)).
VK_N = 50
VK_DELTAS = (0.30, 0.1395, 0.05)


@dataclass(frozen=True)
class SpectrumTolerances:
    """What a spectrum check allows: omega_n and delta omega_n relative, P_n absolute (defaults: the module's
    constants, where their origin is stated)."""

    omega: float = RTOL_OMEGA
    spacing: float = RTOL_SPACING
    P: float = ATOL_P
    Q: float = RTOL_Q

    def __post_init__(self) -> None:
        for key in ("omega", "spacing", "P", "Q"):
            object.__setattr__(self, key, real(f"tolerances.{key}", getattr(self, key), above=0.0))

    def to_dict(self) -> dict[str, float]:
        return {"omega": self.omega, "spacing": self.spacing, "P": self.P, "Q": self.Q}


def _one_mass(N: int, Delta: float) -> Chain:
    """The one-mass chain of Fig. vk's panel Δ: x^2 = 2Δ / (1 + Δ) (Sec. IV.B)."""
    return Chain.one_mass(N, math.sqrt(2 * Delta / (1 + Delta)))


@dataclass(frozen=True)
class SpectrumJob:
    """One spectrum to measure (:func:`run_spectrum_check`); frozen and picklable, so that it may run in another
    process.

    Attributes
    ----------
    name, what : str
        Its name in the report, and the chain in words.
    N : int
        The chain's masses (for the pool's order, before the chain is made).
    chain : callable
        ``chain()`` makes the chain (in the worker: designing it costs time), e.g.
        ``partial(chain_for_case, "two-mass", 20)``.
    effects : tuple of Effect
        Realised on the chain in order (``Walls``, ...); their ``response()`` keywords go to
        :func:`lcchain.runs.spectrum.measure_spectrum`.
    figure : str
        The paper figure its points are drawn on (``"Pk20-100"``, ``"vk"``) or ``""``.
    panel : float, optional
        Which of the figure's panels: N for Fig. Pk20-100, Δ for Fig. vk.
    tolerances : SpectrumTolerances
    simulator : Simulator, optional
        ngspice (default: found in the worker).
    """

    name: str
    what: str
    N: int
    chain: Callable[[], Chain]
    effects: tuple[Effect, ...] = ()
    figure: str = ""
    panel: float | None = None
    tolerances: SpectrumTolerances = SpectrumTolerances()
    simulator: Simulator | None = None

    @property
    def label(self) -> str:
        return f"spectrum {self.name}"

    @property
    def cost(self) -> float:
        """Rough seconds it takes, for the order of a pool (measured: 0.4 s at N = 20 to 0.7 s at N = 100 for the
        optimised chains, whose sweep grows like N^2; designing the chain adds up to 0.6 s)."""
        return 0.6 + 0.3 * (self.N / 100.0) ** 2


def spectrum_jobs(*, quick: bool = False, simulator: Simulator | None = None,
                  tolerances: SpectrumTolerances = SpectrumTolerances()) -> list[SpectrumJob]:
    """The report's spectrum checks: two-mass N = 20 and 100 (Fig. Pk20-100), a perfect cradle (N = 50), walled
    chains (the perfect cradle of N = 50 tied to walls, j = 1; two-mass N = 50 between walls K0 = 0.01), a lossy
    ladder (two-mass N = 20, Q = 100: each mode's Q_n against omega_n Q) and the one-mass chains of Fig. vk
    (N = 50, three Δ).  ``quick`` keeps Fig. vk's middle (optimal) panel only and
    leaves out the two-mass chain with walls."""
    def job(name: str, what: str, N: int, make: Callable[[], Chain], *, effects: tuple[Effect, ...] = (),
            figure: str = "", panel: float | None = None) -> SpectrumJob:
        return SpectrumJob(name, what, N, make, effects, figure, panel, tolerances, simulator)

    jobs = [job("two-mass-N20", "two-mass, N = 20", 20, partial(chain_for_case, "two-mass", 20),
                figure="Pk20-100", panel=20),
            job("two-mass-N100", "two-mass, N = 100", 100, partial(chain_for_case, "two-mass", 100),
                figure="Pk20-100", panel=100),
            job("perfect-N50", "perfect cradle, N = 50", 50, partial(chain_for_case, "perfect", 50)),
            job("perfect-N50-walls", "perfect cradle tied to walls (j = 1), N = 50", 50,
                partial(chain_for_case, "perfect", 50, 1))]
    jobs.append(job("two-mass-N20-losses", f"two-mass, N = 20, losses Q = {LOSSY_Q:g}", 20,
                    partial(chain_for_case, "two-mass", 20), effects=(Losses(LOSSY_Q),)))
    if not quick:
        jobs.append(job("two-mass-N50-walls", "two-mass, N = 50, walls K0 = 0.01", 50,
                        partial(chain_for_case, "two-mass", 50), effects=(Walls(K0=0.01),)))
    for Delta in VK_DELTAS if not quick else VK_DELTAS[1:2]:
        jobs.append(job(f"one-mass-N{VK_N}-Delta{Delta:g}", f"one-mass, N = {VK_N}, Δ = {Delta:g}", VK_N,
                        partial(_one_mass, VK_N, Delta), figure="vk", panel=Delta))
    return jobs


@dataclass
class SpectrumCheck:
    """One ladder's spectrum from ngspice against theory: per mode, the worst errors, the verdict.

    ``modes`` holds one dict per mode: ``n``, ``omega`` and ``omega_theory``, ``spacing`` and
    ``spacing_theory`` (omega_n - omega_(n-1), None for n = 1), ``P`` and ``P_theory`` (the weight in alpha_N),
    ``resolved`` (weighs enough to be placed: the frequency is judged) and ``seen`` (the circuit shows it).
    ``tolerances`` has the keys ``omega``, ``spacing``, ``P``, ``Q``; ``errors`` the first three, and ``Q``
    (each mode's quality factor, relative) for a lossy ladder; an error is None when the check did not run
    (``reason`` says why).
    """

    name: str
    what: str
    N: int
    figure: str
    panel: float | None
    modes: list[LooseJSONObject]
    errors: dict[str, float | None]
    tolerances: dict[str, float]
    passed: bool
    points: int | None = None
    wall_s: float | None = None
    reason: str = ""

    def verdicts(self) -> dict[str, bool]:
        """Each quantity's verdict."""
        return {key: error is not None and error <= self.tolerances[key] for key, error in self.errors.items()}

    def to_dict(self) -> JSONDict:
        """The check with every mode (``report.json``'s ``spectrum``)."""
        return {"name": self.name, "what": self.what, "N": self.N, "figure": self.figure, "panel": self.panel,
                "passed": self.passed, "errors": self.errors, "tolerances": self.tolerances, "points": self.points,
                "wall_s": self.wall_s, "reason": self.reason, "modes": self.modes}

    def checks(self) -> list[JSONDict]:
        """One line of the report's list of checks per quantity (omega_n, delta omega_n, P_n)."""
        units = {"omega": "relative", "spacing": "relative", "P": "absolute", "Q": "relative"}
        verdicts = self.verdicts()
        return [{"name": f"spectrum {self.name}: {symbol}", "what": self.what, "kind": "spectrum",
                 "passed": verdicts[key], "max_abs_error": self.errors[key], "tolerance": self.tolerances[key],
                 "unit": units[key], "wall_s": self.wall_s, "reason": self.reason}
                for key, symbol in (("omega", "ω_n"), ("spacing", "δω_n"), ("P", "P_n"), ("Q", "Q_n"))
                if key in self.errors]


def _modes(omega: np.ndarray, theory: np.ndarray, P: np.ndarray, P_theory: np.ndarray,
           resolved: np.ndarray, low: np.ndarray | None = None,
           bound: np.ndarray | None = None) -> list[LooseJSONObject]:
    """Every mode's values; ``omega_theory_low``: the reference's rest beyond float64
    (:attr:`lcchain.theory.modes.Modes.omega_low`, 0 where it has none), which its error is measured against, and
    ``omega_bound``: the reference's own relative bound (None where it states none)."""
    def plain(value: float) -> float | None:
        return float(value) if np.isfinite(value) else None

    out: list[LooseJSONObject] = []
    for n in range(omega.size):
        seen = bool(np.isfinite(omega[n]))
        out.append({"n": n + 1, "omega": plain(omega[n]), "omega_theory": float(theory[n]),
                    "spacing": plain(omega[n] - omega[n - 1]) if n else None,
                    "spacing_theory": float(theory[n] - theory[n - 1]) if n else None,
                    "P": float(P[n]) if seen else None, "P_theory": float(P_theory[n]), "seen": seen,
                    "resolved": bool(resolved[n]), "omega_theory_low": 0.0 if low is None else float(low[n]),
                    "omega_bound": None if bound is None else float(bound[n])})
    return out


def spacing_error(omega: np.ndarray, theory: np.ndarray, resolved: np.ndarray) -> float:
    """Largest |delta omega_circuit - delta omega_theory| / delta omega_theory over neighbours both resolved (an
    unseen one: infinite)."""
    both = resolved[1:] & resolved[:-1]
    expected = np.diff(theory)[both]
    error = np.abs(np.diff(omega)[both] - expected) / expected
    return float(np.max(np.where(np.isnan(error), np.inf, error), initial=0.0))


@fixed_blas_threads
def run_spectrum_check(job: SpectrumJob) -> SpectrumCheck:
    """Measure one ladder's spectrum in ngspice and judge it against the theory.

    Under one BLAS thread, as the theory: the same bits in the report's pool as here, and the fit's many small
    products are faster so (N = 50: 0.8 s against 10-22 s with two threads on 2 busy cores).
    """
    tolerances = job.tolerances.to_dict()
    try:
        chain = job.chain()
        keywords: dict[str, Any] = {}  # Effect.response()'s floats by SpectrumOptions field: checked there
        for effect in job.effects:
            chain = effect.realise(chain, DEFAULT_L0, DEFAULT_C0)
            keywords.update(effect.response())
        options = SpectrumOptions(L0=DEFAULT_L0, C0=DEFAULT_C0, **keywords)
        report = measure_spectrum(chain, options, simulator=job.simulator)
    except (SimulationError, ParameterError) as error:
        keys = [key for key in tolerances if key != "Q" or any("Q" in effect.response() for effect in job.effects)]
        return SpectrumCheck(job.name, job.what, job.N, job.figure, job.panel, [],
                             dict.fromkeys(keys), tolerances, False, reason=str(error))
    omega, theory, resolved = report.omega, report.theory.omega, report.resolved
    errors: dict[str, float | None] = {"omega": report.max_rel_error_omega,
                                       "spacing": spacing_error(omega, theory, resolved),
                                       "P": report.max_abs_error_P}
    if report.losses is not None:
        errors["Q"] = report.max_rel_error_Q
    check = SpectrumCheck(job.name, job.what, chain.N, job.figure, job.panel,
                          _modes(omega, theory, report.P, report.theory.transfer, resolved, report.theory.omega_low,
                                 report.theory.omega_bound),
                          errors, tolerances,
                          False, report.points, report.timings.get("ngspice_s"))
    check.passed = all(check.verdicts().values())
    return check


def spectrum_checks(jobs: Sequence[SpectrumJob] | None = None, *,
                    progress: Callable[[int, int, str], None] | None = None) -> list[SpectrumCheck]:
    """:func:`run_spectrum_check` of every job (default :func:`spectrum_jobs`), one after the other."""
    jobs = list(jobs) if jobs is not None else spectrum_jobs()
    checks = []
    for done, job in enumerate(jobs):
        if progress is not None:
            progress(done, len(jobs), job.label)
        checks.append(run_spectrum_check(job))
    if progress is not None:
        progress(len(jobs), len(jobs), "done")
    return checks
