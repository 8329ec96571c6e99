"""The validation report as one self-contained page, and its JSON.

Nothing in the page is fetched: figures are PNG ``data:`` URIs, the one style
sheet is inline and named by its SHA-256 in a Content-Security-Policy that
forbids everything else (no script at all, no request of any kind).  The page
prints cleanly (figures and table rows are not split across pages).
"""

from __future__ import annotations

import base64
import hashlib
import io
import json
import math
from collections.abc import Iterable, Mapping
from fractions import Fraction
from typing import TYPE_CHECKING

import numpy as np

from ..core.checks import as_float
from ..core.physical import physical_scales, si_text, units_sentence
from ..core.types import DEFAULT_C0, DEFAULT_L0
from ..studies.validation import CHECKED_MAX_N, LARGE_CHECKS, CircuitCheck
from ..theory.design import DESIGN_TABLES
from .markup import esc, figure_block, num, verdict_cell
from .requirements import requirements_html, requirements_summary
from .spectrum import spectrum_html, spectrum_summary
from .validation import AsymptoticEntry, Perfect, TableEntry, ValidationReport

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["render_html", "report_json", "figure_png", "STYLE", "content_security_policy"]

STYLE = """
:root { --ok: #1d7a34; --bad: #b3261e; --muted: #5f6368; --line: #d9dce1; --off: #fff1c2; }
* { box-sizing: border-box; }
body { font: 15px/1.45 system-ui, -apple-system, "Segoe UI", Roboto, "DejaVu Sans", sans-serif; color: #1f2328;
       margin: 0 auto; max-width: 1180px; padding: 24px 28px 60px; }
h1 { font-size: 26px; margin: 0 0 6px; }
h2 { font-size: 21px; margin: 38px 0 8px; border-bottom: 2px solid var(--line); padding-bottom: 4px; }
h3 { font-size: 17px; margin: 24px 0 6px; }
p, li { max-width: 900px; }
.meta { color: var(--muted); font-size: 13px; }
.verdict { display: inline-block; font-weight: 700; padding: 6px 14px; border-radius: 6px; color: #fff;
           font-size: 17px; margin: 8px 0; }
.verdict.ok { background: var(--ok); } .verdict.bad { background: var(--bad); }
.summary { display: flex; gap: 14px; flex-wrap: wrap; margin: 10px 0 4px; }
.summary div { border: 1px solid var(--line); border-radius: 6px; padding: 8px 12px; min-width: 170px; }
.summary b { font-size: 19px; display: block; }
nav ul { columns: 2; padding-left: 18px; margin: 8px 0; }
table { border-collapse: collapse; margin: 8px 0 14px; font-size: 13px; font-variant-numeric: tabular-nums; }
th, td { border: 1px solid var(--line); padding: 3px 7px; text-align: right; vertical-align: top; }
th { background: #f3f4f6; position: sticky; top: 0; }
td.l, th.l { text-align: left; }
td small { display: block; color: var(--muted); font-size: 11px; white-space: nowrap; }
td.off { background: var(--off); }
.pass { color: var(--ok); font-weight: 700; } .fail { color: var(--bad); font-weight: 700; }
figure { margin: 12px 0 22px; break-inside: avoid; page-break-inside: avoid; }
figure img { max-width: 100%; height: auto; border: 1px solid var(--line); }
figure a.open { display: block; cursor: zoom-in; }
figcaption { color: var(--muted); font-size: 13px; margin-top: 4px; }
figure a.close { display: none; }
figure:has(> .view:target) { position: fixed; inset: 0; z-index: 10; margin: 0; padding: 12px; overflow: auto;
  background: rgba(255, 255, 255, 0.97); display: flex; flex-direction: column; align-items: center; }
figure:has(> .view:target) img { width: 96vw; height: 86vh; max-width: none; object-fit: contain; }
figure:has(> .view:target) a.open { cursor: default; }
figure:has(> .view:target) a.close { display: inline; }
.grid { display: grid; grid-template-columns: repeat(auto-fill, minmax(510px, 1fr)); gap: 14px; }
.grid figure { margin: 0; }
code { font-size: 13px; background: #f3f4f6; padding: 0 3px; border-radius: 3px; }
tr { break-inside: avoid; page-break-inside: avoid; }
@media print { body { max-width: none; padding: 0; font-size: 11px; } th { position: static; }
  h2 { break-after: avoid; } nav { display: none; } .grid { grid-template-columns: repeat(2, 1fr); } }
"""


