"""Exact linear response with losses and pulses (lcchain.response).

Expected values come from the paper (Eq. e.utn: without losses the end loops
follow the transmission and return amplitudes of lcchain.modes) or from
independent computations written here: a DOP853 integration of the 2N
equations of motion m_i Q_i'' + (m_i/Q) Q_i' + (K Q)_i = m_1 g(t) delta_i1 in
physical coordinates (walls Q_0 = Q_{N+1} = 0), and momentum conservation
(its decay exp(-t/Q)) for a free chain.
"""

import math

import numpy as np
import pytest
from helpers.tolerances import (
    ATOL_DOP853_RESPONSE,
    ATOL_LOOPS,
    ATOL_MODAL,
    ATOL_MOMENTUM,
    ATOL_NO_FLOOR,
    ATOL_RESPONSE_ODE,
    ATOL_SHORT_PULSE,
    RTOL_DOP853_RESPONSE,
    RTOL_EXPM1_BASIS,
    RTOL_OVERDAMPED_BASIS,
)
from scipy.integrate import solve_ivp
from scipy.special import ndtr

from lcchain.core.errors import ParameterError
from lcchain.theory.chain import Chain
from lcchain.theory.exact import exact_modes
from lcchain.theory.response import _basis, linear_response, prepare_response, pulse_end
from lcchain.theory.spectrum import return_amplitude, transmission_amplitude

EXCITATIONS = [
    ("kick", None),
    ("displacement", None),
    ("pulse", ("gaussian", 0.4)),
    ("pulse", ("rect", 1.5)),
]
LOSSES = [None, 100.0, 0.3]  # lossless, weak losses, most modes overdamped


def wall_free_chain():
    """A small asymmetric chain: a wall spring before mass 1, a free end after mass N."""
    return Chain([1.3, 0.7, 1.1, 0.9, 1.6], [0.8, 1.0, 1.2, 0.6, 1.1, 0.0])


def gaussian(t, width):
    return np.where(t >= 0, np.exp(-0.5 * ((t - 4 * width) / width) ** 2) / (width * math.sqrt(2 * math.pi)), 0.0)


def integrate(chain, t, excitation="kick", Q=None, pulse=None):
    """Positions and velocities, shape (2N, len(t)), of M Q'' + (M/Q) Q' + K Q = F(t)."""
    m = np.asarray(chain.masses)
    k = np.asarray(chain.springs)
    N = chain.N
    stiffness = np.diag(k[:-1] + k[1:]) - np.diag(k[1:-1], 1) - np.diag(k[1:-1], -1)
    gamma = 0.0 if Q is None else 1.0 / Q
    y0 = np.zeros(2 * N)
    y0[N if excitation != "displacement" else 0] = 1.0 if excitation != "pulse" else 0.0

    def rhs(time, y, force):
        acceleration = -(stiffness @ y[:N]) / m - gamma * y[N:]
        acceleration[0] += force(time)
        return np.concatenate((y[N:], acceleration))

    options = dict(method="DOP853", rtol=RTOL_DOP853_RESPONSE, atol=ATOL_DOP853_RESPONSE)
    if pulse is None:
        solution = solve_ivp(rhs, (0.0, t[-1]), y0, t_eval=t, args=(lambda time: 0.0,), **options)
        assert solution.success
        return solution.y
    shape, width = pulse
    if shape == "gaussian":
        solution = solve_ivp(rhs, (0.0, t[-1]), y0, t_eval=t, max_step=width / 4,
                             args=(lambda time: float(gaussian(np.array(time), width)),), **options)
        assert solution.success
        return solution.y
    # rect: integrate across the jump of g at t = width in two pieces
    inside = t < width
    first = solve_ivp(rhs, (0.0, width), y0, t_eval=np.append(t[inside], width), max_step=width / 4,
                      args=(lambda time: 1.0 / width,), **options)
    second = solve_ivp(rhs, (width, t[-1]), first.y[:, -1], t_eval=t[~inside], args=(lambda time: 0.0,), **options)
    assert first.success and second.success
    return np.hstack((first.y[:, :-1], second.y))


# ---------------------------------------------------------------- lossless
@pytest.mark.parametrize("excitation", ["kick", "displacement"])
def test_lossless_ends_are_the_transmission_and_return_amplitudes(excitation):
    """Eq. e.utn: without losses loop N follows alpha_N(t) and loop 1 the return amplitude."""
    chain = wall_free_chain()
    t = np.linspace(0.0, 40.0, 801)
    response = linear_response(chain, t, excitation=excitation)
    np.testing.assert_allclose(response[0], return_amplitude(chain, t, method="exact"), rtol=0, atol=ATOL_MODAL)
    np.testing.assert_allclose(response[1], transmission_amplitude(chain, t, method="exact"), rtol=0, atol=ATOL_MODAL)
    every = linear_response(chain, t, excitation=excitation, loops="all")
    np.testing.assert_allclose(every[-1], transmission_amplitude(chain, t, method="exact"), rtol=0, atol=ATOL_MODAL)


