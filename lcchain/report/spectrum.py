"""The validation report's section "the spectrum in the circuit" (issue 21): ngspice's normal frequencies, their
spacings and the mode weights against theory, and Figs. Pk20-100 and vk with the circuit's points on top.

The checks are run elsewhere (:mod:`lcchain.studies.spectrum_checks`, in the report's pool); this module draws
and writes what they hold.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING

from ..core.physical import physical_scales
from ..core.types import DEFAULT_C0, DEFAULT_L0
from ..studies.spectrum_checks import VK_DELTAS, VK_N, SpectrumCheck
from .figure_data import DesignRows, pk_data, spectrum_points, vk_data
from .markup import esc, figure_block, num, verdict_cell
from .paper_figures import pk_figure, vk_figure

if TYPE_CHECKING:
    import numpy as np
    from matplotlib.figure import Figure

__all__ = ["SPECTRUM_FIGURES", "spectrum_figures", "spectrum_html", "spectrum_summary", "PER_MODE_CHECK"]

# The spectrum checks run at the default L0 and C0 (lcchain.studies.spectrum_checks): omega = 1 in hertz.
_HERTZ = physical_scales(DEFAULT_L0, DEFAULT_C0)["frequency_unit_Hz"]

#: The section's figures: the paper's label and the caption under it in the page.
SPECTRUM_FIGURES: tuple[tuple[str, str], ...] = (
    ("Pk20-100", "Mode density N P_n and spacing (N/π) δω_n of the optimal two-mass chains, N = 20 (filled) and "
                 "100 (open): theory as in the paper, ngspice's AC measurement as larger open black symbols"),
    ("vk", f"Group velocity and mode density of the one-mass chain, N = {VK_N}: theory as in the paper, "
           "ngspice's as open black rings (v from the measured ω_n between neighbouring modes at mid-k)"),
)
#: The check whose every mode the section lists.
PER_MODE_CHECK = "two-mass-N20"


def spectrum_figures(checks: Sequence[SpectrumCheck], rows: DesignRows) -> dict[str, Figure]:
    """Figs. Pk20-100 and vk (matplotlib Figures, by label) with the points of the checks made for them; a figure
    none of the checks is for is left out."""
    on: dict[str, dict[float, dict[str, np.ndarray]]] = {"Pk20-100": {}, "vk": {}}
    for check in checks:
        if check.figure in on and check.modes and check.panel is not None:
            on[check.figure][check.panel] = spectrum_points(check.modes, check.N)
    figures = {}
    if on["Pk20-100"]:
        pk = {int(N): points for N, points in on["Pk20-100"].items()}
        figures["Pk20-100"] = pk_figure(pk_data(rows), pk)
    if on["vk"]:
        figures["vk"] = vk_figure(vk_data(VK_N, VK_DELTAS), on["vk"])
    return figures


def spectrum_summary(checks: Sequence[SpectrumCheck]) -> tuple[int, float]:
    """How many checks passed, and the worst error over its tolerance among every quantity of every check."""
    ratios = [error / check.tolerances[key] for check in checks for key, error in check.errors.items()
              if error is not None]
    return sum(check.passed for check in checks), max(ratios, default=0.0)


def _summary_table(checks: Sequence[SpectrumCheck]) -> list[str]:
    lines = ["<table><thead><tr><th class=l>check</th><th class=l>chain</th><th>AC points</th>"
             "<th>modes seen / resolved</th><th>ω<sub>n</sub> rel. error</th><th>tolerance</th>"
             "<th>δω<sub>n</sub> rel. error</th><th>tolerance</th><th>P<sub>n</sub> abs. error</th>"
             "<th>tolerance</th><th>Q<sub>n</sub> rel. error</th><th>tolerance</th><th>ngspice s</th>"
             "<th>verdict</th></tr></thead><tbody>"]
    for check in checks:
        verdicts = check.verdicts()
        cells = "".join(f'<td class="{"" if verdicts[key] else "off"}">{num(check.errors[key], 2)}</td>'
                        f"<td>{num(check.tolerances[key], 2)}</td>" if key in check.errors else "<td>–</td><td></td>"
                        for key in ("omega", "spacing", "P", "Q"))
        seen = sum(mode["seen"] for mode in check.modes)
        resolved = sum(mode["resolved"] for mode in check.modes)
        lines.append(f"<tr><td class=l>{esc(check.name)}</td><td class=l>{esc(check.what)}</td>"
                     f"<td>{check.points or '–'}</td><td>{seen} / {resolved}</td>{cells}"
                     f"<td>{num(check.wall_s, 2)}</td><td>{verdict_cell(check.passed, check.reason)}</td></tr>")
    lines.append("</tbody></table>")
    return lines


def _per_mode_table(check: SpectrumCheck) -> list[str]:
    lines = [f'<h3 id="spectrum-modes">Every mode of {esc(check.what)}</h3>',
             "<table><thead><tr><th>n</th><th>ω<sub>n</sub> theory</th><th>f<sub>n</sub> theory (Hz)</th>"
             "<th>ω<sub>n</sub> ngspice</th><th>rel. error</th><th>theory's own bound</th>"
             "<th>δω<sub>n</sub> theory</th>"
             "<th>δω<sub>n</sub> ngspice</th>"
             "<th>P<sub>n</sub> theory</th><th>P<sub>n</sub> ngspice</th><th>|error|</th></tr></thead><tbody>"]
    def fixed(value: float | None, places: int) -> str:
        return "–" if value is None else f"{value:.{places}f}"

    for mode in check.modes:
        theory, measured = mode["omega_theory"], mode["omega"]
        # against the reference beyond float64 (its rest subtracted after the float64 difference, exact this close)
        low = mode.get("omega_theory_low", 0.0)
        error = None if measured is None else abs((measured - theory) - low) / (theory or 1.0)
        P_error = abs((mode["P"] or 0.0) - mode["P_theory"])
        lines.append(f"<tr><td>{mode['n']}</td><td>{fixed(theory, 12)}</td><td>{theory * _HERTZ:.9g}</td>"
                     f"<td>{fixed(measured, 12)}</td>"
                     f"<td>{num(error, 2)}</td><td>{num(mode.get('omega_bound'), 1)}</td>"
                     f"<td>{fixed(mode['spacing_theory'], 12)}</td>"
                     f"<td>{fixed(mode['spacing'], 12)}</td><td>{fixed(mode['P_theory'], 12)}</td>"
                     f"<td>{fixed(mode['P'], 12)}</td><td>{num(P_error, 2)}</td></tr>")
    lines.append("</tbody></table>")
    return lines


def spectrum_html(checks: Sequence[SpectrumCheck], figures: Mapping[str, bytes]) -> str:
    """The section: what is measured and allowed, the table of worst errors and verdicts, every mode of
    two-mass N = 20, and the figures (``figures["spectrum:<label>"]``, PNG)."""
    if not checks:
        return "<p>No spectrum was measured.</p>"
    tolerances = checks[0].tolerances
    lines = ["<p>Each ladder driven in loop 1 by an AC source in ngspice; the poles and residues of I<sub>1</sub>/V"
             "<sub>1</sub> and I<sub>N</sub>/V<sub>1</sub> give ω<sub>n</sub> and P<sub>n</sub>, the mode's weight "
             "in α<sub>N</sub>(t) (<code>lcchain spectrum</code>), set beside the exact modes of the same chain. "
             f"Allowed: ω<sub>n</sub> within {num(tolerances['omega'], 2)} relative over the modes weighing "
             "|P<sub>n</sub>| ≥ 1e-6 at the ends (lighter ones are nearly cancelled poles), "
             f"δω<sub>n</sub> = ω<sub>n</sub> − ω<sub>n−1</sub> within {num(tolerances['spacing'], 2)} relative "
             f"between such neighbours, P<sub>n</sub> within {num(tolerances['P'], 2)} for every mode (an unseen "
             "one counted as 0): about 20 times the worst errors measured over every chain of "
             "benchmarks/spectrum.md. With losses (every coil's Q), each mode's Q<sub>n</sub> = ω<sub>n</sub>/"
             f"γ<sub>n</sub> against ω<sub>n</sub>Q within {num(tolerances['Q'], 2)} relative.</p>",
             *_summary_table(checks)]
    per_mode = next((check for check in checks if check.name == PER_MODE_CHECK and check.modes), None)
    if per_mode is not None:
        lines += _per_mode_table(per_mode)
    lines.append('<div class=grid id="spectrum-figures">')
    for label, caption in SPECTRUM_FIGURES:
        png = figures.get(f"spectrum:{label}")
        if png is not None:
            lines.append(figure_block(png, f"Fig. {label} with ngspice", f"spectrum-{label}",
                                      f"Fig. {esc(label)}: {esc(caption)}", "spectrum-figures"))
    lines.append("</div>")
    return "\n".join(lines)
