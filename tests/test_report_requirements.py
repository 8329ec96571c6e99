"""The validation report's section "How good must the parts be" (issue 30, item 4): a cradle's study run as the
report runs it (real ngspice), then its table, chart and points checked against the study's own results
(:func:`lcchain.circuit.requirements.requirement` and :func:`lcchain.studies.requirements.check_points`)."""

from __future__ import annotations

import dataclasses
import math
import pickle
import re

import pytest

from lcchain.circuit.ladder import Ladder
from lcchain.circuit.requirements import LOSS_TARGETS, PARTS, first_arrival_energy, requirement, si
from lcchain.core.errors import ParameterError
from lcchain.report.html import render_html, report_json
from lcchain.report.requirements import bulk_limit, requirements_figures, requirements_html, requirements_summary
from lcchain.studies.background import Background, Job
from lcchain.studies.requirements import (
    QUICK_GRID_POINTS,
    QUICK_REPORT_CHECKS,
    REPORT_CHECKS,
    CheckPoint,
    RequirementsCheck,
    point_agrees,
    requirements_estimate,
    requirements_jobs,
    run_requirements,
)

pytestmark = pytest.mark.ngspice

#: The cradle built here: the report's cheaper one (the perfect cradle, N = 50) in its quick form, about 2.5 s;
#: the two-mass N = 100 is built by tests/test_report.py's quick report.
CRADLE = "perfect-N50"


def _job(quick: bool = True):
    return next(job for job in requirements_jobs(quick=quick) if job.name == CRADLE)


@pytest.fixture(scope="module")
def check() -> RequirementsCheck:
    return run_requirements(_job())


@pytest.fixture(scope="module")
def study() -> list:
    """The study's own curves and limits for the same cradle, computed here."""
    job = _job()
    ladder = Ladder(job.chain(), job.L0, job.C0)
    return [requirement(ladder, part, points=job.points) for part in PARTS]


def test_the_jobs_are_the_issues_cradles_priced_by_the_study_and_pickle() -> None:
    full, quick = requirements_jobs(), requirements_jobs(quick=True)
    assert [(job.case, job.N) for job in full] == [("two-mass", 100), ("perfect", 50)]
    assert [(job.case, job.N) for job in quick] == [("two-mass", 100), ("perfect", 50)]
    assert {job.checks for job in full} == {REPORT_CHECKS} and {job.checks for job in quick} == {QUICK_REPORT_CHECKS}
    assert {job.points for job in quick} == {QUICK_GRID_POINTS}
    for job, cheap in zip(full, quick, strict=True):
        # every analysis is priced: the pool orders the section's tasks by the study's own estimate
        assert job.cost == requirements_estimate(job.chain(), PARTS, job.checks, job.points).seconds > cheap.cost
        assert pickle.loads(pickle.dumps(job)) == job  # sent to the report's pool


@pytest.mark.parametrize("field, value", [("checks", 0), ("points", 1), ("L0", 0.0), ("C0", math.nan)])
def test_a_job_refuses_a_bad_field_by_name(field: str, value: float) -> None:
    with pytest.raises(ParameterError, match=field):
        dataclasses.replace(_job(), **{field: value})


def test_the_section_holds_the_studys_limits_and_ngspice_points(check: RequirementsCheck, study: list) -> None:
    assert check.passed and not check.reason and check.name == CRADLE
    ladder = check.ladder
    assert check.ideal == first_arrival_energy(ladder)
    assert [r.part for r in check.requirements] == list(PARTS)
    for got, expected in zip(check.requirements, study, strict=True):
        assert (got.values, got.losses, got.limits) == (expected.values, expected.losses, expected.limits)
    # the quick form's points: QUICK_REPORT_CHECKS per curve, each the exact loss at one of the curve's values
    assert len(check.points) == QUICK_REPORT_CHECKS * len(PARTS)
    for point in check.points:
        curve = next(r for r in check.requirements if r.part.key == point.part)
        assert point.theory == curve.losses[curve.values.index(point.value)]
        assert point_agrees(point)
    assert check.estimate_s == _job().cost and check.wall_s is not None and check.wall_s > 0


