"""The data behind the paper's figures (issue 12): tested against the paper and against independent sums,
never against pixels; the figures' artists are checked against their captions (symbols, limits, splines)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from helpers.digits import agrees_with_printed
from helpers.tolerances import (
    ATOL_FIGURE_DENSITY,
    ATOL_FIGURE_DENSITY_SUM,
    ATOL_FLAT_SPACING,
    ATOL_GROUP_VELOCITY,
    ATOL_KICK_AT_ZERO,
    ATOL_LAW_ON_PLOT,
    ATOL_MINIMIZ_TAU,
    ATOL_MINIMIZ_TAU_QUICK,
    ATOL_MINIMUM_DELTA,
    ATOL_PERFECT,
    ATOL_PRINTED_ALPHA,
    ATOL_QUOTED_FLAT_DELTA,
    ATOL_THETA_RATIO,
    ATOL_WEIGHT_AREA,
    RTOL_CRADLE4_ARRIVAL,
    RTOL_CRADLE4_FRACTIONS,
    RTOL_CUBIC_COEFFICIENT,
    RTOL_GRID_POINT,
    RTOL_ONE_OPERATION,
    RTOL_POWER_LAW_FIT,
    RTOL_ROOT_RESIDUAL,
    RTOL_SPLINE_AT_POINTS,
    RTOL_THETA_RATIO,
    RTOL_W_OF_R_STAR,
)

from lcchain.report.figure_data import (
    DesignRows,
    cache_key,
    circuit_data,
    cradle4_data,
    int_rw_data,
    minimiz_data,
    optimum_data,
    pk_data,
    vk_data,
)
from lcchain.report.paper import PRINTED_ROWS
from lcchain.report.paper_figures import FIGURES, delta_from_optimum, make_figures
from lcchain.theory.asymptotic import asymptotic_optimum
from lcchain.theory.cases import chain_for_case
from lcchain.theory.chain import Chain
from lcchain.theory.design import optimal_one_mass
from lcchain.theory.spectrum import normal_modes

#: P_k of Eq. e.PkDelta at the modes' k_n against the closed-form modes' density: one formula evaluated
#: two ways, rounding only.
RTOL_DENSITY = 1e-10
#: The area under the integrand of Eq. e.uinftyz (trapezoid, 40001 points on [0, pi/2]) against lcchain's
#: contour integral: the rule misses the fastest oscillations near pi/2 (observed 3.2e-6).
ATOL_AREA = 1e-5


@pytest.fixture(scope="module")
def rows() -> DesignRows:
    return DesignRows()


def test_cradle4_is_the_perfect_chain_and_its_pulse_arrives_whole() -> None:
    data = cradle4_data(points_per_transit=200)
    assert data["masses"] == pytest.approx([5 / 3, 1, 1, 5 / 3], rel=RTOL_CRADLE4_FRACTIONS)
    assert data["springs"] == pytest.approx([0, 5 / 6, 1, 5 / 6, 0], rel=RTOL_CRADLE4_FRACTIONS)
    assert data["T"] == pytest.approx(math.sqrt(3) * math.pi, rel=RTOL_CRADLE4_ARRIVAL)
    v, t = data["velocities"], data["t"]
    np.testing.assert_allclose(v[:, 0], [1, 0, 0, 0], atol=ATOL_KICK_AT_ZERO)
    at_T = int(np.argmin(np.abs(t - data["T"])))
    assert t[at_T] == pytest.approx(data["T"], rel=RTOL_GRID_POINT)
    np.testing.assert_allclose(v[:, at_T], [0, 0, 0, 1], atol=ATOL_PERFECT)
    assert v[-1, at_T // 2] < 0.5  # and not before


def test_vk_panels() -> None:
    data = vk_data()
    assert [p["Delta"] for p in data["panels"]] == [0.30, 0.1395, 0.05]
    for panel in data["panels"]:
        Delta, N = panel["Delta"], data["N"]
        assert panel["P_n"].sum() == pytest.approx(1.0, abs=ATOL_FIGURE_DENSITY_SUM)
        k = panel["k_n"]
        tan2 = np.tan(k / 2) ** 2
        formula = Delta * (1 + Delta) / ((N * Delta + 1 - Delta) * Delta + (N - 1 + Delta) * tan2)
        formula[0] /= 2  # Eq. e.Pk's 1/(1 + delta_k0)
        np.testing.assert_allclose(panel["P_n"], formula, rtol=RTOL_DENSITY)
        v_at_mid = np.interp(panel["k_mid"], data["k"], panel["v"])
        np.testing.assert_allclose(panel["v_n"], v_at_mid, atol=ATOL_GROUP_VELOCITY)
    # the middle panel is Table I's optimum at N = 50 (the caption)
    assert agrees_with_printed(optimal_one_mass(50).Delta, "0.1395")


def test_optimum_data_holds_the_table_rows(rows: DesignRows) -> None:
    Ns = [3, 4, 5, 20, 100]
    data = optimum_data(rows, Ns)
    delta = delta_from_optimum(data)
    for case, column in (("one-mass", 1), ("two-mass", 2)):
        for N, value in zip(data["N"], delta[case], strict=True):
            assert agrees_with_printed(value, PRINTED_ROWS[case][N][column]), (case, N)
    for N, row in zip(data["N"], data["one-mass"], strict=True):
        assert agrees_with_printed(row["delta_uniform"], PRINTED_ROWS["one-mass"][N][5], 1)
    # Fig. rw: w(r*) is almost w* for N >= 20 (the quartic mode density)
    for N, row, w_of_r in zip(data["N"], data["two-mass"], data["w_of_r"], strict=True):
        if N >= 20:
            assert w_of_r == pytest.approx(row["w"], rel=RTOL_W_OF_R_STAR)
    assert data["asymptotes"]["two-mass"] == pytest.approx(asymptotic_optimum("two-mass").delta, rel=RTOL_ONE_OPERATION)
    c, p = data["laws"]["two-mass"]["r"]
    assert (c, p) == pytest.approx((4.387, -1 / 3), rel=RTOL_POWER_LAW_FIT)


def test_int_rw_area_is_the_asymptotic_amplitude() -> None:
    data = int_rw_data(points=40001)
    names = [curve["name"] for curve in data["curves"]]
    assert names[0].startswith("linear and cubic") and names[1] == "optimum"
    # the pair that cancels both terms (the paper prints +2^(3/2)/3 for tau, a slip): tau = -2^(3/2)/3
    assert data["curves"][0]["tau"] == pytest.approx(-(2**1.5) / 3) and data["curves"][0]["sigma"] == pytest.approx(
        2**1.5)
    for curve in data["curves"]:
        area = np.trapezoid(curve["integrand"], data["zeta"])
        assert area == pytest.approx(curve["alpha"], abs=ATOL_AREA)
    assert np.trapezoid(data["weight"], data["zeta"]) == pytest.approx(1.0, abs=ATOL_WEIGHT_AREA)  # the weight's area
    assert data["curves"][1]["alpha"] == pytest.approx(0.987153, abs=ATOL_PRINTED_ALPHA)  # Sec. V.A


def _theta(tau: float, sigma: float, xi: np.ndarray) -> np.ndarray:
    """theta of Eq. e.uinftyz in xi = tan(zeta), written out here from the paper, not taken from lcchain."""
    return tau * xi**3 - sigma * xi + 2 * np.arctan(np.sqrt(2) * xi / (1 - xi**2))


def test_the_int_rw_pair_cancels_the_linear_and_cubic_terms() -> None:
    from lcchain.report.paper import PRINTED_INT_RW, cancelling_pair

    xi = np.array([1e-3, 2e-3, 4e-3])
    tau, sigma = cancelling_pair()
    # theta = O(xi^5) for the pair: theta / xi^5 stays bounded (its xi^5 coefficient) as xi halves
    ratio = _theta(tau, sigma, xi) / xi**5
    assert np.all(np.abs(ratio) < 10) and np.ptp(ratio) < RTOL_THETA_RATIO * max(1.0, float(np.abs(ratio).max())) + ATOL_THETA_RATIO
    # the printed pair leaves a cubic term 4 sqrt2 / 3
    printed = _theta(*PRINTED_INT_RW, xi) / xi**3
    assert printed == pytest.approx(4 * np.sqrt(2) / 3, rel=RTOL_CUBIC_COEFFICIENT)


def test_the_findings_hold_the_texts_slips() -> None:
    from lcchain.report.paper import findings, vk_flat_delta, vk_left_side
    from lcchain.theory.asymptotic import asymptotic_optimum

    optima = {case: asymptotic_optimum(case) for case in ("one-mass", "two-mass")}
    items = findings(optima, {})
    where = [item["where"] for item in items]
    assert any("Fig. int_rw" in w for w in where) and any("Eq. e.vgquartic" in w for w in where)
    assert any("sin(k_n/2)" in item["correct"] for item in items)
    assert vk_left_side(vk_flat_delta()) == pytest.approx(0.125, rel=RTOL_ROOT_RESIDUAL) and vk_flat_delta() == pytest.approx(
        0.325, abs=ATOL_QUOTED_FLAT_DELTA)  # the text's 0.30 gives 0.161
    inherited = next(item for item in items if "derived from τ*" in item["where"])
    assert "r 4.3868" in inherited["printed"] and "4.3871" in inherited["correct"]
    int_rw = next(item for item in items if "Fig. int_rw" in item["where"])
    assert "0.779356" in int_rw["correct"] and "0.653499" in int_rw["correct"]


def test_minimiz_has_its_minimum_at_the_optimum() -> None:
    optimum = asymptotic_optimum("two-mass")
    data = minimiz_data([2.8, optimum.sigma, 3.5])
    assert min(data["delta_m"]) == pytest.approx(optimum.delta, abs=ATOL_MINIMUM_DELTA)
    assert data["delta_m"][1] < data["delta_m"][0] and data["delta_m"][1] < data["delta_m"][2]
    assert data["tau_m"][1] == pytest.approx(optimum.tau, abs=ATOL_MINIMIZ_TAU)
    assert data["tau_m"][0] < data["tau_m"][1] < data["tau_m"][2]  # tau_m grows with sigma (the blue line)


def test_pk_densities_are_the_exact_ones(rows: DesignRows) -> None:
    data = pk_data(rows)
    assert [p["N"] for p in data["panels"]] == [20, 100]
    for panel in data["panels"]:
        assert panel["P"].sum() == pytest.approx(1.0, abs=ATOL_FIGURE_DENSITY_SUM)
        exact = normal_modes(Chain.from_rw(panel["N"], panel["r"], panel["w"]), method="exact")
        np.testing.assert_allclose(panel["P"], exact.density, atol=ATOL_FIGURE_DENSITY)
        assert panel["spacing"].size == panel["N"] - 1
    big = data["panels"][1]
    assert np.max(np.abs(big["spacing"][:10] - 0.95)) < ATOL_FLAT_SPACING  # flat near k = 0: the caption's point


def test_circuit_drawing_data_is_the_netlist() -> None:
    data = circuit_data("two-mass", 6)
    chain = chain_for_case("two-mass", 6)
    inductors = [e for e in data["elements"] if e["kind"] == "L"]
    capacitors = [e for e in data["elements"] if e["kind"] == "C"]
    assert len(inductors) == 6 and len(capacitors) == 5
    np.testing.assert_allclose([e["value"] for e in inductors], chain.masses * data["L0"], rtol=RTOL_ONE_OPERATION)
    np.testing.assert_allclose([e["value"] for e in capacitors], data["C0"] / chain.springs[1:-1], rtol=RTOL_ONE_OPERATION)
    # a ladder: inductor i joins node i-1 to node i; capacitor i, i+1 hangs from node i to ground
    assert inductors[0]["nodes"][0] == "0" and inductors[-1]["nodes"][1] == "0"
    for left, right in zip(inductors, inductors[1:], strict=False):
        assert left["nodes"][1] == right["nodes"][0]


def test_rows_are_cached_by_code_and_a_damaged_cache_is_recomputed(tmp_path) -> None:
    first = DesignRows(tmp_path)
    row = first.row("two-mass", 20)
    assert first.computed == 1
    again = DesignRows(tmp_path)
    assert again.row("two-mass", 20) == row and again.computed == 0
    (tmp_path / f"designs-{cache_key()}.json").write_text("{ not json")
    damaged = DesignRows(tmp_path)
    assert damaged.row("two-mass", 20)["r"] == row["r"] and damaged.computed == 1


def test_every_figure_is_written_under_its_label(tmp_path, rows: DesignRows) -> None:
    paths = make_figures(tmp_path / "figs", quick=True, fmt="svg", rows=rows)
    assert [p.name for p in paths] == [f"{f.label}.svg" for f in FIGURES]
    assert {f.label for f in FIGURES} == {"cradle4", "vk", "delta", "x_xy", "m_mmK", "int_rw", "minimiz", "rw",
                                          "Pk20-100", "LCcircuit"}
    for path in paths:
        assert path.stat().st_size > 10_000
        assert "<svg" in path.read_text()[:2000]


# ------------------------------------------------------------------ the figures against their captions (issue 21)
#: Ns for the figures' checks: small ones (perfect chains at N = 3, 4) and a few large ones.
CAPTION_N = [3, 4, 5, 6, 8, 10, 20, 50, 100, 200]


def _marked(ax) -> list:
    """The axes' lines drawn as symbols only (no connecting line)."""
    return [line for line in ax.get_lines() if line.get_marker() not in ("None", "", None) and len(line.get_xdata())
            and line.get_linestyle() in ("None", "", " ")]


