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

import sys
from collections.abc import Callable
from pathlib import Path

from ..core.errors import ParameterError
from ..core.json import json_text
from ..scenes.run import SampleResult, SceneResult, transmitted_peaks
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
    claims: list[tuple[str, Path, str | None]] = [(option, Path(path), None)  # "-": stdout, nothing to check
                                                  for option, path in (others or {}).items() if path and path != "-"]
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


def _csv(sample: SampleResult) -> str:
    """A sample's saved arrays as CSV: loops 1 and N against time, or an AC run's phasors against frequency."""
    if sample.waveforms is not None:
        return sample.waveforms.to_csv()
    ac = sample.run.run
    assert ac is not None  # a sample that ran has one or the other
    header = ["frequency_hz"] + [f"{part}({name})" for name in ac.vectors for part in ("re", "im")]
    columns = [ac.frequency] + [getattr(values, part) for values in ac.vectors.values() for part in ("real", "imag")]
    rows = (",".join(repr(float(v)) for v in row) for row in zip(*columns, strict=True))
    return "\n".join([",".join(header), *rows]) + "\n"


def _overlay(result: SceneResult, path: Path) -> None:
    from . import plots

    scene, s = result.scene, result.good()[0]
    signals = s.run.signals
    assert signals is not None
    ylabel = r"$Q_1,\ Q_N\;/\;Q_1(0)$" if scene.excitation.kind == "displacement" else r"$I_1,\ I_N\;/\;I_0$"
    curves = plots.OverlayCurves(signals.t, signals.sim[-1], signals.t, signals.theory[-1],
                                 residual=signals.sim[-1] - signals.theory[-1], first_sim=signals.sim[0],
                                 first_theory=signals.theory[0], arrivals=s.record["arrivals"])
    plots.overlay(curves, title=_with_size(scene.title, s.chain.N), ylabel=ylabel, path=path)


def _spacetime(result: SceneResult, path: Path) -> None:
    from . import plots

    signals = result.good()[0].run.signals
    assert signals is not None
    plots.spacetime(signals.t, signals.sim, title=f"{result.scene.title}: every loop current", path=path)


def _histogram(result: SceneResult, path: Path) -> None:
    from . import plots

    scene = result.scene
    plots.histogram(transmitted_peaks(result), theory=result.report.get("transmitted_peak", {}).get("theory_nominal"),
                    title=f"{scene.title}: transmitted peak over {len(result.good())} samples",
                    xlabel=peak_label(scene.excitation.kind), path=path)


def _spectrum(result: SceneResult, path: Path) -> None:
    """Fig. Pk20-100's panels for the first sample that ran: |P_n| and the spacing, circuit on theory."""
    from . import plots

    s = result.good()[0]
    spectrum = s.run.spectrum
    assert spectrum is not None
    plots.spectrum(spectrum.omega_theory, spectrum.P_theory, spectrum.omega, spectrum.P,
                   title=_with_size(result.scene.title, s.chain.N), path=path)


def _spacing(result: SceneResult, path: Path) -> None:
    """The samples' delta omega_n, each against the nominal theory's."""
    from . import plots

    rows = [s.run.spectrum.spacings() for s in result.good() if s.run.spectrum is not None]
    plots.spacing_band(result.report["omega_nominal"], rows, path=path,
                       title=f"{result.scene.title}: mode spacing over {len(rows)} samples")


#: How each ``[output] plots`` name is drawn from a scene that ran.
_PLOTS: dict[str, Callable[[SceneResult, Path], None]] = {
    "overlay": _overlay, "spacetime": _spacetime, "histogram": _histogram, "spectrum": _spectrum,
    "spacing": _spacing,
}


def write_scene_outputs(result: SceneResult, *, netlist_out: str | None = None,
                        waveform_out: str | None = None, write_outputs: bool = True) -> list[str]:
    """Write the first good sample's netlist and waveforms if asked, then the scene's plots and report.

    Every file is written atomically; ``-`` writes that text to stdout instead.  Returns the files written, in
    order.
    """
    scene = result.scene
    good = result.good()
    written: list[str] = []
    texts: tuple[tuple[str | None, Callable[[], str]], ...] = (
        (netlist_out, lambda: good[0].netlist), (waveform_out, lambda: _csv(good[0])))
    for target, text in texts:
        if not (good and target):
            continue
        if target == "-":
            sys.stdout.write(text())
            sys.stdout.flush()
        else:
            written.append(str(write_text(target, text())))
    if not write_outputs:
        return written
    if scene_outputs(scene):
        _stem(scene)[0].mkdir(parents=True, exist_ok=True)  # only now that the scene has run
    for key, path in scene_outputs(scene):
        if key == "output.report" or not good:
            continue
        _PLOTS[key.split("(")[1].rstrip(")")](result, path)
        written.append(str(path))
    if scene.output.report:
        written.append(scene.output.report)
        write_text(scene.output.report, json_text(dict(result.report, files=written)))
    return written
