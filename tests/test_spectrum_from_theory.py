"""The loop-1 fit from theory's poles (issue 32 item 5: the default spectrum at the engine's cost).

:func:`lcchain.compare.spectrum.fit_from_theory` starts from predicted poles; these tests start it from poles that
are off by 1/4000 of a gap, far beyond its targets, and check what it lands on against an independent
dense eigen-solution of K u = omega^2 M u (tests/helpers/dense.py: scipy.linalg.eigh on the full matrices), not
lcchain's own modes: on exact samples and on ngspice's, in one window and in several (beyond 16 modes, windows of
32 refined on the whole residual).  Every mode that weighs at the ends must land on the dense solution's rounding,
and a weak mode it calls seen within the placement it claims.
"""

from __future__ import annotations

import numpy as np
import pytest
from helpers.dense import dense_modes, dense_shapes
from helpers.tolerances import (
    ATOL_SPECTRUM_FROM_THEORY_LOSSY_P,
    ATOL_SPECTRUM_FROM_THEORY_P,
    RTOL_SPECTRUM_FROM_THEORY_OMEGA,
    RTOL_SPECTRUM_FROM_THEORY_Q,
    RTOL_SPECTRUM_OMEGA,
)

from lcchain.circuit.netlist import probe_names
from lcchain.compare.grid import segment_frequencies, sweep_segments
from lcchain.compare.spectrum import THEORY_MISFIT, fit_from_theory
from lcchain.compare.survey import PLACED
from lcchain.core.errors import ParameterError
from lcchain.runs.request import AC, Request, plan_request
from lcchain.runs.spectrum import OMEGA_WEIGHT_FLOOR
from lcchain.spice.ac import AcJob, run_ac
from lcchain.spice.engines import find_engine
from lcchain.theory.cases import chain_for_case
from lcchain.theory.chain import Chain

#: How far off the fit is started, each pole on omega_n^2 by this fraction of a quarter of its nearest gap (1e-7 ..
#: 1e-5 relative on these chains, 1e5 times the targets below; measured: from 1e-2, a sample nearer the true pole
#: than the start can throw Gauss-Newton off, where theory's poles are within 1e-12 of the circuit's).
_START_OFF = 1e-3


def _room(omega: np.ndarray) -> np.ndarray:
    """A quarter of each omega_n^2's distance to its nearest neighbour."""
    gaps = np.diff(omega**2)
    return np.asarray(0.25 * np.minimum(np.r_[np.inf, gaps], np.r_[gaps, np.inf]))


def _start(omega: np.ndarray, off: float = _START_OFF) -> np.ndarray:
    """The dense frequencies moved by +-``off`` of their room on omega^2 (a seeded generator; a zero mode stays
    at 0)."""
    signs = np.where(np.random.default_rng(32).random(omega.size) < 0.5, -1.0, 1.0)
    moved = omega**2 + off * signs * _room(omega)
    return np.asarray(np.where(omega > 0, np.sqrt(np.clip(moved, 0.0, None)), 0.0))


def _check(chain: Chain, w: np.ndarray, y11: np.ndarray, yN1: np.ndarray) -> np.ndarray:
    """Fit from the moved start and compare every seen mode with the dense solution; the seen modes' indices."""
    omega, P = dense_modes(chain)
    fit, seen = fit_from_theory(w, y11, yN1, _start(omega))
    assert fit.residual <= THEORY_MISFIT  # the fit stands (no fall back to the rational fits)
    strong = np.abs(P) >= OMEGA_WEIGHT_FLOOR
    assert np.isin(np.flatnonzero(strong), seen).all()  # every mode that weighs at the ends is seen
    scale = np.where(omega[seen] > 0, omega[seen], 1.0)
    error = np.abs(fit.omega - omega[seen]) / scale
    assert np.max(error[strong[seen]]) < RTOL_SPECTRUM_FROM_THEORY_OMEGA
    # a weak mode seen is placed as it says: within PLACED of a quarter of its nearest gap (in omega^2)
    assert np.all(np.abs(fit.omega**2 - omega[seen] ** 2) <= 10 * PLACED * _room(omega)[seen])
    measured = np.zeros(chain.N)
    measured[seen] = chain.masses[0] * fit.last
    assert np.max(np.abs(measured - P)) < ATOL_SPECTRUM_FROM_THEORY_P  # an unseen mode counts with P = 0
    return seen


