"""P_n tails: the perfect cradle's exact binomial end weights, and rounding noise marked, never shown as data."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from helpers.tolerances import ATOL_PERFECT_WEIGHTS, RTOL_PERFECT_TAIL, RTOL_TWO_DIGITS

from lcchain.cli.main import main
from lcchain.report.shown import spectrum_figure
from lcchain.runs.spectrum import measure_spectrum
from lcchain.theory.cases import chain_for_case
from lcchain.theory.chain import Chain
from lcchain.theory.exact import driven_modes, exact_modes, perfect_weights
from lcchain.theory.modes import WEIGHT_PRECISION


def _untagged(chain: Chain) -> Chain:
    """The same masses and springs, not marked perfect: LAPACK's eigenvectors give its weights."""
    return Chain(chain.masses, chain.springs, name="custom")


@pytest.mark.parametrize("N", [6, 9, 14, 20])
def test_binomial_weights_are_lapacks_where_float64_resolves_them(N):
    chain = chain_for_case("perfect", N)
    lapack = driven_modes(_untagged(chain))
    exact = driven_modes(chain)
    np.testing.assert_allclose(exact.transfer, lapack.transfer, rtol=0, atol=ATOL_PERFECT_WEIGHTS)
    np.testing.assert_allclose(exact.density, lapack.density, rtol=0, atol=ATOL_PERFECT_WEIGHTS)
    assert exact.density.sum() == pytest.approx(1.0, abs=ATOL_PERFECT_WEIGHTS)
    assert exact.precise().all()


def test_perfect_100_smallest_weight_is_exact():
    N = 100
    modes = driven_modes(chain_for_case("perfect", N))
    smallest = np.min(np.abs(modes.transfer))
    assert smallest == pytest.approx(2.0 ** -(2 * N - 3), rel=RTOL_PERFECT_TAIL)
    assert modes.transfer[-1] == pytest.approx(-5.0e-60, rel=RTOL_TWO_DIGITS)  # (-1)^(N-1): the mirror symmetric sign
    assert perfect_weights(N)[0] == pytest.approx(math.comb(2 * N - 2, N - 1) / 2 ** (2 * N - 2),
                                                  rel=RTOL_PERFECT_TAIL)


def test_noise_is_flagged_not_a_value():
    """The same N = 100 cradle without the mark: the kick's modes come from LAPACK's vectors, whose tail is
    rounding, flagged below precision."""
    modes = exact_modes(_untagged(chain_for_case("perfect", 100)))
    precise = modes.precise()
    assert not precise.all() and precise[:20].all()
    assert np.all(np.abs(modes.transfer[~precise]) < WEIGHT_PRECISION * np.max(np.abs(modes.transfer)))


def test_spectrum_json_prints_no_noise(capsys, tmp_path):
    N = 100
    assert main(["spectrum", "--case", "perfect", "--N", str(N), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    exact = driven_modes(chain_for_case("perfect", N)).transfer
    P_theory = np.array([mode["P_theory"] for mode in data["modes"]], dtype=float)
    np.testing.assert_allclose(P_theory, exact, rtol=RTOL_PERFECT_TAIL, atol=0)
    assert not any(mode["below_precision"] for mode in data["modes"])
    # the unmarked chain: the AC reference's weights come from its frequencies alone (the residue product), so
    # they are the closed form's, to the last weight, and none is noise
    report = measure_spectrum(_untagged(chain_for_case("perfect", N)))
    modes = report.to_dict()["modes"]
    noisy = [mode for mode in modes if mode["below_precision"]]
    assert not noisy
    np.testing.assert_allclose(report.P_theory, exact, rtol=RTOL_PERFECT_TAIL, atol=0)
    fig = spectrum_figure(report)
    theory_points = fig.axes[0].lines[1].get_ydata()
    assert len(theory_points) == N - len(noisy)
