"""Normal modes, the paper's closed form, responses, cosine sums and arrivals.

Expected values come from the paper: Sec. II.B (Eqs. e.utn, e.Pn, e.dotqit),
Sec. II.C (perfect chains, Eq. e.N5), Sec. III (Eqs. e.knfree, e.Pkunif,
e.kn1, e.tudef), Appendix (Eqs. e.IkRk, e.psik, e.Pk) and Table II; or from
independent computations written here (a time integration of the equations
of motion, a direct sum of cosines, a plain fixed-point iteration).
"""

import math

import numpy as np
import pytest
from helpers.tolerances import (
    ATOL_ARRIVAL_TIME,
    ATOL_CLOSED_FORM,
    ATOL_COSINE_SUM,
    ATOL_DOP853_TRANSMISSION,
    ATOL_NORMALISATION,
    ATOL_ODE,
    ATOL_PERFECT,
    ATOL_TABLE_DELAY,
    ATOL_TABLE_LOSS,
    CONVERGED_STEP,
    MAX_PSI_STEP,
    NOT_CONVERGED_STEP,
    RTOL_ARITHMETIC,
    RTOL_CENTRED_DIFFERENCE,
    RTOL_DOP853_TRANSMISSION,
)
from scipy.integrate import solve_ivp

from lcchain.core.errors import ParameterError
from lcchain.theory.arrivals import arrival_window, arrivals, first_arrival
from lcchain.theory.chain import PERFECT_ARRIVAL, Chain
from lcchain.theory.closed_form import closed_form_applies, closed_form_modes, phase_shift
from lcchain.theory.exact import exact_modes
from lcchain.theory.modes import _uniform_runs, cosine_sum
from lcchain.theory.spectrum import normal_modes, return_amplitude, transmission_amplitude

# (r, w) pairs used throughout: near the Table II optimum for N = 100, the
# Table I one-mass optimum for N = 100 (r = 1, w = x*^2), the uniform free
# chain, and the Table II optimum for N = 5.
TWO_MASS_100 = (0.5873, 0.0972)
ONE_MASS_100 = (1.0, 0.4388**2)
UNIFORM = (1.0, 1.0)
TWO_MASS_5 = (0.9151, 0.5024)
RW_CASES = [TWO_MASS_100, ONE_MASS_100, UNIFORM, TWO_MASS_5]

# Sec. II.C: arrival times sqrt(3/2) pi, sqrt(11) pi / 2, sqrt(5) pi.
PAPER_ARRIVAL = {3: math.sqrt(1.5) * math.pi, 4: math.sqrt(11) * math.pi / 2, 5: math.sqrt(5) * math.pi}


def random_asymmetric_chain(N=9, seed=20240607):
    rng = np.random.default_rng(seed)
    springs = rng.uniform(0.3, 2.0, N + 1)
    springs[-1] = 0.0  # one free end, one wall
    return Chain(rng.uniform(0.3, 3.0, N), springs)


def stiffness_matrix(chain):
    """K of M Q'' = -K Q from the Hamiltonian Eq. e.Horig (walls Q_0 = Q_{N+1} = 0)."""
    k = np.asarray(chain.springs)
    return np.diag(k[:-1] + k[1:]) - np.diag(k[1:-1], 1) - np.diag(k[1:-1], -1)


# ------------------------------------------------------------- normalisation
NORMALISATION_CHAINS = {
    "uniform-free": Chain.uniform_free(12),
    "uniform-bounded": Chain.uniform_bounded(12),
    "one-mass": Chain.one_mass(30, 0.4388),
    "two-mass": Chain.two_mass(30, *TWO_MASS_100),
    "random-asymmetric": random_asymmetric_chain(),
    "perfect-5": Chain.perfect(5),
}


@pytest.mark.parametrize("name", sorted(NORMALISATION_CHAINS))
def test_exact_density_sums_to_one(name):
    """Eq. e.Pn: sum_n P_n = 1 by orthogonality of U."""
    modes = exact_modes(NORMALISATION_CHAINS[name])
    assert modes.method == "exact"
    assert np.all(modes.density >= 0)
    assert modes.density.sum() == pytest.approx(1.0, abs=ATOL_NORMALISATION)
    # the first mass's own response starts at 1 (it is sum_n P_n cos 0)
    assert return_amplitude(modes, 0.0) == pytest.approx(1.0, abs=ATOL_NORMALISATION)


