"""The Chain type: constructors, views, perfect chains, immutability, validation.

Expected values are derived by hand from the paper (Sec. II.A, Eqs. e.xyz,
e.mKxyz, e.rw; Sec. II.C, Eqs. e.N3, e.N4, e.N5) with exact fractions.
"""

import dataclasses
import math
import re
from fractions import Fraction as F

import numpy as np
import pytest
from helpers.tolerances import ATOL_ROUND_TRIP, RTOL_ARITHMETIC

from lcchain.core.errors import ParameterError
from lcchain.theory.chain import Chain


def assert_masses_springs(chain, masses, springs):
    np.testing.assert_allclose(chain.masses, [float(m) for m in masses], rtol=RTOL_ARITHMETIC, atol=0)
    np.testing.assert_allclose(chain.springs, [float(k) for k in springs], rtol=RTOL_ARITHMETIC, atol=0)


def raises_naming(field, value_text):
    """pytest.raises for a ParameterError whose message names the field and shows the value."""
    return pytest.raises(ParameterError, match=rf"^{re.escape(field)} = {re.escape(value_text)} is not allowed: expected ")


# ---------------------------------------------------------------- constructors
def test_from_rw_perfect_four_mass_values():
    """Sec. II.C: r = 10/11, w = 6/11 gives m1 = 55/36, m2 = 11/12, K12 = 5/6 (Eq. e.m1m2K12-rw)."""
    chain = Chain.from_rw(4, 10 / 11, 6 / 11)
    m1, m2, K12 = F(55, 36), F(11, 12), F(5, 6)
    # N = 4 layout: (m1, m2, m2, m1), springs (K01, K12, 1, K12, K01) with K01 = 0 (free).
    assert_masses_springs(chain, (m1, m2, m2, m1), (0, K12, 1, K12, 0))
    assert chain.free_ends == (True, True)
    assert chain.springs[0] == 0.0 and chain.springs[-1] == 0.0


def test_from_rw_general_values_and_layout():
    """Eq. e.m1m2K12-rw with r = 1/2, w = 1/4: m1 = r/((2-r) w) = 4/3, m2 = 2/3, K12 = 1/3; uniform bulk."""
    N = 7
    chain = Chain.from_rw(N, 0.5, 0.25)
    m1, m2, K12 = F(4, 3), F(2, 3), F(1, 3)
    assert_masses_springs(chain, (m1, m2, 1, 1, 1, m2, m1), (0, K12, 1, 1, 1, 1, K12, 0))


def test_from_rw_three_masses_layout():
    """N = 3 (Sec. II.C, Eq. e.N3): masses (m1, m2, m1) joined by K12 twice; r = 1, w = 2/3 -> m1 = 3/2."""
    chain = Chain.from_rw(3, 1.0, 2 / 3)
    assert_masses_springs(chain, (F(3, 2), 1, F(3, 2)), (0, 1, 1, 0))


def test_from_xyz_values_bounded():
    """Eq. e.mKxyz with (x, y, z) = (1/2, 1, 1/2): m2 = 1, m1 = 4, K12 = 1, K01 = 4 (3/2 - 1/4) = 5."""
    chain = Chain.from_xyz(6, 0.5, 1.0, 0.5)
    assert_masses_springs(chain, (4, 1, 1, 1, 1, 4), (5, 1, 1, 1, 1, 1, 5))
    # Eq. e.xyz read back from the matrix B of Eq. e.BN: B11 = 2 - z, B12 = -x.
    B11 = (chain.springs[0] + chain.springs[1]) / chain.masses[0]
    assert B11 == pytest.approx(2 - 0.5, rel=RTOL_ARITHMETIC)
    assert chain.springs[1] / math.sqrt(chain.masses[0] * chain.masses[1]) == pytest.approx(0.5, rel=RTOL_ARITHMETIC)


