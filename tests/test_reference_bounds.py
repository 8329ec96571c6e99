"""Issue 32 item 2: every AC comparison states its reference's own error bound, and the bound is at least
:data:`REFERENCE_MARGIN` times below what it measures (ngspice, lossless and lossy).

The bounds (:mod:`lcchain.theory.reference`) are checked against the test's own computation in 50-digit decimal
arithmetic: omega_n by Sturm bisection of B (Eq. e.BN) itself, and P_n = sqrt(m_1/m_N) u_1n u_Nn from B's
eigenvector by its three-term recurrence from mass 1 (not the residue product lcchain uses).
"""

from __future__ import annotations

from decimal import Decimal, localcontext

import numpy as np
import pytest
from helpers.tolerances import DECIMAL_DIGITS, REFERENCE_MARGIN

from lcchain.circuit.effects import Losses
from lcchain.runs.request import AC, Request
from lcchain.runs.spectrum import spectrum
from lcchain.theory.cases import chain_for_case
from lcchain.theory.exact import driven_modes


def _below(diagonal: list[Decimal], off2: list[Decimal], mu: Decimal) -> int:
    """Eigenvalues of the tridiagonal (diagonal, squared off-diagonal off2) below mu: its negative pivots."""
    count, d = 0, diagonal[0] - mu
    for i in range(1, len(diagonal) + 1):
        count += d < 0
        if i == len(diagonal):
            break
        d = diagonal[i] - mu - off2[i - 1] / (d if d != 0 else Decimal("1e-90"))
    return count


def _bisected(below, n: int, w: float, spread: str) -> Decimal:
    """The n-th eigenvalue mu = omega^2 (0-based) by bisection on Sturm counts ``below(mu)``, from the float
    omega_n ``w`` (bracketed within ``spread`` relative) down to DECIMAL_DIGITS - 8 digits."""
    if w == 0:
        return Decimal(0)
    mu = Decimal(float(w)) ** 2
    lo, hi = mu * (1 - Decimal(spread)), mu * (1 + Decimal(spread))
    assert below(lo) <= n < below(hi)
    while hi - lo > mu * Decimal(10) ** (8 - DECIMAL_DIGITS):
        mid = (lo + hi) / 2
        lo, hi = (lo, mid) if below(mid) > n else (mid, hi)
    return (lo + hi) / 2


def _decimal_modes(chain, approx: np.ndarray) -> tuple[list[Decimal], list[Decimal]]:
    """omega_n and P_n of B, every mode, in decimal arithmetic from the chain's float masses and springs."""
    with localcontext() as context:
        context.prec = DECIMAL_DIGITS
        m = [Decimal(float(x)) for x in chain.masses]
        K = [Decimal(float(x)) for x in chain.springs]
        N = len(m)
        diagonal = [(K[i] + K[i + 1]) / m[i] for i in range(N)]
        off = [-K[i + 1] / (m[i] * m[i + 1]).sqrt() for i in range(N - 1)]
        off2 = [b * b for b in off]
        omegas, weights = [], []
        for n, w in enumerate(approx):
            mu = _bisected(lambda x: _below(diagonal, off2, x), n, w, "1e-10")
            u = [Decimal(1), (mu - diagonal[0]) / off[0]]
            for i in range(1, N - 1):
                u.append(((mu - diagonal[i]) * u[i] - off[i - 1] * u[i - 1]) / off[i])
            norm = sum(x * x for x in u)
            omegas.append(mu.sqrt())
            weights.append((m[0] / m[-1]).sqrt() * u[0] * u[-1] / norm)
        return omegas, weights


@pytest.mark.parametrize("case, N", [("two-mass", 37), ("one-mass", 60), ("perfect", 24)])
def test_the_reference_holds_its_own_bounds(case, N):
    chain = chain_for_case(case, N)
    modes = driven_modes(chain)
    omega, P = _decimal_modes(chain, modes.omega)
    assert modes.omega_low is not None and modes.omega_bound is not None and modes.transfer_bound is not None
    for n in range(N):
        if omega[n]:
            error = abs(Decimal(float(modes.omega[n])) + Decimal(float(modes.omega_low[n])) - omega[n]) / omega[n]
            assert float(error) <= modes.omega_bound[n], n
        assert float(abs(Decimal(float(modes.transfer[n])) - P[n])) <= modes.transfer_bound[n], n
    # sharp enough to be worth stating: 1e-17 relative on omega_n, 1e-15 absolute on P_n
    assert np.max(modes.omega_bound) < 1e-17 and np.max(modes.transfer_bound) < 1e-15


@pytest.mark.parametrize("case, N, coupling", [("one-mass", 150, 0.0), ("two-mass", 37, 0.0), ("two-mass", 20, 0.2)])
def test_an_ac_run_is_measured_against_a_reference_ten_times_sharper(case, N, coupling):
    from lcchain.theory.chain import Chain

    chain = chain_for_case(case, N)
    report = spectrum(Request(Chain(chain.masses, chain.springs, coupling=coupling), AC()))
    bounds = report.reference_bounds
    assert bounds["reference_bound_omega"] * REFERENCE_MARGIN <= report.max_rel_error_omega
    assert bounds["reference_bound_P"] * REFERENCE_MARGIN <= report.max_abs_error_P
    data = report.to_dict()
    assert data["reference_bound_omega"] == bounds["reference_bound_omega"]
    assert all(mode["omega_bound"] is not None and mode["P_bound"] is not None for mode in data["modes"])