@pytest.mark.parametrize("N", [5, 17, 400, 3000])
@pytest.mark.parametrize("r, w", RW_CASES)
def test_closed_form_density_sums_to_one(N, r, w):
    """Eq. e.Pk with the halving at k = 0 (1/(1 + delta_k0)) is exactly normalised."""
    modes = closed_form_modes(N, r, w)
    assert modes.method == "closed-form"
    assert modes.density.sum() == pytest.approx(1.0, abs=ATOL_NORMALISATION)


# ------------------------------------------------------------ perfect chains
def test_perfect_arrival_constants():
    for N, t in PAPER_ARRIVAL.items():
        assert PERFECT_ARRIVAL[N] == pytest.approx(t, rel=RTOL_ARITHMETIC)


@pytest.mark.parametrize("N", [3, 4, 5])
def test_perfect_chain_transmits_perfectly(N):
    """Sec. II.C: alpha_N(t_N) = 1 at t_3 = sqrt(3/2) pi, t_4 = sqrt(11) pi/2, t_5 = sqrt(5) pi."""
    chain = Chain.perfect(N)
    assert transmission_amplitude(chain, PAPER_ARRIVAL[N]) == pytest.approx(1.0, abs=ATOL_PERFECT)
    # and at odd multiples (Eq. e.utNperfect); back at mass 1 at even multiples
    assert transmission_amplitude(chain, 3 * PAPER_ARRIVAL[N]) == pytest.approx(1.0, abs=ATOL_PERFECT)
    assert return_amplitude(chain, 2 * PAPER_ARRIVAL[N]) == pytest.approx(1.0, abs=ATOL_PERFECT)
    # a transmission below 1 elsewhere: the test can fail
    assert transmission_amplitude(chain, 0.9 * PAPER_ARRIVAL[N]) < 1 - 1e-3


@pytest.mark.parametrize("N", [3, 4, 5])
def test_perfect_chain_frequencies_equally_spaced(N):
    """Sec. II.C: omega_n = (n - 1) delta_omega with delta_omega = pi / t_N."""
    modes = exact_modes(Chain.perfect(N))
    n = np.arange(N)
    np.testing.assert_allclose(modes.omega, n * modes.omega[1], rtol=0, atol=ATOL_PERFECT)
    assert modes.omega[1] == pytest.approx(math.pi / PAPER_ARRIVAL[N], abs=ATOL_PERFECT)
    # mirror symmetry: transfer = (-1)^(n-1) P_n (Sec. II.B)
    np.testing.assert_allclose(modes.transfer, (-1.0) ** n * modes.density, rtol=0, atol=ATOL_PERFECT)


# --------------------------------------------------- closed form against exact
EXACT_VS_CLOSED = [(N, r, w) for N in (5, 20, 100, 1000) for (r, w) in RW_CASES] + [
    pytest.param(5000, *TWO_MASS_100, marks=pytest.mark.slow)]  # 3 s


@pytest.mark.parametrize("N, r, w", EXACT_VS_CLOSED)
def test_closed_form_matches_exact(N, r, w):
    """Eqs. e.kn1, e.omegak, e.Pk against exact diagonalisation of Eq. e.BN; alpha_N on [0, 3N] (Eq. e.utkn)."""
    chain = Chain.from_rw(N, r, w)
    assert closed_form_applies(chain) == ""
    exact = exact_modes(chain)
    closed = closed_form_modes(N, r, w)
    np.testing.assert_allclose(closed.density, exact.density, rtol=0, atol=ATOL_CLOSED_FORM)
    np.testing.assert_allclose(closed.omega, exact.omega, rtol=0, atol=ATOL_CLOSED_FORM)
    np.testing.assert_allclose(closed.transfer, exact.transfer, rtol=0, atol=ATOL_CLOSED_FORM)
    t = np.linspace(0.0, 3.0 * N, 1501)
    np.testing.assert_allclose(
        transmission_amplitude(closed, t), transmission_amplitude(exact, t), rtol=0, atol=ATOL_CLOSED_FORM
    )
    # the closed form's wave vectors solve Eq. e.kn1 and give omega = 2 sin(k/2) (Eq. e.omegak)
    psi, _ = phase_shift(closed.k, r, w)
    np.testing.assert_allclose(N * closed.k + 2 * psi, math.pi * np.arange(N), rtol=0, atol=ATOL_CLOSED_FORM)
    np.testing.assert_allclose(closed.omega, 2 * np.sin(closed.k / 2), rtol=0, atol=ATOL_CLOSED_FORM)