def test_lossless_ends_of_a_long_chain_use_the_given_modes():
    chain = Chain.two_mass(200, 0.5873, 0.0972)
    modes = exact_modes(chain)
    t = np.linspace(0.0, 600.0, 3001)
    response = linear_response(chain, t, modes=modes)
    np.testing.assert_allclose(response[1], transmission_amplitude(modes, t), rtol=0, atol=ATOL_MODAL)


# ------------------------------------------------- every effect against the ODE
@pytest.mark.parametrize("Q", LOSSES, ids=["lossless", "Q100", "Q0.3"])
@pytest.mark.parametrize("excitation, pulse", EXCITATIONS, ids=["kick", "displacement", "gaussian", "rect"])
def test_response_matches_time_integration(excitation, pulse, Q):
    chain = wall_free_chain()
    N = chain.N
    t = np.linspace(0.0, 20.0, 401)
    every = linear_response(chain, t, excitation=excitation, Q=Q, pulse=pulse, loops="all")
    ends = linear_response(chain, t, excitation=excitation, Q=Q, pulse=pulse)
    y = integrate(chain, t, excitation, Q, pulse)
    expected = y[:N] if excitation == "displacement" else y[N:]
    np.testing.assert_allclose(every, expected, rtol=0, atol=ATOL_RESPONSE_ODE)
    np.testing.assert_allclose(ends, expected[[0, -1]], rtol=0, atol=ATOL_RESPONSE_ODE)
    # every loop moves (the far end by > 2e-3 even when overdamped): the comparison is not 0 == 0
    assert np.min(np.max(np.abs(expected), axis=1)) > 1e-3


@pytest.mark.parametrize("shift", [0.0, 1e-9, -1e-9, 1e-4, -1e-4], ids=["critical", "+1e-9", "-1e-9", "+1e-4", "-1e-4"])
@pytest.mark.parametrize("excitation, pulse", EXCITATIONS, ids=["kick", "displacement", "gaussian", "rect"])
def test_critical_damping_is_exact(excitation, pulse, shift):
    """A mode at (or within a hair of) omega = gamma/2: no 0/0, no cancellation."""
    chain = wall_free_chain()
    omega = exact_modes(chain).omega
    Q = 1.0 / (2.0 * omega[1]) * (1.0 + shift)
    t = np.linspace(0.0, 20.0, 201)
    response = linear_response(chain, t, excitation=excitation, Q=Q, pulse=pulse, loops="all")
    y = integrate(chain, t, excitation, Q, pulse)
    expected = y[: chain.N] if excitation == "displacement" else y[chain.N :]
    np.testing.assert_allclose(response, expected, rtol=0, atol=ATOL_RESPONSE_ODE)


def test_wide_gaussian_with_losses_and_unsorted_times():
    """A pulse longer than the oscillations (many quadrature panels), times in any order."""
    chain = wall_free_chain()
    t = np.linspace(0.0, 60.0, 241)
    order = np.random.default_rng(7).permutation(t.size)
    response = linear_response(chain, t[order], excitation="pulse", Q=5.0, pulse=("gaussian", 3.0))
    y = integrate(chain, t, "pulse", 5.0, ("gaussian", 3.0))
    np.testing.assert_allclose(response, y[chain.N :][[0, -1]][:, order], rtol=0, atol=ATOL_RESPONSE_ODE)


# ------------------------------------------------------------ zero mode, limits
@pytest.mark.parametrize("Q", [None, 2.0, 0.05])
def test_free_chain_momentum_decays_as_exp_minus_t_over_Q(Q):
    """Only the translation mode carries momentum: sum m_i Q_i' = m_1 exp(-t/Q) after a kick."""
    chain = Chain([1.7, 0.6, 1.0, 1.2, 0.8, 1.4], [0.0, 1.0, 0.7, 1.3, 0.9, 1.1, 0.0])
    t = np.linspace(0.0, 50.0, 501)
    velocities = linear_response(chain, t, Q=Q, loops="all")
    assert np.all(np.isfinite(velocities))
    momentum = chain.masses @ velocities
    expected = chain.masses[0] * (np.ones_like(t) if Q is None else np.exp(-t / Q))
    np.testing.assert_allclose(momentum, expected, rtol=0, atol=ATOL_MOMENTUM)
    positions = linear_response(chain, t, excitation="displacement", Q=Q, loops="all")
    assert np.all(np.isfinite(positions))
    # a displacement moves no centre of mass: sum m_i Q_i stays m_1
    np.testing.assert_allclose(chain.masses @ positions, chain.masses[0], rtol=0, atol=ATOL_MOMENTUM)


