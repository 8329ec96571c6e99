"""``lcchain report --quick`` end to end (issue 12): real ngspice, the page opened in a real headless
Chromium (Debian's, driven by Playwright; nothing is downloaded), the JSON read back."""

from __future__ import annotations

import base64
import hashlib
import json
import math
import re
import shutil
from pathlib import Path

import pytest
from helpers.tolerances import ATOL_TABLE_R, RTOL_SI_UNITS

from lcchain.cli import main
from lcchain.report.html import STYLE, content_security_policy, render_html

pytestmark = pytest.mark.ngspice



@pytest.fixture(scope="module")
def report_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("report") / "out"
    status = main(["report", "--out", str(out), "--quick", "--no-cache"])
    assert status == 0, (out / "report.json").read_text()[:2000] if (out / "report.json").exists() else status
    return out


@pytest.fixture(scope="module")
def data(report_dir: Path) -> dict:
    return json.loads((report_dir / "report.json").read_text())


def test_json_holds_tables_checks_and_versions(data: dict) -> None:
    for key in ("tables", "checks", "ngspice_version", "lcchain_version", "created"):
        assert key in data
    assert re.fullmatch(r"\d+\S*", data["ngspice_version"])  # as `ngspice -v` says it: "39"
    table_keys = {"N", "case", "delta", "s", "m1", "m2", "K12"}
    for case in ("one-mass", "two-mass"):
        rows = data["tables"][case]
        assert {3, 4, 20, 100, 1000} <= {row["N"] for row in rows}
        assert table_keys <= set(rows[0])
    names = [c["name"] for c in data["checks"]]
    assert len(names) == len(set(names))
    for check in data["checks"]:
        assert {"name", "passed", "max_abs_error", "tolerance"} <= set(check)
        assert check["passed"] is True, check
    circuit = [c for c in data["checks"] if c["kind"] == "circuit"]
    assert {c["excitation"] for c in circuit} == {"kick", "displacement"}
    assert len(circuit) >= 20 and any("walls+losses" in c["name"] for c in circuit)
    for check in circuit:
        assert 0 < check["max_abs_error"] <= check["tolerance"]
    # every engine installed runs the same reference circuits (CI installs gnucap)
    engines = set(data["engines"])
    assert "ngspice" in engines and ("gnucap" in engines) == (shutil.which("gnucap") is not None)
    by_engine = {engine: sorted(c["name"].removesuffix(f" ({engine})") for c in circuit if c["engine"] == engine)
                 for engine in engines}
    assert len({tuple(names) for names in by_engine.values()}) == 1
    # Table II, N = 100 recomputed: the printed cells are the paper's and lcchain's own value is beside them
    row = next(r for r in data["tables"]["two-mass"] if r["N"] == 100)
    assert row["r"] == pytest.approx(0.5873, abs=ATOL_TABLE_R)
    assert any(f["where"].startswith("Table II, row N → ∞, column m2*") for f in data["paper"]["findings"])


def test_the_spectrum_section_is_measured_and_counts_in_the_verdict(data: dict, report_dir: Path) -> None:
    """Issue 21, section 2: the quick report's spectra (Fig. Pk20-100's chains and a lossy ladder among them) all
    pass, their lines (omega_n, delta omega_n, P_n, and Q_n with losses) are among the checks, and the page has
    the section with its two figures."""
    spectra = {check["name"]: check for check in data["spectrum"]}
    assert {"two-mass-N20", "two-mass-N100", "perfect-N50", "perfect-N50-walls", "two-mass-N20-losses"} <= set(spectra)
    for check in spectra.values():
        assert check["passed"] and len(check["modes"]) == check["N"], check["name"]
    lines = [c for c in data["checks"] if c["kind"] == "spectrum"]
    assert len(lines) == sum(len(check["errors"]) for check in spectra.values()) == 3 * len(spectra) + 1
    assert all(c["passed"] for c in lines) and sum(c["name"].endswith("Q_n") for c in lines) == 1
    page = (report_dir / "index.html").read_text()
    section = page[page.index('<h2 id="spectrum">'):page.index('<h2 id="figures">')]
    assert section.count("<figure") == 2 and 'id="spectrum-modes"' in section
    assert f"{len(spectra)} / {len(spectra)}</b>spectra" in page


def test_the_requirements_section_is_the_studys_and_counts_in_the_verdict(data: dict, report_dir: Path) -> None:
    """Issue 30, item 4: the quick report's "How good must the parts be" for its two cradles. Each limit is the
    study's first crossing of its own curve (between the grid values where the loss passes the target), each
    ngspice point sits on that curve, and the perfect cradle's limits are those lcchain.circuit.requirements
    computes here."""
    from lcchain.circuit.ladder import Ladder
    from lcchain.circuit.requirements import LOSS_TARGETS, PARTS, requirement
    from lcchain.studies.requirements import requirements_jobs

    sections = {section["name"]: section for section in data["requirements"]}
    jobs = {job.name: job for job in requirements_jobs(quick=True)}
    assert set(sections) == set(jobs) == {"two-mass-N100", "perfect-N50"}
    page = (report_dir / "index.html").read_text()
    html = page[page.index('<h2 id="requirements">'):]
    for name, section in sections.items():
        assert section["passed"] and [part["part"] for part in section["parts"]] == [part.key for part in PARTS]
        assert len(section["check"]) == jobs[name].checks * len(PARTS)
        for part in section["parts"]:
            values, losses = part["values"], part["losses"]
            for target in LOSS_TARGETS:
                limit = part["limits"][f"{target:g}"]
                over = [k for k, loss in enumerate(losses) if loss > target]
                if limit is None:  # never crossed in the part's range
                    assert not over
                else:
                    assert values[over[0] - 1] < limit < values[over[0]]
                assert part["statements"][f"{target:g}"] in html
            for point in (p for p in section["check"] if p["part"] == part["part"]):
                assert point["theory"] == losses[values.index(point["value"])]
        assert f'id="requirements-{name}"' in html
    job = jobs["perfect-N50"]
    ladder = Ladder(job.chain(), job.L0, job.C0)
    for part, found in zip(sections["perfect-N50"]["parts"], PARTS, strict=True):
        expected = requirement(ladder, found, points=job.points)
        assert list(part["limits"].values()) == list(expected.limits)
    lines = [c for c in data["checks"] if c["kind"] == "requirements"]
    assert len(lines) == len(sections) and all(c["passed"] for c in lines)
    assert html.count("<figure") == len(sections)
    points = sum(len(section["check"]) for section in sections.values())
    assert f"{points} / {points}</b>ngspice points" in page