def test_a_lossy_run_states_the_bound_of_its_quality_factors():
    report = spectrum(Request(chain_for_case("two-mass", 20), AC(), effects=(Losses(300.0),)))
    bound = report.reference_bounds["reference_bound_Q"]
    assert bound is not None and bound * REFERENCE_MARGIN <= report.max_rel_error_Q


@pytest.mark.parametrize("N, walls", [(12, 0), (12, 1), (30, 2), (60, 1)])
def test_a_perfect_cradles_weights_follow_its_prescribed_spectrum_in_closed_form(N, walls):
    """P_n = c / prod_(m != n) |mu_n - mu_m| with mu_n = (n - 1 + 2 walls)^2: written here in Python fractions."""
    from fractions import Fraction

    from helpers.tolerances import ATOL_PERFECT_CLOSED_FORM, RTOL_PERFECT_CLOSED_FORM

    from lcchain.theory.exact import exact_modes, perfect_weights
    from lcchain.theory.perfect import perfect_design

    mu = [(n + 2 * walls) ** 2 for n in range(N)]
    inverse = []
    for n in range(N):
        product = 1
        for m in range(N):
            if m != n:
                product *= abs(mu[n] - mu[m])
        inverse.append(Fraction(1, product))
    total = sum(inverse)
    exact = np.array([float(w / total) for w in inverse])
    closed = perfect_weights(N, walls)
    assert np.array_equal(closed, exact) or np.max(np.abs(closed - exact) / exact) < RTOL_PERFECT_CLOSED_FORM
    chain = perfect_design(N, walls).chain
    sign = np.where(np.arange(N) % 2 == 0, 1.0, -1.0)
    reference = driven_modes(chain).transfer  # from the designed chain's own frequencies
    assert np.max(np.abs(reference - sign * exact)) < ATOL_PERFECT_CLOSED_FORM
    assert np.max(np.abs(reference - sign * exact) / exact) < RTOL_PERFECT_CLOSED_FORM
    assert np.array_equal(exact_modes(chain).density, closed)  # the transient's theory takes the closed form


def test_the_table_prints_each_modes_bound_beside_its_error(capsys):
    from lcchain.cli.main import main

    assert main(["spectrum", "--case", "two-mass", "--N", "8"]) == 0
    out = capsys.readouterr().out
    assert "ref. bound" in out and out.count("(reference bound ") == 2  # omega_n's and P_n's, on the summary line
    rows = [line.split() for line in out.splitlines() if line.split() and line.split()[0] in {"2", "3", "4"}]
    assert len(rows) == 3 and all(float(row[4]) < 1e-17 for row in rows)  # the column after the error


def _decimal_pencil_modes(chain, approx: np.ndarray) -> tuple[list[Decimal], list[Decimal]]:
    """Coupled coils: omega_n of K u = mu M u by Sturm bisection of K - mu M, and m_1 u_1n u_Nn from the pencil's
    eigenvector by its three-term recurrence, M-normalised, all in decimal arithmetic."""
    with localcontext() as context:
        context.prec = DECIMAL_DIGITS
        m = [Decimal(float(x)) for x in chain.masses]
        K = [Decimal(float(x)) for x in chain.springs]
        k = Decimal(float(chain.coupling))
        N = len(m)
        mo = [k * (m[i] * m[i + 1]).sqrt() for i in range(N - 1)]

        def bands(mu):
            return ([K[i] + K[i + 1] - mu * m[i] for i in range(N)],
                    [-K[i + 1] - mu * mo[i] for i in range(N - 1)])

        def below(mu):
            a, b = bands(mu)
            return _below(a, [x * x for x in b], Decimal(0))

        omegas, weights = [], []
        for n, w in enumerate(approx):
            mu = _bisected(below, n, w, "1e-9")
            a, b = bands(mu)
            u = [Decimal(1), -a[0] / b[0]]
            for i in range(1, N - 1):
                u.append(-(b[i - 1] * u[i - 1] + a[i] * u[i]) / b[i])
            norm = sum(m[i] * u[i] * u[i] for i in range(N)) + 2 * sum(mo[i] * u[i] * u[i + 1] for i in range(N - 1))
            omegas.append(mu.sqrt())
            weights.append(m[0] * u[0] * u[-1] / norm)
        return omegas, weights


@pytest.mark.parametrize("coupling", [0.2, -0.3])
def test_coupled_coils_reference_holds_its_own_bounds(coupling):
    from lcchain.theory.chain import Chain

    base = chain_for_case("two-mass", 20)
    chain = Chain(base.masses, base.springs, coupling=coupling)
    modes = driven_modes(chain)
    omega, P = _decimal_pencil_modes(chain, modes.omega)
    for n in range(chain.N):
        if omega[n]:
            error = abs(Decimal(float(modes.omega[n])) + Decimal(float(modes.omega_low[n])) - omega[n]) / omega[n]
            assert float(error) <= modes.omega_bound[n], n
        assert float(abs(Decimal(float(modes.transfer[n])) - P[n])) <= modes.transfer_bound[n], n
    assert np.max(modes.omega_bound) < 1e-17 and np.max(modes.transfer_bound) < 1e-15