def _horizontal(ax) -> list[float]:
    """y of every horizontal line spanning the axes (axhline: x data in axes coordinates 0 .. 1)."""
    return [float(line.get_ydata()[0]) for line in ax.get_lines()
            if list(line.get_xdata()) == [0, 1] and len(set(map(float, line.get_ydata()))) == 1]


@pytest.fixture(scope="module")
def optimum(rows: DesignRows) -> dict:
    return optimum_data(rows, CAPTION_N)


def test_delta_has_the_three_limits_the_enlargements_and_splines(optimum: dict) -> None:
    from lcchain.report.paper_figures import DELTA_ENLARGE, paper_delta_figure

    data = delta_from_optimum(optimum)
    ax = paper_delta_figure(data).axes[0]
    limits = _horizontal(ax)
    # the caption's three limits: 1 (uniform chain), 0.1531 (one mass), 0.01285 (two masses), each dotted
    for printed in ("1", "0.1531", "0.01285"):
        assert any(agrees_with_printed(y, printed) for y in limits), (printed, limits)
    N = np.asarray(data["N"], dtype=float)
    marked = _marked(ax)
    for case in ("uniform", "one-mass", "two-mass"):
        values = np.asarray(data[case])
        filled = [m for m in marked if np.allclose(m.get_ydata(), values) and m.get_markerfacecolor() != "none"]
        assert filled, case
        # a spline through the points: the same colour, many points, from the first N to the last, never beyond
        colour = filled[0].get_color()
        curves = [line for line in ax.get_lines() if line.get_color() == colour and line.get_marker() in ("None", "")
                  and len(line.get_xdata()) > 10 * N.size]
        assert curves, case
        curve = curves[0]
        xs, ys = np.asarray(curve.get_xdata()), np.asarray(curve.get_ydata())
        assert xs.min() == pytest.approx(N.min()) and xs.max() == pytest.approx(N.max())
        np.testing.assert_allclose(np.interp(np.log(N), np.log(xs), ys), values, atol=RTOL_SPLINE_AT_POINTS * values.max())
    for case, factor in DELTA_ENLARGE.items():  # the open symbols: the optimised cases enlarged
        values = factor * np.asarray(data[case])
        assert any(np.allclose(m.get_ydata(), values) and m.get_markerfacecolor() == "none" for m in marked), case