@pytest.mark.parametrize("N", [5, 20, 100, 1000])
@pytest.mark.parametrize("r, w", RW_CASES)
def test_zero_mode_density_is_halved(N, r, w):
    """Appendix, Eq. e.Pk: P at k = 0 is halved; it equals m1 / M since the zero mode is U_i ~ sqrt(m_i)."""
    chain = Chain.from_rw(N, r, w)
    closed = closed_form_modes(N, r, w)
    m1_over_M = chain.masses[0] / chain.masses.sum()
    assert closed.k[0] == 0.0
    assert closed.density[0] == pytest.approx(m1_over_M, abs=ATOL_CLOSED_FORM)
    assert exact_modes(chain).density[0] == pytest.approx(m1_over_M, abs=ATOL_CLOSED_FORM)


@pytest.mark.parametrize("N", [5, 8, 1000])
def test_uniform_free_closed_form(N):
    """Eq. e.knfree: k_n = pi (n-1)/N; Eq. e.Pkunif: P_k = (2/N) cos^2(k/2), with P = 1/N at k = 0."""
    closed = closed_form_modes(N, 1.0, 1.0)
    k = math.pi * np.arange(N) / N
    expected = 2.0 / N * np.cos(k / 2) ** 2
    expected[0] = 1.0 / N
    np.testing.assert_allclose(closed.k, k, rtol=0, atol=ATOL_CLOSED_FORM)
    np.testing.assert_allclose(closed.density, expected, rtol=0, atol=ATOL_CLOSED_FORM)
    np.testing.assert_allclose(exact_modes(Chain.uniform_free(N)).density, expected, rtol=0, atol=ATOL_CLOSED_FORM)
    # psi_k = 0 for the uniform chain (u~_k = 1, Sec. III.C)
    np.testing.assert_allclose(phase_shift(k, 1.0, 1.0)[0], 0.0, rtol=0, atol=ATOL_CLOSED_FORM)


def _paper_fixed_point(N, r, w, iterations=500):
    """The paper's iteration (Sec. V): k_n <- (pi (n-1) - 2 psi(k_n)) / N from k_n = pi (n-1)/N.

    Returns the last iterate and the size of the last step.
    """
    target = math.pi * np.arange(N)
    k = target / N
    step = np.inf
    for _ in range(iterations):
        psi, _ = phase_shift(k, r, w)
        new = (target - 2 * psi) / N
        step = float(np.max(np.abs(new - k)))
        k = new
    return k, step


@pytest.mark.parametrize("N, r, w", [(5, *TWO_MASS_100), (10, 0.3, 0.02), (6, 0.1, 0.002)])
def test_plain_fixed_point_fails_where_closed_form_succeeds(N, r, w):
    """Eq. e.kn1 by plain iteration diverges where 2 |psi'| > N; the safeguarded solver still matches exact."""
    closed = closed_form_modes(N, r, w)
    _, dpsi = phase_shift(closed.k, r, w)
    assert np.max(2 * np.abs(dpsi)) > N  # the contraction condition fails
    k, step = _paper_fixed_point(N, r, w)
    assert step > NOT_CONVERGED_STEP or np.max(np.abs(k - closed.k)) > NOT_CONVERGED_STEP
    exact = exact_modes(Chain.from_rw(N, r, w))
    np.testing.assert_allclose(closed.omega, exact.omega, rtol=0, atol=ATOL_CLOSED_FORM)
    np.testing.assert_allclose(closed.density, exact.density, rtol=0, atol=ATOL_CLOSED_FORM)


def test_plain_fixed_point_converges_for_long_chain():
    """Control for the test above: for N = 20 and the same (r, w), 2 |psi'| < N and the iteration converges."""
    N, (r, w) = 20, TWO_MASS_100
    closed = closed_form_modes(N, r, w)
    k, step = _paper_fixed_point(N, r, w)
    assert step < CONVERGED_STEP
    np.testing.assert_allclose(k, closed.k, rtol=0, atol=ATOL_CLOSED_FORM)