@pytest.mark.parametrize("chain", [chain_for_case("two-mass", 12), chain_for_case("two-mass", 60),
                                   chain_for_case("uniform-bounded", 40)], ids=["two-mass-12", "two-mass-60",
                                                                               "walls-40"])
def test_the_fit_from_theory_lands_on_exact_samples_poles(chain):
    """Exact samples sum_n (a_n, b_n) / (x_n - w^2) times j w of the dense solution on lcchain's grid."""
    omega, u = dense_shapes(chain)
    a, b = u[0] ** 2, u[0] * u[-1]
    w = segment_frequencies(sweep_segments(omega, 1.05 * omega[-1], 8))
    D = (omega**2)[None, :] - (w * w)[:, None]
    seen = _check(chain, w, 1j * w * (a / D).sum(axis=1), 1j * w * (b / D).sum(axis=1))
    assert seen.size == chain.N
    with pytest.raises(ParameterError, match="omega"):
        fit_from_theory(w[::-1], w, w, omega)


def _ngspice_samples(chain: Chain) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Y_11 Z0 and Y_N1 Z0 from ngspice on the default sweep (lcchain spectrum's netlist)."""
    spec = plan_request(Request(chain, AC())).specs[0]
    result = run_ac(AcJob(spec.netlist, spec.vectors, spec.points), find_engine(spec.engine))
    theory = spec.theory
    w = 2.0 * np.pi * result.frequency * theory.time_unit
    first, last = (result.vectors[name] * theory.impedance for name in probe_names(chain.N, "ends"))
    return w, first, last


@pytest.mark.ngspice
@pytest.mark.parametrize("chain", [chain_for_case("two-mass", 60), chain_for_case("perfect", 40),
                                   chain_for_case("one-mass", 20)], ids=["two-mass-60", "perfect-40", "one-mass-20"])
def test_the_fit_from_theory_lands_on_ngspices_poles(chain):
    """ngspice's samples, started off: the perfect cradle's modes too weak at the ends stay unseen (its
    weakest weigh 2^-(2N-3)), every other is placed to the dense solution's rounding."""
    seen = _check(chain, *_ngspice_samples(chain))
    if chain.name == "perfect":
        assert 0 < seen.size < chain.N
    else:
        assert seen.size == chain.N


def test_a_circuit_that_is_not_its_theory_is_fitted_from_its_samples():
    """Samples of a chain whose middle spring is 2 % stiffer than its theory's: the fit from the theory's poles does
    not explain them (its misfit above THEORY_MISFIT), and compare_spectrum measures the circuit's own modes from
    the samples alone (the rational fits), not the theory's: each omega_n as the dense solution of the stiffer chain
    places it, and its difference from theory's."""
    from lcchain.compare.spectral import compare_spectrum
    from lcchain.theory.exact import driven_modes

    chain = chain_for_case("two-mass", 12)
    springs = chain.springs.copy()
    springs[6] *= 1.02
    circuit = Chain(chain.masses, springs)
    omega, u = dense_shapes(circuit)
    a, b = u[0] ** 2, u[0] * u[-1]
    w = segment_frequencies(sweep_segments(omega, 1.05 * omega[-1], 8))
    D = (omega**2)[None, :] - (w * w)[:, None]
    y11, yN1 = 1j * w * (a / D).sum(axis=1), 1j * w * (b / D).sum(axis=1)
    theory = driven_modes(chain)
    assert fit_from_theory(w, y11, yN1, theory.omega)[0].residual > THEORY_MISFIT
    metrics = compare_spectrum(theory, w, y11, yN1, float(chain.masses[0]))
    moved = np.abs(omega - theory.omega) / np.where(omega > 0, omega, 1.0)
    assert np.max(moved) > 1e-3  # the circuit differs from its theory by far more than the fit's errors
    error = np.abs(metrics.omega - omega) / np.where(omega > 0, omega, 1.0)
    assert np.max(error) < RTOL_SPECTRUM_OMEGA


# ------------------------------------------------------------------------------------------- with losses
#: The losses' Q the fit is started from, relative to the circuit's: every decay rate 1e-4 off (1e4 times the target).
_Q_OFF = 1.0 + 1e-4
#: With losses the poles start off by this fraction of a quarter gap (1e-9 .. 1e-7 relative, 1e2 .. 1e4 times the
#: targets): at Q = 1e4 a perfect cradle's weak modes, which the samples do not place, stay where they start, and
#: from 1e-3 off (N = 40 on ngspice) they left a misfit of 3e-8, above THEORY_MISFIT (from theory's poles: 4e-11).
_START_OFF_LOSSY = 1e-4
#: ... and, started from residues as well (as the loop-1 fit is from theory's), each residue off by this relative
#: amount (1e6 times the P target's scale): the fit must correct it, not copy it.
_RESIDUES_OFF = 1e-6
#: Q_n is held to the target for modes weighing at least this at the ends: a weaker mode's decay rate is placed by
#: its resonance's few samples (measured on ngspice's perfect cradle N = 40 at Q = 1000: the mode of |P_n| = 1.4e-6
#: to 4.6e-8 from this start, to 1.5e-8 by the rational fits of the samples alone; 1e-11 .. 2e-9 above 1e-4).
_Q_WEIGHT = 1e-4


def _separated(omega: np.ndarray, Q: float) -> np.ndarray:
    """Modes of nonzero frequency at least 3 widths 1/Q from both neighbours (the issue's target holds there)."""
    gaps = np.diff(omega)
    nearest = np.minimum(np.r_[np.inf, gaps], np.r_[gaps, np.inf])
    return np.asarray((nearest >= 3.0 / Q) & (omega > 0))


def _residues_off(chain: Chain) -> tuple[np.ndarray, np.ndarray]:
    """The dense solution's residues (u_1n^2, u_1n u_Nn) each moved by a relative :data:`_RESIDUES_OFF` (a seeded
    generator): a start the fit must correct, not copy."""
    _, u = dense_shapes(chain)
    rng = np.random.default_rng(5)
    return (u[0] ** 2 * (1 + _RESIDUES_OFF * rng.standard_normal(chain.N)),
            u[0] * u[-1] * (1 + _RESIDUES_OFF * rng.standard_normal(chain.N)))


def _check_lossy(chain: Chain, Q: float, w: np.ndarray, y11: np.ndarray, yN1: np.ndarray,
                 residues: bool = False) -> np.ndarray:
    """Fit from the moved start (omega_n and Q off; with ``residues``, from moved residues too, as the loop-1 fit
    starts from theory's) and compare every separated, weighty mode with the dense solution: omega_n,
    Q_n = omega_n / gamma_n against omega_n Q, P_n; the seen modes' indices."""
    omega, P = dense_modes(chain)
    fit, seen = fit_from_theory(w, y11, yN1, _start(omega, _START_OFF_LOSSY), Q * _Q_OFF,
                                merged_residues=_residues_off(chain) if residues else None)
    assert fit.residual <= THEORY_MISFIT  # the fit stands (no fall back to the rational fits)
    held = _separated(omega, Q) & (np.abs(P) >= OMEGA_WEIGHT_FLOOR)
    assert held.sum() >= chain.N // 2 and np.isin(np.flatnonzero(held), seen).all()
    mine = held[seen]
    error = np.abs(fit.omega - omega[seen]) / np.where(omega[seen] > 0, omega[seen], 1.0)
    assert np.max(error[mine]) < RTOL_SPECTRUM_OMEGA
    weighty = mine & (np.abs(P[seen]) >= _Q_WEIGHT)
    Q_n = fit.omega[weighty] / fit.gamma[weighty]
    assert np.max(np.abs(Q_n - omega[seen][weighty] * Q) / (omega[seen][weighty] * Q)) < RTOL_SPECTRUM_FROM_THEORY_Q
    assert np.max(np.abs(chain.masses[0] * fit.last[mine] - P[seen][mine])) < ATOL_SPECTRUM_FROM_THEORY_LOSSY_P
    return seen


def _lossy_samples(chain: Chain, Q: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Exact Y_11 Z0 and Y_N1 Z0 of the lossy ladder, sum_n (a_n, b_n) s / (s^2 + s/Q + omega_n^2), from the dense
    solution, on lcchain's grid."""
    omega, u = dense_shapes(chain)
    a, b = u[0] ** 2, u[0] * u[-1]
    w = segment_frequencies(sweep_segments(omega, 1.05 * omega[-1], 8))
    s = 1j * w[:, None]
    D = s * s + s / Q + (omega**2)[None, :]
    return w, (a * s / D).sum(axis=1), (b * s / D).sum(axis=1)


@pytest.mark.parametrize(("chain", "Q"), [(chain_for_case("two-mass", 12), 100.0),
                                          (chain_for_case("two-mass", 60), 1000.0),
                                          (chain_for_case("uniform-bounded", 40), 1e4)],
                         ids=["two-mass-12-Q100", "two-mass-60-Q1000", "walls-40-Q1e4"])
@pytest.mark.parametrize("residues", [False, True], ids=["poles", "poles-and-residues"])
def test_the_lossy_fit_from_theory_lands_on_exact_samples_poles(chain, Q, residues):
    """Exact lossy samples of the dense solution: one window (N = 12) and several (N = 40, 60); started from moved
    poles alone, and from moved residues too (the windows then fit the whole residual's correction)."""
    _check_lossy(chain, Q, *_lossy_samples(chain, Q), residues=residues)


@pytest.mark.ngspice
@pytest.mark.parametrize(("chain", "Q"), [(chain_for_case("two-mass", 200), 1000.0),
                                          (chain_for_case("perfect", 40), 1000.0)],
                         ids=["two-mass-200-Q1000", "perfect-40-Q1000"])
@pytest.mark.parametrize("residues", [False, True], ids=["poles", "poles-and-residues"])
def test_the_lossy_fit_from_theory_lands_on_ngspices_poles(chain, Q, residues):
    """ngspice's lossy ladder (the resistors L_i / (Q tau)) on lcchain's sweep for it: beyond the 100 masses the
    rational fits were measured on, in windows.  (At Q = 1e4 the sweep, 4 samples per spacing, does not resolve
    the resonances: a perfect cradle's Q_n from this start land to 1e-9 .. 7e-9 for |P_n| >= 1e-3, 2e-8 at 1e-4 and
    2e-6 at 4e-6, so the target holds there for the weighty modes only.)"""
    from lcchain.circuit.effects import Losses

    spec = plan_request(Request(chain, AC(), effects=(Losses(Q),))).specs[0]
    result = run_ac(AcJob(spec.netlist, spec.vectors, spec.points), find_engine(spec.engine))
    w = 2.0 * np.pi * result.frequency * spec.theory.time_unit
    first, last = (result.vectors[name] * spec.theory.impedance for name in probe_names(chain.N, "ends"))
    _check_lossy(chain, Q, w, first, last, residues=residues)


def test_a_lossy_circuit_that_is_not_its_theory_is_measured_as_it_is():
    """Lossy samples of a chain whose middle spring is 2 % stiffer than its theory's (its poles 1e-3 .. 1e-2 from
    theory's): compare_spectrum measures the circuit's own modes, not the theory's: omega_n and Q_n as the stiffer
    chain's dense solution places them (at Q = 100 the fit from theory's lossy poles moves them there: its misfit
    then stands at the samples' rounding)."""
    from lcchain.compare.spectral import compare_spectrum
    from lcchain.theory.exact import driven_modes

    chain, Q = chain_for_case("two-mass", 12), 100.0
    springs = chain.springs.copy()
    springs[6] *= 1.02
    circuit = Chain(chain.masses, springs)
    omega, _ = dense_modes(circuit)
    w, y11, yN1 = _lossy_samples(circuit, Q)
    theory = driven_modes(chain)
    metrics = compare_spectrum(theory, w, y11, yN1, float(chain.masses[0]), Q)
    scale = np.where(omega > 0, omega, 1.0)
    assert np.max(np.abs(omega - theory.omega) / scale) > 1e-3  # far more than the fit's errors
    assert np.max(np.abs(metrics.omega - omega) / scale) < RTOL_SPECTRUM_OMEGA
    moving = omega > 0
    Q_n = metrics.omega[moving] / metrics.gamma[moving]
    assert np.max(np.abs(Q_n - omega[moving] * Q) / (omega[moving] * Q)) < RTOL_SPECTRUM_FROM_THEORY_Q