def test_x_xy_draws_y_star_as_red_circles(optimum: dict) -> None:
    from lcchain.report.paper_figures import x_xy_figure

    ax = x_xy_figure(optimum).axes[0]
    marked = _marked(ax)
    for case, key, marker in (("one-mass", "x", "s"), ("two-mass", "x", "o"), ("two-mass", "y", "o")):
        values = [row[key] for row in optimum[case]]
        lines = [m for m in marked if np.allclose(m.get_ydata(), values)]
        assert lines and lines[0].get_marker() == marker, (case, key)


def test_m_mmK_draws_the_two_mass_case_as_circles(optimum: dict) -> None:
    from lcchain.report.paper_figures import m_mmK_figure

    ax = m_mmK_figure(optimum).axes[0]
    marked = _marked(ax)
    for key in ("m1", "m2", "K12"):
        values = [row[key] for row in optimum["two-mass"]]
        assert any(np.allclose(m.get_ydata(), values) and m.get_marker() == "o" for m in marked), key


@pytest.mark.parametrize("name", ["x_xy_figure", "m_mmK_figure", "rw_figure"])
def test_the_laws_stay_inside_the_frame_the_data_set(optimum: dict, name: str) -> None:
    import copy

    from lcchain.report import paper_figures

    build = getattr(paper_figures, name)

    def laws_and_limits(data: dict) -> tuple[list[np.ndarray], tuple[float, float]]:
        ax = build(data).axes[0]
        laws = [np.asarray(line.get_ydata(), dtype=float) for line in ax.get_lines()
                if line.get_marker() in ("None", "") and len(line.get_xdata()) > 50]
        return laws, ax.get_ylim()

    laws, limits = laws_and_limits(optimum)
    assert laws
    for law in laws:
        finite = law[np.isfinite(law)]
        assert finite.size and np.all((finite >= limits[0]) & (finite <= limits[1]))
    marked = np.concatenate([np.asarray(m.get_ydata(), float) for m in _marked(build(optimum).axes[0])])
    marked = marked[np.isfinite(marked)]
    assert limits[0] <= marked.min() and marked.max() <= limits[1]
    # the laws do not set the frame: laws ten times larger leave the limits as they were, and are cut
    stretched = copy.deepcopy(optimum)
    for case in stretched["laws"]:
        stretched["laws"][case] = {key: (10 * c, p) for key, (c, p) in stretched["laws"][case].items()}
    laws, again = laws_and_limits(stretched)
    assert again == pytest.approx(limits)
    for law in laws:
        finite = law[np.isfinite(law)]
        assert np.all((finite >= limits[0]) & (finite <= limits[1]))