# ------------------------------------------------------------------ phase shift
def _tilde_u(k, r, w):
    """u~_k = R_k + i I_k, Eqs. e.tudef and e.IkRk (y^2 - 1 = 1 - r)."""
    R = 1 - (1 - w) * np.cos(k) - (1 - w) * (1 - r) * np.cos(2 * k) + (1 - r) * np.cos(3 * k)
    I = (1 - w) * np.sin(k) + (1 - w) * (1 - r) * np.sin(2 * k) - (1 - r) * np.sin(3 * k)
    return R, I


@pytest.mark.parametrize("r, w", [(0.3496, 0.0232), (0.5, 0.05), TWO_MASS_100, TWO_MASS_5])
def test_phase_shift_is_continuous_and_matches_tilde_u(r, w):
    """Eq. e.psik: psi_k = arg u~_k on the branch continuous from psi_0 = 0."""
    k = np.linspace(0.0, math.pi, 20001)
    psi, dpsi = phase_shift(k, r, w)
    assert psi[0] == 0.0
    assert np.max(np.abs(np.diff(psi))) < MAX_PSI_STEP
    R, I = _tilde_u(k, r, w)
    u = R + 1j * I
    np.testing.assert_allclose(np.exp(1j * psi), u / np.abs(u), rtol=0, atol=ATOL_CLOSED_FORM)
    # psi' against a centred difference of psi (the density of Eq. e.Pk needs it)
    h = 1e-6
    inner = k[1:-1]
    numeric = (phase_shift(inner + h, r, w)[0] - phase_shift(inner - h, r, w)[0]) / (2 * h)
    scale = max(1.0, float(np.max(np.abs(dpsi))))
    np.testing.assert_allclose(dpsi[1:-1], numeric, rtol=0, atol=RTOL_CENTRED_DIFFERENCE * scale)


def test_phase_shift_continuous_where_real_part_is_negative():
    """Two-mass case with R_k < 0 on part of [0, pi] (Table II, N = 1000): atan2 branches must not show."""
    r, w = 0.3496, 0.0232
    k = np.linspace(0.0, math.pi, 20001)
    R, _ = _tilde_u(k, r, w)
    assert R[0] > 0 and np.any(R < 0)
    psi, _ = phase_shift(k, r, w)
    assert np.max(np.abs(np.diff(psi))) < MAX_PSI_STEP
    # in the R < 0 half plane |psi| > pi/2; at k = pi, u~ = r (2 - w) > 0 is real (Eq. e.IkRk) and the
    # continuous branch is back at 0, not at +-2 pi
    assert np.max(np.abs(psi[R < 0])) > math.pi / 2
    assert psi[-1] == pytest.approx(0.0, abs=ATOL_CLOSED_FORM)


# -------------------------------------------------------------------- zero mode
FREE_CHAINS = {
    "uniform-free": Chain.uniform_free(50),
    "one-mass": Chain.one_mass(50, 0.4388),
    "two-mass": Chain.two_mass(50, *TWO_MASS_100),
    "perfect-3": Chain.perfect(3),
    "perfect-5": Chain.perfect(5),
    "asymmetric-free": Chain([1.3, 0.8, 1.1, 2.0, 0.7], [0.0, 0.9, 1.2, 0.6, 1.4, 0.0]),
}


@pytest.mark.parametrize("name", sorted(FREE_CHAINS))
def test_free_chain_zero_mode_is_exact_and_finite(name):
    """Sec. II.A: a free chain has the Goldstone mode omega_1 = 0; nothing may become NaN."""
    chain = FREE_CHAINS[name]
    modes = exact_modes(chain)
    assert modes.omega[0] == 0.0
    assert np.all(np.diff(modes.omega) > 0)
    t = np.linspace(0.0, 4.0 * chain.N, 801)
    for values in (modes.omega, modes.density, modes.transfer,
                   transmission_amplitude(modes, t), return_amplitude(modes, t)):
        assert np.all(np.isfinite(values))
    # the zero mode is U_i ~ sqrt(m_i) (uniform translation, Sec. II.B), so P_1 = m_1 / M
    assert modes.density[0] == pytest.approx(chain.masses[0] / chain.masses.sum(), abs=ATOL_NORMALISATION)