def content_security_policy(style: str = STYLE) -> str:
    """No request of any kind; images only as data: URIs; the one inline style sheet by its hash."""
    digest = base64.b64encode(hashlib.sha256(style.encode()).digest()).decode()
    return (f"default-src 'none'; img-src data:; style-src 'sha256-{digest}'; base-uri 'none'; "
            "form-action 'none'")


def figure_png(figure: Figure, dpi: int = 110) -> bytes:
    """A matplotlib Figure as PNG bytes (never shown, never written to disk)."""
    buffer = io.BytesIO()
    figure.savefig(buffer, format="png", dpi=dpi)
    return buffer.getvalue()


def _decimals(text: str) -> int:
    return len(text.split(".")[1]) if "." in text else 0


def _fraction(value: float) -> str:
    exact = Fraction(value).limit_denominator(100)
    return str(exact) if abs(float(exact) - value) < 1e-12 else f"{value:.6g}"


# ------------------------------------------------------------------ sections
_COLUMN_TITLES = {"x": "x*", "delta": "δ*", "s": "s*", "m1": "m1*", "Delta": "Δ*", "delta_uniform": "δ*(1)",
                  "r": "r*", "w": "w*", "m2": "m2*", "K12": "K12*"}
_DEFAULT_DECIMALS = {"x": 4, "delta": 4, "s": 2, "m1": 3, "Delta": 4, "delta_uniform": 4, "r": 4, "w": 4, "m2": 4,
                     "K12": 4}


#: Decimals a design's table shows beyond the defaults: Table II's delta (the paper prints five).
_CASE_DECIMALS: dict[str, dict[str, int]] = {"two-mass": {"delta": 5}}


def _table_html(case: str, entries: list[TableEntry], columns: tuple[str, ...]) -> str:
    title = ": ".join(DESIGN_TABLES[case])
    decimals = {**_DEFAULT_DECIMALS, **_CASE_DECIMALS.get(case, {})}
    head = "".join(f"<th>{esc(_COLUMN_TITLES[c])}</th>" for c in columns)
    lines = [f'<h3 id="{case}">{esc(title)}</h3>',
             "<p class=meta>Each cell: lcchain's value to two more digits than the paper prints; under it the "
             "paper's printed value and the difference in units of its last digit (highlighted beyond one "
             "unit). Rows without a printed value are not in the paper's copy; lcchain computes them from "
             "scratch.</p>",
             f'<table class="rows"><thead><tr><th>N</th>{head}<th>seconds</th></tr></thead><tbody>']
    for entry in entries:
        row: Mapping[str, object] = entry["row"]  # read by the columns' names
        printed = {cell["key"]: cell for cell in entry["printed"]}
        cells = []
        for key in columns:
            value = as_float(row[key]) if row[key] is not None else math.nan
            if key == "delta":
                value = max(value, 0.0)
            cell = printed.get(key)
            places = (_decimals(cell["printed"]) if cell else decimals[key]) + 2
            shown = f"{value:.{places}f}" if math.isfinite(value) else "–"
            if cell is None:
                cells.append(f"<td>{shown}</td>")
                continue
            off = abs(cell["units"]) > 1.0
            cells.append(f'<td class="{"off" if off else ""}">{shown}<small>paper {esc(cell["printed"])} '
                         f'({cell["units"]:+.2f})</small></td>')
        seconds = entry.get("seconds")
        lines.append(f"<tr><td>{row['N']}</td>{''.join(cells)}<td>{'' if seconds is None else f'{seconds:.2f}'}"
                     "</td></tr>")
    lines.append("</tbody></table>")
    return "\n".join(lines)


def _asymptotic_html(items: list[AsymptoticEntry]) -> str:
    lines = ['<h3 id="asymptotic">The large-N constants</h3>',
             "<table><thead><tr><th class=l>case</th><th class=l>quantity</th><th class=l>printed in</th>"
             "<th>printed</th><th>lcchain</th><th>units off</th></tr></thead><tbody>"]
    for item in items:
        places = _decimals(item["printed"]) + 2
        off = abs(item["units"]) > 1.0
        lines.append(f"<tr><td class=l>{esc(item['case'])}</td><td class=l>{esc(item['key'])}</td>"
                     f"<td class=l>{esc(item['where'])}</td><td>{esc(item['printed'])}</td>"
                     f"<td>{item['computed']:.{places}f}</td>"
                     f"<td class=\"{'off' if off else ''}\">{item['units']:+.2f}</td></tr>")
    lines.append("</tbody></table>")
    return "\n".join(lines)