def test_from_xyz_values_general_y():
    """Eq. e.mKxyz with x = 1/2, y^2 = 1/2 (r = 3/2), z = 0: m2 = 2, m1 = 18, K12 = 3, K01 = 12 (3 - 1/4) = 33."""
    chain = Chain.from_xyz(5, 0.5, math.sqrt(0.5), 0.0)
    assert_masses_springs(chain, (18, 2, 1, 2, 18), (33, 3, 1, 1, 3, 33))
    # the constraint A_22 = 0 of Eq. e.xyz: (K12 + 1) / m2 = 2
    assert (chain.springs[1] + 1) / chain.masses[1] == pytest.approx(2.0, rel=RTOL_ARITHMETIC)


@pytest.mark.parametrize("x, y", [(0.3, 0.7), (0.5, 1.2), (0.9, 1.1), (0.7, 0.9), (1.3, 0.4), (0.1, 1.3)])
def test_from_xyz_at_z0_has_free_ends(x, y):
    """Sec. II.A: z = z0 = 2 - x^2/(2 - y^2) makes K01 vanish: the chain is free (Eq. e.z0)."""
    z0 = 2 - x * x / (2 - y * y)
    chain = Chain.from_xyz(8, x, y, z0)
    assert chain.springs[0] == 0.0 and chain.springs[-1] == 0.0, chain.springs[[0, -1]]
    assert chain.is_free
    r, w = chain.rw()
    assert (r, w) == pytest.approx((2 - y * y, x * x / (2 - y * y)), abs=ATOL_ROUND_TRIP)


def test_one_mass_values():
    """Eq. e.m1x: m1 = m_N = 1/x^2, everything else uniform, free ends; x = 1/2 -> m1 = 4."""
    chain = Chain.one_mass(6, 0.5)
    assert_masses_springs(chain, (4, 1, 1, 1, 1, 4), (0, 1, 1, 1, 1, 1, 0))
    assert chain.rw() == pytest.approx((1.0, 0.25), abs=ATOL_ROUND_TRIP)


def test_uniform_chains():
    """Sec. II.A: uniform free has K01 = 0, uniform bounded has wall springs K01 = 1."""
    free = Chain.uniform_free(6)
    bounded = Chain.uniform_bounded(6)
    assert_masses_springs(free, [1] * 6, [0, 1, 1, 1, 1, 1, 0])
    assert_masses_springs(bounded, [1] * 6, [1] * 7)
    assert free.is_free and free.free_ends == (True, True)
    assert not bounded.is_free and bounded.free_ends == (False, False)


def test_uniform_chains_xyz():
    """Sec. II.A: uniform-free is (x, y, z) = (1, 1, 1), uniform-bounded (1, 1, 0); r = w = 1 (Eq. e.rw)."""
    assert Chain.uniform_free(7).xyz() == pytest.approx((1.0, 1.0, 1.0), abs=ATOL_ROUND_TRIP)
    assert Chain.uniform_bounded(7).xyz() == pytest.approx((1.0, 1.0, 0.0), abs=ATOL_ROUND_TRIP)
    assert Chain.uniform_free(7).rw() == pytest.approx((1.0, 1.0), abs=ATOL_ROUND_TRIP)
    # the same from the masses and springs alone (no stored parameters)
    assert Chain(np.ones(7), Chain.uniform_free(7).springs).xyz() == pytest.approx((1, 1, 1), abs=ATOL_ROUND_TRIP)
    assert Chain(np.ones(7), np.ones(8)).xyz() == pytest.approx((1, 1, 0), abs=ATOL_ROUND_TRIP)


def test_two_mass_is_from_rw():
    assert Chain.two_mass(9, 0.5873, 0.0972) == Chain.from_rw(9, 0.5873, 0.0972)


# ------------------------------------------------------------------ round trips
XYZ_CASES = [
    (3, 0.8, 1.0, 0.2),  # N = 3 needs y = 1
    (4, 0.6, 1.1, -0.5),
    (5, 0.5, 0.8, 1.0),
    (12, 1.2, 0.3, -3.0),
    (12, 0.2, 1.35, 1.5),
]
RW_CASES = [(3, 1.0, 2 / 3), (4, 10 / 11, 6 / 11), (5, 0.9151, 0.5024), (100, 0.5873, 0.0972), (1000, 0.3496, 0.0232)]


