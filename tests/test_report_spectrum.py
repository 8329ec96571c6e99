"""The validation report's section "the spectrum in the circuit" (issue 21, section 2): real ngspice AC runs of
the reference ladders, their tables, Figs. Pk20-100 and vk with the circuit's points (checked on the drawn
artists), and a check made to fail through its tolerances."""

from __future__ import annotations

import dataclasses
import math
import pickle
import re

import numpy as np
import pytest
from helpers.figures import assert_legends_off_lines
from helpers.tolerances import ATOL_GROUP_VELOCITY, ATOL_NO_FLOOR, ATOL_PLOTTED, RTOL_PLOTTED, RTOL_RECOMPUTED_ERROR

from lcchain.core.errors import ParameterError
from lcchain.report.figure_data import DesignRows
from lcchain.report.html import render_html
from lcchain.report.spectrum import PER_MODE_CHECK, spectrum_figures, spectrum_html
from lcchain.studies.background import Background, Job
from lcchain.studies.spectrum_checks import (
    VK_DELTAS,
    SpectrumCheck,
    SpectrumTolerances,
    run_spectrum_check,
    spectrum_checks,
    spectrum_jobs,
)

pytestmark = pytest.mark.ngspice


@pytest.fixture(scope="module")
def checks() -> list[SpectrumCheck]:
    return spectrum_checks(spectrum_jobs())


@pytest.fixture(scope="module")
def figures(checks: list[SpectrumCheck]) -> dict:
    return spectrum_figures(checks, DesignRows())


def _by_name(checks: list[SpectrumCheck], name: str) -> SpectrumCheck:
    return next(check for check in checks if check.name == name)


def test_the_jobs_cover_the_issues_circuits_and_pickle() -> None:
    jobs = spectrum_jobs()
    names = [job.name for job in jobs]
    assert {"two-mass-N20", "two-mass-N100", "perfect-N50", "perfect-N50-walls", "two-mass-N50-walls",
            "two-mass-N20-losses"} <= set(names)
    assert sorted(job.panel for job in jobs if job.figure == "vk") == sorted(VK_DELTAS)
    assert {job.panel for job in jobs if job.figure == "Pk20-100"} == {20, 100}
    quick = [job.name for job in spectrum_jobs(quick=True)]
    assert set(quick) < set(names) and {"two-mass-N20", "two-mass-N100"} <= set(quick)
    for job in jobs:  # the report's pool sends them to other processes
        assert pickle.loads(pickle.dumps(job)).name == job.name


def test_every_spectrum_passes_within_its_stated_tolerances(checks: list[SpectrumCheck]) -> None:
    for check in checks:
        assert check.passed, (check.name, check.errors, check.reason)
        assert len(check.modes) == check.N
        for key, error in check.errors.items():
            assert error is not None and error <= check.tolerances[key], (check.name, key)
        # the errors are those of the modes listed: recomputed here from the circuit's and the theory's values (the
        # theory's rest beyond float64 subtracted after the float64 difference, exact this close)
        resolved = [m for m in check.modes if m["resolved"]]
        omega = max(abs((m["omega"] - m["omega_theory"]) - m["omega_theory_low"]) / (m["omega_theory"] or 1.0)
                    for m in resolved)
        assert omega == pytest.approx(check.errors["omega"], rel=RTOL_RECOMPUTED_ERROR, abs=ATOL_NO_FLOOR)
        P = max(abs((m["P"] or 0.0) - m["P_theory"]) for m in check.modes)
        assert P == pytest.approx(check.errors["P"], rel=RTOL_RECOMPUTED_ERROR, abs=ATOL_NO_FLOOR)
        assert ("Q" in check.errors) == ("losses" in check.name)  # each mode's Q_n, for the lossy ladder only
        assert check.wall_s is not None and check.points and check.points >= check.N
    walls = _by_name(checks, "two-mass-N50-walls")
    assert walls.modes[0]["omega_theory"] > 0  # tied to walls: no zero mode
    assert _by_name(checks, "two-mass-N20").modes[0]["omega_theory"] == 0.0


def test_the_section_holds_the_circuits_values_beside_theory(checks: list[SpectrumCheck], figures: dict) -> None:
    page = spectrum_html(checks, {f"spectrum:{label}": b"png" for label in figures})
    summary = page[:page.index('id="spectrum-modes"')]
    for check in checks:
        assert f"<td class=l>{check.name}</td>" in summary
    assert summary.count('class="pass">passed') == len(checks) and "FAILED" not in page
    per_mode = _by_name(checks, PER_MODE_CHECK)
    rows = re.findall(r"<tr><td>(\d+)</td>(.*?)</tr>", page[page.index('id="spectrum-modes"'):])
    assert [int(n) for n, _ in rows] == list(range(1, 21))
    for (_, cells), mode in zip(rows, per_mode.modes, strict=True):
        assert f"{mode['omega_theory']:.12f}" in cells and f"{mode['omega']:.12f}" in cells
        assert f"{mode['P_theory']:.12f}" in cells and f"{mode['P']:.12f}" in cells
    assert page.count("<figure") == 2 and 'alt="Fig. Pk20-100 with ngspice"' in page


def _circuit_lines(ax) -> list:
    return [line for line in ax.get_lines() if line.get_label().startswith("ngspice")
            or (line.get_markerfacecolor() == "none" and line.get_color() == "k")]


