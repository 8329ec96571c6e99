"""A scene's files: its JSON report, its plots, and the netlist and waveforms asked for.

:func:`check_scene_outputs` checks every output path before anything runs, and
:func:`write_scene_outputs` writes what the scene's ``[output]`` table asks for
from a simulated scene, each file atomically (:func:`lcchain.app.scenes.run_scene`
does the three in order).  Paths in
``[output]`` are relative to the current directory and stay inside it; the
plots are named after the report (``out/r.json`` -> ``out/r-overlay.png``), or
after the scene file when there is no report.
"""

from __future__ import annotations

import json
from pathlib import Path

from ..core.errors import ParameterError
from ..scenes.run import SceneResult, transmitted_peaks
from ..scenes.schema import Scene
from .files import check_inside, check_not_input, check_output, write_text

__all__ = ["write_scene_outputs", "scene_outputs", "check_scene_outputs"]


def _with_size(title: str, N: int) -> str:
    """``title (N = 100)``, unless the title already says N = 100."""
    size = f"N = {N}"
    return title if size in title else f"{title} ({size})"


def peak_label(kind: str) -> str:
    """The axis label of a first-arrival peak: of the kicked loop's current, or of the pulse source's."""
    if kind == "pulse":
        return "transmitted peak: first arrival's max $I_N\\,/\\,I_0$ ($I_0$: the pulse source's peak)"
    if kind == "displacement":
        return "transmitted peak: first arrival's max $Q_N\\,/\\,Q_1(0)$"
    return "transmitted peak: first arrival's max $I_N\\,/\\,I_1(0)$"


def _stem(scene: Scene) -> tuple[Path, str]:
    if scene.output.report:
        path = Path(scene.output.report)
        return path.parent, path.stem
    return Path("."), Path(scene.source).stem if scene.source else "scene"


def scene_outputs(scene: Scene) -> list[tuple[str, Path]]:
    """(key, path) of every file the scene's ``[output]`` asks for, plots first, the report last.

    A plot a scene cannot draw (``spacetime`` without every loop, a
    ``histogram`` of one sample) is refused by the schema, so every path here
    is written when the scene runs.
    """
    folder, stem = _stem(scene)
    files = [(f"output.plots ({kind})", folder / f"{stem}-{kind}.png") for kind in scene.output.plots]
    if scene.output.report:
        files.append(("output.report", Path(scene.output.report)))
    return files


def check_scene_outputs(scenes: list[Scene], others: dict[str, str | None] | None = None,
                        inputs: list[tuple[str, str]] | None = None) -> None:
    """Refuse, before anything runs, a scene output that cannot be written, that two outputs share, that would
    overwrite an input (a scene file), or that leaves the current folder through a symlink.

    Nothing is created here: the report's folder is made when the results are
    written (:func:`write_scene_outputs`), so a refused scene leaves nothing.

    Parameters
    ----------
    scenes : list of Scene
        The scenes of one ``lcchain run``.
    others : dict, optional
        The command's own output files (option -> path).
    inputs : list of (str, str), optional
        Files the command reads (what named it, its path); every scene's own
        file is one.
    """
    inputs = [*(inputs or []), *(("SCENE", scene.source) for scene in scenes if scene.source)]
    seen: dict[Path, str] = {}
    claims: list[tuple[str, Path, str | None]] = [(option, Path(path), None)
                                                  for option, path in (others or {}).items() if path]
    for scene in scenes:
        claims += [(key, path, scene.source) for key, path in scene_outputs(scene)]
    for key, path, source in claims:
        try:
            if source is not None:  # the README: a scene's [output] stays in the current folder
                check_inside(key, path, Path.cwd())
            check_output(key, path, make_folder=True)
            check_not_input(key, path, inputs)
        except ParameterError as error:
            raise error.located(source) from None
        resolved = path.resolve()
        if resolved in seen:
            raise ParameterError(key, str(path), f"a file no other output writes ({seen[resolved]} writes it too: "
                                 "give each scene its own output.report)", source)
        seen[resolved] = f"{source}: {key}" if source else key


def write_scene_outputs(result: SceneResult, *, netlist_out: str | None = None,
                        waveform_out: str | None = None, write_outputs: bool = True) -> list[str]:
    """Write the first good sample's netlist and waveforms if asked, then the scene's plots and report.

    Every file is written atomically.  Returns the files written, in order.
    """
    from . import plots

    scene, report = result.scene, result.report
    good = result.good()
    written: list[str] = []
    if good and netlist_out:
        written.append(str(write_text(netlist_out, good[0].netlist)))
    if good and waveform_out:
        waveforms = good[0].waveforms
        assert waveforms is not None
        written.append(str(write_text(waveform_out, waveforms.to_csv())))
    if not write_outputs:
        return written
    if scene_outputs(scene):
        _stem(scene)[0].mkdir(parents=True, exist_ok=True)  # only now that the scene has run
    ylabel = r"$Q_1,\ Q_N\;/\;Q_1(0)$" if scene.excitation.kind == "displacement" else r"$I_1,\ I_N\;/\;I_0$"
    for key, path in scene_outputs(scene):
        if key == "output.report" or not good:
            continue
        s, kind = good[0], key.split("(")[1].rstrip(")")
        signals = s.run.signals
        assert signals is not None
        if kind == "overlay":
            plots.overlay(signals.t, signals.sim[-1], signals.t, signals.theory[-1],
                          residual=signals.sim[-1] - signals.theory[-1], first_sim=signals.sim[0],
                          first_theory=signals.theory[0], arrivals=s.record["arrivals"],
                          title=_with_size(scene.title, s.chain.N), ylabel=ylabel, path=path)
        elif kind == "spacetime":
            plots.spacetime(signals.t, signals.sim, title=f"{scene.title}: every loop current", path=path)
        else:
            plots.histogram(transmitted_peaks(result), theory=report.get("transmitted_peak", {}).get("theory_nominal"),
                            title=f"{scene.title}: transmitted peak over {len(good)} samples",
                            xlabel=peak_label(scene.excitation.kind), path=path)
        written.append(str(path))
    if scene.output.report:
        written.append(scene.output.report)
        write_text(scene.output.report, json.dumps(dict(report, files=written), indent=2))
    return written
