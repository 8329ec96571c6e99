"""Tables I and II of the paper, recomputed from scratch and compared digit by digit.

Source: the rows of Tables I (t.opt_y1) and II (t.opt_rw) present in the
shared copy of the paper (some rows are left out of it on purpose: the code
computes any N and looks nothing up).  Each value must round to the printed
digits.  Where the paper's last digit differs by one unit, the test says why,
with the unrounded value we compute:

* Table I, N = 100, delta*(1) = 0.5611453 (printed 0.5612): the paper scanned
  the delay s on a grid; with a step of 0.1 the uniform chain's best loss is
  0.5611956, which rounds to 0.5612.  Our value is the true maximum.
* Table I, N = 1000, delta* = 0.1185497 (printed 0.1186): within 3e-7 of the
  rounding boundary 0.11855.
* Table II, N = 20, r* = 0.7712484 (printed 0.7713): within 2e-6 of the
  rounding boundary 0.77125.
* Table II, N = 1000, m1* = 9.145198 (printed 9.146): the optimum is flat
  along m1; at m1 = 9.146 the best amplitude is 0.98621082896 against our
  0.98621083055, so ours is the better optimum (see test below).
"""

import pytest
from helpers.digits import agrees_with_printed

from lcchain.theory.arrivals import first_arrival
from lcchain.theory.closed_form import closed_form_modes
from lcchain.theory.design import optimal_one_mass, optimal_two_mass

# Table I: N, x*, delta*(x*), s*(x*), m1*, Delta*, delta*(1)
TABLE_I = [
    (3, "0.8165", "0.0000", "0.85", "1.500", "0.5000", "0.0292"),
    (4, "0.7731", "0.0041", "1.08", "1.673", "0.4261", "0.0608"),
    (5, "0.7414", "0.0083", "1.28", "1.819", "0.3790", "0.0900"),
    (6, "0.7171", "0.0123", "1.44", "1.945", "0.3461", "0.1161"),
    (7, "0.6975", "0.0160", "1.58", "2.056", "0.3214", "0.1395"),
    (8, "0.6811", "0.0193", "1.71", "2.156", "0.3020", "0.1606"),
    (9, "0.6670", "0.0223", "1.83", "2.248", "0.2861", "0.1796"),
    (10, "0.6548", "0.0251", "1.94", "2.333", "0.2728", "0.1969"),
    (12, "0.6341", "0.0299", "2.13", "2.487", "0.2517", "0.2274"),
    (14, "0.6173", "0.0341", "2.31", "2.625", "0.2353", "0.2535"),
    (16, "0.6031", "0.0377", "2.46", "2.750", "0.2223", "0.2762"),
    (18, "0.5908", "0.0409", "2.61", "2.865", "0.2114", "0.2962"),
    (20, "0.5801", "0.0437", "2.74", "2.972", "0.2023", "0.3141"),
    (100, "0.4388", "0.0826", "5.49", "5.194", "0.1065", "0.5612"),
    (1000, "0.2951", "0.1186", "13.17", "11.486", "0.04551", "0.7881"),
]
# Table II: N, r*, w*, delta*, s*, m1*, m2*, K12*
TABLE_II = [
    (3, "1.0000", "0.6667", "0.00000", "0.85", "1.500", "1.0000", "1.0000"),
    (4, "0.9091", "0.5455", "0.00000", "1.21", "1.528", "0.9167", "0.8333"),
    (5, "0.9151", "0.5024", "0.00304", "1.40", "1.679", "0.9218", "0.8435"),
    (6, "0.9003", "0.4610", "0.00505", "1.59", "1.776", "0.9093", "0.8187"),
    (7, "0.8853", "0.4273", "0.00664", "1.77", "1.859", "0.8971", "0.7942"),
    (8, "0.8718", "0.3996", "0.00794", "1.93", "1.933", "0.8863", "0.7727"),
    (9, "0.8595", "0.3764", "0.00902", "2.08", "2.002", "0.8768", "0.7536"),
    (10, "0.8483", "0.3565", "0.00991", "2.22", "2.066", "0.8683", "0.7366"),
    (12, "0.8285", "0.3241", "0.01130", "2.47", "2.182", "0.8536", "0.7073"),
    (14, "0.8115", "0.2986", "0.01230", "2.70", "2.287", "0.8414", "0.6828"),
    (16, "0.7965", "0.2779", "0.01305", "2.91", "2.382", "0.8309", "0.6619"),
    (18, "0.7832", "0.2606", "0.01361", "3.10", "2.470", "0.8218", "0.6437"),
    (20, "0.7713", "0.2460", "0.01405", "3.28", "2.552", "0.8138", "0.6277"),
    (100, "0.5873", "0.0972", "0.01555", "7.04", "4.275", "0.7079", "0.4157"),
    (1000, "0.3496", "0.0232", "0.01379", "17.72", "9.146", "0.6059", "0.2119"),
]
# (table, N, column) -> why a one-unit difference in the last digit is accepted (module docstring)
ONE_UNIT_OFF = {
    ("I", 100, "delta_uniform"): "paper's coarse s grid; true 0.5611453",
    ("I", 1000, "delta"): "0.1185497 is within 3e-7 of the rounding boundary",
    ("II", 20, "r"): "0.7712484 is within 2e-6 of the rounding boundary",
    ("II", 1000, "m1"): "flat optimum along m1; ours is higher (test_table_ii_n1000_m1_is_a_better_optimum)",
}