@pytest.mark.parametrize("N, x, y, z", XYZ_CASES)
def test_xyz_round_trip(N, x, y, z):
    """from_xyz -> xyz(), and xyz() recomputed from masses and springs only (Eq. e.xyz)."""
    chain = Chain.from_xyz(N, x, y, z)
    assert chain.xyz() == pytest.approx((x, y, z), abs=ATOL_ROUND_TRIP)
    bare = Chain(np.array(chain.masses), np.array(chain.springs))
    assert bare == chain
    assert bare.is_quasi_uniform()
    assert bare.xyz() == pytest.approx((x, y, z), abs=ATOL_ROUND_TRIP)


@pytest.mark.parametrize("N, r, w", RW_CASES)
def test_rw_round_trip(N, r, w):
    """from_rw -> rw() and xyz(), and both recomputed from masses and springs only (Eq. e.rw)."""
    chain = Chain.from_rw(N, r, w)
    expected_xyz = (math.sqrt(r * w), math.sqrt(2 - r), 2 - w)  # Eq. e.rw, z = z0 (Eq. e.z0)
    assert chain.rw() == pytest.approx((r, w), abs=ATOL_ROUND_TRIP)
    assert chain.xyz() == pytest.approx(expected_xyz, abs=ATOL_ROUND_TRIP)
    bare = Chain(list(chain.masses), list(chain.springs))
    assert bare.rw() == pytest.approx((r, w), abs=ATOL_ROUND_TRIP)
    assert bare.xyz() == pytest.approx(expected_xyz, abs=ATOL_ROUND_TRIP)


def test_rw_view_needs_free_ends():
    with raises_naming("chain", "'uniform-bounded'"):
        Chain.uniform_bounded(6).rw()
    with raises_naming("chain", "'custom'"):
        Chain(np.ones(6), np.ones(7)).rw()


# --------------------------------------------------------------- perfect chains
def test_perfect_three():
    """Sec. II.C, Eq. e.N3: masses (3/2, 1, 3/2) ~ (3, 2, 3), springs (1, 1), free ends; x^2 = 2/3."""
    chain = Chain.perfect(3)
    assert_masses_springs(chain, (F(3, 2), 1, F(3, 2)), (0, 1, 1, 0))
    np.testing.assert_allclose(chain.masses / chain.masses[1] * 2, [3, 2, 3], rtol=RTOL_ARITHMETIC)
    assert chain.is_quasi_uniform()
    # x^2 = 1/m1 = 2/3, y = 1, z = z0 = 2 - x^2 = 4/3 (B11 = x^2 in Eq. e.N3)
    assert chain.xyz() == pytest.approx((math.sqrt(2 / 3), 1.0, 4 / 3), abs=ATOL_ROUND_TRIP)
    assert chain.rw() == pytest.approx((1.0, 2 / 3), abs=ATOL_ROUND_TRIP)


def test_perfect_four():
    """Sec. II.C: m1 = 55/36, m2 = 11/12, K12 = 5/6; masses ~ (5,3,3,5), springs ~ (5,6,5); r = 10/11, w = 6/11."""
    chain = Chain.perfect(4)
    m1, m2, K12 = F(55, 36), F(11, 12), F(5, 6)
    assert_masses_springs(chain, (m1, m2, m2, m1), (0, K12, 1, K12, 0))
    np.testing.assert_allclose(chain.masses / chain.masses[1] * 3, [5, 3, 3, 5], rtol=RTOL_ARITHMETIC)
    np.testing.assert_allclose(chain.springs[1:-1] / chain.springs[1] * 5, [5, 6, 5], rtol=RTOL_ARITHMETIC)
    from_rw = Chain.from_rw(4, 10 / 11, 6 / 11)
    np.testing.assert_allclose(chain.masses, from_rw.masses, rtol=RTOL_ARITHMETIC)
    np.testing.assert_allclose(chain.springs, from_rw.springs, rtol=RTOL_ARITHMETIC)
    assert chain.rw() == pytest.approx((10 / 11, 6 / 11), abs=ATOL_ROUND_TRIP)
    # y^2 = 12/11, x = sqrt(60)/11 (Sec. II.C)
    assert chain.xyz() == pytest.approx((math.sqrt(60) / 11, math.sqrt(12 / 11), 2 - 6 / 11), abs=ATOL_ROUND_TRIP)