def _perfect_html(perfect: Perfect) -> str:
    lines = ['<h3 id="perfect">The perfect chains</h3>',
             "<p>The paper's perfect cradles (Sec. II.C and Appendix A), recomputed by lcchain's inverse spectral "
             "design (bulk units: central mass and central spring 1; the paper's N = 4 chain of Sec. II.C is this "
             "one with every mass × 11/12).</p>",
             "<table><thead><tr><th>N</th><th class=l>masses</th><th class=l>springs (walls first and last)</th>"
             "<th>T</th><th>1 − α<sub>N</sub>(T)</th></tr></thead><tbody>"]
    for item in perfect["paper"]:
        lines.append(f"<tr><td>{item['N']}</td><td class=l>{esc(', '.join(map(_fraction, item['masses'])))}</td>"
                     f"<td class=l>{esc(', '.join(map(_fraction, item['springs'])))}</td>"
                     f"<td>{item['t_arrival']:.6f}</td><td>{num(item['delta'], 2)}</td></tr>")
    lines.append("</tbody></table>")
    lines.append("<p>And for any N (not in the paper): equally spaced frequencies, α<sub>N</sub>(T) = 1.</p>"
                 "<table><thead><tr><th>N</th><th>walls j</th><th>T</th><th>1 − α<sub>N</sub>(T)</th>"
                 "<th>masses</th><th>springs</th><th>distinct masses</th><th>distinct springs</th></tr></thead>"
                 "<tbody>")
    for chain in perfect["any_N"]:
        lines.append(f"<tr><td>{chain['N']}</td><td>{chain['walls']}</td><td>{chain['t_arrival']:.6g}</td>"
                     f"<td>{num(chain['delta'], 2)}</td><td>{chain['mass_min']:.4g} – {chain['mass_max']:.4g}</td>"
                     f"<td>{chain['spring_min']:.4g} – {chain['spring_max']:.4g}</td>"
                     f"<td>{chain['distinct_masses']}</td><td>{chain['distinct_springs']}</td></tr>")
    lines.append("</tbody></table>")
    return "\n".join(lines)


def _findings_html(items: list[dict[str, str]]) -> str:
    lines = ['<h3 id="findings">Where the paper slips</h3>',
             "<table><thead><tr><th class=l>where</th><th class=l>printed</th><th class=l>correct</th>"
             "<th class=l>why</th></tr></thead><tbody>"]
    for item in items:
        lines.append(f"<tr><td class=l>{esc(item['where'])}</td><td class=l>{esc(item['printed'])}</td>"
                     f"<td class=l>{esc(item['correct'])}</td><td class=l>{esc(item['note'])}</td></tr>")
    lines.append("</tbody></table>")
    return "\n".join(lines)


def _sizes_html(quick: bool, default_engine: str) -> str:
    """Which reference chains each engine runs, and why not all of them at every N (issue 35)."""
    every = (f"Every engine runs every reference chain of N ≤ {CHECKED_MAX_N} with both excitations, and the scene "
             "with losses and walls")
    if quick:
        return f"<p>Sizes: {every} (--quick: nothing larger).</p>"
    large = ", ".join(f"{name.removesuffix('.cir')} with a {excitation}" for name, excitation in LARGE_CHECKS)
    return (f"<p>Sizes: {every}; above that {esc(default_engine)} runs {esc(large)}, the chain whose error grows "
            "with N. The other runs at N = 1000 (the two-mass chain, the displacements, the other engines) cost "
            "a hundred times a run at N = 100 and measured nothing more: their errors were those at N = 100, or "
            "the kick's, to three digits (measured for issue 35; lcchain.studies.validation gives the "
            "numbers).</p>")