@pytest.mark.parametrize("Q", [None, 100.0, 0.3])
def test_short_pulse_is_a_kick(Q):
    """Width -> 0: the rect tends to the kick, the truncated gaussian to (1 - Phi(-4)) times it.

    To second order in the width a short pulse is a kick delayed to the
    pulse's centre (w/2 for the rect, 4 w for the gaussian) and scaled by its
    area; the unscaled gaussian differs from the kick by its missing area
    Phi(-4) = 3.2e-5 (it is not renormalised).  Pulses are at least
    :data:`lcchain.core.limits.MIN_PULSE_WIDTH` wide, so the limit is shown by its order: halving the width
    halves the rect's distance to the kick and quarters both pulses' distance to the delayed kick.
    """
    chain = wall_free_chain()
    t = np.linspace(0.1, 30.0, 300)  # after the pulse (over at 1.6e-2); at t = 0 it has not started
    kick = linear_response(chain, t, Q=Q)
    area = 1.0 - ndtr(-4.0)
    errors = []
    for width in (2e-3, 1e-3):
        rect = linear_response(chain, t, excitation="pulse", Q=Q, pulse=("rect", width))
        gauss = linear_response(chain, t, excitation="pulse", Q=Q, pulse=("gaussian", width))
        errors.append((np.max(np.abs(rect - kick)),
                       np.max(np.abs(rect - linear_response(chain, t - width / 2, Q=Q))),
                       np.max(np.abs(gauss - area * linear_response(chain, t - 4 * width, Q=Q)))))
    (kick_2, rect_2, gauss_2), (kick_1, rect_1, gauss_1) = errors
    assert 1.8 < kick_2 / kick_1 < 2.2  # first order in the width
    assert 3.5 < rect_2 / rect_1 < 4.5 and 3.5 < gauss_2 / gauss_1 < 4.5  # second order
    assert rect_1 < ATOL_SHORT_PULSE and gauss_1 < ATOL_SHORT_PULSE


def test_mode_functions_in_every_regime():
    """X = s (impulse response) and Y of the damped oscillator against their textbook forms.

    omega = 1 with gamma = 1 (underdamped), 2 (critical: s = t exp(-t)), 4
    (overdamped) and the zero mode (s = (1 - exp(-gamma t))/gamma), up to
    t = 1e4 where cosh and sinh alone would overflow.
    """
    t = np.array([0.0, 0.5, 3.0, 40.0, 1e4])
    omega = np.array([1.0, 0.0])
    X, Y = _basis(omega, 1.0, t)
    root = math.sqrt(0.75)
    np.testing.assert_allclose(X[:, 0], np.exp(-t / 2) * np.sin(root * t) / root, rtol=0, atol=ATOL_MODAL)
    np.testing.assert_allclose(Y[:, 0], np.exp(-t / 2) * np.cos(root * t), rtol=0, atol=ATOL_MODAL)
    X, Y = _basis(omega, 2.0, t)
    np.testing.assert_allclose(X[:, 0], t * np.exp(-t), rtol=0, atol=ATOL_MODAL)
    np.testing.assert_allclose(Y[:, 0], np.exp(-t), rtol=0, atol=ATOL_MODAL)
    np.testing.assert_allclose(X[:, 1], -np.expm1(-2.0 * t) / 2.0, rtol=RTOL_EXPM1_BASIS, atol=0)
    X, Y = _basis(omega, 4.0, t)
    slow, fast = -2.0 + math.sqrt(3.0), -2.0 - math.sqrt(3.0)
    np.testing.assert_allclose(X[:, 0], (np.exp(slow * t) - np.exp(fast * t)) / (slow - fast), rtol=RTOL_OVERDAMPED_BASIS, atol=ATOL_NO_FLOOR)
    np.testing.assert_allclose(Y[:, 0], (np.exp(slow * t) + np.exp(fast * t)) / 2, rtol=RTOL_OVERDAMPED_BASIS, atol=ATOL_NO_FLOOR)
    np.testing.assert_allclose(Y[:, 1] - 2.0 * X[:, 1], np.exp(-4.0 * t), rtol=0, atol=ATOL_MODAL)  # s' of the zero mode