def test_fig_pk20_100_has_the_circuits_points_on_top(checks: list[SpectrumCheck], figures: dict) -> None:
    fig = figures["Pk20-100"]
    left, right = fig.axes
    P_lines, spacing_lines = _circuit_lines(left), _circuit_lines(right)
    assert len(P_lines) == len(spacing_lines) == 2  # N = 20 and N = 100
    for N, P_line, spacing_line in zip((20, 100), P_lines, spacing_lines, strict=True):
        modes = _by_name(checks, f"two-mass-N{N}").modes
        omega = np.array([m["omega"] for m in modes])
        k = 2 * np.arcsin(omega / 2)  # Eq. e.omegak
        np.testing.assert_allclose(P_line.get_xdata(), k, rtol=RTOL_PLOTTED, atol=ATOL_PLOTTED)
        np.testing.assert_allclose(P_line.get_ydata(), N * np.abs([m["P"] for m in modes]), rtol=RTOL_PLOTTED)
        np.testing.assert_allclose(spacing_line.get_ydata(), np.diff(omega) * N / math.pi, rtol=RTOL_PLOTTED)
        for line, theory in ((P_line, f"N P_n, N = {N}"), (spacing_line, f"(N/π) δω_n, N = {N}")):
            assert line.get_markerfacecolor() == "none" and line.get_linestyle() in ("None", "none", "")
            drawn = [other.get_label() for other in line.axes.get_lines()]
            assert drawn.index(line.get_label()) > drawn.index(theory)  # on top of the theory's symbols
    # named once in the legend, which stays off the data
    labels = [text.get_text() for text in left.get_legend().get_texts()]
    assert labels.count("ngspice (AC): N |P_n|") == 1 and labels.count("ngspice (AC): (N/π) δω_n") == 1
    assert_legends_off_lines(fig)


def test_fig_vk_has_the_circuits_group_velocity_in_every_panel(checks: list[SpectrumCheck], figures: dict) -> None:
    fig = figures["vk"]
    assert len(fig.axes) == len(VK_DELTAS)
    for ax, Delta in zip(fig.axes, VK_DELTAS, strict=True):
        lines = {line.get_label(): line for line in _circuit_lines(ax)}
        v = lines["ngspice (AC): (N/π) Δω_n"]
        omega = np.array([m["omega"] for m in _by_name(checks, f"one-mass-N50-Delta{Delta:g}").modes])
        k = 2 * np.arcsin(omega / 2)
        np.testing.assert_allclose(v.get_xdata(), (k[1:] + k[:-1]) / 2, rtol=RTOL_PLOTTED, atol=ATOL_PLOTTED)
        np.testing.assert_allclose(v.get_ydata(), np.diff(omega) * 50 / math.pi, rtol=RTOL_PLOTTED)
        # on the theory's curve v_k (Eq. e.vk) within the difference's O(1/N^2) (ATOL_GROUP_VELOCITY, as tests/test_figures.py)
        theory = next(line for line in ax.get_lines() if line.get_label() == "v_k")
        assert np.max(np.abs(v.get_ydata() - np.interp(v.get_xdata(), *theory.get_data()))) < ATOL_GROUP_VELOCITY
        assert "ngspice (AC): P_n" in lines
    legend = [text.get_text() for text in fig.legends[0].get_texts()]
    assert legend.count("ngspice (AC): (N/π) Δω_n") == 1
    assert_legends_off_lines(fig)


def test_a_tolerance_forced_tiny_fails_the_check_and_the_report(checks: list[SpectrumCheck]) -> None:
    job = next(job for job in spectrum_jobs(quick=True) if job.name == PER_MODE_CHECK)
    tiny = SpectrumTolerances(omega=1e-300, spacing=1e-300, P=1e-300)
    failed = run_spectrum_check(dataclasses.replace(job, tolerances=tiny))
    assert not failed.passed and not all(failed.verdicts().values())
    assert failed.tolerances == tiny.to_dict()
    lines = failed.checks()
    assert {line["kind"] for line in lines} == {"spectrum"} and not all(line["passed"] for line in lines)
    assert "FAILED" in spectrum_html([failed], {})
    report = {"title": "t", "created": "now", "lcchain_version": "0", "ngspice_version": "0",
              "machine": {"system": "", "release": "", "machine": "", "python": "", "numpy": ""}, "quick": True,
              "seconds": 1.0, "checks": lines, "circuit": [], "spectrum": [failed],
              "paper": {"tables": {}, "columns": {}, "asymptotic": [], "perfect": {"paper": [], "any_N": []},
                        "findings": []}}
    page = render_html(report, {}, [])
    failing = sum(not line["passed"] for line in lines)
    assert f"{failing} of {len(lines)} checks failed" in page and "spectrum two-mass-N20: " in page
    assert "0 / 1</b>spectra" in page


def test_a_spectrum_measured_by_the_pool_is_the_one_measured_here(checks: list[SpectrumCheck]) -> None:
    """The report runs the jobs in its pool (:class:`Background`): the same numbers, bit for bit (one BLAS thread
    in both, ngspice deterministic)."""
    jobs = [job for job in spectrum_jobs(quick=True) if job.N <= 50]
    with Background([Job(i, job.cost, run_spectrum_check, (job,)) for i, job in enumerate(jobs)], workers=2) as pool:
        assert pool.workers == 2
        pooled = [pool.take(i) for i in range(len(jobs))]
    for check in pooled:
        here = _by_name(checks, check.name)
        assert check.passed and (check.errors, check.modes, check.points) == (here.errors, here.modes, here.points)


def test_a_tolerance_must_be_positive() -> None:
    with pytest.raises(ParameterError, match="tolerances.P"):
        SpectrumTolerances(P=0.0)