def test_perfect_five_is_not_quasi_uniform():
    """Eq. e.N5: (35/18, 10/9, 1, 10/9, 35/18), K12 = 7/9; A_22 = (K12+1)/m2 = 8/5 != 2, outside Eq. e.xyz."""
    chain = Chain.perfect(5)
    m1, m2, K12 = F(35, 18), F(10, 9), F(7, 9)
    assert_masses_springs(chain, (m1, m2, 1, m2, m1), (0, K12, 1, 1, K12, 0))
    assert chain.is_symmetric and chain.is_free
    assert not chain.is_quasi_uniform()
    with pytest.raises(ParameterError, match=r"^chain = 'perfect' is not allowed: expected .*quasi-uniform"):
        chain.xyz()
    with pytest.raises(ParameterError, match=r"chain = 'perfect'"):
        chain.rw()


@pytest.mark.parametrize("N", [2, 6, 0, 4.5, "4", True])
def test_perfect_other_sizes_rejected(N):
    with pytest.raises(ParameterError, match=rf"^N = {re.escape(repr(N))} is not allowed: expected 3, 4 or 5"):
        Chain.perfect(N)


# ----------------------------------------------------------------- immutability
def test_attributes_cannot_be_assigned():
    chain = Chain.from_rw(6, 0.5, 0.25)
    with pytest.raises(dataclasses.FrozenInstanceError):
        chain.masses = np.ones(6)
    with pytest.raises(dataclasses.FrozenInstanceError):
        chain.name = "other"


def test_arrays_are_read_only_and_copied():
    source_m = np.array([1.5, 1.0, 1.5])
    source_k = np.array([0.0, 1.0, 1.0, 0.0])
    chain = Chain(source_m, source_k)
    assert not chain.masses.flags.writeable and not chain.springs.flags.writeable
    with pytest.raises(ValueError, match="read-only"):
        chain.masses[0] = 2.0
    with pytest.raises(ValueError, match="read-only"):
        chain.springs[1] = 2.0
    source_m[0] = 99.0  # the caller's array is not shared
    source_k[0] = 99.0
    assert chain.masses[0] == 1.5 and chain.springs[0] == 0.0


def test_equality_and_hash():
    a = Chain.from_rw(6, 0.5, 0.25)
    b = Chain(list(a.masses), list(a.springs), name="another label")
    c = Chain.from_rw(6, 0.5, 0.26)
    assert a == b and hash(a) == hash(b)
    assert a != c
    assert len({a, b, c}) == 2
    assert a != "not a chain"
    assert Chain.perfect(4) == Chain.perfect(4) and hash(Chain.perfect(4)) == hash(Chain.perfect(4))


def test_equal_chains_hash_equal_with_signed_zero_wall():
    """Python's rule: a == b implies hash(a) == hash(b); a free end written -0.0 (e.g. from JSON) is still 0."""
    a = Chain([1.0, 1.0, 1.0], [0.0, 1.0, 1.0, 0.0])
    b = Chain([1.0, 1.0, 1.0], [-0.0, 1.0, 1.0, 0.0])
    assert b.is_free
    assert a == b
    assert hash(a) == hash(b)
    assert len({a, b}) == 1


# ------------------------------------------------------------------- bad input
def test_too_few_masses():
    with raises_naming("N", "2"):
        Chain([1.0, 1.0], [0.0, 1.0, 0.0])
    with raises_naming("N", "2"):
        Chain.from_rw(2, 1.0, 1.0)
    with raises_naming("N", "2"):
        Chain.uniform_free(2)
    with raises_naming("N", "2"):
        Chain.from_xyz(2, 1.0, 1.0, 0.0)
    with raises_naming("N", "2.5"):
        Chain.one_mass(2.5, 0.5)