@pytest.mark.parametrize("Q", [1e-3, 1e6])
@pytest.mark.parametrize("excitation, pulse", EXCITATIONS, ids=["kick", "displacement", "gaussian", "rect"])
def test_extreme_losses_stay_finite(excitation, pulse, Q):
    """Very strong and very weak losses over long times: no overflow, NaN or warning."""
    chain = Chain([1.7, 0.6, 1.0, 1.2, 0.8, 1.4], [0.0, 1.0, 0.7, 1.3, 0.9, 1.1, 0.0])  # free: a zero mode
    t = np.concatenate((np.linspace(0.0, 10.0, 101), [1e3, 1e5]))
    response = linear_response(chain, t, excitation=excitation, Q=Q, pulse=pulse, loops="all")
    assert np.all(np.isfinite(response))
    if excitation != "displacement":
        # passivity: the kinetic energy never exceeds the m_1/2 the kick (or unit-area pulse) gives
        assert np.max(chain.masses @ response**2) <= chain.masses[0] * (1.0 + 1e-12)


def test_pulse_end():
    assert pulse_end("rect", 0.5) == 0.5
    assert pulse_end("gaussian", 0.5) == 8.0


@pytest.mark.parametrize("Q", [None, 20.0])
@pytest.mark.parametrize("excitation, pulse", EXCITATIONS, ids=["kick", "displacement", "gaussian", "rect"])
def test_all_loops_agree_with_ends(excitation, pulse, Q):
    chain = Chain.one_mass(12, 0.4388)
    t = np.linspace(0.0, 40.0, 400)
    ends = linear_response(chain, t, excitation=excitation, Q=Q, pulse=pulse)
    every = linear_response(chain, t, excitation=excitation, Q=Q, pulse=pulse, loops="all")
    assert ends.shape == (2, t.size) and every.shape == (chain.N, t.size)
    np.testing.assert_allclose(every[[0, -1]], ends, rtol=0, atol=ATOL_LOOPS)


# ------------------------------------------------------------ prepared once
@pytest.mark.parametrize("loops", ["ends", "all"])
@pytest.mark.parametrize("Q", [None, 20.0])
@pytest.mark.parametrize("excitation, pulse", EXCITATIONS, ids=["kick", "displacement", "gaussian", "rect"])
def test_a_prepared_response_computes_what_linear_response_computes(excitation, pulse, Q, loops):
    """A peak search calls the prepared response of one circuit ~75 times with one time each (issue 23): each
    call, and a call on a whole grid, performs linear_response's own operations on the same arrays -- the same
    values to the bit, whatever was called before (a Monte Carlo's stored metrics must not move)."""
    chain = wall_free_chain()
    keywords = dict(excitation=excitation, Q=Q, pulse=pulse, loops=loops)
    response = prepare_response(chain, **keywords)
    t = np.linspace(0.0, 30.0, 301)  # inside and after either pulse
    for time in (t[250], t[3], t[120], 0.0, t[3]):
        np.testing.assert_array_equal(response(np.array([time])), linear_response(chain, [time], **keywords))
    np.testing.assert_array_equal(response(t), linear_response(chain, t, **keywords))
    assert not response.weights.flags.writeable and not response.omega.flags.writeable


# ------------------------------------------------------------------ validation
@pytest.mark.parametrize(
    "kwargs, field",
    [
        (dict(excitation="shake"), "excitation"),
        (dict(excitation="pulse"), "pulse"),
        (dict(excitation="kick", pulse=("rect", 1.0)), "pulse"),
        (dict(excitation="pulse", pulse=("square", 1.0)), "pulse shape"),
        (dict(excitation="pulse", pulse=("rect", 0.0)), "pulse width"),
        (dict(excitation="pulse", pulse=("gaussian", -1.0)), "pulse width"),
        (dict(excitation="pulse", pulse=("gaussian", float("nan"))), "pulse width"),
        (dict(excitation="pulse", pulse=("gaussian",)), "pulse"),
        (dict(Q=0.0), "Q"),
        (dict(Q=-3.0), "Q"),
        (dict(Q=float("inf")), "Q"),
        (dict(Q=True), "Q"),
        (dict(loops="middle"), "loops"),
        (dict(modes="exact"), "modes"),
    ],
)
def test_bad_input_names_the_field(kwargs, field):
    chain = wall_free_chain()
    with pytest.raises(ParameterError) as error:
        linear_response(chain, np.linspace(0.0, 1.0, 5), **kwargs)
    assert error.value.field == field
    assert field in str(error.value)


@pytest.mark.parametrize("t", [np.array([0.0, -1.0, 2.0]), np.array([0.0, np.nan]), np.zeros((2, 2))])
def test_bad_times_raise(t):
    with pytest.raises(ParameterError) as error:
        linear_response(wall_free_chain(), t)
    assert error.value.field.startswith("t")


def test_modes_of_another_chain_raise():
    other = exact_modes(Chain.uniform_free(7))
    with pytest.raises(ParameterError, match="modes"):
        linear_response(wall_free_chain(), np.linspace(0.0, 1.0, 5), modes=other)