def test_x_xy_laws_are_not_drawn_at_N_3_where_they_leave_the_frame(optimum: dict) -> None:
    from lcchain.report.paper_figures import x_xy_figure

    ax = x_xy_figure(optimum).axes[0]
    c, p = optimum["laws"]["two-mass"]["x"]
    assert c * 3.0**p > ax.get_ylim()[1]  # the two-mass x* law at N = 3 is above the data's frame ...
    laws = [line for line in ax.get_lines() if line.get_marker() in ("None", "") and len(line.get_xdata()) > 50]
    law = next(line for line in laws if np.nanmax(np.abs(np.asarray(line.get_ydata()) - c * np.asarray(
        line.get_xdata()) ** p)) < ATOL_LAW_ON_PLOT)
    assert np.isnan(law.get_ydata()[0])  # ... so it is not drawn there


def test_cradle4_has_the_auxiliary_green_masses() -> None:
    from matplotlib.colors import to_rgb
    from matplotlib.patches import Rectangle

    from lcchain.report.paper_figures import cradle4_figure

    data = cradle4_data(points_per_transit=50)
    fig = cradle4_figure(data)
    scheme = next(ax for ax in fig.axes if any(isinstance(p, Rectangle) for p in ax.patches))
    blocks = sorted((p for p in scheme.patches if isinstance(p, Rectangle)), key=lambda p: p.get_x())
    assert len(blocks) == len(data["masses"]) + 2  # the chain and one auxiliary mass at each end
    for block in (blocks[0], blocks[-1]):
        r, g, b = to_rgb(block.get_facecolor())
        assert g > r and g > b, "the auxiliary masses are green"
        # equal to the end masses: the same block (area proportional to the mass)
        assert block.get_width() == pytest.approx(blocks[1].get_width())
    for block in blocks[1:-1]:
        r, g, b = to_rgb(block.get_facecolor())
        assert not (g > r and g > b)