@pytest.mark.parametrize("r, w", RW_CASES)
def test_closed_form_zero_mode_is_finite(r, w):
    modes = closed_form_modes(1000, r, w)
    assert modes.omega[0] == 0.0 and modes.k[0] == 0.0
    t = np.linspace(0.0, 3000.0, 301)
    for values in (modes.omega, modes.density, transmission_amplitude(modes, t), return_amplitude(modes, t)):
        assert np.all(np.isfinite(values))


# ---------------------------------------------- responses against integration
ODE_CHAINS = {
    "wall-and-free": random_asymmetric_chain(N=6, seed=7),
    "free-free": Chain([1.3, 0.8, 1.1, 2.0, 0.7, 1.5], [0.0, 0.9, 1.2, 0.6, 1.4, 0.8, 0.0]),
    "two-mass": Chain.two_mass(8, *TWO_MASS_5),
}


def _integrate(chain, t, kick):
    """Q'' = -M^-1 K Q (Eq. e.Horig) with Q_1(0) = 1 (displacement) or Q_1'(0) = 1 (kick)."""
    N = chain.N
    stiffness = stiffness_matrix(chain)
    inverse_mass = 1.0 / np.asarray(chain.masses)

    def rhs(_, y):
        return np.concatenate((y[N:], -inverse_mass * (stiffness @ y[:N])))

    y0 = np.zeros(2 * N)
    y0[N if kick else 0] = 1.0
    solution = solve_ivp(rhs, (0.0, t[-1]), y0, method="DOP853", rtol=RTOL_DOP853_TRANSMISSION, atol=ATOL_DOP853_TRANSMISSION, t_eval=t)
    assert solution.success
    return solution.y


@pytest.mark.parametrize("name", sorted(ODE_CHAINS))
def test_transmission_amplitude_matches_time_integration(name):
    """Eqs. e.qit / e.dotqit: far-end velocity after a kick and far-end position after a displacement of mass 1."""
    chain = ODE_CHAINS[name]
    N = chain.N
    t = np.linspace(0.0, 3.0 * N, 241)
    modal = transmission_amplitude(chain, t, method="exact")
    kick = _integrate(chain, t, kick=True)
    displacement = _integrate(chain, t, kick=False)
    far_velocity = kick[2 * N - 1]  # Q_N'(t) / Q_1'(0)
    far_position = displacement[N - 1]  # Q_N(t) / Q_1(0)
    np.testing.assert_allclose(far_velocity, modal, rtol=0, atol=ATOL_ODE)
    np.testing.assert_allclose(far_position, modal, rtol=0, atol=ATOL_ODE)
    np.testing.assert_allclose(far_velocity, far_position, rtol=0, atol=ATOL_ODE)
    # the near end (return amplitude) too
    np.testing.assert_allclose(kick[N], return_amplitude(chain, t, method="exact"), rtol=0, atol=ATOL_ODE)
    assert np.max(np.abs(modal)) > 0.1  # a signal arrives: the comparison is not 0 == 0


# ------------------------------------------------------------------ cosine sums
def _split_path_case():
    modes = closed_form_modes(1000, *TWO_MASS_100)
    t = np.linspace(0.0, 3000.0, 5001)  # >= 64 uniform points and J N = 5.0e6 > 4e6: split path
    return modes, t


def _brute_force(weights, omega, t):
    return np.cos(np.multiply.outer(t, omega)) @ weights


def test_cosine_sum_split_path_equals_direct_path():
    """The split-grid expansion of cos(a_p + b_q) against the same times in chunks of 50 (direct path)."""
    modes, t = _split_path_case()
    assert _uniform_runs(t) == [(0, t.size, True)]  # the whole grid is one uniform run
    split = cosine_sum(modes.transfer, modes.omega, t)
    chunks = np.concatenate([cosine_sum(modes.transfer, modes.omega, t[i : i + 50]) for i in range(0, t.size, 50)])
    np.testing.assert_allclose(split, chunks, rtol=0, atol=ATOL_COSINE_SUM)
    np.testing.assert_allclose(split, _brute_force(modes.transfer, modes.omega, t), rtol=0, atol=ATOL_COSINE_SUM)