def _check(table, N, design, expected):
    failures = []
    for key, text in expected.items():
        value = getattr(design, key)
        if key == "delta":
            value = max(value, 0.0)  # a perfect chain's loss is 0 up to rounding (-1e-16 prints as 0.0000)
        allowed = 1 if (table, N, key) in ONE_UNIT_OFF else 0
        if not agrees_with_printed(value, text, allowed):
            failures.append(f"{key}: computed {value!r}, printed {text}")
    assert not failures, f"Table {table} N={N}: " + "; ".join(failures)


@pytest.mark.parametrize("row", TABLE_I, ids=[f"N{r[0]}" for r in TABLE_I])
def test_table_i_row(row):
    N, x, delta, s, m1, Delta, delta1 = row
    design = optimal_one_mass(N)
    _check("I", N, design, {"x": x, "delta": delta, "s": s, "m1": m1, "Delta": Delta, "delta_uniform": delta1})


@pytest.mark.parametrize("row", TABLE_II, ids=[f"N{r[0]}" for r in TABLE_II])
def test_table_ii_row(row):
    N, r, w, delta, s, m1, m2, K12 = row
    design = optimal_two_mass(N)
    _check("II", N, design, {"r": r, "w": w, "delta": delta, "s": s, "m1": m1, "m2": m2, "K12": K12})


def test_table_ii_n1000_m1_is_a_better_optimum():
    """Our m1* = 9.1452 beats the printed 9.146 (the best chain with m1 = 9.146)."""
    from scipy.optimize import minimize_scalar

    ours = optimal_two_mass(1000)
    best_printed = minimize_scalar(
        lambda r: -first_arrival(closed_form_modes(1000, r, r / ((2 - r) * 9.146))).peak,
        bounds=(0.34, 0.36), method="bounded", options={"xatol": 1e-10})
    assert 1 - ours.delta > -best_printed.fun


def test_perfect_small_chains_are_the_optima():
    """Tables I (N=3) and II (N=3, 4): the optimum is the perfect chain of Sec. II.C."""
    assert optimal_one_mass(3).x == pytest.approx((2 / 3) ** 0.5, abs=1e-7)
    four = optimal_two_mass(4)
    assert (four.r, four.w) == pytest.approx((10 / 11, 6 / 11), abs=1e-6)
    assert four.delta < 1e-12