def test_minimiz_quick_and_full_agree_and_find_the_boundary_minimum() -> None:
    from lcchain.report.figure_data import JUMP_XTOL
    from lcchain.theory.asymptotic import asymptotic_amplitude

    sigmas = [2.0, 2.3, 2.45, 3.0, 4.0]
    quick, full = minimiz_data(sigmas, quick=True), minimiz_data(sigmas, quick=False)
    for s in sigmas:
        i, j = quick["sigma"].index(s), full["sigma"].index(s)
        assert quick["tau_m"][i] == pytest.approx(full["tau_m"][j], abs=ATOL_MINIMIZ_TAU_QUICK), s
        assert quick["delta_m"][i] == pytest.approx(full["delta_m"][j], abs=ATOL_MINIMUM_DELTA), s
    # one jump (the minimum leaves tau = 0) between 2.3 and 2.45, found at the same sigma by both
    assert len(quick["jumps"]) == len(full["jumps"]) == 1
    assert quick["jumps"][0][0] == pytest.approx(full["jumps"][0][0], abs=2 * JUMP_XTOL)
    assert 2.3 < quick["jumps"][0][0] < 2.45
    # at sigma = 2.3 no tau >= 0 of a dense grid does better than tau_m (the old quick grid drew 0.0097)
    i = quick["sigma"].index(2.3)
    taus = np.concatenate(([0.0], np.geomspace(1e-4, 1.5, 300)))
    brute = min(1 - asymptotic_amplitude(float(t), 2.3) for t in taus)
    assert quick["delta_m"][i] <= brute + 1e-12
    assert quick["tau_m"][i] == 0.0


def test_minimiz_breaks_the_blue_line_at_the_jump() -> None:
    from lcchain.report.paper_figures import minimiz_figure

    data = minimiz_data([2.2, 2.3, 2.45, 2.6], quick=True)
    ax = minimiz_figure(data).axes[0]
    blue = max(ax.get_lines(), key=lambda line: len(line.get_xdata()))
    assert np.isnan(np.asarray(blue.get_ydata(), dtype=float)).sum() == len(data["jumps"]) == 1