def test_the_page_shows_each_limit_in_bulk_and_physical_units(check: RequirementsCheck) -> None:
    figures = requirements_figures([check])
    page = requirements_html([check], {f"requirements:{name}": b"png" for name in figures})
    section = page[page.index(f'id="requirements-{CRADLE}"'):]
    units = f"for L0 = {si(check.ladder.L0, 'H')}, C0 = {si(check.ladder.C0, 'F')}"
    assert units in section and "10 µH" in units and "10 nF" in units
    rows = re.findall(r"<tr><td class=l>(\w+)</td><td class=l>[^<]*</td>(.*?)</tr>", section)
    assert [key for key, _ in rows] == [part.key for part in PARTS]
    for (_, cells), found in zip(rows, check.requirements, strict=True):
        for k in range(len(LOSS_TARGETS)):
            bulk, physical = bulk_limit(found, k), found.statement(k, check.ladder)
            assert f"<td>{bulk.replace('<', '&lt;')}</td>" in cells and physical.replace("&", "&amp;") in cells
            assert f"{found.limits[k]:.3g}" in bulk
    assert "self-resonance above" in section and "MHz" in section
    for point in check.points:
        assert f"<td>{point.loss:.5e}</td>" in section or f"<td>{point.loss:.6g}</td>" in section
    assert page.count("<figure") == 1 and "FAILED" not in page
    assert requirements_summary([check]) == (len(check.points), len(check.points))


def test_the_chart_draws_the_studys_curves_and_points(check: RequirementsCheck) -> None:
    figure = requirements_figures([check])[CRADLE]
    panels = [ax for ax in figure.axes if ax.get_visible()]
    assert len(panels) == len(PARTS)
    for ax, found in zip(panels, check.requirements, strict=True):
        lines = {line.get_label(): line for line in ax.get_lines()}
        theory = lines["circuit theory"]
        assert list(theory.get_xdata()) == list(found.values)
        assert list(theory.get_ydata()) == [abs(loss) for loss in found.losses]
        mine = [point for point in check.points if point.part == found.part.key]
        assert list(lines["ngspice"].get_xdata()) == [point.value for point in mine]


def test_a_point_off_its_curve_fails_the_section_and_the_report(check: RequirementsCheck) -> None:
    point = check.points[0]
    off = CheckPoint(point.part, point.value, point.theory + 0.1, point.theory)
    assert not point_agrees(off) and not point_agrees(dataclasses.replace(point, loss=math.nan))
    failed = dataclasses.replace(check, points=[off, *check.points[1:]], passed=False)
    lines = failed.checks()
    assert [line["kind"] for line in lines] == ["requirements"] and not lines[0]["passed"]
    assert lines[0]["max_abs_error"] > lines[0]["tolerance"]
    report = {"title": "t", "created": "now", "lcchain_version": "0", "ngspice_version": "0",
              "machine": {"system": "", "release": "", "machine": "", "python": "", "numpy": ""}, "quick": True,
              "seconds": 1.0, "checks": lines, "circuit": [], "spectrum": [], "requirements": [failed],
              "tables": {}, "engines": {}, "passed": False,
              "paper": {"tables": {}, "columns": {}, "asymptotic": [], "perfect": {"paper": [], "any_N": []},
                        "findings": []}}
    page = render_html(report, {}, [])
    assert "1 of 1 checks failed" in page and "FAILED" in page
    assert f"{len(check.points) - 1} / {len(check.points)}</b>ngspice points" in page
    data = report_json(report)
    assert f'"name": "{CRADLE}"' in data and '"passed": false' in data


def test_the_pool_returns_the_section_computed_here(check: RequirementsCheck) -> None:
    """The report runs the job in its pool (:class:`Background`): the same numbers, bit for bit (one BLAS thread
    in both, ngspice deterministic), and the parts come back as PARTS' own."""
    job = _job()
    with Background([Job("a", job.cost, run_requirements, (job,)), Job("b", 0.0, abs, (-1,))], workers=2) as pool:
        pooled = pool.take("a")
        assert pool.take("b") == 1
    assert all(got.part is part for got, part in zip(pooled.requirements, PARTS, strict=True))
    assert [(r.values, r.losses, r.limits) for r in pooled.requirements] == \
        [(r.values, r.losses, r.limits) for r in check.requirements]
    assert pooled.points == check.points and pooled.ideal == check.ideal