def test_a_grid_drifting_like_a_simulators_still_takes_the_split_path():
    """ngspice's times drift from t0 + j h by its accumulated rounding (3.3e-8 after 10^5 steps, issue 23): the
    split path with its first-order correction equals the direct sum at the drifting times themselves."""
    modes, t = _split_path_case()
    walk = np.cumsum(np.random.default_rng(2).normal(0.0, 2e-10, t.size))  # a drift of a few 1e-8
    drifting = t + walk
    drift = 1e-7 / np.max(modes.omega)  # the phase drift _uniform_runs is told to accept
    assert 1e-8 < np.max(np.abs(walk)) < drift
    assert _uniform_runs(drifting, drift) == [(0, t.size, True)] and _uniform_runs(drifting) != [(0, t.size, True)]
    np.testing.assert_allclose(cosine_sum(modes.transfer, modes.omega, drifting),
                               _brute_force(modes.transfer, modes.omega, drifting), rtol=0, atol=ATOL_COSINE_SUM)


def test_a_run_drifting_further_than_the_bound_is_split_into_runs_within_it():
    """A long run at a small step strays further from its end-to-end grid than 1e-7 / omega_max (issue 23: the
    theory then took the direct path, 60x slower): it is halved into runs each within the bound of its own grid,
    which together cover every time, and the sums at the drifting times themselves stay exact."""
    modes = closed_form_modes(1000, *TWO_MASS_100)
    t = np.linspace(0.0, 3000.0, 40001)
    drift = 1e-7 / np.max(modes.omega)
    drifting = t + 8.0 * drift * (t / t[-1]) ** 2  # strays 2 bounds from its chord, a half 0.5 from its own
    assert _uniform_runs(drifting, 0.0) != [(0, t.size, True)]
    runs = _uniform_runs(drifting, drift)
    assert len(runs) > 1 and all(uniform for _, _, uniform in runs)
    assert [start for start, _, _ in runs] == [0] + [stop for _, stop, _ in runs[:-1]] and runs[-1][1] == t.size
    for start, stop, _ in runs:
        part = drifting[start:stop]
        grid = np.linspace(part[0], part[-1], part.size)
        assert np.max(np.abs(part - grid)) <= drift and (stop - start) * modes.N > 4_000_000  # split path
    expected = np.concatenate([_brute_force(modes.transfer, modes.omega, drifting[i : i + 2000])
                               for i in range(0, t.size, 2000)])
    np.testing.assert_allclose(cosine_sum(modes.transfer, modes.omega, drifting), expected, rtol=0,
                               atol=ATOL_COSINE_SUM)


def test_cosine_sum_does_not_depend_on_time_order():
    """The same times shuffled (not a uniform grid) must give the same values."""
    modes, t = _split_path_case()
    order = np.random.default_rng(1).permutation(t.size)
    shuffled = cosine_sum(modes.transfer, modes.omega, t[order])
    expected = _brute_force(modes.transfer, modes.omega, t[order])
    np.testing.assert_allclose(shuffled, expected, rtol=0, atol=ATOL_COSINE_SUM)


def test_cosine_sum_irregular_times():
    """Many unequally spaced times (a variable-step simulator's output) through the public function."""
    modes, _ = _split_path_case()
    t = np.sort(np.random.default_rng(2).uniform(0.0, 3000.0, 5001))
    np.testing.assert_allclose(
        cosine_sum(modes.density, modes.omega, t), _brute_force(modes.density, modes.omega, t),
        rtol=0, atol=ATOL_COSINE_SUM,
    )


def test_cosine_sum_shapes():
    modes = exact_modes(Chain.perfect(4))
    assert isinstance(cosine_sum(modes.density, modes.omega, 1.5), float)
    grid = np.linspace(0.0, 10.0, 12).reshape(3, 4)
    values = cosine_sum(modes.density, modes.omega, grid)
    assert values.shape == (3, 4)
    np.testing.assert_allclose(values.ravel(), _brute_force(modes.density, modes.omega, grid.ravel()),
                               rtol=0, atol=ATOL_COSINE_SUM)