@pytest.mark.parametrize(
    "masses, field, shown",
    [
        ([1.0, 0.0, 1.0], "masses[1]", "0.0"),
        ([1.0, 1.0, -2.0], "masses[2]", "-2.0"),
        ([float("nan"), 1.0, 1.0], "masses[0]", "nan"),
        ([1.0, float("inf"), 1.0, 1.0], "masses[1]", "inf"),
    ],
)
def test_bad_masses(masses, field, shown):
    springs = [0.0] + [1.0] * (len(masses) - 1) + [0.0]
    with raises_naming(field, shown):
        Chain(masses, springs)


@pytest.mark.parametrize(
    "springs, field, shown, allowed",
    [
        ([-0.5, 1.0, 1.0, 0.0], "springs[0]", "-0.5", ">= 0"),
        ([0.0, 1.0, 1.0, -1e-3], "springs[3]", "-0.001", ">= 0"),
        ([0.0, 1.0, 0.0, 0.0], "springs[2]", "0.0", "> 0"),
        ([0.0, float("nan"), 1.0, 0.0], "springs[1]", "nan", "finite"),
    ],
)
def test_bad_springs(springs, field, shown, allowed):
    with pytest.raises(ParameterError) as info:
        Chain([1.0, 1.0, 1.0], springs)
    assert info.value.field == field
    message = str(info.value)
    assert message.startswith(f"{field} = {shown} is not allowed: expected ")
    assert allowed in message


def test_wrong_number_of_springs():
    with pytest.raises(ParameterError, match=r"^springs = '3 values' is not allowed: expected N\+1 = 5 values"):
        Chain([1.0, 1.0, 1.0, 1.0], [0.0, 1.0, 0.0])
    with pytest.raises(ParameterError, match=r"^springs = "):
        Chain([1.0, 1.0, 1.0], [[0.0, 1.0], [1.0, 0.0]])


@pytest.mark.parametrize(
    "r, w, field, shown",
    [
        (0.0, 0.5, "r", "0.0"),
        (-0.1, 0.5, "r", "-0.1"),
        (2.0, 0.5, "r", "2.0"),
        (2.5, 0.5, "r", "2.5"),
        (0.5, 0.0, "w", "0.0"),
        (0.5, -1.0, "w", "-1.0"),
        (float("nan"), 0.5, "r", "nan"),
        (0.5, float("inf"), "w", "inf"),
    ],
)
def test_bad_rw(r, w, field, shown):
    with raises_naming(field, shown):
        Chain.from_rw(10, r, w)


def test_three_masses_need_r_equal_one():
    """Sec. II.C / Eq. e.N3: for N = 3 the constrained model fixes y = 1 (r = 1)."""
    with raises_naming("r", "0.9"):
        Chain.from_rw(3, 0.9, 0.5)
    with raises_naming("y", "1.1"):
        Chain.from_xyz(3, 0.5, 1.1, 1.0)


@pytest.mark.parametrize("x, shown", [(0.0, "0.0"), (-0.3, "-0.3"), (math.sqrt(2), repr(math.sqrt(2))), (1.5, "1.5")])
def test_one_mass_x_range(x, shown):
    with raises_naming("x", shown):
        Chain.one_mass(10, x)


@pytest.mark.parametrize(
    "x, y, z, field, shown",
    [
        (0.0, 1.0, 0.0, "x", "0.0"),
        (-1.0, 1.0, 0.0, "x", "-1.0"),
        (1.0, 0.0, 0.0, "y", "0.0"),
        (1.0, math.sqrt(2), 0.0, "y", repr(math.sqrt(2))),
        (1.0, -0.5, 0.0, "y", "-0.5"),
        (1.0, 1.0, 1.01, "z", "1.01"),  # z0 = 2 - 1/1 = 1
        (0.5, 1.2, 2.0, "z", "2.0"),
        (float("nan"), 1.0, 0.0, "x", "nan"),
    ],
)
def test_bad_xyz(x, y, z, field, shown):
    with raises_naming(field, shown):
        Chain.from_xyz(10, x, y, z)


