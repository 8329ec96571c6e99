"""A tour of lcchain's Python API: theory, a design, an ngspice run, a scene.

Run from the repository root (CI runs it too):

    .venv/bin/python examples/python_api.py [OUTPUT_FOLDER]

It writes three PNG files to OUTPUT_FOLDER (default: the current directory): the report's figure, the overlay
and a scene's space-time map.
"""

import sys
from pathlib import Path

import numpy as np

import lcchain
from lcchain import plots


def main(out: Path) -> None:
    out.mkdir(parents=True, exist_ok=True)

    # Theory: the paper's two-mass chain from (r, w) (Eq. e.rw), its modes and alpha_N(t) (Eq. e.utn).
    chain = lcchain.Chain.from_rw(100, r=0.5873, w=0.0972)
    modes = lcchain.normal_modes(chain)
    t = np.linspace(0, 250, 2501)
    alpha = lcchain.transmission_amplitude(modes, t)
    first = lcchain.first_arrival(modes)
    print(f"N = 100, (r, w) = (0.5873, 0.0972): first arrival at t = {first.time:.4f}, peak {first.peak:.6f} "
          f"(the largest alpha_N on the grid: {alpha.max():.6f})")

    # The optimal two-mass design for any N (a row of Table II).
    design = lcchain.optimal_two_mass(1000)
    print(f"optimal two-mass N = 1000: r* = {design.r:.6f}, w* = {design.w:.6f}, delta* = {design.delta:.3e}")

    # The LC ladder in ngspice against alpha_N(t), the step chosen for an accuracy.
    report = lcchain.simulate_chain(chain, lcchain.ChainOptions(accuracy=1e-3, transits=1))
    print(f"ngspice {report.run.ngspice_version}: dt = {report.options.dt:.4f}, "
          f"max |simulation - theory| = {report.comparison.max_abs_error:.2e}")
    report.plot().savefig(out / "python-api-report.png")  # the report's own figure, as `lcchain simulate --plot`
    w, c = report.waveforms, report.comparison
    plots.overlay(plots.OverlayCurves(w.t, w.last, t, alpha, residual=w.last - c.theory_last),
                  title="N = 100 two-mass, ngspice", path=out / "python-api-overlay.png")

    # A scene built in Python rather than read from TOML: losses and a gaussian pulse.
    scene = lcchain.parse_scene({
        "title": "N = 30 with losses and a gaussian pulse",
        "chain": {"case": "two-mass", "N": 30},
        "excitation": {"kind": "pulse", "shape": "gaussian", "width": 0.3},
        "effects": {"losses": {"Q": 80}},
        "output": {"probes": "all", "plots": ["spacetime"]},
    }, source="examples/python_api.py")
    result = lcchain.run_scene(scene, lcchain.SceneRun(write_outputs=False))
    sample = result.samples[0]
    print(f"scene: max |simulation - theory| over every loop = {result.report['max_abs_error']:.2e}")
    assert sample.t is not None and sample.sim is not None  # a finished sample keeps its waveforms
    plots.spacetime(sample.t, sample.sim, title=scene.title, path=out / "python-api-spacetime.png")


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else Path("."))
