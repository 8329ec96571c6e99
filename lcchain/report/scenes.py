"""A scene's files: its JSON report, its plots, and the netlist and waveforms asked for.

:func:`run_scene` is the whole of ``lcchain run`` for one scene: simulate
(:func:`lcchain.scenes.run.simulate_scene`), then write what the scene's
``[output]`` table asks for.  Paths in ``[output]`` are relative to the
current directory.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from dataclasses import replace
from pathlib import Path

from ..scenes.run import SceneResult, simulate_scene, transmitted_peaks
from ..scenes.schema import Scene
from ..spice.simulator import Simulator

__all__ = ["run_scene", "write_scene_outputs"]


def _output_stem(scene: Scene) -> tuple[Path, str]:
    if scene.output.report:
        path = Path(scene.output.report)
        return path.parent, path.stem
    stem = Path(scene.source).stem if scene.source else "scene"
    return Path("."), stem


def _ylabel(scene: Scene) -> str:
    return r"$Q_N\,/\,Q_1(0)$" if scene.excitation.kind == "displacement" else r"$I_N\,/\,I_0$"


def write_scene_outputs(result: SceneResult, *, netlist_out: str | None = None,
                        waveform_out: str | None = None, write_outputs: bool = True) -> list[str]:
    """Write the first good sample's netlist and waveforms if asked, then the scene's plots and report.

    Returns
    -------
    list of str
        The files written, in order.
    """
    from . import plots

    scene, report = result.scene, result.report
    good = result.good()
    written: list[str] = []
    if good and netlist_out:
        Path(netlist_out).write_text(good[0].netlist, encoding="utf-8")
        written.append(netlist_out)
    if good and waveform_out:
        waveforms = good[0].waveforms
        assert waveforms is not None
        Path(waveform_out).write_text(waveforms.to_csv(), encoding="utf-8")
        written.append(waveform_out)
    if not write_outputs:
        return written
    folder, stem = _output_stem(scene)
    wanted = set(scene.output.plots)
    if good and wanted:
        folder.mkdir(parents=True, exist_ok=True)
        s = good[0]
        signals = s.run.signals
        assert signals is not None
        if "overlay" in wanted:
            path = folder / f"{stem}-overlay.png"
            plots.overlay(signals.t, signals.sim[-1], signals.t, signals.theory[-1],
                          residual=signals.sim[-1] - signals.theory[-1],
                          arrivals=[a for a in s.record["arrivals"] if a["end"] == "last"],
                          title=f"{scene.title} (N = {s.chain.N})", ylabel=_ylabel(scene), path=str(path))
            written.append(str(path))
        if "spacetime" in wanted and scene.output.probes == "all":
            path = folder / f"{stem}-spacetime.png"
            plots.spacetime(signals.t, signals.sim, title=f"{scene.title}: every loop current", path=str(path))
            written.append(str(path))
        if "histogram" in wanted and len(good) > 1:
            path = folder / f"{stem}-histogram.png"
            plots.histogram(transmitted_peaks(result), theory=report.get("transmitted_peak", {}).get("theory_nominal"),
                            title=f"{scene.title}: transmitted peak over {len(good)} samples", path=str(path))
            written.append(str(path))
    if scene.output.report:
        path = Path(scene.output.report)
        path.parent.mkdir(parents=True, exist_ok=True)
        written.append(str(path))
        path.write_text(json.dumps(dict(report, files=written), indent=2), encoding="utf-8")
    return written


def run_scene(scene: Scene, *, netlist_out: str | None = None, waveform_out: str | None = None,
              write_outputs: bool = True, progress: Callable[[float], None] | None = None,
              simulator: Simulator | None = None) -> SceneResult:
    """Run every sample of a scene, write its report and plots, return the result.

    Parameters
    ----------
    scene : Scene
    netlist_out, waveform_out : str, optional
        Keep the (first sample's) netlist, and its end waveforms as CSV
        ``t,first,last`` (dimensionless, as ``lcchain simulate`` writes them).
    write_outputs : bool
        Write the report file and plots named by the scene's ``[output]``.
    progress : callable, optional
        Called with the fraction of the scene's simulations done (0 to 1).
    simulator : Simulator, optional
        Found once by the caller; found here when omitted.
    """
    result = simulate_scene(scene, progress=progress, simulator=simulator)
    files = write_scene_outputs(result, netlist_out=netlist_out, waveform_out=waveform_out,
                                write_outputs=write_outputs)
    result.report["files"] = files
    return replace(result, files=tuple(files))