def test_z_limit_message_names_z0():
    """Sec. II.A: z <= z0 = 2 - x^2/(2 - y^2); for x = y = 1, z0 = 1."""
    with pytest.raises(ParameterError, match=r"z0 = 2 - x\^2/\(2-y\^2\) = 1\.0"):
        Chain.from_xyz(6, 1.0, 1.0, 1.5)


def test_require_symmetric():
    asymmetric = Chain([1.0, 2.0, 3.0, 4.0], [0.0, 1.0, 1.0, 1.0, 0.0])
    assert not asymmetric.is_symmetric
    with pytest.raises(ParameterError, match=r"^chain = .*masses\[0\]=1\.0, masses\[-1\]=4\.0.* mirror-symmetric"):
        asymmetric.require_symmetric()
    Chain.from_rw(6, 0.5, 0.25).require_symmetric()  # does not raise
    assert not asymmetric.is_quasi_uniform()


# --------------------------------------------------------------------- dicts
def test_dict_round_trip():
    for chain in (Chain.from_rw(7, 0.5873, 0.0972), Chain.uniform_bounded(4), Chain.perfect(5)):
        data = chain.to_dict()
        assert set(data) == {"masses", "springs"}
        assert all(type(v) is float for v in data["masses"] + data["springs"])
        back = Chain.from_dict(data)
        assert back == chain
        np.testing.assert_array_equal(back.masses, chain.masses)
        np.testing.assert_array_equal(back.springs, chain.springs)


def test_from_dict_accepts_asymmetric_chain_and_name():
    data = {"masses": [1.0, 2, 0.5, 3.0], "springs": [0.25, 1.0, 2.0, 0.5, 0], "name": "lab"}
    chain = Chain.from_dict(data)
    assert chain.name == "lab"
    assert not chain.is_symmetric
    np.testing.assert_array_equal(chain.masses, [1.0, 2.0, 0.5, 3.0])
    assert chain.to_dict() == {"masses": [1.0, 2.0, 0.5, 3.0], "springs": [0.25, 1.0, 2.0, 0.5, 0.0]}


@pytest.mark.parametrize(
    "data, pattern",
    [
        ({"masses": [1, 1, 1], "springs": [0, 1, 1, 0], "mass": [1]}, r"^scene\.json: mass = \[1\] is not allowed: expected only the keys"),
        ({"masses": (1, 1, 1), "springs": [0, 1, 1, 0]}, r"^scene\.json: masses = \(1, 1, 1\) is not allowed: expected a list"),
        ({"masses": [1, 1, 1], "springs": "0 1 1 0"}, r"^scene\.json: springs = '0 1 1 0' is not allowed: expected a list"),
        ({"masses": ["1", 1, 1], "springs": [0, 1, 1, 0]}, r"^scene\.json: masses = \['1', 1, 1\] is not allowed"),
        ({"masses": [True, 1, 1], "springs": [0, 1, 1, 0]}, r"^scene\.json: masses = \[True, 1, 1\] is not allowed"),
        ({"masses": [1, 1, 1]}, r"^scene\.json: springs = None is not allowed"),
        ([[1, 1, 1], [0, 1, 1, 0]], r"^scene\.json: chain = 'list' is not allowed: expected an object"),
        ({"masses": [1, -1, 1], "springs": [0, 1, 1, 0]}, r"^scene\.json: masses\[1\] = -1\.0 is not allowed"),
    ],
)
def test_from_dict_rejects(data, pattern):
    with pytest.raises(ParameterError, match=pattern):
        Chain.from_dict(data, where="scene.json")


def test_error_is_a_value_error_with_fields():
    with pytest.raises(ValueError) as info:
        Chain.from_rw(10, 3.0, 0.5)
    error = info.value
    assert isinstance(error, ParameterError)
    assert (error.field, error.value) == ("r", 3.0)
    assert "0 < r < 2" in error.allowed