def _circuit_html(checks: list[CircuitCheck], figures: Mapping[str, bytes], time_unit: float, quick: bool = False,
                  default_engine: str = "ngspice") -> str:
    lines = [_sizes_html(quick, default_engine),
             "<p>Each run: ngspice's end-loop current I<sub>N</sub>/I<sub>1</sub>(0) (or charge, after a "
             "displacement) against lcchain's exact theory of the same chain over the whole window. A fixed-step "
             "run passes when its largest error stays below 1.5 × the trapezoidal error model's prediction "
             "+ 1e-9; the scene with losses and walls, below the accuracy it asked for. The step dt is in units "
             "of sqrt(L0 C0) and in seconds.</p>",
             "<table><thead><tr><th class=l>run</th><th class=l>chain</th><th class=l>excitation</th><th>dt</th>"
             "<th>dt (s)</th>"
             "<th>max |sim − theory|</th><th>predicted</th><th>tolerance</th><th>ngspice s</th><th>verdict</th>"
             "</tr></thead><tbody>"]
    for check in checks:
        verdict = verdict_cell(check.passed, check.reason)
        lines.append(f"<tr><td class=l>{esc(check.name)}</td><td class=l>{esc(check.what)}</td>"
                     f"<td class=l>{esc(check.excitation)}</td><td>{num(check.dt, 3)}</td>"
                     f"<td>{'' if check.dt is None else esc(si_text(check.dt * time_unit, 's', 4))}</td>"
                     f"<td>{num(check.max_abs_error, 3)}</td><td>{num(check.predicted_error, 3)}</td>"
                     f"<td>{num(check.tolerance, 3)}</td><td>{num(check.wall_s, 2)}</td><td>{verdict}</td></tr>")
    lines.append("</tbody></table><div class=grid id=circuit-figures>")
    for check in checks:
        png = figures.get(f"check:{check.name}")
        if png is not None:
            lines.append(figure_block(png, check.name, f"check-{check.name}", f"{esc(check.name)}: {esc(check.what)}, "
                                 f"max error {num(check.max_abs_error, 3)}", "circuit-figures"))
    lines.append("</div>")
    return "\n".join(lines)


def _figures_html(figures: Mapping[str, bytes], captions: Iterable[tuple[str, str]]) -> str:
    lines = []
    for label, caption in captions:
        png = figures.get(f"paper:{label}")
        if png is not None:
            lines.append(figure_block(png, "Fig. " + label, f"fig-{label}", f"Fig. {esc(label)}: {esc(caption)}",
                                 f"fig-{esc(label)}", f' id="fig-{esc(label)}"'))
    return "\n".join(lines)


def _number(value: object) -> float | None:
    """A check's number as JSON holds it (None: it has none)."""
    return None if value is None else as_float(value)