def test_page_forbids_every_request(report_dir: Path) -> None:
    page = (report_dir / "index.html").read_text()
    digest = base64.b64encode(hashlib.sha256(STYLE.encode()).digest()).decode()
    assert f'content="{content_security_policy()}"' in page and f"'sha256-{digest}'" in page
    assert "default-src 'none'" in page and "<script" not in page
    for attribute in re.findall(r'(?:src|href)="([^"]*)"', page):
        assert attribute.startswith(("data:image/png;base64,", "#")), attribute[:80]


def test_a_failed_check_turns_the_verdict(data: dict) -> None:
    """The verdict is computed from the checks: one failing check makes the page say so (and the CLI exit 1)."""
    from lcchain.report.validation import CircuitCheck

    failing = CircuitCheck("made-up run", "two-mass, N = 20", 20, "kick", 0.05, 1e-3, 1e-6, 2.5e-6, False)
    report = {"title": "t", "created": "now", "lcchain_version": "0", "ngspice_version": "0",
              "machine": {"system": "", "release": "", "machine": "", "python": "", "numpy": ""}, "quick": True,
              "seconds": 1.0, "checks": [failing.to_dict()], "circuit": [failing],
              "paper": {"tables": {}, "columns": {}, "asymptotic": [], "perfect": {"paper": [], "any_N": []},
                        "findings": []}}
    page = render_html(report, {}, [])
    assert "1 of 1 checks failed" in page and "FAILED" in page


@pytest.mark.chromium
def test_page_renders_in_chromium_without_a_request_or_an_error(report_dir: Path) -> None:
    from playwright.sync_api import sync_playwright

    url = (report_dir / "index.html").resolve().as_uri()
    requests, errors = [], []
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=shutil.which("chromium"), headless=True, args=["--no-sandbox"])
        try:
            page = browser.new_page(viewport={"width": 1366, "height": 900})
            page.on("request", lambda r: requests.append(r.url))
            page.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
            page.on("pageerror", lambda e: errors.append(str(e)))
            page.goto(url, wait_until="load")
            sizes = page.eval_on_selector_all("img", "imgs => imgs.map(i => [i.naturalWidth, i.naturalHeight])")
            title = page.title()
            table_ii = page.inner_text("#two-mass + p + table")
            verdict = page.inner_text(".verdict")
            pdf = page.pdf()  # it prints
        finally:
            browser.close()
    assert title == "lcchain validation report"
    assert [r for r in requests if not r.startswith("data:") and r != url] == []
    assert errors == []
    assert len(sizes) >= 30 and all(w > 100 and h > 100 for w, h in sizes)
    assert "0.58728" in table_ii and "paper 0.5873" in table_ii  # computed beside printed
    assert verdict == "Every check passed"
    assert pdf[:4] == b"%PDF" and len(pdf) > 100_000


def test_each_thumbnail_is_a_link_to_itself_full_size(report_dir: Path) -> None:
    """Issue 22: every image sits in a link to an in-page view of it (the page fetches nothing, so no file)."""
    page = (report_dir / "index.html").read_text()
    images = re.findall(r"<img ", page)
    linked = re.findall(r'<figure[^>]*><span class=view id="([^"]+)"></span><a class=open href="#([^"]+)"[^>]*><img ',
                        page)
    assert len(images) >= 30 and len(linked) == len(images)
    assert all(view == target for view, target in linked)
    assert len({view for view, _ in linked}) == len(linked)
    assert "figure:has(> .view:target)" in STYLE and "minmax(510px" in STYLE  # shown at their own size


def test_the_report_says_its_units_in_si(data: dict, report_dir: Path) -> None:
    """Issue 33, item 3: the report gives the bulk units in seconds, hertz and ohms (the circuit runs' L0 and C0),
    each step in seconds beside sqrt(L0 C0), and each mode's frequency in hertz."""
    physical = data["physical"]
    tau = math.sqrt(physical["L0_H"] * physical["C0_F"])
    assert physical["time_unit_s"] == pytest.approx(tau, rel=RTOL_SI_UNITS)
    assert physical["frequency_unit_Hz"] == pytest.approx(1 / (2 * math.pi * tau), rel=RTOL_SI_UNITS)
    page = (report_dir / "index.html").read_text()
    assert "time unit sqrt(L0 C0) = 316.228 ns" in page and "impedance sqrt(L0/C0) = 31.6228 ohm" in page
    assert "<th>dt (s)</th>" in page and "f<sub>n</sub> theory (Hz)" in page
    circuit = next(c for c in data["checks"] if c["kind"] == "circuit" and c["dt"])
    assert f"{circuit['dt'] * tau * 1e9:.4g} ns" in page