# --------------------------------------------------------------------- arrivals
@pytest.mark.parametrize("N", [3, 4, 5])
def test_perfect_chain_arrivals(N):
    """Sec. II.C: arrival j at j t_N with peak 1; odd j at the far end, even j back at mass 1."""
    T = PAPER_ARRIVAL[N]
    found = arrivals(Chain.perfect(N), count=4)
    assert [a.index for a in found] == [1, 2, 3, 4]
    assert [a.end for a in found] == ["last", "first", "last", "first"]
    for arrival in found:
        assert arrival.time == pytest.approx(arrival.index * T, abs=ATOL_ARRIVAL_TIME)
        assert arrival.peak == pytest.approx(1.0, abs=ATOL_PERFECT)
        assert arrival.loss == pytest.approx(0.0, abs=ATOL_PERFECT)
    first = first_arrival(Chain.perfect(N))
    assert first.time == pytest.approx(T, abs=ATOL_ARRIVAL_TIME)


def test_arrival_window_for_three_masses_stays_away_from_3T():
    """arrivals.py: W_j <= T/2, so for N = 3 the first window cannot reach the next far-end arrival at 3T,
    where alpha_3 is 1 again (Eq. e.utNperfect)."""
    T = PERFECT_ARRIVAL[3]
    for index in (1, 2, 3):
        lo, hi = arrival_window(index, T)
        assert lo == pytest.approx((index - 0.5) * T) and hi == pytest.approx((index + 0.5) * T)
    assert arrival_window(1, T)[1] < 3 * T
    # the documented reason: the far end peaks at 1 again at 3T, a different arrival
    assert transmission_amplitude(Chain.perfect(3), 3 * T) == pytest.approx(1.0, abs=ATOL_PERFECT)


def test_arrival_window_rejects_index_zero():
    with pytest.raises(ParameterError, match=r"^index = 0 is not allowed"):
        arrival_window(0, 10.0)
    with pytest.raises(ParameterError, match=r"^count = 0 is not allowed"):
        arrivals(Chain.perfect(3), count=0)


def test_two_mass_first_arrival_table_ii():
    """Table II, N = 100: (r*, w*) = (0.5873, 0.0972) arrives with delay s* = t* - N = 7.04 and delta* = 0.01555."""
    N = 100
    arrival = first_arrival(Chain.two_mass(N, *TWO_MASS_100))
    assert arrival.end == "last"
    assert arrival.time - N == pytest.approx(7.04, abs=ATOL_TABLE_DELAY)
    assert arrival.loss == pytest.approx(0.01555, abs=ATOL_TABLE_LOSS)


# ----------------------------------------------------------------- bad methods
def test_unknown_method_rejected():
    chain = Chain.perfect(3)
    with pytest.raises(ParameterError, match=r"^method = 'fast' is not allowed: expected auto \| exact \| closed-form"):
        normal_modes(chain, "fast")
    with pytest.raises(ParameterError, match=r"^method = 'Exact' is not allowed"):
        transmission_amplitude(chain, 1.0, method="Exact")


@pytest.mark.parametrize(
    "chain, reason",
    [
        (Chain.uniform_bounded(20), "free ends"),
        (Chain.from_rw(4, 10 / 11, 6 / 11), "N >= 5"),
        (Chain.perfect(5), "quasi-uniform"),
        (random_asymmetric_chain(N=20), "free ends"),
    ],
)
def test_closed_form_refuses_chains_it_does_not_cover(chain, reason):
    """The closed form (Eqs. e.kn1, e.Pk) is derived for free chains with the matrix of Eq. e.AN, N >= 5."""
    assert reason in closed_form_applies(chain)
    with pytest.raises(ParameterError, match=r"^method = 'closed-form' is not allowed: expected a chain the closed form covers"):
        normal_modes(chain, "closed-form")


def test_closed_form_modes_rejects_short_chain():
    with pytest.raises(ParameterError, match=r"^N = 4 is not allowed"):
        closed_form_modes(4, 10 / 11, 6 / 11)


def test_auto_method_choice():
    """'auto' uses the closed form for long free quasi-uniform chains, exact diagonalisation otherwise."""
    assert normal_modes(Chain.two_mass(1000, *TWO_MASS_100)).method == "closed-form"
    assert normal_modes(Chain.two_mass(50, *TWO_MASS_100)).method == "exact"
    assert normal_modes(Chain.uniform_bounded(1000)).method == "exact"