def render_html(report: ValidationReport, figures: Mapping[str, bytes], captions: Iterable[tuple[str, str]],
                command: str = "lcchain report") -> str:
    """The page: verdict first, then the paper reproduced, the circuit validated, the figures and how good the
    parts must be."""
    checks = report["checks"]
    paper_checks = [c for c in checks if c.get("kind") == "paper"]
    circuit = report["circuit"]
    failed = [c for c in checks if not c["passed"]]
    verdict = ('<span class="verdict ok">Every check passed</span>' if not failed else
               f'<span class="verdict bad">{len(failed)} of {len(checks)} checks failed</span>')
    paper = report["paper"]
    worst_paper = max((as_float(c["max_abs_error"]) for c in paper_checks), default=0.0)
    worst_ratio = max(((c.max_abs_error or 0.0) / c.tolerance for c in circuit if c.tolerance), default=0.0)
    rows_computed = sum(len(v) for v in paper["tables"].values())
    spectrum = report.get("spectrum", [])
    spectra_passed, spectra_worst = spectrum_summary(spectrum)
    requirements = report.get("requirements", [])
    points_agreeing, points = requirements_summary(requirements)
    engines = ", ".join(f"{name} {version}" for name, version in
                        (report.get("engines") or {"ngspice": report["ngspice_version"]}).items())
    failed_list = "".join(f"<li>{esc(c['name'])}: {esc(c.get('reason') or '')} max error "
                          f"{num(_number(c['max_abs_error']))} &gt; tolerance {num(_number(c['tolerance']))}</li>"
                          for c in failed)
    machine = report["machine"]
    physical = report.get("physical") or physical_scales(DEFAULT_L0, DEFAULT_C0)
    parts = [
        "<!doctype html>",
        '<html lang="en"><head><meta charset="utf-8">',
        f'<meta http-equiv="Content-Security-Policy" content="{content_security_policy()}">',
        '<meta name="viewport" content="width=device-width, initial-scale=1">',
        f"<title>{esc(report['title'])}</title>",
        f"<style>{STYLE}</style></head><body>",
        f"<header><h1>{esc(report['title'])}</h1>",
        f"<p class=meta>lcchain {esc(report['lcchain_version'])} · {esc(engines)} · "
        f"{esc(machine['system'])} {esc(machine['release'])} {esc(machine['machine'])} · "
        f"Python {esc(machine['python'])}"
        f" · numpy {esc(machine['numpy'])} · made {esc(report['created'])} by <code>{esc(command)}</code>"
        f"{' (quick)' if report['quick'] else ''} in {report['seconds']:.0f} s</p>",
        f"<p class=meta>Units: lcchain computes in the chain's bulk units (times in sqrt(L0 C0), angular "
        f"frequencies in 1/sqrt(L0 C0)); the circuit runs use "
        f"{esc(units_sentence(physical['L0_H'], physical['C0_F']))}.</p>",
        verdict,
        f"<ul>{failed_list}</ul>" if failed else "",
        '<div class="summary">',
        f"<div><b>{rows_computed}</b>rows of Tables I and II computed</div>",
        f"<div><b>{len(paper_checks)}</b>printed rows compared; worst cell {worst_paper:.2f} units of the last "
        "digit</div>",
        f"<div><b>{sum(c.passed for c in circuit)} / {len(circuit)}</b>circuit runs within tolerance; worst "
        f"{worst_ratio:.2f} × its tolerance</div>",
        f"<div><b>{spectra_passed} / {len(spectrum)}</b>spectra (ω<sub>n</sub>, δω<sub>n</sub>, P<sub>n</sub>) "
        f"within tolerance; worst {spectra_worst:.1e} × its tolerance</div>" if spectrum else "",
        f"<div><b>{points_agreeing} / {points}</b>ngspice points on the parts' requirement curves</div>"
        if requirements else "",
        "</div></header>",
        "<nav><ul><li><a href=\"#paper\">The paper reproduced</a></li><li><a href=\"#one-mass\">Table I</a></li>"
        "<li><a href=\"#two-mass\">Table II</a></li><li><a href=\"#asymptotic\">Large-N constants</a></li>"
        "<li><a href=\"#perfect\">Perfect chains</a></li><li><a href=\"#findings\">Where the paper slips</a></li>"
        "<li><a href=\"#circuit\">The circuit validated</a></li><li><a href=\"#spectrum\">The spectrum in the "
        "circuit</a></li><li><a href=\"#figures\">The paper's figures</a></li>"
        "<li><a href=\"#requirements\">How good must the parts be</a></li></ul></nav>",
        '<h2 id="paper">The paper reproduced</h2>',
        "<p>Tables I and II recomputed from scratch at every N of the paper's list (the optimiser, the closed-form "
        "modes and the arrival search of lcchain; nothing is looked up), beside the rows the paper prints.</p>",
        *(_table_html(case, entries, tuple(paper["columns"][case])) for case, entries in paper["tables"].items()),
        _asymptotic_html(paper["asymptotic"]),
        _perfect_html(paper["perfect"]),
        _findings_html(paper["findings"]),
        f'<h2 id="circuit">The circuit validated ({esc(engines)})</h2>',
        _circuit_html(circuit, figures, physical["time_unit_s"], bool(report.get("quick")),
                      next(iter(report.get("engines") or {"ngspice": ""}))),
        '<h2 id="spectrum">The spectrum in the circuit (ngspice AC)</h2>',
        spectrum_html(spectrum, figures),
        '<h2 id="figures">The paper\'s figures, recomputed</h2>',
        _figures_html(figures, captions),
        '<h2 id="requirements">How good must the parts be</h2>',
        requirements_html(requirements, figures),
        "</body></html>",
    ]
    return "\n".join(part for part in parts if part)


def _plain(value: object) -> object:
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, (np.floating, np.integer)):
        return value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    return value


def report_json(report: ValidationReport) -> str:
    """``report.json``: tables, checks, versions, created, and the paper section's details (no curves)."""
    data: dict[str, object] = {key: report[key] for key in (
        "title", "created", "lcchain_version", "ngspice_version", "engines", "machine", "quick", "passed", "seconds",
        "tables", "checks")}
    data["physical"] = report.get("physical") or physical_scales(DEFAULT_L0, DEFAULT_C0)
    data["spectrum"] = [check.to_dict() for check in report.get("spectrum", [])]
    data["requirements"] = [check.to_dict() for check in report.get("requirements", [])]
    paper = report["paper"]
    data["paper"] = {"asymptotic": paper["asymptotic"], "perfect": paper["perfect"], "findings": paper["findings"],
                     "printed_rows": {case: [{"N": e["row"]["N"], "cells": e["printed"]} for e in entries
                                             if e["printed"]] for case, entries in paper["tables"].items()},
                     "row_seconds": {case: {str(e["row"]["N"]): e["seconds"] for e in entries}
                                     for case, entries in paper["tables"].items()}}
    return json.dumps(_plain(data), indent=1)
